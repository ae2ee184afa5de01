"""The lidar's ranges against shapely's ray intersections, and its beams' angles."""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import Point

from mazegen.runtime.simulation._lidar import beam_angles, scan
from tests.runtime.simulation.worlds import SIZE, outline, random_parts, reference_range, world


def test_ranges_match_shapely_ray_intersections():
    rng = np.random.default_rng(11)
    angles = beam_angles(36, 2 * math.pi)
    for _ in range(15):
        parts = random_parts(rng, 10)
        floor, obstacles = world(parts), outline(parts)
        near = np.zeros(len(parts), np.int64)
        out = np.zeros(len(angles))
        for _ in range(5):
            x, y = rng.uniform((0, 0), SIZE)
            if obstacles.contains(Point(x, y)):
                continue  # inside a part the first edge is the way out; shapely's boundary agrees, but skip
            theta = rng.uniform(-math.pi, math.pi)
            reach = rng.uniform(50, 300)
            scan(x, y, theta, angles, reach, 0, floor.arrays, near, out)
            expected = [reference_range(obstacles, x, y, theta + a, reach) for a in angles]
            np.testing.assert_allclose(out, expected, atol=1e-7)


def test_a_beam_meets_nothing_within_range_reads_the_range():
    floor = world([])
    out = np.zeros(1)
    scan(200.0, 150.0, 0.0, np.zeros(1), 50.0, 0, floor.arrays, np.zeros(0, np.int64), out)
    assert out[0] == 50.0
    scan(200.0, 150.0, 0.0, np.zeros(1), 500.0, 0, floor.arrays, np.zeros(0, np.int64), out)
    assert out[0] == pytest.approx(200.0)  # the east wall at x = 400


def test_beams_spread_over_the_field_of_view_centred_on_the_heading():
    full = beam_angles(4, 2 * math.pi)
    np.testing.assert_allclose(full, [-math.pi, -math.pi / 2, 0, math.pi / 2])
    np.testing.assert_allclose(beam_angles(3, math.pi), [-math.pi / 2, 0, math.pi / 2])
    assert beam_angles(1, 1.0).tolist() == [0.0] and beam_angles(0, 1.0).size == 0


def test_the_beams_of_a_span_are_found_as_numpys_searchsorted_finds_them():
    from mazegen.runtime.simulation._lidar import _first_above, _first_not_below

    angles = beam_angles(9, math.pi)
    for value in [-4.0, angles[0], *angles[3:5], (angles[4] + angles[5]) / 2, angles[-1], 4.0]:
        assert _first_not_below(angles, value) == np.searchsorted(angles, value, side="left")
        assert _first_above(angles, value) == np.searchsorted(angles, value, side="right")
