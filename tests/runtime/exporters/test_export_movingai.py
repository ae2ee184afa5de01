"""MovingAI exports: the map is the engine's configuration space, the optimal lengths are right."""

from __future__ import annotations

import heapq
import math

import numpy as np
import pytest

import mazegen
from mazegen.errors import MazeError
from mazegen.runtime.documents._floor import load_floor
from mazegen.runtime.exporters._floor import ExportOptions
from mazegen.runtime.exporters._movingai import movingai_files, octile_length
from mazegen.runtime.geometry._cspace import grid_of
from mazegen.runtime.navigation._paths import free_cells
from tests.conftest import EXAMPLES
from tests.runtime.floors import floor_file


def read_map(text: str) -> np.ndarray:
    """``bool[height, width]`` passable cells of a MovingAI map, row 0 the first line."""
    lines = text.splitlines()
    assert lines[0] == "type octile" and lines[3] == "map"
    height, width = int(lines[1].split()[1]), int(lines[2].split()[1])
    rows = lines[4:]
    assert len(rows) == height and all(len(row) == width and set(row) <= {".", "@"} for row in rows)
    return np.array([[cell == "." for cell in row] for row in rows])


def dijkstra(passable: np.ndarray, start: tuple[int, int], goal: tuple[int, int]) -> float:
    """Plain Dijkstra over (x, y) cells, 8 moves, a diagonal only between two passable cells."""
    height, width = passable.shape
    distance = {start: 0.0}
    queue = [(0.0, start)]
    while queue:
        d, (x, y) = heapq.heappop(queue)
        if (x, y) == goal:
            return d
        if d > distance[(x, y)]:
            continue
        for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1)):
            nx, ny = x + dx, y + dy
            if not (0 <= nx < width and 0 <= ny < height and passable[ny, nx]):
                continue
            if dx and dy and not (passable[y, nx] and passable[ny, x]):
                continue
            nd = d + (math.sqrt(2) if dx and dy else 1.0)
            if nd < distance.get((nx, ny), math.inf):
                distance[(nx, ny)] = nd
                heapq.heappush(queue, (nd, (nx, ny)))
    return math.inf


def exported(floor, cell: float | None = None) -> tuple[np.ndarray, list[list[str]]]:
    files = movingai_files(floor, ExportOptions(cell=cell))
    scen = files[f"{floor.name}.scen"].decode().splitlines()
    assert scen[0] == "version 1"
    return read_map(files[f"{floor.name}.map"].decode()), [line.split("\t") for line in scen[1:]]


@pytest.mark.parametrize("cell", [None, 25.0, 7.5])
def test_optimal_lengths_equal_an_independent_search(factory_run, cell):
    spec = mazegen.load(EXAMPLES / "factory.maze")
    for path in sorted(factory_run.glob("run-*/best-*.json")):
        floor = load_floor(path)
        passable, problems = exported(floor, cell)
        height, width = passable.shape
        assert width == math.ceil(spec.arena.width / (cell or spec.arena.cell))
        if cell is None:  # at the engine's own cell the map is its configuration space
            engine = free_cells(floor.population, grid_of(spec.arena), 0)
            assert np.array_equal(passable, engine[::-1])
            assert bool(problems) == floor.document["metrics"]["solvable"]
        for bucket, name, w, h, sx, sy, gx, gy, length in problems:
            assert (name, int(w), int(h)) == (f"{path.stem}.map", width, height)
            expected = dijkstra(passable, (int(sx), int(sy)), (int(gx), int(gy)))
            assert float(length) == pytest.approx(expected, abs=1e-6)
            assert int(bucket) == int(expected // 4)
            # The start and goal cells hold the arena's start and goal (rows counted from the top).
            size = cell or spec.arena.cell
            start, goal = spec.arena.start, spec.arena.goal
            assert (int(sx), height - 1 - int(sy)) == (int(start[0] // size), int(start[1] // size))
            assert (int(gx), height - 1 - int(gy)) == (int(goal[0] // size), int(goal[1] // size))


def test_no_corner_cutting_and_exact_octile_lengths():
    free = np.ones((5, 5), bool)
    assert octile_length(free, (0, 0), (4, 4)) == pytest.approx(4 * math.sqrt(2))
    assert octile_length(free, (0, 0), (1, 4)) == pytest.approx(3 + math.sqrt(2))
    # Two blocked cells meeting at a corner: a diagonal may not squeeze between them.
    pinched = np.array([[1, 0], [0, 1]], bool)
    assert octile_length(pinched, (0, 0), (1, 1)) == math.inf
    # A wall with one gap: around through the gap, not over the wall.
    wall = np.ones((5, 5), bool)
    wall[2, :4] = False
    assert octile_length(wall, (0, 0), (4, 0)) == pytest.approx(dijkstra(wall, (0, 0), (0, 4)))
    assert octile_length(wall, (0, 0), (0, 0)) == 0.0
    wall[0, 0] = False
    assert octile_length(wall, (0, 0), (4, 0)) == math.inf


def test_a_floor_without_a_path_has_no_problem_line(tmp_path):
    path = floor_file(
        tmp_path / "closed.json", {"type": "vwall", "x": 700, "y": 525, "width": 20, "depth": 1100}
    )
    passable, problems = exported(load_floor(path, mazegen.load(EXAMPLES / "factory.maze")))
    assert problems == [] and passable.any() and not passable.all()


@pytest.mark.parametrize(
    ("cell", "message"), [(0.0, "must be a positive number"), (0.1, "choose a larger cell")]
)
def test_bad_cells_are_refused(factory_run, cell, message):
    floor = load_floor(factory_run / "run-01" / "best-01.json")
    with pytest.raises(MazeError, match=message):
        movingai_files(floor, ExportOptions(cell=cell))
