"""move_base as BARN's timing runs ran it: navfn on an inflated costmap, replanned every control step,
and base_local_planner's TrajectoryPlanner with ``dwa: true``, one robot per call.

Each call (a control step) it:

1. **plans**: descends navfn's potential (:mod:`mazegen.runtime.simulation._costmap`) from the robot's
   cell to the goal's (move_base's ``planner_frequency`` of 20 Hz replans at every control step; the
   potential of a static map does not change, so a plan is a descent from wherever the robot stands);
   the plan's cells near the robot are those a rollout's end can be nearest to;
2. **samples the dynamic window** as TrajectoryPlanner does: speeds from ``max(min_vel, v - accel ·
   period)`` to ``min(max_speed, goal distance / horizon, v + accel · period)`` (never below
   ``min_vel``), ``v_samples`` of them; for each, turn rate 0 and then ``w_samples - 1`` turn rates
   from the window's lowest up in steps of ``(high - low) / (w_samples - 1)``; then ``w_samples``
   turns on the spot (at least ``min_in_place_turn`` fast, the near-zero ones skipped);
3. **rolls out and scores** each (:mod:`mazegen.runtime.simulation._rollout`);
4. **chooses** the cheapest forward rollout (the first of equal costs), unless a turn on the spot
   costs no more and faces, ``heading_lookahead`` ahead, a cell nearer the goal than every such turn
   before it. The **oscillation guard** then forbids turning back the other way on the spot, once a
   turn has repeated, until the robot has moved ``oscillation_reset``;
5. with no valid rollout, **backs up** at ``escape_vel`` (unless its rollout is cut off from the
   goal: then it stands), and while backing up samples no forward rollout, until it has moved
   ``escape_reset_dist`` or turned ``escape_reset_theta``. A robot whose ``min speed`` is 0 cannot
   reverse: it stands.

move_base's recovery behaviours (clearing costmaps, rotating) never start in BARN's timing runs: the
timer republishes the goal at 10 Hz, and each new goal resets move_base's patience.

The result is the plain rule above; the search only skips work that cannot change it. Every
rollout's cost is at least its end's distances plus the occupancy of the robot's own pose (the first
of every rollout), so forward samples are rolled out cheapest bound first, and a sample or a rollout
stops once its bound passes the best so far.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mazegen.runtime.compiling import counted_kernel, inner_kernel
from mazegen.runtime.simulation._controllers import ACCEL, MAX_SPEED, MAX_TURN, TURN_ACCEL
from mazegen.runtime.simulation._costmap import descend
from mazegen.runtime.simulation._rollout import (
    CUT,
    GOAL_DISTANCE,
    OUTLINES,
    bound,
    cell_of,
    frame_of,
    plan_term,
    pose_cost,
    score,
    trajectory,
)

# Parameters, in the order of movebase's row in mazegen/controllers.py (the rollout's own are
# _rollout's); tests/runtime/simulation/test_registry.py checks them.
V_SAMPLES, W_SAMPLES, HORIZON = 0, 1, 2
PERIOD, MIN_VEL, MIN_IN_PLACE_TURN = range(5, 8)
HEADING_LOOKAHEAD, OSCILLATION_RESET, ESCAPE_VEL, ESCAPE_RESET_DIST, ESCAPE_RESET_THETA = range(11, 16)
ROTATING_LEFT, ROTATING_RIGHT, STUCK_LEFT, STUCK_RIGHT, PREV_X, PREV_Y = range(6)
ESCAPING, ESCAPE_X, ESCAPE_Y, ESCAPE_THETA = range(6, 10)
"""TrajectoryPlanner's state, carried from step to step (all 0 when an episode begins)."""
STATE = 10
"""Its length."""
MEMORY = STATE + 5 * OUTLINES
"""A robot's memory: its state, then the outlines it has traced on its floor (:func:`pose_cost`'s)."""


@njit(cache=True, inline="always")
def memory_for(movebase):  # pragma: no cover - compiled
    """A robot's memory for a drive, given the episode loop's ``movebase`` slot: :data:`MEMORY` when
    movebase drives, else a few values (no other bundled controller keeps any), so that zeroing it for
    each episode costs the others nothing."""
    return np.zeros(MEMORY if movebase is not None else STATE)


POTENTIAL = 0
"""navfn's potential's layer of ``nav``."""
PLAN_CELLS = 1024
"""Plan cells kept near the robot at most."""


