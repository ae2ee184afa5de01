"""Tests of the unit-frame parts built for each shape kind."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

from mazegen.dsl.shapes import (
    bar_parts,
    polygon_parts,
    rect_parts,
    regular_polygon_parts,
    square_parts,
    triangle_parts,
)
from mazegen.spec import Part

L_SHAPE = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
U_SHAPE = [(0, 0), (30, 0), (30, 30), (20, 30), (20, 10), (10, 10), (10, 30), (0, 30)]
ARROW_CW = [(0, 1), (3, 1), (3, 2), (5, 0), (3, -2), (3, -1), (0, -1)]
STAR = [
    (
        math.cos(math.pi / 2 + k * math.pi / 5) * (1.0 if k % 2 == 0 else 0.4),
        math.sin(math.pi / 2 + k * math.pi / 5) * (1.0 if k % 2 == 0 else 0.4),
    )
    for k in range(10)
]
COMB = [
    (0, 0),
    (50, 0),
    (50, 20),
    (40, 20),
    (40, 5),
    (30, 5),
    (30, 20),
    (20, 20),
    (20, 5),
    (10, 5),
    (10, 20),
    (0, 20),
]
NON_CONVEX = {
    "L": L_SHAPE,
    "U": U_SHAPE,
    "arrow_cw": ARROW_CW,
    "star": STAR,
    "comb": COMB,
    "closed_l": [*L_SHAPE, L_SHAPE[0]],
    "far_away": [(x * 1e3 + 5e5, y * 1e3 - 7e5) for x, y in U_SHAPE],
}

BAR_L = [((0, 0), (0, 2)), ((0, 0), (1, 0))]
BAR_E = [((0, 0), (0, 4)), ((0, 0), (3, 0)), ((0, 2), (2, 2)), ((0, 4), (3, 4))]
BAR_ANGLE = [((0, 0), (3, 0)), ((0, 0), (2, 2))]
BAR_SQUARE = [((0, 0), (1, 0)), ((1, 0), (1, 1)), ((1, 1), (0, 1)), ((0, 1), (0, 0))]

SHAPES = {
    "rect": rect_parts(),
    "square": square_parts(),
    "triangle": triangle_parts(),
    **{f"regular_{n}": regular_polygon_parts(n) for n in (3, 4, 5, 6, 7, 8, 12)},
    **{f"polygon_{name}": polygon_parts(points) for name, points in NON_CONVEX.items()},
    "polygon_convex": polygon_parts([(0, 0), (4, 0), (5, 2), (2, 4), (-1, 2)]),
    "bar_l": bar_parts(BAR_L, 8.0),
    "bar_e": bar_parts(BAR_E, 8.0),
    "bar_angle": bar_parts(BAR_ANGLE, 8.0),
    "bar_square": bar_parts(BAR_SQUARE, 8.0),
}


def _vertices(part: Part, size: float = 100.0) -> np.ndarray:
    """A part's vertices at a uniform size (offsets are absolute)."""
    return np.asarray(part.unit) * size + np.asarray(part.offset)


def _cross(ring: np.ndarray) -> np.ndarray:
    """Cross products of consecutive edges at every vertex."""
    before = ring - np.roll(ring, 1, axis=0)
    after = np.roll(ring, -1, axis=0) - ring
    return before[:, 0] * after[:, 1] - before[:, 1] * after[:, 0]


def _normalised(points: list[tuple[float, float]]) -> np.ndarray:
    pts = np.asarray(points, float)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    return (pts - (lo + hi) / 2) / (hi - lo).max()


def _union(parts: tuple[Part, ...], size: float = 1.0):
    return shapely.union_all([Polygon(_vertices(p, size)) for p in parts])


@pytest.mark.parametrize("name", SHAPES)
def test_unit_bounding_box_is_centred_with_longest_side_one(name: str) -> None:
    unit = np.concatenate([np.asarray(p.unit) for p in SHAPES[name]])
    lo, hi = unit.min(axis=0), unit.max(axis=0)
    assert (hi - lo).max() == pytest.approx(1.0, abs=1e-12)
    assert np.allclose((lo + hi) / 2, 0.0, atol=1e-12)


@pytest.mark.parametrize("name", SHAPES)
def test_parts_are_convex_and_counter_clockwise(name: str) -> None:
    for part in SHAPES[name]:
        assert len(part.unit) == len(part.offset) >= 3
        assert (_cross(_vertices(part)) > 1e-9).all()


def test_rect_and_square_are_the_unit_square() -> None:
    assert rect_parts() == square_parts()
    assert _union(rect_parts()).equals(shapely.box(-0.5, -0.5, 0.5, 0.5))


def test_triangle_is_equilateral_pointing_up() -> None:
    (part,) = triangle_parts()
    ring = np.asarray(part.unit)
    sides = np.linalg.norm(np.roll(ring, -1, axis=0) - ring, axis=1)
    assert np.allclose(sides, 1.0)
    assert ring[:, 1].argmax() == 2 and ring[2, 0] == 0.0


