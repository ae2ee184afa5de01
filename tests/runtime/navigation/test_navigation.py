"""Solvability and path length against independent references: shapely rasters, a plain
breadth-first search, and floors whose answer is known."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon, box

import mazegen
from mazegen.runtime.geometry._cspace import Grid
from mazegen.runtime.geometry._elements import world_parts
from mazegen.runtime.navigation._paths import free_cells, navigate
from mazegen.spec import Arena
from tests.conftest import EXAMPLES
from tests.runtime.floors import (
    ARENA,
    NAMES,
    TABLE,
    geometrically_solvable,
    population,
    random_floors,
    reachable,
)


def test_open_floor_is_a_straight_line():
    nav = navigate(population(ARENA, [[]]), Grid.from_arena(ARENA))
    assert nav.solvable.tolist() == [True]
    assert nav.path_length[0] == pytest.approx(
        math.dist(ARENA.start, ARENA.goal), abs=ARENA.cell * math.sqrt(2)
    )
    assert nav.path_length[0] / nav.straight == pytest.approx(1.0, abs=1e-9)


def test_start_near_a_wall_on_a_coarse_grid_is_still_free():
    """Start 25 from the walls with radius 25: its 40-wide cell's centre is only 20 from them."""
    arena = Arena("hall", 1000, 600, "cm", (25, 25), (975, 575), 25, 40)
    nav = navigate(population(arena, [[]]), Grid.from_arena(arena))
    assert nav.solvable.tolist() == [True]


def test_a_wall_across_the_floor_blocks_it():
    nav = navigate(population(ARENA, [[("vwall", 500, 300, 20, 700, 0)]]), Grid.from_arena(ARENA))
    assert nav.solvable.tolist() == [False] and np.isnan(nav.path_length[0])


@pytest.mark.parametrize(("gap", "solvable"), [(30.0, False), (38.0, False), (52.0, True), (80.0, True)])
def test_the_robot_passes_a_gap_only_when_it_fits(gap, solvable):
    """Two walls leave a gap; the robot (radius 20, so 40 wide) on a 5-unit grid."""
    arena = Arena("hall", 1000, 600, "cm", (50, 50), (950, 550), 20, 5)
    low = 300 - gap / 2
    walls = [
        ("vwall", 500, low / 2, 20, low, 0),
        ("vwall", 500, (600 + 300 + gap / 2) / 2, 20, 300 - gap / 2, 0),
    ]
    nav = navigate(population(arena, [walls]), Grid.from_arena(arena))
    assert nav.solvable.tolist() == [solvable]


def test_path_bends_round_a_wall_as_geometry_says():
    """A wall from the floor to y=450 at x=500: the path hugs its inflated top corners."""
    nav = navigate(population(ARENA, [[("vwall", 500, 225, 20, 450, 0)]]), Grid.from_arena(ARENA))
    r = ARENA.robot_radius
    corner_a, corner_b = (490 - r, 450 + r), (510 + r, 450 + r)
    taut = math.dist(ARENA.start, corner_a) + math.dist(corner_a, corner_b) + math.dist(corner_b, ARENA.goal)
    assert nav.path_length[0] == pytest.approx(taut, abs=2 * ARENA.cell)


@pytest.mark.parametrize("downwards", [False, True])
def test_path_zigzags_through_two_walls(downwards):
    """Walls from the floor at x=330 and from the ceiling at x=660 (mirrored: start at the top)."""
    arena = Arena(
        "hall",
        1000,
        600,
        "cm",
        (50, 550) if downwards else (50, 50),
        (950, 50) if downwards else (950, 550),
        20,
        10,
    )
    flip = (lambda y: 600 - y) if downwards else (lambda y: y)
    walls = [("vwall", 330, flip(225), 20, 450, 0), ("vwall", 660, flip(375), 20, 450, 0)]
    nav = navigate(population(arena, [walls]), Grid.from_arena(arena))
    r = arena.robot_radius
    corners = [(320 - r, 450 + r), (340 + r, 450 + r), (650 - r, 150 - r), (670 + r, 150 - r)]
    points = [arena.start, *[(x, flip(y)) for x, y in corners], arena.goal]
    taut = sum(math.dist(a, b) for a, b in itertools.pairwise(points))
    assert nav.path_length[0] == pytest.approx(taut, abs=2 * arena.cell)


