"""The vector field histogram (Borenstein and Koren, IEEE T-RA 1991), one robot per call: a
reactive controller that reads the lidar and the goal's bearing only, no map.

Every step:

1. **Polar histogram**: ``sectors`` equal sectors around the robot. A reading ``d`` closer than
   ``window`` has density ``1 - d / window`` (the paper's ``a - b·d`` with ``a - b·window = 0``,
   certainty 1 for a lidar) and, as in VFH+ (Ulrich and Borenstein 1998), is enlarged by the
   angle ``asin((radius + safety) / d)`` the robot plus its safety distance subtends there, so
   that every sector it covers holds at least that density. Sectors no beam sees (a lidar
   narrower than a full turn) are blocked.
2. **Binary histogram**: a sector is blocked when its density exceeds ``threshold``.
3. **Openings**: runs of free sectors. The goal's sector, when free, is steered at. Otherwise
   each opening offers the direction ``wide / 2`` in from each of its edges, or its middle when
   it is narrower than ``wide`` (the paper's wide and narrow valleys, ``s_max``); the offer
   nearest the goal's bearing wins.
4. **Speed**: ``v = max_speed · (1 - density straight ahead) · max(cos(error), 0)``, turn rate
   ``heading_gain × error``: slower near obstacles and while turning. With no opening at all the
   robot turns on the spot toward the goal's side.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mazegen.runtime.compiling import counted_kernel, leaf_kernel
from mazegen.runtime.simulation._controllers import MAX_SPEED, MAX_TURN, RADIUS, wrap

# Parameters, in the order of vfh's row in mazegen/controllers.py; tests/runtime/simulation/test_registry.py
# checks them.
SECTORS, THRESHOLD, SAFETY, WINDOW, WIDE, HEADING_GAIN = range(6)


@counted_kernel
def vfh_command(
    params, limits, pose, goal, nav, clear, grid, path, scan, angles, memory, out
):  # pragma: no cover
    """Steer through the lidar opening nearest the goal's bearing; ``(v, w)`` to ``out``."""
    n = max(int(params[SECTORS]), 1)
    width = 2.0 * math.pi / n
    density = np.zeros(n)  # one small array a step: the histogram
    seen = np.zeros(n, np.bool_)
    window, reach = params[WINDOW], limits[RADIUS] + params[SAFETY]
    for b in range(scan.shape[0]):
        own = _sector(angles[b], width, n)
        seen[own] = True
        d = scan[b]
        if d >= window:
            continue
        weight = 1.0 - d / window
        density[own] = max(density[own], weight)
        # The enlargement: every sector whose centre, -pi + (k + 0.5) width, lies within the
        # angle the robot subtends (k counted on past the circle's ends, then wrapped).
        spread = math.pi / 2 if d <= reach else math.asin(reach / d)
        centre = (angles[b] + math.pi) / width - 0.5
        for k in range(math.ceil(centre - spread / width), math.floor(centre + spread / width) + 1):
            s = k % n
            density[s] = max(density[s], weight)
    threshold = params[THRESHOLD]
    bearing = wrap(math.atan2(goal[1] - pose[1], goal[0] - pose[0]) - pose[2])
    target = _sector(bearing, width, n)
    steer = bearing
    if not _free(density, seen, target, threshold):
        steer = _opening(density, seen, threshold, width, params[WIDE], bearing)
    if steer == math.inf:  # boxed in: turn on the spot toward the goal's side
        out[0] = 0.0
        out[1] = math.copysign(limits[MAX_TURN], bearing)
        return
    ahead = density[_sector(0.0, width, n)]
    out[0] = limits[MAX_SPEED] * (1.0 - ahead) * max(math.cos(steer), 0.0)
    out[1] = params[HEADING_GAIN] * steer


@njit(cache=True, inline="always")
def _free(density, seen, s, threshold):  # pragma: no cover - compiled
    return seen[s] and density[s] <= threshold


@leaf_kernel
def _opening(density, seen, threshold, width, wide, bearing):  # pragma: no cover - compiled
    """The candidate direction (robot frame) nearest ``bearing`` over every opening; ``inf`` if none."""
    n = density.shape[0]
    start = -1  # a blocked sector to start the circular walk from
    for s in range(n):
        if not _free(density, seen, s, threshold):
            start = s
            break
    if start < 0:  # nothing blocked: the goal's sector is free (not reached)
        return bearing
    best, best_error = math.inf, math.inf
    run = 0
    for k in range(1, n + 1):
        s = (start + k) % n
        if _free(density, seen, s, threshold):
            run += 1
            continue
        if run:
            # Free sectors start + k - run .. start + k - 1: edges at the sector boundaries.
            low = (start + k - run) * width - math.pi
            high = low + run * width
            if run * width <= wide:
                offers = (0.5 * (low + high), 0.5 * (low + high))
            else:
                offers = (low + 0.5 * wide, high - 0.5 * wide)
            for direction in offers:
                error = abs(wrap(direction - bearing))
                if error < best_error:
                    best, best_error = wrap(direction), error
        run = 0
    return best


@njit(cache=True, inline="always")
def _sector(angle, width, n):  # pragma: no cover - compiled
    """The sector holding ``angle`` (radians from the heading); sector 0 starts at -pi."""
    if not -math.pi <= angle < math.pi:  # beam angles are already: no remainder to take
        angle = wrap(angle)
    return min(int((angle + math.pi) / width), n - 1)