@counted_kernel
def movebase_command(
    params, limits, pose, goal, nav, clear, grid, path, scan, angles, memory, out
):  # pragma: no cover - compiled
    """The velocity move_base would command, written to ``out`` (``(0, 0)``: stand)."""
    x, y, theta, v = pose[0], pose[1], pose[2], pose[3]
    out[0], out[1] = 0.0, 0.0
    outlines = memory[STATE:].reshape((OUTLINES, 5))
    frame = frame_of(params, grid)
    rr, rc = cell_of(frame, clear, x, y)
    if rr < 0:
        return
    horizon = params[HORIZON]
    reach = horizon * max(limits[MAX_SPEED], abs(v)) + frame[2]
    plan = np.empty((PLAN_CELLS, 2), np.int64)
    within = int(2.0 * math.sqrt(2.0) * reach / frame[2]) + 2
    n_plan = descend(nav[POTENTIAL], clear, (frame[3], frame[4], frame[5]), rr, rc, within, plan)
    if n_plan < 0:
        return  # no plan: move_base has nothing to follow
    here = pose_cost(frame, clear, nav, x, y, math.cos(theta), math.sin(theta), outlines)
    best, best_v, best_w = math.inf, 0.0, 0.0
    escaping = memory[ESCAPING] > 0.0
    if here >= 0.0:
        best, best_v, best_w = _choose(
            params, limits, pose, goal, frame, nav, clear, plan, n_plan, here, escaping, memory, outlines
        )
    if best < math.inf:
        if not best_v > 0.0:
            _note_turn(memory, x, y, best_w)
        _lift_guard(memory, x, y, params[OSCILLATION_RESET])
    else:  # back up
        poses, _ = trajectory(params, limits, pose, params[ESCAPE_VEL], 0.0)
        backup = score(params, frame, nav, clear, plan, n_plan, poses, -1.0, math.inf, outlines)
        _lift_guard(memory, x, y, params[OSCILLATION_RESET])
        if not escaping and backup > CUT:
            memory[ESCAPING], memory[ESCAPE_X], memory[ESCAPE_Y], memory[ESCAPE_THETA] = 1.0, x, y, theta
        if backup > CUT:
            best_v = params[ESCAPE_VEL]
    turned = abs((theta - memory[ESCAPE_THETA] + math.pi) % (2.0 * math.pi) - math.pi)
    if (
        math.hypot(x - memory[ESCAPE_X], y - memory[ESCAPE_Y]) > params[ESCAPE_RESET_DIST]
        or turned > params[ESCAPE_RESET_THETA]
    ):
        memory[ESCAPING] = 0.0
    out[0], out[1] = best_v, best_w


@inner_kernel
def _choose(
    params, limits, pose, goal, frame, nav, clear, plan, n_plan, here, escaping, memory, outlines
):  # pragma: no cover - compiled
    """``(cost, v, w)`` of the chosen valid rollout, cost ``inf`` when none is valid."""
    x, y, v, w = pose[0], pose[1], pose[3], pose[4]
    horizon, period = params[HORIZON], params[PERIOD]
    v_hi = min(limits[MAX_SPEED], math.hypot(goal[0] - x, goal[1] - y) / horizon)
    v_hi = max(min(v_hi, v + limits[ACCEL] * period), params[MIN_VEL])
    v_lo = max(params[MIN_VEL], v - limits[ACCEL] * period)
    w_hi = min(limits[MAX_TURN], w + limits[TURN_ACCEL] * period)
    w_lo = max(-limits[MAX_TURN], w - limits[TURN_ACCEL] * period)
    nv, nw = int(params[V_SAMPLES]), int(params[W_SAMPLES])
    dv = (v_hi - v_lo) / (nv - 1) if nv > 1 else 0.0
    dw = (w_hi - w_lo) / (nw - 1) if nw > 1 else 0.0
    best, best_k, best_v, best_w = math.inf, -1, 0.0, 0.0
    if not escaping:  # forward samples, cheapest bound first; the least (cost, sample order) wins
        bounds = np.empty(nv * nw)
        ends = np.empty((nv * nw, 2), np.int64)
        for k in range(nv * nw):
            vs, ws = _forward_sample(k, nw, v_lo, dv, w_lo, dw)
            bounds[k], ends[k, 0], ends[k, 1] = bound(params, limits, frame, nav, clear, pose, vs, ws, here)
        for k in stable_order(bounds):
            if bounds[k] > best or (bounds[k] == best and k > best_k):
                break  # (the rest bound no lower)
            whole = bounds[k] + plan_term(params, plan, n_plan, ends[k, 0], ends[k, 1])
            if whole > best or (whole == best and k > best_k):
                continue
            vs, ws = _forward_sample(k, nw, v_lo, dv, w_lo, dw)
            poses, _ = trajectory(params, limits, pose, vs, ws)
            limit = np.nextafter(best, math.inf) if k < best_k else best  # (an earlier sample wins a tie)
            cost = score(params, frame, nav, clear, plan, n_plan, poses, here, limit, outlines)
            if cost >= 0.0:
                best, best_k, best_v, best_w = cost, k, vs, ws
    # Turns on the spot, in order: one that costs no more and faces nearer the goal takes over.
    facing = math.inf
    ws = w_lo
    for _ in range(nw):
        blocked = (ws < 0.0 and memory[STUCK_LEFT] > 0.0) or (ws > 0.0 and memory[STUCK_RIGHT] > 0.0)
        if (ws > dw or ws < -dw) and not blocked:
            turn = max(ws, params[MIN_IN_PLACE_TURN]) if ws > 0.0 else min(ws, -params[MIN_IN_PLACE_TURN])
            least, r, c = bound(params, limits, frame, nav, clear, pose, 0.0, turn, here)
            if least + plan_term(params, plan, n_plan, r, c) <= best:
                poses, heading = trajectory(params, limits, pose, 0.0, turn)
                ahead = _facing(params, frame, nav, clear, poses[-1, 0], poses[-1, 1], heading)
                if ahead < facing:  # (one facing no nearer than a turn taken before cannot take over)
                    limit = np.nextafter(best, math.inf)
                    cost = score(params, frame, nav, clear, plan, n_plan, poses, here, limit, outlines)
                    if cost >= 0.0:
                        best, best_v, best_w, facing = cost, 0.0, turn, ahead
        ws += dw
    return best, best_v, best_w


