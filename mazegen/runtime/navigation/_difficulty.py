"""How hard is a floor to drive through: BARN's difficulty metrics along the robot's path.

The metrics of Perille et al. (2020, "Benchmarking Metric Ground Navigation")
are measured on the configuration-space grid of :mod:`mazegen.runtime.geometry._cspace`
(blocked cells are where the robot's centre cannot be; cells outside the grid
count as blocked) at the **path cells**: the cells the path found by
:mod:`mazegen.runtime.navigation._paths` passes through, in order. Distances are in
arena units (cells times the cell size). Per path cell:

* **closest obstacle**: distance from its centre to the nearest blocked cell's centre;
* **visibility**: mean over the 8 king-move directions of the free length
  before the first blocked cell (free cells stepped over times the step, 1 or √2 cells);
* **characteristic dimension**: over the 4 axes (horizontal, vertical, two
  diagonals), the smallest free length in both directions together;
* **dispersion**: over 16 rays (the 8 king moves and the 8 knight moves, in
  angular order) to the dispersion radius, the number of neighbouring rays where
  one meets a blocked cell and the other does not.

Each is averaged over the path cells. With them: **tortuosity** (path length over
the straight start-goal distance), the **path-length ratio** (the robot's path
over the path of a point robot on the same grid: the detour the robot's width
forces) and the **narrowest passage** (the smallest characteristic dimension on
the path: 0 when the robot just fits). :func:`difficulty_score` combines the
metrics into one score from 0 (open floor) to 100, in two versions: BARN's five metrics averaged
(version 1) and a fit to measured traversal (version 2, the default).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from mazegen.runtime.compiling import inner_kernel, wrapped_leaf_kernel
from mazegen.runtime.geometry import (
    ONE,
    floor_cells,
    grid_args,
    grid_of,
    is_free,
    point_grid_of,
    row_runs_of,
    run_arrays,
)
from mazegen.runtime.navigation._paths import Navigation, kernel_args, route, route_scratch
from mazegen.runtime.threads import in_blocks
from mazegen.spec import PATH_METRICS

if TYPE_CHECKING:
    from mazegen.runtime.engine import Population

METRICS = tuple(name for name in PATH_METRICS if name != "path_length")
"""Column order of :attr:`Survey.table` (the path length is in :attr:`Survey.navigation`)."""

KING = np.array([(0, 1), (1, 1), (1, 0), (1, -1), (0, -1), (-1, -1), (-1, 0), (-1, 1)], np.int64)
"""The 8 ray directions as (row step, column step); direction ``d + 4`` is opposite ``d``."""

RAYS16 = np.array(
    [
        (0, 1), (1, 2), (1, 1), (2, 1), (1, 0), (2, -1), (1, -1), (1, -2),
        (0, -1), (-1, -2), (-1, -1), (-2, -1), (-1, 0), (-2, 1), (-1, 1), (-1, 2),
    ],
    np.int64,
)  # fmt: skip
"""The 16 dispersion rays as (row step, column step), in angular order: ray ``2 d`` is ``KING[d]``."""


@dataclass(frozen=True)
class Survey:
    """Solvability, path and difficulty metrics of every individual of a population.

    Attributes:
        navigation: Solvability, path length and coverage, as :func:`navigation.navigate` gives.
        table: ``float64[N, len(METRICS)]``: each metric per individual, NaN when unsolvable.
        robot_radius: The robot's radius, which the difficulty score is scaled by.
        tasks: The surveys of each task of a floor of several (:meth:`over_tasks`), else empty.
    """

    navigation: Navigation
    table: np.ndarray
    robot_radius: float
    tasks: tuple[Survey, ...] = ()

    @classmethod
    def over_tasks(cls, surveys: Sequence[Survey]) -> Survey:
        """The survey of floors of several tasks, one survey each: solvable where every task is, each
        metric and the difficulty the tasks' mean (NaN where one is unsolvable)."""
        table = np.mean(np.stack([survey.table for survey in surveys]), axis=0)
        navigation = Navigation.over_tasks([survey.navigation for survey in surveys])
        return cls(navigation, table, surveys[0].robot_radius, tuple(surveys))

    def metric(self, name: str) -> np.ndarray:
        """One metric's column (a name of :data:`METRICS`, or ``path_length``)."""
        if name == "path_length":
            return self.navigation.path_length
        return self.table[:, METRICS.index(name)]

    def summary(self, index: int) -> dict[str, bool | float | None]:
        """Everything measured of individual ``index``, JSON-ready: null where unsolvable."""
        nav = self.navigation
        values = {
            "path_length": float(nav.path_length[index]),
            "difficulty": float(self.difficulty[index]),
            **{name: float(self.table[index, k]) for k, name in enumerate(METRICS)},
        }
        return {
            "solvable": bool(nav.solvable[index]),
            "coverage": float(nav.coverage[index]),
            **{key: value if math.isfinite(value) else None for key, value in values.items()},
            "difficulty_version": DIFFICULTY_VERSION,
        }

    @cached_property
    def difficulty(self) -> np.ndarray:
        """:func:`difficulty_score` of every individual, NaN when unsolvable (the tasks' mean)."""
        if self.tasks:
            return np.mean(np.stack([survey.difficulty for survey in self.tasks]), axis=0)
        return difficulty_score(self.table, self.robot_radius or self.navigation.cell)


