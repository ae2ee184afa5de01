"""The swept-disc collision verdict and the clearance distance against shapely, a plain reference."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, Point

from mazegen.runtime.simulation._collide import NO_HIT, distance, sweep
from tests.runtime.simulation.worlds import SIZE, outline, random_parts, walls, world

SQUARE = np.array([[100.0, 100.0], [200.0, 100.0], [200.0, 200.0], [100.0, 200.0]])


def reference_distance(obstacles, segment) -> float:
    """Distance from the segment to the parts or the walls (0 when it crosses either)."""
    inside = shapely.box(0, 0, *SIZE)
    if not inside.contains(segment):
        return 0.0
    found = segment.distance(walls())
    return min(found, segment.distance(obstacles)) if not obstacles.is_empty else found


def test_swept_verdicts_match_shapely_on_random_floors():
    rng = np.random.default_rng(7)
    checked = hits = 0
    for _ in range(40):
        parts = random_parts(rng, 12)
        floor, obstacles = world(parts), outline(parts)
        for _ in range(60):
            start = rng.uniform((0, 0), SIZE)
            end = start + rng.normal(0, 30, 2)
            r = rng.uniform(1, 25)
            segment = LineString([start, end])
            expected = reference_distance(obstacles, segment)
            if abs(expected - r) < 1e-7:
                continue  # too close to call in floating point: the touching tests decide these
            t = sweep(*start, *end, r, 0, floor.arrays)
            assert (t <= 1.0) == (expected <= r), (start, end, r, expected, t)
            checked += 1
            if t <= 1.0:
                hits += 1
                contact = start + t * (end - start)
                before = LineString([start, contact]) if t > 0 else Point(start)
                # The first contact: touching there, and clear of everything before it.
                assert reference_distance(obstacles, before) == pytest.approx(r, abs=1e-6) or t == 0.0
                assert (
                    t == 0.0
                    or reference_distance(obstacles, LineString([start, start + 0.999 * t * (end - start)]))
                    > r - 1e-9
                )
    assert checked > 2000 and 0.2 < hits / checked < 0.8


def test_touching_is_a_collision_and_a_hair_away_is_not():
    floor = world([SQUARE])
    r = 10.0
    # Ends exactly r short of the square's left side, then a hair shorter.
    assert sweep(50.0, 150.0, 90.0, 150.0, r, 0, floor.arrays) == 1.0
    assert sweep(50.0, 150.0, 89.9999, 150.0, r, 0, floor.arrays) == NO_HIT
    # Touching a corner diagonally: distance from (90, 90) to (100, 100) is 10·sqrt(2).
    assert sweep(80.0, 80.0, 100 - 10 / np.sqrt(2), 100 - 10 / np.sqrt(2), r, 0, floor.arrays) <= 1.0
    # The walls too: the disc may come to r from a wall, not closer.
    assert sweep(50.0, 30.0, 50.0, 10.0, r, 0, floor.arrays) == 1.0
    assert sweep(50.0, 30.0, 50.0, 10.5, r, 0, floor.arrays) == NO_HIT


def test_grazing_along_a_side_at_the_radius_collides():
    floor = world([SQUARE])
    assert sweep(50.0, 90.0, 250.0, 90.0, 10.0, 0, floor.arrays) <= 1.0  # slides along y = 100 - r
    assert sweep(50.0, 89.999, 250.0, 89.999, 10.0, 0, floor.arrays) == NO_HIT


def test_a_thin_wall_cannot_be_stepped_through():
    wall = np.array([[199.5, 20.0], [200.5, 20.0], [200.5, 280.0], [199.5, 280.0]])
    floor = world([wall])
    # Both ends are well clear of the wall: only the motion between them crosses it.
    assert reference_distance(outline([wall]), Point(150, 150)) > 10
    assert reference_distance(outline([wall]), Point(250, 150)) > 10
    t = sweep(150.0, 150.0, 250.0, 150.0, 10.0, 0, floor.arrays)
    assert t == pytest.approx((189.5 - 150) / 100)


def test_distance_is_shapelys_nearest_part_or_wall():
    rng = np.random.default_rng(3)
    for _ in range(20):
        parts = random_parts(rng, 10)
        floor, obstacles = world(parts), outline(parts)
        for point in rng.uniform((0, 0), SIZE, (30, 2)):
            expected = min(Point(point).distance(walls()), Point(point).distance(obstacles))
            assert distance(*point, 0, floor.arrays, np.inf) == pytest.approx(expected, abs=1e-9)
            assert distance(*point, 0, floor.arrays, 5.0) == pytest.approx(min(expected, 5.0), abs=1e-9)
