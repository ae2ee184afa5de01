"""The vector field histogram's kernel against a plain reference of the same rules, its choices
where the answer is known, and whole drives: it arrives in the open and fails behind a wall."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from mazegen.controllers import BUNDLED
from mazegen.runtime.simulation import _choice, drive
from mazegen.runtime.simulation._episodes import ARRIVED, NO_PATH
from mazegen.runtime.simulation._lidar import beam_angles
from mazegen.runtime.simulation._vfh import vfh_command
from tests.runtime.floors import ARENA, population, random_floors
from tests.runtime.simulation.kernel_args import LIMITS, ROBOT, on_one_thread_and_on_all, params_of

PARAMS = params_of("vfh")
NONE2 = np.zeros((1, 1), np.float32)


def wrap(angle: float) -> float:
    return (angle + math.pi) % (2 * math.pi) - math.pi


def reference(params, pose, goal, scan, angles):
    """VFH as documented, written plainly: sector centres tested against every reading."""
    sectors, threshold, safety, window, wide, gain = params
    n = int(sectors)
    width = 2 * math.pi / n
    centres = [-math.pi + (k + 0.5) * width for k in range(n)]
    own = [min(int((wrap(a) + math.pi) / width), n - 1) for a in angles]
    density = [0.0] * n
    reach = ARENA.robot_radius + safety
    for a, d, s in zip(angles, scan, own, strict=True):
        if d >= window:
            continue
        spread = math.pi / 2 if d <= reach else math.asin(reach / d)
        for k in range(n):
            if k == s or abs(wrap(centres[k] - a)) <= spread:
                density[k] = max(density[k], 1 - d / window)
    free = [k in own and density[k] <= threshold for k in range(n)]
    bearing = wrap(math.atan2(goal[1] - pose[1], goal[0] - pose[0]) - pose[2])
    steer = bearing
    if not free[min(int((bearing + math.pi) / width), n - 1)]:
        offers = []
        if all(free):
            offers = [bearing]
        start = free.index(False) if not all(free) else 0
        run = 0
        for k in range(1, n + 1 if not all(free) else 0):
            if free[(start + k) % n]:
                run += 1
                continue
            if run:
                low = (start + k - run) * width - math.pi
                high = low + run * width
                offers += [(low + high) / 2] if run * width <= wide else [low + wide / 2, high - wide / 2]
            run = 0
        if not offers:
            return 0.0, math.copysign(ROBOT.max_turn, bearing)
        steer = wrap(min(offers, key=lambda o: abs(wrap(o - bearing))))
    ahead = density[min(int(math.pi / width), n - 1)]
    return ROBOT.max_speed * (1 - ahead) * max(math.cos(steer), 0), gain * steer


def command(params, pose, goal, scan, angles):
    out = np.zeros(2)
    vfh_command(params, LIMITS, np.array(pose, np.float64), np.array(goal, np.float64), NONE2, NONE2,
                np.zeros(5), np.zeros((0, 2)), scan, angles, np.zeros(0), out)  # fmt: skip
    return tuple(out)


def test_vfh_matches_a_plain_reference_on_random_scans():
    rng = np.random.default_rng(4)
    for trial in range(300):
        beams = int(rng.choice([8, 90, 360]))
        fov = 2 * math.pi if trial % 2 else rng.uniform(1.0, 6.0)
        angles = beam_angles(beams, fov)
        # Clutter: some beams far, some close, some runs of close ones (walls).
        scan = rng.choice([rng.uniform(5, 300), 1000.0], size=beams)
        if trial % 3 == 0:
            lo = rng.integers(0, beams)
            scan[lo : lo + beams // 3] = rng.uniform(10, 120)
        params = PARAMS.copy()
        params[0] = rng.choice([8, 36, 72, 180])
        pose = (500.0, 300.0, rng.uniform(-math.pi, math.pi))
        goal = (rng.uniform(0, 1000), rng.uniform(0, 600))
        got = command(params, pose, goal, scan, angles)
        np.testing.assert_allclose(
            got, reference(params, pose, goal, scan, angles), atol=1e-9, err_msg=str(trial)
        )


def test_vfh_steers_around_an_obstacle_ahead_and_slows_near_it():
    angles = beam_angles(360, 2 * math.pi)
    scan = np.full(360, 1000.0)
    ahead = np.abs(angles) < math.radians(20)
    scan[ahead] = 60.0  # a post 60 cm ahead, the goal straight behind it
    v, w = command(PARAMS, (0.0, 0.0, 0.0), (900.0, 0.0), scan, angles)
    assert abs(w) > 0.3  # turns off the line to the goal
    v_open, w_open = command(PARAMS, (0.0, 0.0, 0.0), (900.0, 0.0), np.full(360, 1000.0), angles)
    assert (v_open, w_open) == (ROBOT.max_speed, 0.0)
    assert v < 0.5 * v_open


def test_vfh_turns_on_the_spot_when_boxed_in():
    angles = beam_angles(360, 2 * math.pi)
    v, w = command(PARAMS, (0.0, 0.0, 0.0), (0.0, 500.0), np.full(360, 25.0), angles)
    assert (v, w) == (0.0, ROBOT.max_turn)


@pytest.mark.parametrize(
    "floor, arrives",
    [([], True), ([("vwall", 500, 300, 20, 600, 0)], False), ([("vwall", 500, 250, 20, 500, 0)], True)],
)
def test_vfh_drives_the_open_floor_and_fails_behind_a_wall(floor, arrives):
    # An empty arena, a wall across it (no way through), a wall with a gap at the top.
    episodes = drive(population(ARENA, [floor]), robot=ROBOT, controller="vfh")
    assert (episodes.outcome[0] == ARRIVED) == arrives


def test_vfh_drives_alike_on_one_thread_and_on_two():
    rng = np.random.default_rng(8)
    pop = population(ARENA, [[], *random_floors(rng, 12, ARENA)])
    one, two = on_one_thread_and_on_all(pop, "vfh")
    assert (one.outcome == ARRIVED).sum() >= 1
    assert (one.outcome != NO_PATH).sum() >= 4
    assert one.outcome.tobytes() == two.outcome.tobytes()
    assert one.trajectory.tobytes() == two.trajectory.tobytes()


def test_vfh_drives_alike_with_its_lidar_cast_only_as_far_as_its_window(monkeypatch):
    # vfh ignores readings beyond its window, so the lidar is cast no farther: same commands.
    rng = np.random.default_rng(3)
    pop = population(ARENA, [[], *random_floors(rng, 7, ARENA)])
    assert _choice.choose("vfh", ROBOT, ARENA).reach == PARAMS[3] < ROBOT.lidar_range
    short = drive(pop, robot=ROBOT, controller="vfh", record=True)
    monkeypatch.setitem(BUNDLED, "vfh", replace(BUNDLED["vfh"], window=None))
    assert _choice.choose("vfh", ROBOT, ARENA).reach == ROBOT.lidar_range
    full = drive(pop, robot=ROBOT, controller="vfh", record=True)
    assert (full.outcome != NO_PATH).sum() >= 3
    assert short.trajectory.tobytes() == full.trajectory.tobytes()
