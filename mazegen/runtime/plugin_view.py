"""What a metric plug-in sees of a population: :class:`Floors`, a stable, documented view.

The view's fields keep their names, shapes, dtypes and units across MazeGen versions
(docs/extending.md); the population behind them may change. Arrays are read-only views: a
plug-in returns its values, it never writes into the floors. What costs a search (the
configuration space, the paths) is found when first asked for, once per population, and shared
with the fitness terms that read it too.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from mazegen.runtime.engine import SX, SY, THETA, Population, X, Y
from mazegen.runtime.geometry import element_bounds, grid_of, world_parts
from mazegen.runtime.navigation import corner_paths_of, free_cells, navigation_of, reach_of
from mazegen.spec import Arena, metres_per_unit


def _read_only(array: np.ndarray) -> np.ndarray:
    view = array.view()
    view.flags.writeable = False
    return view


@dataclass(frozen=True, eq=False)
class Floors:
    """N floors of up to K elements each, in arena units, as a metric plug-in reads them.

    Attributes:
        types: The scenario's element type names; :attr:`type` holds indices into it.
    """

    _population: Population
    types: tuple[str, ...]

    @property
    def arena(self) -> Arena:
        """The arena the floors are placed on."""
        return self._population.arena

    @property
    def size(self) -> int:
        """N, the number of floors."""
        return self._population.size

    @property
    def slots(self) -> int:
        """K, the element slots of each floor (``count[i] <= K``)."""
        return int(self._population.element_ids.shape[1])

    @cached_property
    def valid(self) -> np.ndarray:
        """``bool[N]``: the genome mapped to a complete floor. An invalid floor has no elements; its
        value is ignored (it scores nothing)."""
        return _read_only(np.asarray(self._population.valid, dtype=bool))

    @cached_property
    def count(self) -> np.ndarray:
        """``int64[N]``: elements on each floor; slots ``count[i]:`` are padding."""
        return _read_only(self._population.n_elements.astype(np.int64))

    @cached_property
    def type(self) -> np.ndarray:
        """``int64[N, K]``: each element's index in :attr:`types`, -1 in padding."""
        return _read_only(self._population.element_ids.astype(np.int64))

    def _param(self, column: int) -> np.ndarray:
        return _read_only(self._population.params[:, :, column])

    @property
    def x(self) -> np.ndarray:
        """``float64[N, K]``: x of each element's position (the centre of its bounding box before
        rotation), arena units; 0 in padding."""
        return self._param(X)

    @property
    def y(self) -> np.ndarray:
        """``float64[N, K]``: y of each element's position, arena units; 0 in padding."""
        return self._param(Y)

    @property
    def width(self) -> np.ndarray:
        """``float64[N, K]``: each element's size along its own x axis before rotation (a rect's
        width, another shape's size), arena units."""
        return self._param(SX)

    @property
    def depth(self) -> np.ndarray:
        """``float64[N, K]``: each element's size along its own y axis before rotation (a rect's
        depth, another shape's size again), arena units."""
        return self._param(SY)

    @property
    def rotation(self) -> np.ndarray:
        """``float64[N, K]``: each element's rotation, radians, counter-clockwise."""
        return self._param(THETA)

    @cached_property
    def bounds(self) -> np.ndarray:
        """``float64[N, K, 4]``: each element's world bounding box ``(xmin, ymin, xmax, ymax)``,
        arena units; NaN in padding."""
        pop = self._population
        return _read_only(element_bounds(pop.table, pop.element_ids, pop.n_elements, pop.params))

    def outline(self, floor: int, element: int) -> list[np.ndarray]:
        """The world outline of one element: a ``float64[v, 2]`` counter-clockwise polygon per convex
        part, arena units."""
        pop = self._population
        if not 0 <= element < int(pop.n_elements[floor]):
            raise IndexError(f"floor {floor} has {int(pop.n_elements[floor])} elements, not {element + 1}")
        return world_parts(pop.table, int(pop.element_ids[floor, element]), pop.params[floor, element])

    @property
    def robot_radius(self) -> float:
        """The driven robot's radius, arena units (the configuration space is widened by it)."""
        return float(self._population.arena.robot_radius)

    @property
    def metres_per_unit(self) -> float:
        """Metres in one arena unit (a ``px`` arena: sized from its robot)."""
        return metres_per_unit(self.arena)

    @property
    def cell(self) -> float:
        """The side of a cell of the configuration space grid, arena units."""
        return float(grid_of(self.arena).cell)

    def free(self, floor: int) -> np.ndarray:
        """``bool[rows, cols]``: the cells of floor ``floor``'s configuration space where the robot's
        centre may stand (row 0 at y = 0, cells of side :attr:`cell`)."""
        return free_cells(self._population, grid_of(self.arena), floor)

    @property
    def solvable(self) -> np.ndarray:
        """``bool[N]``: a robot of :attr:`robot_radius` can get from start to goal."""
        return _read_only(np.asarray(reach_of(self._population).solvable, dtype=bool))

    @property
    def path_length(self) -> np.ndarray:
        """``float64[N]``: length of the robot's path from start to goal, arena units; NaN without one."""
        return _read_only(navigation_of(self._population).path_length)

    @property
    def paths(self) -> list[np.ndarray | None]:
        """Each floor's path, start to goal: ``float64[n, 2]`` corners in arena units, or None."""
        return corner_paths_of(self._population)