DIFFICULTY_VERSION = 2
"""The version of :func:`difficulty_score` that scenario documents and surveys give by default."""

HARDNESS = ("clearance", "visibility", "dispersion", "dimension", "tortuosity", "path_ratio", "narrowest")
"""The columns of :func:`hardness`: each metric turned into a hardness in [0, 1]."""

INTERCEPT = 0.0489
"""Version 2's intercept: measured difficulty of a floor every hardness calls open."""

WEIGHTS = np.array([0.0, 0.0, 0.5069, 0.0, 0.6713, 0.0, 0.1781])
"""Version 2's weight of each :data:`HARDNESS` column, fitted by ``benchmarks/calibration.py`` to
the measured traversal difficulty of the bundled controllers (docs/difficulty.md)."""


def hardness(table: np.ndarray, scale: float) -> np.ndarray:
    """``float64[N, len(HARDNESS)]``: each metric of ``table`` (:data:`METRICS` columns) as a hardness
    in [0, 1] against the robot's size ``scale`` (its radius); NaN where the metric is."""
    column = {name: table[:, k] for k, name in enumerate(METRICS)}
    return np.column_stack(
        (
            np.exp(-column["clearance"] / (2.0 * scale)),
            np.exp(-column["visibility"] / (8.0 * scale)),
            1.0 - np.exp(-column["dispersion"] / 2.0),
            np.exp(-column["dimension"] / (4.0 * scale)),
            1.0 - np.exp(-(column["tortuosity"] - 1.0) / 0.5),
            1.0 - np.exp(-(column["path_ratio"] - 1.0) / 0.1),
            np.exp(-column["narrowest"] / (2.0 * scale)),
        )
    )


def difficulty_score(table: np.ndarray, scale: float, *, version: int = DIFFICULTY_VERSION) -> np.ndarray:
    """One number from 0 (open) to 100 (hard) out of the metrics of ``table``.

    Version 1 is BARN's five metrics as hardnesses (:func:`hardness`'s first five columns:
    ``exp(-clearance / 2s)``, ``exp(-visibility / 8s)``, ``1 - exp(-dispersion / 2)``,
    ``exp(-dimension / 4s)``, ``1 - exp(-(tortuosity - 1) / 0.5)``), 100 times their mean.
    Version 2 is the measured traversal difficulty those hardnesses and the path ratio's and
    narrowest passage's predict: 100 × (:data:`INTERCEPT` + hardness · :data:`WEIGHTS`), clipped
    to [0, 100], where 0 is the optimal time and 100 the timeout (docs/difficulty.md).
    """
    terms = hardness(table, scale)
    if version == 1:
        return 100.0 * np.mean(terms[:, :5].T, axis=0)  # summed in version 1's order, bit for bit
    if version == 2:
        return 100.0 * np.clip(INTERCEPT + terms @ WEIGHTS, 0.0, 1.0)
    raise ValueError(f"difficulty score version {version} is not 1 or 2")


def dispersion_radius(robot_radius: float, cell: float) -> float:
    """Reach of the dispersion rays in cells: the robot's diameter, at least one cell."""
    return max(2.0 * robot_radius / cell, 1.0)


def survey(pop: Population) -> Survey:
    """Navigation and difficulty metrics of every individual of ``pop`` on its arena's grid."""
    arena = pop.arena
    grid = grid_of(arena)
    n = pop.size
    solvable = np.zeros(n, dtype=np.bool_)
    length = np.full(n, np.nan)
    coverage = np.zeros(n)
    table = np.full((n, len(METRICS)), np.nan)
    if n:
        in_blocks(
            _survey_all,
            n,
            *kernel_args(pop),
            grid_args(grid),
            grid_args(point_grid_of(arena)),
            dispersion_radius(arena.robot_radius, grid.cell),
            solvable,
            length,
            coverage,
            table,
            per_thread=16,
        )
    straight = math.dist(grid.start, grid.goal)
    table[:, METRICS.index("tortuosity")] = length / straight if straight > 0 else np.nan
    return Survey(Navigation(solvable, length, coverage, straight, grid.cell), table, arena.robot_radius)


