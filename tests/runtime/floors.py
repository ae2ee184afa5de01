"""Floors shared by the navigation, connectivity, difficulty and suite tests: element types,
arenas, populations built from element lists, an exact-geometry solvability check, bit rows
packed from cell grids and a plain breadth-first search over cells."""

from __future__ import annotations

import json
import math
from collections import deque
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Polygon, box

import mazegen
from mazegen.runtime.engine._population import Population
from mazegen.runtime.geometry._elements import ElementTable
from mazegen.spec import Arena
from tests.conftest import EXAMPLES

TYPES = mazegen.load(EXAMPLES / "factory.maze").scenario_elements
TABLE = ElementTable.from_types(TYPES)
NAMES = [t.name for t in TYPES]
ARENA = Arena("hall", 1000, 600, "cm", (50, 50), (950, 550), 20, 10)
ZIGZAG = [("vwall", 330, 225, 20, 450, 0), ("vwall", 660, 375, 20, 450, 0)]
"""Two walls, each across three quarters of ARENA, from opposite sides: a zig-zag path."""


def population(arena: Arena, scenarios: list[list[tuple]]) -> Population:
    """Scenarios of (type, x, y, width, depth, degrees) elements."""
    slots = max(1, max(len(s) for s in scenarios))
    ids = np.full((len(scenarios), slots), -1, np.int32)
    params = np.zeros((len(scenarios), slots, 5))
    for i, elements in enumerate(scenarios):
        for k, (name, x, y, sx, sy, degrees) in enumerate(elements):
            ids[i, k] = NAMES.index(name)
            params[i, k] = (x, y, sx, sy, math.radians(degrees))
    count = np.array([len(s) for s in scenarios], np.int32)
    return Population(ids, count, lambda: params, np.ones(len(scenarios), bool), TABLE, arena)


def random_floors(rng: np.random.Generator, count: int, arena: Arena) -> list[list[tuple]]:
    floors = []
    for _ in range(count):
        elements = []
        for _ in range(rng.integers(0, 14)):
            name = NAMES[rng.integers(0, len(NAMES))]
            kind = TYPES[NAMES.index(name)]
            sx = rng.uniform(*kind.size)
            sy = rng.uniform(*kind.size2) if kind.size2 else sx
            x, y = rng.uniform(-50, arena.width + 50), rng.uniform(-50, arena.height + 50)
            elements.append((name, x, y, sx, sy, rng.uniform(0, 360)))
        floors.append(elements)
    return floors


def geometrically_solvable(document: dict) -> bool:
    """Exact geometry, no grid: the floor shrunk by the robot radius, minus every part grown by
    it; start and goal must lie in one piece of what remains."""
    arena = document["arena"]
    r = arena["robot_radius"]
    parts = [Polygon(part) for element in document["elements"] for part in element["parts"]]
    room = box(r, r, arena["width"] - r, arena["height"] - r)
    free = room.difference(shapely.union_all(parts).buffer(r)) if parts else room
    start, goal = shapely.Point(arena["start"]), shapely.Point(arena["goal"])
    pieces = getattr(free, "geoms", [free])
    return any(piece.covers(start) and piece.covers(goal) for piece in pieces)


def floor_file(path: Path, *elements: dict) -> Path:
    """Write a hand-drawn scenario document (elements only, no arena) to ``path``."""
    path.write_text(json.dumps({"format": "mazegen-scenario", "version": 1, "elements": list(elements)}))
    return path


def pack(free: np.ndarray) -> np.ndarray:
    """Bit rows of ``uint64`` words from ``bool[rows, cols]`` (padding columns blocked)."""
    rows, cols = free.shape
    words = (cols + 63) // 64
    padded = np.zeros((rows, words * 64), bool)
    padded[:, :cols] = free
    return np.packbits(padded, axis=1, bitorder="little").view("<u8").astype(np.uint64)


def reachable(free: np.ndarray, start: tuple[int, int], goal: tuple[int, int]) -> bool:
    """Plain breadth-first search over 4-connected free cells."""
    if not (free[start] and free[goal]):
        return False
    seen, queue = {start}, deque([start])
    while queue:
        r, c = queue.popleft()
        if (r, c) == goal:
            return True
        for nr, nc in ((r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)):
            if 0 <= nr < free.shape[0] and 0 <= nc < free.shape[1] and free[nr, nc] and (nr, nc) not in seen:
                seen.add((nr, nc))
                queue.append((nr, nc))
    return False
