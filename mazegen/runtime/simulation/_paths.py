"""MazeGen's own paths of the driven floors: their lengths (BARN's optimal time) and corners.

The search is :func:`mazegen.runtime.navigation._paths.route`, the one the solvability and
difficulty metrics run, so a floor's optimal time is the path length the metrics report (read
from the population's navigation when the metrics have already searched it). It runs in parallel
over the driven floors, each block of floors with its own scratch.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numba import njit

from mazegen.runtime.engine import Population
from mazegen.runtime.geometry import grid_args, grid_of
from mazegen.runtime.navigation import copy_points, kernel_args, route, route_scratch
from mazegen.runtime.threads import in_blocks
from mazegen.spec import Arena


@dataclass(frozen=True)
class FloorPaths:
    """The paths of M driven floors.

    Attributes:
        length: ``float64[M]`` path length in arena units, NaN where MazeGen finds no path.
        corners: ``float64[M, C, 2]`` the corners of the path to follow, start to goal, padded; ``C``
            is 1 when the corners were not asked for.
        count: ``int64[M]`` corners of each path to follow (0 without a path).
    """

    length: np.ndarray
    corners: np.ndarray
    count: np.ndarray


def floor_paths(population: Population, indices: np.ndarray, *, margin: float | None) -> FloorPaths:
    """Paths of individuals ``indices`` of ``population``; their corners too unless ``margin`` is None.

    The lengths are MazeGen's (the robot's radius); the corners are those of the path for a robot
    ``margin`` wider where there is one, else ``margin / 2`` wider, else MazeGen's: a controller
    cutting corners then keeps clear, as a planner's inflation keeps it clear (MazeGen's path
    touches the configuration space's edge).
    """
    rows = np.ascontiguousarray(indices, np.int64)
    searched = population.measured.get("navigation")
    if margin is None and searched is not None:  # the metrics' search: its lengths are these
        nothing = np.zeros(len(rows), np.int64)
        return FloorPaths(
            np.asarray(searched.path_length, np.float64)[rows], np.zeros((len(rows), 1, 2)), nothing
        )
    shapes, ids, n_el, params, valid = kernel_args(population)
    arena = population.arena
    plain = grid_args(grid_of(arena))
    wide = plain if not margin else grid_args(grid_of(_wider(arena, margin)))
    half = plain if not margin else grid_args(grid_of(_wider(arena, margin / 2)))
    capacity = 0 if margin is None else CORNERS
    while True:
        length = np.full(len(rows), np.nan)
        count = np.zeros(len(rows), np.int64)
        points = np.zeros((len(rows), max(capacity, 1), 2))
        arrays = (shapes, ids, n_el, params, valid, rows, plain, half, wide, bool(margin))
        if len(rows):  # (none: nothing to compile)
            in_blocks(_paths, len(rows), *arrays, capacity, length, count, points, per_thread=8)
        if count.max(initial=0) <= capacity or margin is None:
            return FloorPaths(length, points, count if margin is not None else np.zeros_like(count))
        capacity = int(count.max())  # a rare path with more corners than CORNERS: once more, wider


CORNERS = 64
"""Corners kept per path at first; a drive with a longer path searches again with room for it."""


def _wider(arena: Arena, margin: float) -> Arena:
    return replace(arena, robot_radius=arena.robot_radius + margin, grid=arena.cell)


@njit(cache=True, nogil=True)
def _paths(
    first,
    last,
    shapes,
    ids,
    n_el,
    params,
    valid,
    rows,
    plain,
    half,
    wide,
    widen,
    capacity,
    length,
    count,
    points,
):  # pragma: no cover
    """Lengths of the paths of ``rows[first:last]`` on the ``plain`` grid; when ``capacity`` is positive, the
    corners of the path on the widest grid (``wide``, ``half`` when ``widen``, ``plain``) that has one
    too, or how many there would be when more than ``capacity``."""
    scratch = route_scratch(shapes, ids.shape[1], plain)
    half_scratch = route_scratch(shapes, ids.shape[1], half)
    wide_scratch = route_scratch(shapes, ids.shape[1], wide)
    for j in range(first, last):
        i = rows[j]
        if not valid[i]:
            continue
        _, found, total, turns = route(shapes, ids[i], n_el[i], params[i], plain, scratch)
        if not found:
            continue
        length[j] = total
        if capacity == 0:
            continue
        corners = scratch[5]
        found, wide_turns = False, 0
        if widen:
            _, found, _, wide_turns = route(shapes, ids[i], n_el[i], params[i], wide, wide_scratch)
        if found:
            corners, turns = wide_scratch[5], wide_turns
        elif widen:
            _, found, _, half_turns = route(shapes, ids[i], n_el[i], params[i], half, half_scratch)
            if found:
                corners, turns = half_scratch[5], half_turns
        count[j] = turns
        if turns <= capacity:
            copy_points(corners, np.int64(0), points[j], np.int64(0), turns)