@njit(cache=True, nogil=True)
def _survey_all(  # pragma: no cover - compiled
    first, last, shapes, ids, n_el, params, valid, grid, point_grid, reach, solvable, length, coverage, table
):
    """Fill the outputs of individuals ``first`` to ``last - 1``."""
    rows, cols = grid[1], grid[2]
    floor = floor_cells(grid)
    scratch = route_scratch(shapes, ids.shape[1], grid)
    cells = np.zeros((rows * cols, 2), np.int64)  # path_cells stops when it is full
    steps = step_arrays(rows, cols)
    for i in range(first, last):
        if not valid[i]:
            continue
        occupied, found, total, turns = route(shapes, ids[i], n_el[i], params[i], grid, scratch)
        coverage[i] = occupied / floor
        if not found:
            continue
        solvable[i] = True
        length[i] = total
        free = scratch[1]
        count = path_cells(scratch[5], turns, free, grid[0], cols, cells)
        fill_free_steps(free, cols, steps)
        _path_metrics(free, cols, steps, cells, count, reach, grid[0], table[i])
        # The robot's scratch serves the point: same cells, and no wider dilation padding.
        _, point_found, point_total, _ = route(shapes, ids[i], n_el[i], params[i], point_grid, scratch)
        # The robot's path is a path for a point too: the point's is the shorter of the two.
        table[i, 5] = total / min(point_total, total) if point_found and total > 0.0 else 1.0


@wrapped_leaf_kernel
def path_cells(corners, turns, free, cell, cols, out):  # pragma: no cover - compiled
    """The free cells the polyline ``corners[:turns]`` passes through, in order; returns their count.

    The path runs along cell edges and through cell corners where it hugs an
    obstacle; a point on an edge belongs to every cell it touches, and the first
    free one of them is taken. Points in no free cell (an end the coarse grid put
    in a blocked cell) are skipped.
    """
    count = 0
    for t in range(turns - 1):
        ax, ay, bx, by = corners[t, 0], corners[t, 1], corners[t + 1, 0], corners[t + 1, 1]
        steps = max(1, math.ceil(2.0 * math.hypot(bx - ax, by - ay) / cell))
        last = steps if t == turns - 2 else steps - 1
        for s in range(last + 1):
            u = s / steps
            x, y = (ax + (bx - ax) * u) / cell, (ay + (by - ay) * u) / cell
            r, c = _free_cell_at(free, x, y, cols)
            if r < 0 or (count > 0 and out[count - 1, 0] == r and out[count - 1, 1] == c):
                continue
            if count == out.shape[0]:
                return count
            out[count, 0], out[count, 1] = r, c
            count += 1
    return count


@njit(cache=True, inline="always")
def _free_cell_at(free, x, y, cols):  # pragma: no cover - compiled
    """A free cell holding the point ``(x, y)`` (in cells), or (-1, -1)."""
    r0, c0 = math.floor(y), math.floor(x)
    on_row_edge = y - r0 < 1e-7
    on_col_edge = x - c0 < 1e-7
    for dr in range(2):
        if dr == 1 and not on_row_edge:
            break
        for dc in range(2):
            if dc == 1 and not on_col_edge:
                break
            if is_free(free, r0 - dr, c0 - dc, cols):
                return r0 - dr, c0 - dc
    return -1, -1


@inner_kernel
def _path_metrics(free, cols, arrays, cells, count, reach, cell, out):  # pragma: no cover - compiled
    """Write the per-cell metrics' averages over the ``count`` path cells into ``out``
    (``arrays`` as :func:`fill_free_steps` leaves them for ``free``)."""
    if count == 0:
        return
    steps = arrays[1]
    clearance = visibility = dispersion = dimension = 0.0
    narrowest = np.inf
    rays = np.zeros(8)
    for k in range(count):
        r, c = cells[k, 0], cells[k, 1]
        clearance += math.sqrt(closest_blocked(arrays, r, c))
        for d in range(8):
            rays[d] = steps[d, r + 1, c + 1] * math.sqrt(KING[d, 0] * KING[d, 0] + KING[d, 1] * KING[d, 1])
        visibility += rays.sum() / 8.0
        width = min(rays[0] + rays[4], rays[1] + rays[5], rays[2] + rays[6], rays[3] + rays[7])
        dimension += width
        narrowest = min(narrowest, width)
        dispersion += cell_dispersion(free, steps, r, c, reach, cols)
    out[0] = clearance / count * cell
    out[1] = visibility / count * cell
    out[2] = dispersion / count
    out[3] = dimension / count * cell
    out[6] = narrowest * cell


