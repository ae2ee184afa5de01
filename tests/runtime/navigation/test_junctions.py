"""The free rectangles cut down to junctions and chains (what the class search walks): dead ends
pruned, every chain a run of touching rectangles, and one independent cycle per obstacle the free
space wraps round."""

from __future__ import annotations

from collections import deque
from itertools import pairwise

import numpy as np
import pytest

from mazegen.runtime.geometry import FIRST_COL, FIRST_ROW, LAST_COL, LAST_ROW, decompose, rectangle_arrays
from mazegen.runtime.navigation._classes import _bit_rows
from mazegen.runtime.navigation._holes import hole_arrays, holes_of
from mazegen.runtime.navigation._junctions import COUNT, FIRST, FROM, TO, junction_arrays, junctions


def walled(rows: int, cols: int) -> np.ndarray:
    free = np.ones((rows, cols), bool)
    free[0], free[-1], free[:, 0], free[:, -1] = False, False, False, False
    return free


def cut(free: np.ndarray, start: tuple[int, int], goal: tuple[int, int]) -> dict:
    """The decomposition of ``free`` and its junctions and chains, as plain Python."""
    rows, cols = free.shape
    rectangles = rectangle_arrays(rows, cols)
    count, s, g = decompose(_bit_rows(free), cols, np.array([*start, *goal], np.int64), rectangles)
    arrays = junction_arrays(len(rectangles[0]))
    found, n_chains = junctions(rectangles[0], rectangles[1], count, s, g, arrays)
    left, _, junction_of, rectangle, chains, interior, _, _ = arrays
    return {
        "rects": rectangles[0][:count].copy(),
        "start": s,
        "goal": g,
        "pruned": {r for r in range(count) if left[r] < 0},
        "junctions": rectangle[:found].tolist(),
        "goal junction": int(junction_of[g]),
        "chains": [
            [
                int(rectangle[c[FROM]]),
                *interior[c[FIRST] : c[FIRST] + c[COUNT]].tolist(),
                int(rectangle[c[TO]]),
            ]
            for c in chains[:n_chains]
        ],
    }


def touching(rects: np.ndarray, a: int, b: int) -> bool:
    below, above = (a, b) if rects[a, LAST_ROW] < rects[b, FIRST_ROW] else (b, a)
    return (
        rects[below, LAST_ROW] + 1 == rects[above, FIRST_ROW]
        and rects[below, FIRST_COL] <= rects[above, LAST_COL]
        and rects[above, FIRST_COL] <= rects[below, LAST_COL]
    )


def holes(free: np.ndarray) -> int:
    rows, cols = free.shape
    ends = np.array([1.5, 1.5, cols - 1.5, rows - 1.5])
    return int(holes_of(_bit_rows(free), cols, ends, hole_arrays(rows, cols)))


def free_components(free: np.ndarray) -> int:
    seen = np.zeros_like(free)
    components = 0
    for cell in zip(*np.nonzero(free)):
        if seen[cell]:
            continue
        components += 1
        queue = deque([cell])
        seen[cell] = True
        while queue:
            r, c = queue.popleft()
            for nr, nc in ((r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)):
                if 0 <= nr < free.shape[0] and 0 <= nc < free.shape[1] and free[nr, nc] and not seen[nr, nc]:
                    seen[nr, nc] = True
                    queue.append((nr, nc))
    return components


def test_a_pillar_makes_one_cycle_and_a_dead_end_alcove_is_pruned():
    free = walled(20, 40)
    free[8:12, 18:22] = False  # a pillar between start and goal
    free[14:19, 30] = False  # an alcove's wall from the top edge: the cells right of it above row 14
    free[14, 30:39] = False
    found = cut(free, (10, 2), (10, 37))
    rects = found["rects"]
    alcove = {r for r in range(len(rects)) if rects[r, FIRST_ROW] >= 15 and rects[r, FIRST_COL] >= 31}
    assert alcove and alcove <= found["pruned"]
    assert len(found["chains"]) - len(found["junctions"]) + 1 == 1  # one pillar, one cycle
    assert found["junctions"][0] == found["start"] and found["goal junction"] >= 0
    for chain in found["chains"]:
        assert all(touching(rects, a, b) for a, b in pairwise(chain))
        assert not set(chain) & found["pruned"]


@pytest.mark.parametrize("seed", range(12))
def test_the_junctions_have_one_cycle_per_hole_of_a_connected_floor(seed):
    rng = np.random.default_rng(seed)
    free = walled(30, 50)
    for _ in range(rng.integers(3, 12)):
        r, c = rng.integers(2, 26), rng.integers(4, 44)
        free[r : r + rng.integers(1, 5), c : c + rng.integers(1, 6)] = False
    free[1:4, 1:4] = free[-4:-1, -4:-1] = True
    if free_components(free) != 1:
        pytest.skip("the floor's free space is in pieces")
    found = cut(free, (2, 2), (27, 47))
    interior = [r for chain in found["chains"] for r in chain[1:-1]]
    assert len(interior) == len(set(interior))  # a rectangle is in one chain at most
    assert not set(found["junctions"]) & set(interior)
    assert len(found["chains"]) - len(found["junctions"]) + 1 == holes(free)
