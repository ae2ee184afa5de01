"""The dynamic window approach's kernel against a plain reference that scores every sample the
same way (no pruning, closed-form arcs), and its choices where the answer is known."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from mazegen.runtime.geometry._cspace import grid_of
from mazegen.runtime.navigation._paths import path_of
from mazegen.runtime.simulation import _drive, drive
from mazegen.runtime.simulation._dwa import LETHAL, dwa_command
from mazegen.runtime.simulation._episodes import ARRIVED
from mazegen.runtime.simulation._fields import floor_fields
from tests.runtime.floors import ARENA, ZIGZAG, population, random_floors
from tests.runtime.simulation.kernel_args import LIMITS, ROBOT, on_one_thread_and_on_all, params_of

PARAMS = params_of("dwa")
GOAL = np.array(ARENA.goal, np.float64)
NONE = np.zeros(0)


def field_at(field: np.ndarray, grid: np.ndarray, x: float, y: float, outside: float) -> float:
    u, t = (x - grid[0]) / grid[2], (y - grid[1]) / grid[2]
    if u < 0 or t < 0 or int(t) >= field.shape[0] or int(u) >= field.shape[1]:
        return outside
    return float(field[int(t), int(u)])


def to_path(path: np.ndarray, x: float, y: float) -> float:
    best = math.inf
    for (ax, ay), (bx, by) in itertools.pairwise(path):
        ex, ey = bx - ax, by - ay
        den = ex * ex + ey * ey
        u = 0.0 if den == 0 else min(max(((x - ax) * ex + (y - ay) * ey) / den, 0.0), 1.0)
        best = min(best, math.hypot(ax + u * ex - x, ay + u * ey - y))
    return best


def reference(params, pose, nav, clear, grid, path):
    """Every sample of the window scored in full: ``{(v, w): (cost, tie)}`` of the admissible ones."""
    x, y, theta, v_now, w_now = pose
    max_speed, min_speed, max_turn, accel, turn_accel, dt, radius = LIMITS[:7]
    v_lo, v_hi = max(min_speed, v_now - accel * dt), min(max_speed, v_now + accel * dt)
    w_lo, w_hi = max(-max_turn, w_now - turn_accel * dt), min(max_turn, w_now + turn_accel * dt)
    nv, nw, horizon, occ, pdist, gdist, inflation, decay, resolution, forward, _ = params
    speeds = np.linspace(v_lo, v_hi, int(nv))
    turns = (
        [0.0, *np.linspace(w_lo, w_hi, int(nw) - 1)]
        if w_lo <= 0 <= w_hi
        else np.linspace(w_lo, w_hi, int(nw))
    )
    here = field_at(clear, grid, x, y, 0.0)
    scores = {}
    for v in speeds:
        points = max(1, math.ceil(v * horizon / grid[2]))
        for w in turns:
            times = horizon * np.arange(1, points + 1) / points
            if abs(w) > 1e-9:
                xs = x + v / w * (np.sin(theta + w * times) - math.sin(theta))
                ys = y + v / w * (math.cos(theta) - np.cos(theta + w * times))
            else:
                xs, ys = x + v * times * math.cos(theta), y + v * times * math.sin(theta)
            clears = [field_at(clear, grid, px, py, 0.0) for px, py in zip(xs, ys)]
            hit = min(clears) <= radius if here > radius else min(clears) < here
            goal = field_at(nav, grid, xs[-1], ys[-1], math.inf)
            if hit or goal == math.inf:
                continue
            gap = min(clears) - radius
            obstacle = LETHAL * math.exp(-max(gap, 0) / decay) if gap < inflation else 0.0
            cost = (gdist * goal + pdist * to_path(path, xs[-1], ys[-1])) / resolution + occ * obstacle
            end = theta + w * horizon
            tie = field_at(
                nav, grid, xs[-1] + forward * math.cos(end), ys[-1] + forward * math.sin(end), math.inf
            )
            scores[(float(v), float(w))] = (cost, tie)
    return scores


def command(params, pose, nav, clear, grid, path):
    out = np.zeros(2)
    dwa_command(
        params, LIMITS, np.asarray(pose, np.float64), GOAL, nav, clear, grid, path, NONE, NONE, NONE, out
    )
    return float(out[0]), float(out[1])


def test_dwa_picks_the_cheapest_sample_of_the_window_as_a_plain_search_does():
    rng = np.random.default_rng(2)
    pop = population(ARENA, [*random_floors(rng, 20, ARENA), ZIGZAG])
    grid_cells = grid_of(ARENA)
    paths = [path_of(pop, grid_cells, i) for i in range(pop.size)]
    keep = [i for i, p in enumerate(paths) if p is not None]
    nav, clear, grid = floor_fields(pop, ROBOT, np.array(keep))
    checked = agreed = 0
    for m, i in enumerate(keep):
        free = np.argwhere(np.isfinite(nav[m]))
        for _ in range(15):
            r, c = free[rng.integers(len(free))]
            pose = (
                (c + rng.random()) * grid[2],
                (r + rng.random()) * grid[2],
                rng.uniform(-math.pi, math.pi),
                rng.uniform(0, ROBOT.max_speed),
                rng.uniform(-ROBOT.max_turn, ROBOT.max_turn),
            )
            params = PARAMS.copy()
            if checked % 3 == 1:  # fewer samples
                params[0], params[1] = 3, 7
            scores = reference(params, pose, nav[m], clear[m], grid, paths[i])
            v, w = command(params, pose, nav[m], clear[m], grid, paths[i])
            checked += 1
            if not scores:
                assert (v, w) == (0.0, 0.0)
                agreed += 1
                continue
            best = min(scores.values())
            picked = min(scores, key=scores.__getitem__)
            driven = [
                k
                for k in scores
                if math.isclose(k[0], v, abs_tol=1e-9) and math.isclose(k[1], w, abs_tol=1e-9)
            ]
            assert driven, "the kernel drove a sample the reference discards"
            assert scores[driven[0]][0] <= best[0] * (1 + 1e-9) + 1e-9
            agreed += driven[0] == picked
    # Arcs computed two ways may land on either side of a cell edge now and then.
    assert agreed >= 0.97 * checked, (agreed, checked)


@pytest.mark.parametrize("theta, wall_y, turn", [(math.radians(100), 350, -1), (math.radians(-100), 250, 1)])
def test_dwa_turns_toward_the_goal_when_facing_a_wall(theta, wall_y, turn):
    # A wall 20 cm ahead of the robot's edge: going on hits it; the goal lies to one side.
    pop = population(ARENA, [[("vwall", 500, wall_y, 300, 20, 0)]])
    nav, clear, grid = floor_fields(pop, ROBOT, None)
    path = np.array([[500.0, 300.0], GOAL])
    v, w = command(PARAMS, (500.0, 300.0, theta, 0.0, 0.0), nav[0], clear[0], grid, path)
    assert w * turn > 0.3 * ROBOT.max_turn, (v, w)


def test_dwa_stops_when_no_sample_is_admissible():
    pop = population(ARENA, [[]])
    nav, clear, grid = floor_fields(pop, ROBOT, None)
    # Up against the arena's corner inside the blocked border, heading out of the floor, moving
    # too fast to stop or turn in one step: every arc goes deeper.
    limits_slow = LIMITS.copy()
    pose = (1.0, 1.0, math.radians(-135), ROBOT.max_speed, 0.0)
    out = np.zeros(2)
    limits_slow[3], limits_slow[4] = 1e-6, 1e-6
    dwa_command(
        PARAMS,
        limits_slow,
        np.array(pose),
        GOAL,
        nav[0],
        clear[0],
        grid,
        np.array([[1.0, 1.0], GOAL]),
        NONE,
        NONE,
        NONE,
        out,
    )
    assert out.tolist() == [0.0, 0.0]


@pytest.mark.parametrize("heading", [0.0, 1.0, -2.0])
def test_dwa_heads_for_the_goal_in_the_open(heading):
    pop = population(ARENA, [[]])
    nav, clear, grid = floor_fields(pop, ROBOT, None)
    x, y = 500.0, 300.0
    path = np.array([[x, y], GOAL])
    v, w = command(PARAMS, (x, y, heading, ROBOT.max_speed, 0.0), nav[0], clear[0], grid, path)
    bearing = math.atan2(GOAL[1] - y, GOAL[0] - x)
    error = (bearing - heading + math.pi) % (2 * math.pi) - math.pi
    assert w * error > 0  # turns toward the goal
    if abs(error) < 0.3:
        assert v == pytest.approx(ROBOT.max_speed)


U_TRAP = [("vwall", 600, 300, 20, 260, 0), ("vwall", 500, 420, 220, 20, 0), ("vwall", 500, 180, 220, 20, 0)]
"""A cup open toward the start, its back across the straight line to the goal."""
WALL = [("vwall", 500, 300, 20, 600, 0)]
"""A wall from the arena's bottom to its top: no way through."""