def reference_free(arena: Arena, grid: Grid, elements: list[tuple]) -> np.ndarray:
    """Free cells by definition: shapely marks the cells a part touches; cells whose centre is
    within the robot radius of a marked cell's centre, or of the arena edge, are blocked."""
    occupied = np.zeros((grid.rows, grid.cols), bool)
    for name, x, y, sx, sy, degrees in elements:
        for part in world_parts(TABLE, NAMES.index(name), (x, y, sx, sy, math.radians(degrees))):
            polygon = Polygon(part)
            for r in range(grid.rows):
                for c in range(grid.cols):
                    cell = box(c * grid.cell, r * grid.cell, (c + 1) * grid.cell, (r + 1) * grid.cell)
                    occupied[r, c] |= cell.intersects(polygon)
    rr, cc = np.nonzero(occupied)
    ys, xs = np.mgrid[0 : grid.rows, 0 : grid.cols]
    reach = arena.robot_radius / grid.cell
    blocked = np.zeros_like(occupied)
    for r, c in zip(rr, cc):
        blocked |= (ys - r) ** 2 + (xs - c) ** 2 <= reach * reach + 1e-9
    cx, cy = (xs + 0.5) * grid.cell, (ys + 0.5) * grid.cell
    r = arena.robot_radius
    blocked |= (cx < r) | (cx > arena.width - r) | (cy < r) | (cy > arena.height - r)
    return ~blocked


def test_free_cells_and_solvability_equal_the_reference_on_random_floors():
    arena = Arena("hall", 800, 500, "cm", (40, 40), (760, 460), 25, 20)
    grid = Grid.from_arena(arena)
    floors = random_floors(np.random.default_rng(3), 30, arena)
    pop = population(arena, floors)
    nav = navigate(pop, grid)
    answers = []
    for i, elements in enumerate(floors):
        expected = reference_free(arena, grid, elements)
        assert np.array_equal(free_cells(pop, grid, i), expected), i
        answers.append(reachable(expected, grid.start_cell, grid.goal_cell))
    assert nav.solvable.tolist() == answers
    assert 0 < sum(answers) < len(answers)  # both outcomes occur
    lengths = nav.path_length[nav.solvable]
    assert (lengths >= nav.straight - 1e-9).all() and np.isnan(nav.path_length[~nav.solvable]).all()


def test_solvable_floors_have_a_collision_free_path_by_shapely():
    """Independent of the grid: shapely buffers the elements by the robot radius; some cell-centre
    path of the kernel's free cells avoids the buffered union, so the floor is truly passable."""
    arena = Arena("hall", 800, 500, "cm", (40, 40), (760, 460), 25, 10)
    grid = Grid.from_arena(arena)
    floors = random_floors(np.random.default_rng(8), 12, arena)
    pop = population(arena, floors)
    nav = navigate(pop, grid)
    for i, elements in enumerate(floors):
        if not nav.solvable[i]:
            continue
        polygons = [
            Polygon(part)
            for name, x, y, sx, sy, degrees in elements
            for part in world_parts(TABLE, NAMES.index(name), (x, y, sx, sy, math.radians(degrees)))
        ]
        keep_out = shapely.union_all(polygons).buffer(arena.robot_radius) if polygons else Polygon()
        free = free_cells(pop, grid, i)
        rows, cols = np.nonzero(free)
        centres = shapely.points((cols + 0.5) * grid.cell, (rows + 0.5) * grid.cell)
        assert not shapely.intersects(centres, keep_out).any()


def test_solvable_required_runs_return_only_solvable_floors():
    spec = mazegen.load(EXAMPLES / "factory.maze")
    assert any(term.kind == "solvable" and term.reject for term in spec.fitness)
    result = mazegen.run(spec, seed=4, population=300, generations=6, runs=2)
    documents = [document for run in result.best for document in run]
    assert len(documents) >= 10 and all(document["valid"] for document in documents)
    assert all(geometrically_solvable(document) for document in documents)
    # The check itself can say no: a wall across the floor.
    arena = documents[0]["arena"]
    wall = [[700, -10], [720, -10], [720, arena["height"] + 10], [700, arena["height"] + 10]]
    assert not geometrically_solvable({"arena": arena, "elements": [{"parts": [wall]}]})
