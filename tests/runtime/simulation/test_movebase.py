"""movebase against plain references: the inflation cost against costmap_2d's formula, navfn's
potential against a brute-force Dijkstra, the goal distance against a breadth-first search, each
rollout's score against a direct computation, the choice against a plain search of every sample;
and a drive that replans around a corridor closed to the padded footprint."""

from __future__ import annotations

import dataclasses
import heapq
import itertools
import math
from collections import deque

import numpy as np
import pytest

from mazegen.errors import MazeError
from mazegen.runtime.simulation import ARRIVED, drive
from mazegen.runtime.simulation._choice import bundled_params
from mazegen.runtime.simulation._costmap import costmap_fields, descend
from mazegen.runtime.simulation._movebase import MEMORY, movebase_command
from mazegen.runtime.simulation._paths import floor_paths
from mazegen.runtime.simulation._rollout import CUT, OFF, OUTLINES, frame_of, score, trajectory
from mazegen.runtime.simulation._state import robot_limits
from mazegen.spec import Arena, ControllerSpec, robot_for
from tests.runtime.floors import population

YARD = Arena("yard", 4.0, 3.0, "m", (0.5, 1.5), (3.5, 1.5), 0.2, 0.05)
GAP = [("vwall", 2.0, 0.625, 0.1, 1.25, 0), ("vwall", 2.0, 1.85, 0.1, 0.2, 0)]
"""A wall across YARD with a 0.5 m gap on the straight route, open to MazeGen's 0.2 m disc but not to
the padded footprint (0.53 m wide), and a 1.05 m opening at the top."""
CLUTTER = [
    ("router", 1.3, 1.2, 0.3, 0.3, 20),
    ("vwall", 2.2, 2.1, 0.1, 1.2, 0),
    ("hwall", 2.8, 0.9, 0.9, 0.1, 15),
    ("cobot", 3.0, 2.3, 0.4, 0.4, 70),
]
ROBOT = robot_for(YARD, min_speed=-0.5)
PARAMS = bundled_params("movebase", (), YARD)
LIMITS = robot_limits(ROBOT, YARD)
INSCRIBED, INFLATION, DECAY = 0.265, 0.30, 0.1