@pytest.mark.parametrize("sides", [3, 5, 6, 9])
def test_regular_polygon_has_equal_sides_and_flat_bottom(sides: int) -> None:
    (part,) = regular_polygon_parts(sides)
    ring = np.asarray(part.unit)
    lengths = np.linalg.norm(np.roll(ring, -1, axis=0) - ring, axis=1)
    assert len(ring) == sides
    assert np.allclose(lengths, lengths[0])
    assert ring[0, 1] == pytest.approx(ring[1, 1]) == pytest.approx(ring[:, 1].min())


def test_convex_polygon_is_one_part_and_clockwise_input_is_reversed() -> None:
    (part,) = polygon_parts([(0, 0), (0, 2), (3, 2), (3, 0)])
    assert Polygon(part.unit).equals(shapely.box(-0.5, -1 / 3, 0.5, 1 / 3))
    assert (_cross(np.asarray(part.unit)) > 0).all()


def test_straight_vertices_are_dropped() -> None:
    (part,) = polygon_parts([(0, 0), (1, 0), (2, 0), (2, 1), (2, 2), (0, 2), (0, 1)])
    assert part.unit == ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5))


@pytest.mark.parametrize("name", NON_CONVEX)
def test_non_convex_parts_tile_the_normalised_polygon(name: str) -> None:
    parts = SHAPES[f"polygon_{name}"]
    expected = Polygon(_normalised(NON_CONVEX[name]))
    union = _union(parts)
    assert len(parts) > 1
    assert union.area == pytest.approx(expected.area, rel=1e-9)
    assert union.symmetric_difference(expected).area < 1e-9
    assert sum(Polygon(p.unit).area for p in parts) == pytest.approx(expected.area, rel=1e-9)


def test_merging_leaves_fewer_parts_than_triangles() -> None:
    assert len(polygon_parts(L_SHAPE)) == 2
    assert len(polygon_parts(U_SHAPE)) < len(U_SHAPE) - 2


def test_random_star_shaped_polygons_tile_exactly() -> None:
    rng = np.random.default_rng(7)
    for _ in range(60):
        n = int(rng.integers(5, 16))
        angles = np.sort(rng.uniform(0, 2 * np.pi, n))
        radii = rng.uniform(0.2, 1.0, n)
        points = list(zip(radii * np.cos(angles), radii * np.sin(angles), strict=True))
        expected = Polygon(_normalised(points))
        if not expected.is_valid:
            continue
        parts = polygon_parts(points)
        for part in parts:
            assert (_cross(np.asarray(part.unit)) > 0).all()
        assert sum(Polygon(p.unit).area for p in parts) == pytest.approx(expected.area, rel=1e-9)
        assert _union(parts).symmetric_difference(expected).area < 1e-9


def test_bar_l_shape_is_two_square_capped_rectangles() -> None:
    size, thickness = 100.0, 8.0
    parts = bar_parts(BAR_L, thickness)
    assert len(parts) == 2
    vertical, horizontal = (Polygon(_vertices(p, size)) for p in parts)
    # Unit endpoints: the L is 1 wide and 2 high, so it is normalised to 0.5 × 1.
    assert vertical.equals(shapely.box(-25 - 4, -50 - 4, -25 + 4, 50 + 4))
    assert horizontal.equals(shapely.box(-25 - 4, -50 - 4, 25 + 4, -50 + 4))
    union = _union(parts, size)
    assert union.geom_type == "Polygon"
    assert union.area == pytest.approx((1.5 * size + thickness) * thickness)
    for part in parts:
        assert part.unit[0] == part.unit[3] and part.unit[1] == part.unit[2]
        assert np.allclose(np.abs(part.offset), thickness / 2)


@pytest.mark.parametrize("segments", [BAR_E, BAR_SQUARE, BAR_ANGLE])
def test_bar_figures_are_connected(segments: list) -> None:
    union = _union(bar_parts(segments, 6.0), 100.0)
    assert union.geom_type == "Polygon"


@pytest.mark.parametrize(
    ("points", "message"),
    [
        ([(0, 0), (1, 1)], "3 distinct"),
        ([(0, 0), (1, 1), (0, 0), (1, 1)], "3 distinct"),
        ([(0, 0), (1, 1), (3, 3)], "zero area"),
        ([(0, 0), (1, 0), (2, 0), (3, 0)], "zero area"),
        ([(0, 0), (1, 1), (1, 0), (0, 1)], "cross"),
        ([(0, 0), (2, 0), (2, 2), (1, -1), (0, 2)], "cross"),
        ([(0, 0), (2, 0), (2, 2), (1, 0), (0, 2)], "cross"),
        ([(0, 0), (2, 0), (1, 0), (1, 2)], "cross"),
    ],
)
def test_polygon_errors(points: list, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        polygon_parts(points)


def test_regular_polygon_needs_three_sides() -> None:
    with pytest.raises(ValueError, match="at least 3 sides"):
        regular_polygon_parts(2)


@pytest.mark.parametrize(
    ("segments", "thickness", "message"),
    [
        ([((0, 0), (0, 0))], 1.0, "zero length"),
        ([((0, 0), (1, 0)), ((1, 1), (1, 1))], 1.0, "zero length"),
        ([], 1.0, "at least one segment"),
        ([((0, 0), (1, 0))], 0.0, "thickness"),
        ([((0, 0), (1, 0))], -2.0, "thickness"),
    ],
)
def test_bar_errors(segments: list, thickness: float, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        bar_parts(segments, thickness)
