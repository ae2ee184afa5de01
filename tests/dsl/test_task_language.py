"""Tasks in the language: stations and listed tasks, tasks drawn at random, and how terms score them."""

from __future__ import annotations

import json
import math
from collections import deque

import numpy as np
import pytest

from mazegen.dsl.loader import load_spec
from mazegen.maps import base_on_grid, near_cells
from mazegen.spec import Spec, Task
from tests.map_files import hall_pixels, write_map

ELEMENT = "element box { shape square size 20..40 }\n"
TAIL = "scenario s on floor { elements box }\nfitness { count  solvable required }\n"


def arena(body: str, *, size: str = "1000 x 800 cm") -> str:
    return f"{ELEMENT}arena floor {{ size {size} robot radius 20\n{body} }}\n{TAIL}"


def test_listed_tasks_join_stations_and_the_first_is_the_arenas_start_and_goal(write_spec):
    spec = load_spec(
        write_spec(
            arena(
                "station dock (100, 100) heading 90  station line1 (900, 700) heading -90\n"
                "station line2 (900, 100)  task dock -> line1  task line2 -> dock"
            )
        )
    )
    a = spec.arena
    assert [s.name for s in a.stations] == ["dock", "line1", "line2"]
    assert a.tasks == (
        Task("dock -> line1", (100.0, 100.0), (900.0, 700.0), 90.0, 270.0),
        Task("line2 -> dock", (900.0, 100.0), (100.0, 100.0), None, 90.0),
    )
    assert (a.start, a.goal) == ((100.0, 100.0), (900.0, 700.0))
    assert a.every_task == a.tasks
    assert Spec.from_json(spec.to_json()) == spec


def test_an_arena_of_one_start_and_goal_has_one_task_and_writes_no_tasks(write_spec):
    spec = load_spec(write_spec(arena("start (50, 50) goal (950, 750)")))
    assert spec.arena.tasks == () and spec.arena.every_task == (Task("start -> goal", (50, 50), (950, 750)),)
    written = json.loads(spec.to_json())
    assert "tasks" not in written["arena"] and "stations" not in written["arena"]
    assert all("tasks" not in term for term in written["fitness"])


def _joined(free: np.ndarray, a: tuple[int, int], b: tuple[int, int]) -> bool:
    """Whether cells ``a`` and ``b`` of ``free`` are joined by edge-sharing free cells (a plain search)."""
    seen, queue = {a}, deque([a])
    while queue:
        r, c = queue.popleft()
        if (r, c) == b:
            return True
        for n in ((r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)):
            if 0 <= n[0] < free.shape[0] and 0 <= n[1] < free.shape[1] and free[n] and n not in seen:
                seen.add(n)
                queue.append(n)
    return False


def test_drawn_tasks_are_repeatable_far_enough_apart_and_where_the_robot_stands(write_spec):
    text = arena("tasks 12 seed 7 min distance 4 m")
    spec = load_spec(write_spec(text))
    again = load_spec(write_spec(text, name="again.maze"))
    other = load_spec(write_spec(text.replace("seed 7", "seed 8"), name="other.maze"))
    tasks = spec.arena.tasks
    assert tasks == again.arena.tasks and tasks != other.arena.tasks
    assert [t.name for t in tasks] == [f"drawn {k}" for k in range(1, 13)]
    for task in tasks:
        assert math.dist(task.start, task.goal) >= 400  # 4 m in the arena's cm
        for x, y in (task.start, task.goal):
            assert 20 <= x <= 980 and 20 <= y <= 780  # the robot's disc inside the arena


def test_drawn_tasks_on_a_map_keep_off_its_walls_and_each_goal_is_reachable(tmp_path, write_spec):
    # A hall of two rooms joined by a gap in the middle wall, and a closed room beside it.
    pixels = hall_pixels(60, 30, gap=(2, 8))
    pixels[:, 45] = 0  # a wall with no gap: the right part is a room of its own
    write_map(tmp_path, pixels)
    text = (
        f'{ELEMENT}arena floor {{ map "hall.yaml" cm robot radius 15 grid 5\n'
        f"tasks 30 seed 2 min distance 1 m }}\n{TAIL}"
    )
    spec = load_spec(write_spec(text))
    base = spec.arena.base
    assert base is not None and len(spec.arena.tasks) == 30
    walls = np.flipud(pixels == 0)  # row 0 the lowest
    cell = 5.0
    grid_walls = base_on_grid(base, cell, 60, 120)
    free = ~near_cells(grid_walls, 15 / cell)
    for task in spec.arena.tasks:
        for x, y in (task.start, task.goal):
            # The robot's disc touches no wall cell of the map (10 cm cells): checked on the map's own cells.
            rows, cols = np.nonzero(walls)
            dx = np.maximum(np.abs((cols + 0.5) * 10 - x) - 5, 0)
            dy = np.maximum(np.abs((rows + 0.5) * 10 - y) - 5, 0)
            assert np.hypot(dx, dy).min() > 15
        cells = [(int(y // cell), int(x // cell)) for x, y in (task.start, task.goal)]
        assert _joined(free, *cells)
        assert math.dist(task.start, task.goal) >= 100


@pytest.mark.parametrize(("words", "how"), [("", "mean"), (" tasks worst", "worst"), (" tasks all", "all")])
def test_difficulty_and_metric_terms_say_how_they_score_several_tasks(write_spec, words, how):
    text = arena("station a (100, 100) station b (900, 700) task a -> b task b -> a").replace(
        "solvable required }", f"difficulty target hard{words}  tortuosity 1..2{words} }}"
    )
    spec = load_spec(write_spec(text))
    assert [term.tasks for term in spec.fitness if term.kind in ("difficulty", "metric")] == [how, how]
    assert Spec.from_json(spec.to_json()) == spec
