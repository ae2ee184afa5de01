"""Elements and an arena's zones: the kernel's verdicts against shapely's, for rectangles, convex and
non-convex zones and every rule."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

from mazegen.dsl.shapes import polygon_parts
from mazegen.runtime.geometry import ZoneArrays, elements_off_zones
from mazegen.spec import Zone
from tests.runtime.elements import TABLE, TYPES, random_population, shapely_geometries

NAMES = tuple(t.name for t in TYPES)


def zone(name: str, rule: str, outline: list[tuple[float, float]], types: tuple[str, ...] = ()) -> Zone:
    """A zone as the language makes it: its convex parts from :func:`polygon_parts`, moved back."""
    xs, ys = [x for x, _ in outline], [y for _, y in outline]
    span = max(max(xs) - min(xs), max(ys) - min(ys))
    cx, cy = (max(xs) + min(xs)) / 2, (max(ys) + min(ys)) / 2
    parts = tuple(
        tuple((ux * span + cx, uy * span + cy) for ux, uy in part.unit) for part in polygon_parts(outline)
    )
    return Zone(name, rule, tuple(outline), parts, types)


ZONES = (
    zone("lane", "clear", [(0, 200), (500, 200), (500, 260), (0, 260)]),
    zone(
        "ell", "accepts", [(300, 300), (480, 300), (480, 480), (400, 480), (400, 380), (300, 380)], ("box",)
    ),
    zone("store", "holds", [(20, 20), (260, 20), (260, 180), (20, 180)], ("tri", "hex")),
    zone("wedge", "holds", [(300, 20), (480, 20), (480, 180), (390, 100), (300, 180)], ("hex",)),
)


def _truth(name: str, element, zones: tuple[Zone, ...]) -> bool | None:
    """Whether ``element`` breaks a zone's rule by shapely, or None where a hair decides."""
    outlines = {z.name: Polygon(z.outline) for z in zones}
    for z in zones:
        allowed = z.rule == "holds" or (z.rule == "accepts" and name in z.types)
        if not allowed and element.intersection(outlines[z.name]).area > 1e-9:
            return True
    holding = [outlines[z.name] for z in zones if z.rule == "holds" and name in z.types]
    if not holding:
        return False
    inside = any(h.buffer(1e-6).covers(element) for h in holding)
    if inside != any(h.buffer(-1e-6).covers(element) for h in holding):
        return None
    return not inside


@pytest.mark.parametrize("seed", [1, 2])
def test_the_kernel_breaks_the_rules_shapely_breaks(seed):
    rng = np.random.default_rng(seed)
    ids, n_elements, params = random_population(rng, 400, 4, 500.0, 500.0)
    params[..., 2:4] *= 0.5
    broken = elements_off_zones(TABLE, ids, n_elements, params, ZoneArrays.of(ZONES, NAMES), (500.0, 500.0))
    arena = shapely.box(0, 0, 500, 500)
    seen = {True: 0, False: 0}
    for i, elements in enumerate(shapely_geometries(TABLE, ids, n_elements, params)):
        for k, element in enumerate(elements):
            if not arena.covers(element):
                assert not broken[i, k]  # outside the rectangle: counted as outside, not here
                continue
            truth = _truth(NAMES[ids[i, k]], element, ZONES)
            if truth is not None:
                assert broken[i, k] == truth, (i, k, NAMES[ids[i, k]])
                seen[truth] += 1
    assert seen[True] > 100 and seen[False] > 100


def test_an_element_wholly_inside_a_non_convex_zone_holding_it_is_allowed():
    ell = zone("ell", "holds", [(0, 0), (300, 0), (300, 100), (100, 100), (100, 300), (0, 300)], ("box",))
    arrays = ZoneArrays.of((ell,), NAMES)
    ids = np.zeros((1, 3), np.int32)
    # inside the foot of the L; a bar from one arm to the other (every vertex inside, its long edges
    # across the inner corner); beyond the inner corner
    params = np.array([[[200, 50, 60, 40, 0.0], [150, 150, 270, 10, -np.pi / 4], [250, 250, 40, 40, 0.0]]])
    broken = elements_off_zones(TABLE, ids, np.array([3], np.int32), params, arrays, (400.0, 400.0))
    truth = [_truth("box", e, (ell,)) for e in shapely_geometries(TABLE, ids, np.array([3]), params)[0]]
    assert broken[0].tolist() == truth == [False, True, True]
