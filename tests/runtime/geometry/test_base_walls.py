"""An arena's base map in the configuration space: its walls widened by the robot's disc join the
grid's border, and elements that stand on them are counted (checked with shapely on the map's cells)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import shapely
from shapely.geometry import box

from mazegen.maps import base_map_of, base_on_grid
from mazegen.runtime.geometry import Grid, elements_on_walls, unpack
from mazegen.runtime.geometry._overlap import elements_outside
from mazegen.spec import Arena
from tests.runtime.elements import TABLE, random_population, shapely_geometries

CELLS = np.random.default_rng(11).random((30, 40)) < 0.08
"""A base of 40 x 30 cells of 10 units, some blocked."""
BASE = base_map_of(CELLS, source="test.yaml", resolution=10.0, origin=(0.0, 0.0), unknown="blocked")
ARENA = Arena("hall", 400.0, 300.0, "cm", (60.0, 60.0), (340.0, 240.0), 15.0, 5.0, BASE)


def test_the_border_holds_the_walls_widened_by_the_disc():
    grid = Grid.from_arena(ARENA)
    walls = base_on_grid(BASE, 5.0, grid.rows, grid.cols)
    assert (unpack(grid.base, grid.cols) == walls).all()
    centres = (np.argwhere(walls) + 0.5) * 5.0
    expected = np.zeros_like(walls)
    for r in range(grid.rows):
        for c in range(grid.cols):
            y, x = (r + 0.5) * 5.0, (c + 0.5) * 5.0
            near_edge = min(x, y, 400.0 - x, 300.0 - y) < 15.0
            near_wall = bool(np.any(np.hypot(centres[:, 0] - y, centres[:, 1] - x) <= 15.0 + 1e-9))
            expected[r, c] = near_edge or near_wall
    assert (unpack(grid.border, grid.cols) == expected).all()
    plain = Grid.from_arena(replace(ARENA, base=None))
    assert not plain.base.any()
    assert (unpack(plain.border, plain.cols) <= expected).all()


def test_elements_on_the_walls_are_counted_and_those_clear_of_them_are_not():
    rng = np.random.default_rng(5)
    ids, n_elements, params = random_population(rng, 300, 4, 400.0, 300.0)
    params[..., 2:4] *= 0.4  # elements of 8 to 48 units, some between the walls
    grid = Grid.from_arena(ARENA)
    counted = elements_on_walls(TABLE, ids, n_elements, params, grid, (400.0, 300.0)).sum(axis=1)
    outside = elements_outside(TABLE, ids, n_elements, params, 400.0, 300.0)
    walls = shapely.union_all(
        [box(c * 10, r * 10, (c + 1) * 10, (r + 1) * 10) for r, c in np.argwhere(CELLS)]
    )
    arena = box(0, 0, 400, 300)
    reach = 5.0 * math.sqrt(2) + 1e-6  # a touched grid cell reaches a wall cell within its diagonal
    seen = {"on": 0, "clear": 0}
    for i, elements in enumerate(shapely_geometries(TABLE, ids, n_elements, params)):
        inside = [e for e in elements if arena.covers(e)]
        on = sum(e.intersection(walls).area > 0 for e in inside)
        near = sum(e.distance(walls) <= reach for e in inside)
        assert on <= counted[i] <= near
        assert outside[i] == len(elements) - len(inside)
        seen["on"] += on
        seen["clear"] += len(inside) - near
    assert seen["on"] > 50 and seen["clear"] > 50  # both kinds were tested


def test_an_arena_without_a_map_has_no_element_on_walls():
    rng = np.random.default_rng(2)
    ids, n_elements, params = random_population(rng, 20, 4, 400.0, 300.0)
    grid = Grid.from_arena(replace(ARENA, base=None))
    assert not elements_on_walls(TABLE, ids, n_elements, params, grid, (400.0, 300.0)).any()
