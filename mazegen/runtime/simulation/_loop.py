"""The episode loop: every driven floor's robot runs its whole episode in one compiled kernel.

Floors are independent, so blocks of floors run in parallel (``prange``) and each robot's
episode is the same whatever the thread count: a drive is deterministic. A controller is
chosen by an integer code (:data:`CODES`); :func:`command` is the one dispatch point every
per-robot controller kernel plugs into, all with the signature of
:mod:`mazegen.runtime.simulation._controllers`.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from mazegen.runtime.simulation._controllers import purepursuit_command, straight_command
from mazegen.runtime.simulation._dwa import dwa_command
from mazegen.runtime.simulation._lidar import scan
from mazegen.runtime.simulation._step import ACTIVE, X, advance, begin
from mazegen.runtime.simulation._vfh import vfh_command

CODES = {"straight": 0, "purepursuit": 1, "dwa": 2, "vfh": 3}
"""The code of each bundled controller in :func:`command`."""
STRAIGHT, PUREPURSUIT, DWA, VFH = 0, 1, 2, 3


@njit(cache=True)
def command(
    code, params, limits, pose, goal, nav, clear, grid, path, ranges, angles, out
):  # pragma: no cover
    """Controller ``code``'s command for one robot, written to ``out``: THE dispatch point."""
    if code == STRAIGHT:
        straight_command(params, limits, pose, goal, nav, clear, grid, path, ranges, angles, out)
    elif code == PUREPURSUIT:
        purepursuit_command(params, limits, pose, goal, nav, clear, grid, path, ranges, angles, out)
    elif code == DWA:
        dwa_command(params, limits, pose, goal, nav, clear, grid, path, ranges, angles, out)
    elif code == VFH:
        vfh_command(params, limits, pose, goal, nav, clear, grid, path, ranges, angles, out)
    else:
        out[0] = 0.0
        out[1] = 0.0


@njit(cache=True, parallel=True)
def begin_all(starts, limits, goal, world, state, outcome):  # pragma: no cover - compiled
    """Put every robot still to drive (outcome ``ACTIVE``) at its start."""
    for m in prange(starts.shape[0]):
        if outcome[m] == ACTIVE:
            begin(m, starts[m, 0], starts[m, 1], starts[m, 2], limits, goal, world, state, outcome)


@njit(cache=True)
def _record(trajectory, m, step, state):  # pragma: no cover - compiled
    if trajectory.shape[0]:
        for k in range(3):
            trajectory[m, step, k] = state[m, X + k]


@njit(cache=True, parallel=True)
def run_all(
    code, params, world, episode, paths, path_count, fields, angles, reach, blocks, robots, trajectory
):  # pragma: no cover - compiled
    """Drive every active robot to the end of its episode with controller ``code``.

    ``episode`` and ``robots`` are as :func:`mazegen.runtime.simulation._step.advance` takes them;
    ``fields`` is ``(nav, clear, grid)``: per-floor fields, or one dummy shared by all floors;
    ``trajectory`` has no rows unless poses are recorded.
    """
    nav, clear, grid = fields
    limits, goal = episode[0], episode[1]
    state, outcome, steps = robots[0], robots[1], robots[2]
    m_all = state.shape[0]
    parts = world[0][1:] - world[0][:-1]
    most = parts.max() if parts.shape[0] else 0
    for block in prange(blocks):
        ranges = np.zeros(angles.shape[0])
        near = np.zeros(most, np.int64)
        pose = np.zeros(5)
        out = np.zeros(2)
        for m in range(block * m_all // blocks, (block + 1) * m_all // blocks):
            f = m if nav.shape[0] > 1 else 0
            floor_nav, floor_clear = nav[f], clear[f]
            path = paths[m, : path_count[m]]
            _record(trajectory, m, 0, state)
            while outcome[m] == ACTIVE:
                for k in range(5):
                    pose[k] = state[m, X + k]
                if angles.shape[0]:
                    scan(pose[0], pose[1], pose[2], angles, reach, m, world, near, ranges)
                command(
                    code, params, limits, pose, goal, floor_nav, floor_clear, grid, path, ranges, angles, out
                )
                advance(m, out[0], out[1], world, episode, robots)
                _record(trajectory, m, steps[m], state)
