"""The episode loop: every driven floor's robot runs its whole episode in one compiled kernel.

Floors are independent, so blocks of floors run on threads of their own
(:func:`mazegen.runtime.threads.in_blocks`) and each robot's episode is the same whatever the
thread count: a drive is deterministic. A bundled controller is chosen by the argument slot its
parameters are given in, the slot of its row's ``code`` (:mod:`mazegen.controllers`);
:func:`command` is the one dispatch point every per-robot controller kernel plugs into, all with
the signature of :mod:`mazegen.runtime.simulation._controllers`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from mazegen.controllers import BUNDLED
from mazegen.runtime.compiling import leaf_kernel, wrapped_leaf_kernel
from mazegen.runtime.simulation._controllers import purepursuit_command, straight_command
from mazegen.runtime.simulation._dwa import dwa_command
from mazegen.runtime.simulation._lidar import scan
from mazegen.runtime.simulation._movebase import memory_for, movebase_command
from mazegen.runtime.simulation._state import ACTIVE, DriveState, X
from mazegen.runtime.simulation._step import advance
from mazegen.runtime.simulation._vfh import vfh_command
from mazegen.runtime.threads import in_blocks


def run_bundled(drive: DriveState, fields: tuple) -> None:
    """Drive every robot of ``drive`` still driving to the end of its episode with its bundled
    controller; ``fields`` is ``(nav, clear, grid)``: per-floor fields, or one dummy for all."""
    setup, robots = drive.setup, drive.robots
    in_blocks(
        run_all,
        len(robots.outcome),
        *controller_slots(drive.choice.code, setup.params),
        setup.params,
        setup.world.arrays,
        setup.episode,
        setup.paths.corners,
        setup.paths.count,
        fields,
        setup.angles,
        setup.reach,
        robots.arrays,
        robots.trajectory,
        setup.boxes,
        per_thread=32,  # episodes differ in length: many small blocks even them out
    )


def controller_slots(code: int, params: np.ndarray) -> tuple[np.ndarray | None, ...]:
    """:func:`command`'s first arguments for controller ``code``: its parameters (a row per robot) in
    its slot, None in the others. numba compiles the kernels once per combination of array and None,
    leaving out the branches of the None ones: a drive compiles only the controller it drives."""
    return tuple(params if slot == code else None for slot in range(len(BUNDLED)))


@wrapped_leaf_kernel
def command(
    straight,
    purepursuit,
    dwa,
    vfh,
    movebase,
    params,
    limits,
    pose,
    goal,
    nav,
    clear,
    grid,
    path,
    ranges,
    angles,
    memory,
    out,
):  # pragma: no cover
    """The command of the controller whose slot is given (the others None), with its parameters
    ``params`` (the robot's row), written to ``out``: THE dispatch point, one slot per bundled
    controller in the order of their codes (a test checks it against the rows)."""
    if straight is not None:
        straight_command(params, limits, pose, goal, nav, clear, grid, path, ranges, angles, memory, out)
    elif purepursuit is not None:
        purepursuit_command(params, limits, pose, goal, nav, clear, grid, path, ranges, angles, memory, out)
    elif dwa is not None:
        dwa_command(params, limits, pose, goal, nav, clear, grid, path, ranges, angles, memory, out)
    elif vfh is not None:
        vfh_command(params, limits, pose, goal, nav, clear, grid, path, ranges, angles, memory, out)
    elif movebase is not None:
        movebase_command(params, limits, pose, goal, nav, clear, grid, path, ranges, angles, memory, out)
    else:
        out[0] = 0.0
        out[1] = 0.0


@leaf_kernel
def _record(trajectory, m, step, state):  # pragma: no cover - compiled
    if trajectory.shape[0]:
        for k in range(3):
            trajectory[m, step, k] = state[m, X + k]


@njit(cache=True, nogil=True)
def run_all(
    first,
    last,
    straight,
    purepursuit,
    dwa,
    vfh,
    movebase,
    params,
    world,
    episode,
    paths,
    path_count,
    fields,
    angles,
    reach,
    robots,
    trajectory,
    boxes,
):  # pragma: no cover - compiled
    """Drive robots ``first`` to ``last - 1``, those still active, to the end of their episodes with the
    controller whose slot is given (:func:`controller_slots`), each with its row of ``params``.

    ``episode``, ``robots`` and ``boxes`` are as :func:`mazegen.runtime.simulation._step.advance` takes them;
    ``fields`` is ``(nav, clear, grid)``: per-floor fields on grids of their own (``grid[f]`` = ``(x0,
    y0, cell, rows, cols)``; the arrays padded to the largest grid with what the controllers read
    off a grid, ``inf`` and 0), or one dummy shared by all floors;
    ``reach`` each robot's lidar range; ``trajectory`` has no rows unless poses are recorded.
    """
    nav, clear, grid = fields
    limits, goal = episode[0], episode[1]
    state, outcome, steps = robots[0], robots[1], robots[2]
    most = 0  # the most parts a floor holds (a loop: numba's max compiles for a quarter second)
    for f in range(world[0].shape[0] - 1):
        most = max(most, world[0][f + 1] - world[0][f])
    ranges = np.zeros(angles.shape[0])
    near = np.zeros(most, np.int64)
    pose = np.zeros(5)
    memory = memory_for(movebase)
    out = np.zeros(2)
    for m in range(first, last):
        f = m if nav.shape[0] > 1 else 0
        floor_nav, floor_clear, floor_grid = nav[f], clear[f], grid[f]
        robot_limits, robot_goal = limits[m], goal[m]
        robot_params = params[m]
        path = paths[m, : path_count[m]]
        memory[:] = 0.0
        _record(trajectory, m, np.int64(0), state)
        while outcome[m] == ACTIVE:
            for k in range(5):
                pose[k] = state[m, X + k]
            if angles.shape[0]:
                scan(pose[0], pose[1], pose[2], angles, reach[m], m, world, near, ranges)
            command(
                straight, purepursuit, dwa, vfh, movebase, robot_params, robot_limits, pose, robot_goal,
                floor_nav, floor_clear, floor_grid, path, ranges, angles, memory, out,
            )  # fmt: skip
            advance(m, out[0], out[1], world, episode, robots, boxes)
            _record(trajectory, m, steps[m], state)
