"""The box robot's collision verdict and clearance against shapely, a plain reference: the box moved
along its heading, then turned on the spot, and its distance to the parts and walls; and a drive in
which the box's width, not the arena's radius, decides a gap."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from shapely import affinity

from mazegen.runtime.simulation import ARRIVED, COLLISION, drive
from mazegen.runtime.simulation._box import box_distance, box_sweep, turn_touches
from mazegen.runtime.simulation._collide import NO_HIT
from mazegen.spec import Arena, robot_for
from tests.runtime.floors import population
from tests.runtime.simulation.worlds import SIZE, outline, random_parts, walls, world


def placed(x: float, y: float, theta: float, length: float, width: float):
    """The box at ``(x, y)`` heading ``theta``, as shapely."""
    body = shapely.box(-length / 2, -width / 2, length / 2, width / 2)
    return affinity.translate(affinity.rotate(body, theta, origin=(0, 0), use_radians=True), x, y)


def reference_distance(obstacles, shape) -> float:
    """Distance from ``shape`` to the parts or the walls (0 where it overlaps or leaves the arena)."""
    if not shapely.box(0, 0, *SIZE).contains(shape):
        return 0.0
    found = shape.distance(walls())
    return min(found, shape.distance(obstacles)) if not obstacles.is_empty else found


def random_box(rng: np.random.Generator) -> tuple[float, float, float, float, float]:
    """``(x, y, theta, length, width)``: some long and thin, some nearly square."""
    length = rng.uniform(4, 60)
    x, y = rng.uniform((0, 0), SIZE)
    return x, y, rng.uniform(-math.pi, math.pi), length, length * rng.uniform(0.2, 1.0)


def test_a_moved_boxs_first_contact_matches_shapely():
    rng = np.random.default_rng(11)
    checked = hits = 0
    for _ in range(30):
        parts = random_parts(rng, 12)
        floor, obstacles = world(parts), outline(parts)
        for _ in range(60):
            x, y, theta, length, width = random_box(rng)
            reach = rng.normal(0, 30)  # along the heading, either way
            dx, dy = reach * math.cos(theta), reach * math.sin(theta)
            start, end = placed(x, y, theta, length, width), placed(x + dx, y + dy, theta, length, width)
            expected = reference_distance(obstacles, shapely.convex_hull(shapely.union(start, end)))
            if expected < 1e-7 and reference_distance(obstacles, start) < 1e-7 and expected != 0.0:
                continue  # too close to call in floating point
            t = box_sweep(x, y, theta, dx, dy, 0.0, length / 2, width / 2, 0, floor.arrays)
            assert (t <= 1.0) == (expected == 0.0), (x, y, theta, length, width, reach, expected, t)
            checked += 1
            if t <= 1.0:
                hits += 1
                # The first contact: touching there, and clear of everything before it.
                there = placed(x + t * dx, y + t * dy, theta, length, width)
                assert reference_distance(obstacles, there) == pytest.approx(0.0, abs=1e-6)
                if t > 0.0:
                    before = placed(x + 0.999 * t * dx, y + 0.999 * t * dy, theta, length, width)
                    swept = shapely.convex_hull(shapely.union(start, before))
                    assert reference_distance(obstacles, swept) > 0.0
    assert checked > 1500 and 0.2 < hits / checked < 0.8


def test_a_turned_boxs_verdict_matches_shapely_sampled_finely():
    """A box clear where it stands, near a part or wall, touches as it turns exactly when one of many
    finely spaced headings over the turn touches; cases closer than the spacing can tell are left
    out."""
    rng = np.random.default_rng(12)
    checked = hits = 0
    for _ in range(30):
        parts = random_parts(rng, 12)
        floor, obstacles = world(parts), outline(parts)
        for _ in range(120):
            x, y, theta, length, width = random_box(rng)
            if not 0.0 < reference_distance(obstacles, placed(x, y, theta, length, width)) < 3.0:
                continue  # (clear, and near enough something for a turn to matter)
            turn = rng.uniform(-1.2, 1.2)
            samples = 400
            nearest = min(
                reference_distance(obstacles, placed(x, y, theta + turn * k / samples, length, width))
                for k in range(samples + 1)
            )
            spacing = math.hypot(length, width) / 2 * abs(turn) / samples
            if 0.0 < nearest < spacing:
                continue  # a touch could hide between two samples
            touched = turn_touches(x, y, theta, turn, length / 2, width / 2, 0, floor.arrays)
            assert touched == (nearest == 0.0), (x, y, theta, turn, length, width, nearest)
            checked += 1
            hits += touched
    assert checked > 200 and 0.2 < hits / checked < 0.8


def test_a_box_that_only_turns_into_a_part_touches_at_the_end_of_its_move():
    square = np.array([[100.0, 100.0], [200.0, 100.0], [200.0, 200.0], [100.0, 200.0]])
    floor = world([square])
    # A 60 x 50 box heading along x, its centre at x = 60 and its nose 10 short of the square's side:
    # moving 5 on clears it, and turning a quarter there swings a corner 39 from the centre into it.
    hl, hw = 30.0, 25.0
    assert box_sweep(60.0, 150.0, 0.0, 5.0, 0.0, 0.0, hl, hw, 0, floor.arrays) == NO_HIT
    assert box_sweep(60.0, 150.0, 0.0, 5.0, 0.0, math.pi / 2, hl, hw, 0, floor.arrays) == 1.0
    assert box_sweep(60.0, 150.0, 0.0, 20.0, 0.0, 0.0, hl, hw, 0, floor.arrays) == pytest.approx(0.5)
    # The same turn above the square touches nothing.
    assert not turn_touches(60.0, 255.0, 0.0, math.pi / 2, hl, hw, 0, floor.arrays)


def test_a_boxs_clearance_is_shapelys_distance():
    rng = np.random.default_rng(13)
    for _ in range(20):
        parts = random_parts(rng, 12)
        floor, obstacles = world(parts), outline(parts)
        for _ in range(50):
            x, y, theta, length, width = random_box(rng)
            found = box_distance(x, y, theta, length / 2, width / 2, 0, floor.arrays, np.inf)
            expected = reference_distance(obstacles, placed(x, y, theta, length, width))
            assert found == pytest.approx(expected, abs=1e-9)
            assert box_distance(x, y, theta, length / 2, width / 2, 0, floor.arrays, 5.0) == min(found, 5.0)


YARD = Arena("yard", 4.0, 3.0, "m", (0.5, 1.5), (3.5, 1.5), 0.2, 0.05)
GAP = [("vwall", 2.0, 0.625, 0.1, 1.25, 0), ("vwall", 2.0, 2.375, 0.1, 1.25, 0)]
"""A wall across YARD with a 0.5 m gap on the straight route."""


def full_speed_ahead(observations):
    """A user's policy: straight on at top speed, stepped between the kernels' steps."""
    return np.column_stack([np.full(observations.floor.size, 0.5), np.zeros(observations.floor.size)])


@pytest.mark.parametrize("controller", ["straight", full_speed_ahead], ids=["bundled", "policy"])
@pytest.mark.parametrize(("width", "arrives"), [(0.4, True), (0.6, False)])
def test_the_boxs_width_not_the_arenas_radius_decides_a_gap(width, arrives, controller):
    floors = population(YARD, [GAP])
    robot = robot_for(YARD, footprint=(0.5, width))
    episodes = drive(floors, robot=robot, controller=controller)
    assert episodes.outcome[0] == (ARRIVED if arrives else COLLISION)
    if arrives:  # its closest approach is the box's to the gap's sides
        assert episodes.clearance[0] == pytest.approx((0.5 - width) / 2, abs=0.02)
    else:  # it touched with its front corners at the wall's face
        assert episodes.collision[0, 0] + 0.25 == pytest.approx(1.95, abs=1e-9)
    disc = drive(floors, robot=robot_for(YARD), controller=controller)
    assert disc.outcome[0] == ARRIVED  # the arena's 0.2 m disc passes either way