def test_dwa_escapes_a_u_trap_that_catches_straight():
    pop = population(ARENA, [U_TRAP])
    assert drive(pop, robot=ROBOT, controller="straight").outcome[0] != ARRIVED
    episodes = drive(pop, robot=ROBOT, controller="dwa", record=True)
    assert episodes.outcome[0] == ARRIVED
    assert episodes.clearance[0] > 0
    # It went round the cup, not through it: somewhere beyond its arms.
    track = episodes.trajectory[0, : episodes.steps[0] + 1]
    assert ((track[:, 1] > 430) | (track[:, 1] < 170)).any()


def test_dwa_arrives_in_the_open_and_fails_behind_a_wall():
    episodes = drive(population(ARENA, [[], WALL]), robot=ROBOT, controller="dwa")
    assert episodes.outcome[0] == ARRIVED
    # Little slower than the optimal time: accelerating, and turning toward the goal at first.
    assert episodes.time[0] <= episodes.optimal_time[0] + 2.0
    assert episodes.failed[1]


def test_dwa_drives_alike_on_one_thread_and_on_two():
    rng = np.random.default_rng(8)
    pop = population(ARENA, [*random_floors(rng, 12, ARENA), U_TRAP, ZIGZAG])
    one, two = on_one_thread_and_on_all(pop, "dwa")
    assert (one.outcome == ARRIVED).sum() >= 3
    assert one.outcome.tobytes() == two.outcome.tobytes()
    assert one.trajectory.tobytes() == two.trajectory.tobytes()


def test_dwa_drives_alike_in_chunks_of_floors(monkeypatch):
    # The fields are built a chunk of floors at a time: chunks of 4 drive as one chunk does.
    rng = np.random.default_rng(9)
    pop = population(ARENA, [*random_floors(rng, 9, ARENA), U_TRAP])
    whole = drive(pop, robot=ROBOT, controller="dwa", record=True)
    grid = grid_of(ARENA)
    monkeypatch.setattr(_drive, "FIELD_CELLS", 4 * grid.rows * grid.cols)
    chunked = drive(pop, robot=ROBOT, controller="dwa", record=True)
    assert (whole.outcome == ARRIVED).sum() >= 3
    assert whole.outcome.tobytes() == chunked.outcome.tobytes()
    assert whole.trajectory.tobytes() == chunked.trajectory.tobytes()