def fields(floor: list[tuple]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    nav, clear, grid = costmap_fields(population(YARD, [floor]), PARAMS, np.array([0]))
    return nav[0], clear[0], grid


def formula(d: float) -> float:
    """costmap_2d's InflationLayer::computeCost, distances in metres."""
    if d == 0:
        return 254.0
    if d <= INSCRIBED:
        return 253.0
    if d > INFLATION:
        return 0.0
    return float(math.floor(252 * math.exp(-(d - INSCRIBED) / DECAY)))


def test_the_inflation_cost_is_costmap_2ds_formula():
    nav, clear, _ = fields(CLUTTER)
    expected = np.vectorize(formula)(clear.astype(np.float64))
    assert np.array_equal(nav[2], expected.astype(np.float32))
    assert {254.0, 253.0, 0.0} <= set(np.unique(nav[2]).tolist())
    band = nav[2][(nav[2] > 0) & (nav[2] < 253)]
    assert band.size and band.min() >= math.floor(252 * math.exp(-(INFLATION - INSCRIBED) / DECAY))
    assert formula(INSCRIBED + 0.01) == 228.0  # ⌊252 · e^-0.1⌋


def _neighbours(r: int, c: int, rows: int, cols: int):
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            if (dr or dc) and 0 <= r + dr < rows and 0 <= c + dc < cols:
                yield r + dr, c + dc, math.sqrt(2.0) if dr and dc else 1.0


def brute_potential(cost: np.ndarray, goal: tuple[int, int]) -> np.ndarray:
    """Dijkstra with a heap over the 8-connected cells: a cell costs 50 + 0.8 · cost, cells of cost 253
    or more are walls (the goal's own cell excepted), a step costs the mean of its cells times its
    length."""
    rows, cols = cost.shape

    def own(r, c):
        if (r, c) == goal:
            return 50.0
        return math.inf if cost[r, c] >= 253 else 50.0 + 0.8 * float(cost[r, c])

    best = np.full(cost.shape, np.inf)
    best[goal] = 0.0
    heap = [(0.0, goal)]
    while heap:
        key, (r, c) = heapq.heappop(heap)
        if key > best[r, c]:
            continue
        for nr, nc, length in _neighbours(r, c, rows, cols):
            theirs = own(nr, nc)
            if theirs == math.inf:
                continue
            reached = key + 0.5 * (own(r, c) + theirs) * length
            if reached < best[nr, nc]:
                best[nr, nc] = reached
                heapq.heappush(heap, (reached, (nr, nc)))
    return best


GOAL_BY_A_WALL = [*CLUTTER, ("vwall", 3.8, 1.5, 0.1, 0.6, 0)]
"""CLUTTER with a wall 0.25 m beyond the goal: the goal's cell is within the inscribed radius, a wall to
navfn but for its being the goal (BARN's goals by their side walls are)."""


@pytest.mark.parametrize("floor", [CLUTTER, GOAL_BY_A_WALL], ids=["clutter", "goal-by-a-wall"])
def test_navfns_potential_is_a_brute_force_dijkstra_and_the_plan_descends_it(floor):
    nav, clear, grid = fields(floor)
    goal = (int(YARD.goal[1] / grid[2]), int(YARD.goal[0] / grid[2]))
    assert (nav[2][goal] >= 253) == (floor is GOAL_BY_A_WALL)
    reference = brute_potential(nav[2], goal)
    reached = np.isfinite(reference)
    assert np.array_equal(np.isfinite(nav[0]), reached)
    assert np.allclose(nav[0][reached], reference[reached], rtol=1e-5)
    # the plan from the start: adjacent cells down to the goal, costing what the potential says
    frame = frame_of(PARAMS, grid)
    start = (int(YARD.start[1] / grid[2]), int(YARD.start[0] / grid[2]))
    plan = np.empty((4096, 2), np.int64)
    n = descend(nav[0], clear, (frame[3], frame[4], frame[5]), start[0], start[1], 10**6, plan)
    cells = [tuple(cell) for cell in plan[:n]]
    assert cells[0] == start and cells[-1] == goal
    steps = list(itertools.pairwise(cells))
    assert all(max(abs(a[0] - b[0]), abs(a[1] - b[1])) == 1 for a, b in steps)

    def navfn(cell):  # the robot's own cell and the goal's count as free, as navfn has them
        return 50.0 if cell in (start, goal) else 50.0 + 0.8 * float(nav[2][cell])

    cost = sum(0.5 * (navfn(a) + navfn(b)) * math.hypot(a[0] - b[0], a[1] - b[1]) for a, b in steps)
    cheapest = min(
        reference[r, c] + 0.5 * (50.0 + navfn((r, c))) * length
        for r, c, length in _neighbours(*start, *nav[0].shape)
    )
    assert cost == pytest.approx(cheapest, rel=1e-5)


def test_the_goal_distance_is_a_breadth_first_search_of_4_connected_cells():
    nav, _, grid = fields(CLUTTER)
    goal = (int(YARD.goal[1] / grid[2]), int(YARD.goal[0] / grid[2]))
    rows, cols = nav[1].shape
    steps = np.full((rows, cols), np.inf)
    steps[goal] = 0
    queue = deque([goal])
    while queue:
        r, c = queue.popleft()
        for nr, nc in ((r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)):
            if 0 <= nr < rows and 0 <= nc < cols and steps[nr, nc] == np.inf and nav[2][nr, nc] < 253:
                steps[nr, nc] = steps[r, c] + 1
                queue.append((nr, nc))
    assert np.array_equal(nav[1], steps.astype(np.float32))


def _bresenham(r0: int, c0: int, r1: int, c1: int) -> list[tuple[int, int]]:
    """base_local_planner's line of cells from (x0, y0) = (c0, r0) to (x1, y1) = (c1, r1), both ends
    included: a step along the longer axis every cell, along the other when the error overflows."""
    cells = []
    along_x = abs(c1 - c0) >= abs(r1 - r0)
    major, minor = (abs(c1 - c0), abs(r1 - r0)) if along_x else (abs(r1 - r0), abs(c1 - c0))
    step_c, step_r = (1 if c1 >= c0 else -1), (1 if r1 >= r0 else -1)
    r, c, num = r0, c0, major // 2
    for _ in range(major + 1):
        cells.append((r, c))
        num += minor
        overflow = num >= major
        if overflow:
            num -= major
        r += step_r if (overflow if along_x else True) else 0
        c += step_c if (True if along_x else overflow) else 0
    return cells


def plain_score(nav, grid, plan, pose, vs, ws, params=PARAMS):
    """The rollout of (vs, ws) scored directly: every pose by its own cos and sin, every outline cell
    traced, in time order."""
    horizon, n_steps = params[2], int(max(abs(vs) * params[2] / params[3], abs(ws) / params[4]) + 0.5)
    n_steps = max(n_steps, 1)
    dt = horizon / n_steps
    x, y, theta, v, w = pose
    a, b = 0.5 * params[16] + params[18], 0.5 * params[17] + params[18]
    cell, rows, cols = grid[2], nav.shape[1], nav.shape[2]
    occupancy, (r, c) = 0.0, (0, 0)

    def cell_of(px, py):
        col, row = math.floor(px / cell), math.floor(py / cell)
        return (row, col) if 0 <= row < rows and 0 <= col < cols else None

    for k in range(n_steps):
        if k:
            v = min(vs, v + LIMITS[3] * dt) if vs >= v else max(vs, v - LIMITS[3] * dt)
            w = min(ws, w + LIMITS[4] * dt) if ws >= w else max(ws, w - LIMITS[4] * dt)
            x, y, theta = x + v * math.cos(theta) * dt, y + v * math.sin(theta) * dt, theta + w * dt
        here = cell_of(x, y)
        if here is None:
            return OFF
        corners = [
            cell_of(
                x + fx * math.cos(theta) - fy * math.sin(theta),
                y + fx * math.sin(theta) + fy * math.cos(theta),
            )
            for fx, fy in ((-a, -b), (-a, b), (a, b), (a, -b))
        ]
        if any(corner is None for corner in corners):
            return OFF
        outline = [cell for k in range(4) for cell in _bresenham(*corners[k], *corners[(k + 1) % 4])]
        if any(nav[2][cell] > 253 for cell in outline):
            return OFF
        if nav[1][here] == np.inf:
            return CUT
        occupancy = max([occupancy, float(nav[2][here])] + [float(nav[2][cell]) for cell in outline])
        r, c = here
    path = min(abs(pr - r) + abs(pc - c) for pr, pc in plan)
    return (params[8] * path + params[9] * float(nav[1][r, c])) * params[21] + params[10] * occupancy


def _plan(nav, clear, grid, x, y):
    frame = frame_of(PARAMS, grid)
    plan = np.empty((1024, 2), np.int64)
    r, c = int(y / grid[2]), int(x / grid[2])
    reach = PARAMS[2] * LIMITS[0] + grid[2]
    n = descend(
        nav[0], clear, (frame[3], frame[4], frame[5]), r, c, int(2 * math.sqrt(2) * reach / grid[2]) + 2, plan
    )
    return frame, plan, n


POSES = [
    (0.6, 1.4, 0.3, 0.4, 0.2),  # drives on
    (1.7, 0.6, 1.2, 0.1, -0.5),
    (1.75, 2.0, -0.4, 0.5, 0.0),  # its footprint on the wall: backs up
    (2.6, 1.5, 2.9, 0.0, 1.0),
    (0.7, 2.4, 3.0, 0.0, 0.0),  # facing away from the goal: turns on the spot
    (3.3, 0.5, 1.6, 0.1, 0.0),
]
"""Poses ``(x, y, theta, v, w)`` among CLUTTER where every kind of choice is made."""


def test_each_rollouts_score_is_a_direct_computation():
    nav, clear, grid = fields(CLUTTER)
    verdicts = set()
    outlines = np.zeros((OUTLINES, 5))  # one floor's: outlines traced for one rollout serve the next
    for pose in POSES:
        frame, plan, n = _plan(nav, clear, grid, pose[0], pose[1])
        for vs in (0.0, 0.1, 0.3, 0.5, -0.5):
            for ws in (-1.5, -0.7, 0.0, 0.4, 1.57):
                expected = plain_score(nav, grid, plan[:n], pose, vs, ws)
                poses, _ = trajectory(PARAMS, LIMITS, np.array(pose), vs, ws)
                got = score(PARAMS, frame, nav, clear, plan, n, poses, -1.0, math.inf, outlines)
                assert got == pytest.approx(expected, abs=1e-9), (pose, vs, ws)
                verdicts.add(expected if expected < 0 else "valid")
    assert {"valid", OFF} <= verdicts  # valid rollouts and rollouts into obstacles among them


def plain_choice(nav, clear, grid, pose, goal, params):
    """TrajectoryPlanner::createTrajectories over every sample, each scored directly (a robot with no
    oscillation flags set, not escaping), and its escape when none is valid."""
    x, y, _theta, v, w = pose
    _, plan, n = _plan(nav, clear, grid, x, y)
    plan = plan[:n]
    v_hi = min(LIMITS[0], math.hypot(goal[0] - x, goal[1] - y) / params[2])
    v_hi = max(min(v_hi, v + LIMITS[3] * params[5]), params[6])
    v_lo = max(params[6], v - LIMITS[3] * params[5])
    w_hi, w_lo = min(LIMITS[2], w + LIMITS[4] * params[5]), max(-LIMITS[2], w - LIMITS[4] * params[5])
    nv, nw = int(params[0]), int(params[1])
    dv, dw = (v_hi - v_lo) / (nv - 1), (w_hi - w_lo) / (nw - 1)
    best, chosen = math.inf, (0.0, 0.0)
    for i in range(nv):
        vs = v_lo + i * dv
        for ws in [0.0] + [w_lo + j * dw for j in range(nw - 1)]:
            cost = plain_score(nav, grid, plan, pose, vs, ws, params)
            if 0 <= cost < best:
                best, chosen = cost, (vs, ws)
    facing = math.inf
    for j in range(nw):
        ws = w_lo + j * dw
        if not (ws > dw or ws < -dw):
            continue
        turn = max(ws, params[7]) if ws > 0 else min(ws, -params[7])
        cost = plain_score(nav, grid, plan, pose, 0.0, turn, params)
        if cost < 0 or cost > best:
            continue
        poses, heading = trajectory(params, LIMITS, np.array(pose), 0.0, turn)
        ax, ay = poses[-1, 0] + params[11] * math.cos(heading), poses[-1, 1] + params[11] * math.sin(heading)
        row, col = int(ay / grid[2]), int(ax / grid[2])
        if 0 <= row < nav.shape[1] and 0 <= col < nav.shape[2]:
            ahead = float(nav[1][row, col]) if np.isfinite(nav[1][row, col]) else float(nav[1].size)
            if ahead < facing:
                best, chosen, facing = cost, (0.0, turn), ahead
    if best < math.inf:
        return chosen
    backup = plain_score(nav, grid, plan, pose, params[13], 0.0, params)  # nothing valid: back up
    return (params[13], 0.0) if backup > CUT else (0.0, 0.0)


@pytest.mark.parametrize("pose", POSES)
def test_the_choice_is_the_plain_rule_over_every_sample(pose):
    nav, clear, grid = fields(CLUTTER)
    params = PARAMS.copy()
    params[0], params[1] = 4, 9  # fewer samples: the plain search is slow in Python
    out = np.zeros(2)
    movebase_command(params, LIMITS, np.array(pose), np.array(YARD.goal), nav, clear, grid, np.zeros((0, 2)),
                     np.zeros(0), np.zeros(0), np.zeros(MEMORY), out)  # fmt: skip
    assert out == pytest.approx(plain_choice(nav, clear, grid, pose, YARD.goal, params), abs=1e-12)


def test_a_robot_whose_footprint_touches_an_obstacle_backs_up_and_one_that_cannot_stands():
    nav, clear, grid = fields(GAP)
    # facing the wall, its front 3 cm into it: every rollout's first pose is invalid
    pose = np.array([2.0 - 0.05 - 0.31 + 0.03, 0.5, 0.0, 0.0, 0.0])
    memory, out = np.zeros(MEMORY), np.zeros(2)
    args = (np.array(YARD.goal), nav, clear, grid, np.zeros((0, 2)), np.zeros(0), np.zeros(0), memory, out)
    movebase_command(PARAMS, LIMITS, pose, *args)
    assert out.tolist() == [PARAMS[13], 0.0]  # escape_vel: move_base backs up
    assert memory[6] == 1.0  # escaping: no forward samples until it has moved away
    stuck = robot_for(YARD)  # min speed 0: the step keeps it where it is
    episodes = drive(population(dataclasses.replace(YARD, start=(1.67, 0.5)), [GAP]), robot=stuck,
                     controller="movebase", starts=np.array([[1.67, 0.5, 0.0]]))  # fmt: skip
    assert episodes.outcome[0] != ARRIVED and episodes.distance[0] < 0.05


def test_a_corridor_closed_to_the_padded_footprint_is_planned_around_and_replanned_on_the_way():
    pop = population(YARD, [GAP])
    # MazeGen's own path, for its 0.2 m disc, goes through the gap
    mazegen_path = floor_paths(pop, np.array([0]), margin=0.0)
    assert mazegen_path.length[0] < 3.2
    episodes = drive(pop, robot=ROBOT, controller="movebase", record=True)
    assert episodes.outcome[0] == ARRIVED
    track = episodes.trajectory[0]
    track = track[~np.isnan(track[:, 0])]
    near_wall = np.abs(track[:, 0] - 2.0) < 0.3
    assert near_wall.any() and (track[near_wall, 1] > 2.1).all()  # over the top, never the gap
    nav, clear, grid = fields(GAP)
    plans = []
    for x, y, _ in track[:: max(1, len(track) // 12)]:
        _, plan, n = _plan(nav, clear, grid, x, y)
        cells = [tuple(cell) for cell in plan[:n]]
        assert cells[0] == (int(y / grid[2]), int(x / grid[2]))  # from where the robot stands
        plans.append(cells)
    # the robot strays from the first plan's cells, and the plan follows it: replanned, not replayed
    first = set(plans[0])
    assert any(not set(plan) <= first for plan in plans[1:])


def test_a_rollout_costs_the_same_in_centimetres_as_in_metres():
    """meter_scoring weighs distances in metres and the obstacle cost as it is, so the obstacle weight
    is a length: the arena's unit scales it with the distances, and no choice depends on the unit."""
    cm = dataclasses.replace(YARD, width=400.0, height=300.0, unit="cm", start=(50.0, 150.0),
                             goal=(350.0, 150.0), robot_radius=20.0, grid=5.0)  # fmt: skip
    in_cm = [(name, 100 * x, 100 * y, 100 * w, 100 * d, r) for name, x, y, w, d, r in CLUTTER]
    params_cm = bundled_params("movebase", (), cm)
    limits_cm = robot_limits(robot_for(cm, min_speed=-50.0), cm)
    nav, clear, grid = fields(CLUTTER)
    nav_cm, clear_cm, grid_cm = costmap_fields(population(cm, [in_cm]), params_cm, np.array([0]))
    frame_cm = frame_of(params_cm, grid_cm)
    no_obstacles = PARAMS.copy()
    no_obstacles[10] = 0.0  # obstacle_weight
    occupied = 0
    for pose in POSES:
        frame, plan, n = _plan(nav, clear, grid, pose[0], pose[1])
        pose_cm = np.array(pose) * [100, 100, 1, 100, 1]
        for vs, ws in ((0.0, 0.8), (0.2, -0.5), (0.5, 0.0), (0.4, 1.2)):
            poses, _ = trajectory(PARAMS, LIMITS, np.array(pose), vs, ws)
            table = np.zeros((OUTLINES, 5))
            metres = score(PARAMS, frame, nav, clear, plan, n, poses, -1.0, math.inf, table)
            poses_cm, _ = trajectory(params_cm, limits_cm, pose_cm, 100 * vs, ws)
            table = np.zeros((OUTLINES, 5))
            centimetres = score(
                params_cm, frame_cm, nav_cm[0], clear_cm[0], plan, n, poses_cm, -1.0, math.inf, table
            )
            # (the grids' roundings differ by a cell or a unit of cost here and there: within 1 %)
            assert centimetres == pytest.approx(100 * metres if metres >= 0 else metres, rel=0.01)
            free = score(
                no_obstacles, frame, nav, clear, plan, n, poses, -1.0, math.inf, np.zeros((OUTLINES, 5))
            )
            occupied += metres > free  # the outline's cost weighs in
    assert occupied  # rollouts whose outline costs something among them


def test_a_resolution_too_fine_for_the_arena_is_one_line_before_anything_is_built():
    fine = ControllerSpec("movebase", (("resolution", 1e-4),))
    with pytest.raises(
        MazeError, match=r"^controller movebase's resolution 0.0001 makes more than 4096 cells"
    ):
        drive(population(YARD, [GAP]), robot=ROBOT, controller=fine)


def test_the_samples_are_tried_in_numpys_stable_order_ties_by_index_and_nan_last():
    from mazegen.runtime.simulation._movebase import stable_order

    rng = np.random.default_rng(7)
    for n in (0, 1, 2, 3, 17, 64, 120):
        keys = rng.integers(0, 5, n).astype(np.float64)  # many ties
        keys[rng.random(n) < 0.1] = np.nan
        keys[rng.random(n) < 0.1] = np.inf
        assert stable_order(keys).tolist() == np.argsort(keys, kind="mergesort").tolist()


def test_rollouts_from_random_poses_score_as_the_direct_computation():
    """Every pose's outline counts, however near the edge of the inflation it passes: rollouts from
    random poses among CLUTTER, against every outline cell traced."""
    nav, clear, grid = fields(CLUTTER)
    rng = np.random.default_rng(5)
    compared, verdicts = 0, set()
    outlines = np.zeros((8, 5))  # few rows: outlines remembered are overwritten all the time
    while compared < 400:
        pose = (
            *rng.uniform((0.3, 0.3), (3.7, 2.7)),
            rng.uniform(-math.pi, math.pi),
            rng.uniform(0, 0.5),
            0.0,
        )
        frame, plan, n = _plan(nav, clear, grid, pose[0], pose[1])
        if n < 1:
            continue
        vs, ws = rng.uniform(0.0, 0.5), rng.uniform(-1.5, 1.5)
        poses, _ = trajectory(PARAMS, LIMITS, np.array(pose), vs, ws)
        expected = plain_score(nav, grid, plan[:n], pose, vs, ws)
        assert score(PARAMS, frame, nav, clear, plan, n, poses, -1.0, math.inf, outlines) == pytest.approx(
            expected, abs=1e-9
        ), (pose, vs, ws)
        compared += 1
        verdicts.add(expected if expected < 0 else "valid")
    assert {"valid", OFF} <= verdicts