@njit(cache=True)
def step_arrays(rows, cols):  # pragma: no cover - compiled
    """Scratch of :func:`fill_free_steps` on a ``rows`` x ``cols`` grid (a ring of blocked cells
    around it, so no step needs a bounds test; the ring is never written)."""
    return (
        np.zeros((rows + 2, cols + 2), np.int32),  # 1 on free cells
        np.zeros((8, rows + 2, cols + 2), np.int32),  # free steps along each king direction
        run_arrays(np.int64(1), cols),  # one row's runs
    )


@wrapped_leaf_kernel
def fill_free_steps(free, cols, arrays):  # pragma: no cover - compiled
    """For every cell ``(r, c)`` and king direction ``d``, the free cells stepped over from it along
    ``KING[d]`` before the first blocked one (cells outside the grid are blocked), into
    ``arrays[1][d, r + 1, c + 1]``: each ray of the metrics is then one look-up.

    Along a row the steps are read off each run's ends; across rows each row follows from
    the row it steps into, a whole row at a time.
    """
    is_open, steps, runs = arrays
    rows = free.shape[0]
    # (Slices rather than offset indices: indices the compiler knows are not negative spare it
    # the wrap-around test that would keep these loops from being vectorised.)
    for r in range(rows):
        for w in range(free.shape[1]):
            x = free[r, w]
            cells = is_open[r + 1, 1 + 64 * w : 1 + min(64 * (w + 1), cols)]
            for b in range(cells.shape[0]):
                cells[b] = (x >> np.uint64(b)) & ONE
        for j in range(row_runs_of(free, r, cols, runs, 0)):
            lo, hi = runs[0, j, 0], runs[0, j, 1]
            right = steps[0, r + 1, lo + 1 : hi + 2]
            left = steps[4, r + 1, lo + 1 : hi + 2]
            for c in range(hi - lo + 1):
                right[c] = hi - lo - c
                left[c] = c
    for d in (1, 2, 3, 5, 6, 7):
        dr, dc = KING[d, 0], KING[d, 1]
        for k in range(rows):
            here = rows - k if dr > 0 else k + 1  # the row it steps into comes first
            into = steps[d, here, 1 : cols + 1]
            ahead = steps[d, here + dr, 1 + dc : cols + 1 + dc]
            opened = is_open[here + dr, 1 + dc : cols + 1 + dc]
            for c in range(cols):
                into[c] = opened[c] * (ahead[c] + 1)


@wrapped_leaf_kernel
def cell_dispersion(free, steps, r, c, reach, cols):  # pragma: no cover - compiled
    """Alternations between rays that meet a blocked cell within ``reach`` cells and rays that do not
    (``steps`` as :func:`fill_free_steps` leaves them: the king rays' first blocked cells)."""
    hits = 0  # bit d: ray d meets a blocked cell (a bit set, not an array: no allocation per cell)
    for d in range(16):
        dr, dc = RAYS16[d, 0], RAYS16[d, 1]
        step = math.sqrt(dr * dr + dc * dc)
        if d % 2 == 0:  # a king move: its first blocked cell is known
            hits |= ((steps[d // 2, r + 1, c + 1] + 1) * step <= reach + 1e-9) << d
            continue
        k = 1
        while k * step <= reach + 1e-9:
            if not is_free(free, r + k * dr, c + k * dc, cols):
                hits |= 1 << d
                break
            k += 1
    changes = 0
    for d in range(16):
        changes += ((hits >> d) ^ (hits >> ((d + 1) % 16))) & 1
    return changes


@wrapped_leaf_kernel
def closest_blocked(arrays, r, c):  # pragma: no cover - compiled
    """Squared distance, in cells, from cell ``(r, c)`` to the nearest blocked cell (outside counts),
    ``arrays`` as :func:`fill_free_steps` leaves them.

    Rows are searched outwards while they can hold a nearer one; in each, the nearest blocked
    cell is the one in column ``c`` or the first one met going left or right from it.
    """
    is_open, steps = arrays[0], arrays[1]
    best = np.inf
    dy = 0
    while dy * dy < best:
        for row in (r - dy + 1, r + dy + 1):  # padded rows: the ring outside the grid is blocked
            dx = min(steps[0, row, c + 1], steps[4, row, c + 1]) + 1 if is_open[row, c + 1] else 0
            best = min(best, float(dy * dy + dx * dx))
        dy += 1
    return best