@njit(cache=True)
def stable_order(keys):  # pragma: no cover - compiled
    """``np.argsort(keys, kind="mergesort")`` (ties in index order, NaN last), a bottom-up merge sort
    written out: numba's compiles for about a second."""
    n = keys.shape[0]
    order, merged = np.arange(n), np.empty(n, np.int64)
    width = 1
    while width < n:
        for lo in range(0, n, 2 * width):
            mid, hi = min(lo + width, n), min(lo + 2 * width, n)
            i, j = lo, mid
            for t in range(lo, hi):
                if i < mid and (
                    j >= hi or keys[order[i]] <= keys[order[j]] or keys[order[j]] != keys[order[j]]
                ):
                    merged[t] = order[i]
                    i += 1
                else:
                    merged[t] = order[j]
                    j += 1
        for t in range(n):
            order[t] = merged[t]
        width *= 2
    return order


@njit(cache=True, inline="always")
def _forward_sample(k, nw, v_lo, dv, w_lo, dw):  # pragma: no cover - compiled
    """Forward sample ``k``: speed ``k // nw``; turn rate 0 first, then the window's from its lowest."""
    j = k % nw
    return v_lo + (k // nw) * dv, 0.0 if j == 0 else w_lo + (j - 1) * dw


@njit(cache=True, inline="always")
def _facing(params, frame, nav, clear, x, y, heading):  # pragma: no cover - compiled
    """The goal distance ``heading_lookahead`` ahead of a turn's end ``(x, y, heading)``
    (base_local_planner's obstacle cost, the map's cell count, where none reaches), ``inf`` off the map."""
    lookahead = params[HEADING_LOOKAHEAD]
    r, c = cell_of(frame, clear, x + lookahead * math.cos(heading), y + lookahead * math.sin(heading))
    if r < 0:
        return math.inf
    ahead = float(nav[GOAL_DISTANCE, r, c])
    return float(clear.shape[0] * clear.shape[1]) if ahead == math.inf else ahead


@njit(cache=True, inline="always")
def _note_turn(memory, x, y, w):  # pragma: no cover - compiled
    """TrajectoryPlanner's oscillation guard, a turn on the spot at ``w`` chosen: the same turn repeated
    forbids turning back the other way on the spot (flags named as base_local_planner names them)."""
    if w < 0.0:
        if memory[ROTATING_RIGHT] > 0.0:
            memory[STUCK_RIGHT] = 1.0
        memory[ROTATING_RIGHT] = 1.0
    elif w > 0.0:
        if memory[ROTATING_LEFT] > 0.0:
            memory[STUCK_LEFT] = 1.0
        memory[ROTATING_LEFT] = 1.0
    memory[PREV_X], memory[PREV_Y] = x, y


@njit(cache=True, inline="always")
def _lift_guard(memory, x, y, reset):  # pragma: no cover - compiled
    """Moving ``reset`` from where the robot last turned on the spot lifts the oscillation guard."""
    if math.hypot(x - memory[PREV_X], y - memory[PREV_Y]) > reset:
        for k in (ROTATING_LEFT, ROTATING_RIGHT, STUCK_LEFT, STUCK_RIGHT):
            memory[k] = 0.0
