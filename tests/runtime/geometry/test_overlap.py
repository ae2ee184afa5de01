"""Tests of the overlap and containment counts against shapely and a plain SAT reference."""

from __future__ import annotations

import numpy as np
import shapely

from mazegen.runtime.geometry._elements import ElementTable, element_bounds, world_parts
from mazegen.runtime.geometry._overlap import elements_outside, overlapping_pairs
from tests.runtime.elements import SQUARE, TABLE, random_population, shapely_geometries, squares


def sat_overlap(a: np.ndarray, b: np.ndarray) -> bool:
    """Reference SAT: convex CCW polygons overlap iff their projections on every edge normal overlap."""
    for poly in (a, b):
        edges = np.roll(poly, -1, axis=0) - poly
        normals = np.column_stack([edges[:, 1], -edges[:, 0]])
        pa, pb = a @ normals.T, b @ normals.T
        if np.any((pa.max(axis=0) <= pb.min(axis=0)) | (pb.max(axis=0) <= pa.min(axis=0))):
            return False
    return True


def reference_pairs(table, ids, n_elements, params) -> np.ndarray:
    counts = np.zeros(len(ids), np.int32)
    for i in range(len(ids)):
        parts = [world_parts(table, ids[i, k], params[i, k]) for k in range(n_elements[i])]
        for a in range(len(parts)):
            for b in range(a + 1, len(parts)):
                counts[i] += any(sat_overlap(pa, pb) for pa in parts[a] for pb in parts[b])
    return counts


def test_overlaps_match_shapely_on_random_scenarios() -> None:
    rng = np.random.default_rng(2024)
    ids, n_elements, params = random_population(rng, 2000, 8, 400.0, 300.0)
    geometries = shapely_geometries(TABLE, ids, n_elements, params)
    owners, first, second = [], [], []
    for i, row in enumerate(geometries):
        for a in range(len(row)):
            for b in range(a + 1, len(row)):
                owners.append(i)
                first.append(row[a])
                second.append(row[b])
    areas = shapely.area(shapely.intersection(np.array(first), np.array(second)))
    expected = np.bincount(np.array(owners)[areas > 1e-9], minlength=len(ids))
    got = overlapping_pairs(TABLE, ids, n_elements, params)
    assert got.dtype == np.int32
    np.testing.assert_array_equal(got, expected)
    assert (got == 0).sum() > 100 and got.max() >= 5  # both outcomes are well exercised


def test_overlaps_match_reference_sat_exactly() -> None:
    rng = np.random.default_rng(5)
    ids, n_elements, params = random_population(rng, 600, 7, 300.0, 250.0)
    np.testing.assert_array_equal(
        overlapping_pairs(TABLE, ids, n_elements, params), reference_pairs(TABLE, ids, n_elements, params)
    )


def test_touching_on_a_grid_matches_reference_and_shapely() -> None:
    # Axis-aligned squares on a grid of their own size: many exactly shared edges and corners.
    rng = np.random.default_rng(11)
    table = ElementTable.from_types(SQUARE)
    n, k = 400, 6
    params = np.zeros((n, k, 5))
    params[..., :2] = rng.integers(0, 5, (n, k, 2)) * 10.0
    params[..., 2:4] = rng.choice([10.0, 20.0], (n, k, 1))
    ids = np.zeros((n, k), np.int32)
    n_elements = np.full(n, k, np.int32)
    got = overlapping_pairs(table, ids, n_elements, params)
    np.testing.assert_array_equal(got, reference_pairs(table, ids, n_elements, params))
    geometries = shapely_geometries(table, ids, n_elements, params)
    expected = [
        sum(row[a].intersection(row[b]).area > 1e-9 for a in range(k) for b in range(a + 1, k))
        for row in geometries
    ]
    np.testing.assert_array_equal(got, expected)


def test_separated_squares_do_not_overlap() -> None:
    table = ElementTable.from_types(SQUARE)
    assert overlapping_pairs(table, *squares((10, 10), (40, 10), (10, 40), (40, 40))).tolist() == [0]


def test_touching_squares_do_not_overlap() -> None:
    table = ElementTable.from_types(SQUARE)
    assert overlapping_pairs(table, *squares((10, 10), (30, 10), (30, 30), (50, 50))).tolist() == [0]


def test_figure_19_three_overlapping_pairs() -> None:
    table = ElementTable.from_types(SQUARE)
    pairs = overlapping_pairs(table, *squares((10, 10), (25, 10), (40, 10), (55, 10)))
    assert pairs.tolist() == [3]
    assert 4 - 0.5 * pairs[0] == 2.5  # the paper's fitness with K = 0.5


def test_nested_and_crossing_elements_overlap() -> None:
    table = ElementTable.from_types(SQUARE)
    nested = squares((50, 50), (50, 50))
    nested[2][0, 1, 2:4] = 5.0
    assert overlapping_pairs(table, *nested).tolist() == [1]
    cross = squares((50, 50), (50, 50))
    cross[2][0, 0, 2:4] = (100.0, 4.0)
    cross[2][0, 1, 2:4] = (4.0, 100.0)
    assert overlapping_pairs(table, *cross).tolist() == [1]


def test_outside_matches_shapely() -> None:
    rng = np.random.default_rng(3)
    width, height = 300.0, 200.0
    ids, n_elements, params = random_population(rng, 1500, 6, width, height, margin=30.0)
    got = elements_outside(TABLE, ids, n_elements, params, width, height)
    inner = shapely.box(0, 0, width, height).buffer(-1e-9, join_style="mitre")
    outer = shapely.box(0, 0, width, height).buffer(1e-9, join_style="mitre")
    expected, ambiguous = [], 0
    for row in shapely_geometries(TABLE, ids, n_elements, params):
        inside_inner = np.array([inner.contains(g) for g in row], bool)
        inside_outer = np.array([outer.contains(g) for g in row], bool)
        ambiguous += int((inside_inner != inside_outer).sum())
        expected.append(int((~inside_outer).sum()))
    assert ambiguous == 0
    np.testing.assert_array_equal(got, expected)
    assert 0 < got.mean() < 3


def test_outside_counts_boundary_as_inside() -> None:
    table = ElementTable.from_types(SQUARE)
    assert elements_outside(table, *squares((10, 10), (90, 40), (50, 25)), 100, 50).tolist() == [0]
    assert elements_outside(table, *squares((9.5, 10), (90, 40.5), (50, 25)), 100, 50).tolist() == [2]


def test_empty_population_and_empty_individuals() -> None:
    ids, n_elements, params = np.zeros((0, 4), np.int32), np.zeros(0, np.int32), np.zeros((0, 4, 5))
    assert overlapping_pairs(TABLE, ids, n_elements, params).shape == (0,)
    assert elements_outside(TABLE, ids, n_elements, params, 10, 10).shape == (0,)
    assert element_bounds(TABLE, ids, n_elements, params).shape == (0, 4, 4)
    ids, n_elements, params = np.full((3, 2), -1, np.int32), np.zeros(3, np.int32), np.full((3, 2, 5), np.nan)
    assert overlapping_pairs(TABLE, ids, n_elements, params).tolist() == [0, 0, 0]
