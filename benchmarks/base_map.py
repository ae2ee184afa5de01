"""Static evaluation on a 2,000 × 2,000-cell base map against an empty arena of the same size (issue 28).

Usage:
    python benchmarks/base_map.py                 # populations 1,000 and 5,000, median of 9 (~3 min)
    python benchmarks/base_map.py --repeats 7 --populations 1000

Writes, in a temporary folder, a map_server map of 2,000 × 2,000 cells at 5 cm (100 × 100 m: outer
walls with unknown cells outside them, a lattice of pillars, two long internal walls and a cross wall
with doors, rows of shelving) and specs that differ only in their arena: ``map "hall.yaml" m`` or
``size 100 x 100 m``, with the same start, goal, robot radius and grid (25 cm: 400 × 400 cells), the
same elements (in metres) and the same fitness, ``outside reject`` in both, in two variants: ``solvable``
(count, overlap, outside, solvable) and ``difficulty`` (the same plus ``difficulty target medium``).

Per variant and population, the same random genomes are evaluated (mapping, decoding, every fitness term,
into a kept workspace, all threads) on both arenas, A and B interleaved and their order alternated so
machine noise hits both, after three untimed calls each. Then, on the largest population decoded once,
each costly part alone (the outside term, the solvability search, the difficulty survey), and the
one-off costs per arena: loading the spec (reading the map) and building the navigation grid. Prints
Markdown tables and writes ``benchmarks/base_map.csv``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path

import numpy as np
from common import BENCHMARKS, ROOT, markdown_table, median_seconds, write_csv
from numba import njit

import mazegen
from mazegen.maps._base import base_cells
from mazegen.runtime import metrics
from mazegen.runtime.engine._operators import random_codons, random_genes
from mazegen.runtime.engine._population import Population
from mazegen.runtime.engine._problem import Problem, Workspace
from mazegen.runtime.geometry import Grid, cspace, grid_args, grid_of, raster_arrays, straight_free, unpack
from mazegen.runtime.navigation._connectivity import reach
from mazegen.runtime.navigation._difficulty import survey
from mazegen.runtime.navigation._paths import kernel_args
from mazegen.runtime.threads import in_blocks, thread_count
from mazegen.spec import Arena

CELLS, RESOLUTION = 2_000, 0.05
FREE, OCCUPIED, UNKNOWN = 254, 0, 205
WARMUP = 3
"""Untimed calls of each full evaluation (numba compiles on the first; see kernels.py on fresh pages)."""
ARENAS = {"map": 'map "hall.yaml" m', "empty": "size 100 x 100 m"}
TERMS = {
    "solvable": "count  overlap penalty 0.5  outside reject  solvable required",
    "difficulty": "count  overlap penalty 0.5  outside reject  solvable required  difficulty target medium",
}
SPEC = """
element rack   {{ shape rect  size 1..4 x 0.5..1  rotation 0, 90  class machine }}
element box    {{ shape square  size 0.5..1.5 }}
element wall   {{ shape rect  size 2..8 x 0.1..0.2  rotation 0, 90  class wall }}
element cobot  {{ shape triangle  size 0.6..1.2  rotation any  class robot }}
arena hall {{ {arena}  start (2, 2)  goal (98, 98)  robot radius 0.25  grid 0.25 }}
scenario layout on hall {{
    grammar custom {{
        <scenario> ::= <group> | <group> <scenario>
        <group> ::= <element> <element> <element> <element>
        <element> ::= rack | box | wall | cobot
    }}
    max elements 32
}}
fitness {{ {terms} }}
evolution {{ population 5000  generations 15  genome 32  seed 1 }}
"""


def hall_pixels() -> np.ndarray:
    """The map's pixels, top row first: a hall of 97.6 × 97.6 m in 100 × 100 m, unknown outside."""

    def at(metres: float) -> int:
        return round(metres / RESOLUTION)

    cells = np.full((CELLS, CELLS), FREE, dtype=np.uint8)  # row 0 the lowest (y up) until the flip

    def block(x0: float, y0: float, x1: float, y1: float, value: int = OCCUPIED) -> None:
        cells[at(y0) : at(y1), at(x0) : at(x1)] = value

    block(0, 0, 100, 100, UNKNOWN)  # outside the hall: never seen by the mapping robot
    block(1.0, 1.0, 99.0, 99.0)  # the outer walls, 20 cm thick
    block(1.2, 1.2, 98.8, 98.8, FREE)
    for x in range(10, 100, 10):  # pillars of 40 cm every 10 m
        for y in range(10, 100, 10):
            block(x - 0.2, y - 0.2, x + 0.2, y + 0.2)
    for x, doors in ((33.0, (15, 50, 85)), (66.0, (30, 70))):  # long walls north-south, doors of 2 m
        block(x, 1.2, x + 0.2, 98.8)
        for y in doors:
            block(x, y - 1, x + 0.2, y + 1, FREE)
    block(66.2, 45.0, 98.8, 45.2)  # a cross wall east of the second, two doors
    for x in (75, 92):
        block(x - 1, 45.0, x + 1, 45.2, FREE)
    for y in range(62, 92, 5):  # shelving in the west aisle: 20 × 1 m racks, 4 m aisles
        block(5.0, y, 25.0, y + 1.0)
    return np.flipud(cells)


def write_specs(folder: Path) -> dict[tuple[str, str], Path]:
    """The map (binary PGM and YAML) and a spec per (variant, arena) in ``folder``."""
    (folder / "hall.pgm").write_bytes(f"P5\n{CELLS} {CELLS}\n255\n".encode() + hall_pixels().tobytes())
    (folder / "hall.yaml").write_text(
        f"image: hall.pgm\nmode: trinary\nresolution: {RESOLUTION}\norigin: [0.0, 0.0, 0.0]\n"
        "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    paths = {}
    for variant, terms in TERMS.items():
        for name, arena in ARENAS.items():
            paths[variant, name] = folder / f"{variant}-{name}.maze"
            paths[variant, name].write_text(SPEC.format(arena=arena, terms=terms))
    return paths


def load_problem(path: Path, folder: Path) -> Problem:
    """Build the spec at ``path`` into a folder of its own and load it."""
    out = folder / f"build-{path.stem}"
    mazegen.build(path, out)
    return Problem.from_build_dir(out)


def interleaved(actions: dict[str, Callable[[], object]], repeats: int, warmup: int = WARMUP) -> dict:
    """Median seconds of each action, the actions called in turn (order reversed every round)."""
    names = list(actions)
    for _ in range(warmup):
        for name in names:
            actions[name]()
    times: dict[str, list[float]] = {name: [] for name in names}
    for round_ in range(repeats):
        for name in names if round_ % 2 == 0 else names[::-1]:
            started = time.perf_counter()
            actions[name]()
            times[name].append(time.perf_counter() - started)
    return {name: statistics.median(values) for name, values in times.items()}


def compare(what: str, rows: int, seconds: dict[str, float], **extra: object) -> dict:
    """A row of the table: both arenas' seconds and rates, the ratio map/empty and the overhead."""
    ratio = seconds["map"] / seconds["empty"]
    return {
        "what": what,
        "individuals": rows,
        "map_s": seconds["map"],
        "empty_s": seconds["empty"],
        "map_per_s": rows / seconds["map"],
        "empty_per_s": rows / seconds["empty"],
        "ratio": ratio,
        "overhead_pct": 100 * (ratio - 1),
        **extra,
    }


def evaluations(problems: dict[str, Problem], rows: int, repeats: int) -> tuple[dict, dict[str, Population]]:
    """Time the full evaluation of ``rows`` random genomes on each arena; the row and the populations."""
    rng = np.random.default_rng(rows)
    settings = problems["map"].spec.evolution
    codons = random_codons(rng, rows, settings.genome, settings.codon_max)
    genes = random_genes(rng, rows, problems["map"].slots)
    done = {name: problem.evaluate(codons, genes) for name, problem in problems.items()}
    shares = {f"{name}_valid_pct": 100 * float(np.isfinite(e.fitness).mean()) for name, e in done.items()}
    actions = {name: partial(p.evaluate, codons, genes, Workspace()) for name, p in problems.items()}
    seconds = interleaved(actions, repeats)
    return compare("full evaluation", rows, seconds, **shares), {n: e.population for n, e in done.items()}


@njit(nogil=True)
def _cspaces(first, last, shapes, ids, n_el, params, valid, grid, straight):  # pragma: no cover - compiled
    """The configuration space of individuals ``first`` to ``last - 1`` alone (occupancy, the base's
    walls ORed in, the disc dilation), as the searches build it; with ``straight[0]`` of size 1, no more,
    else whether each one's straight start-goal line is free (the searches' first test)."""
    raster = raster_arrays(grid, ids.shape[1], shapes[2].shape[1], shapes[2].shape[2])
    free = np.zeros((grid[1], grid[4].shape[1]), np.uint64)
    for i in range(first, last):
        if valid[i]:
            cspace(shapes, ids[i], n_el[i], params[i], grid, raster, free)
            if straight.shape[0] > 1:
                straight[i] = straight_free(free, grid[2], grid[0], grid[5])


def cspaces(pop: Population, *, straight: bool = False) -> np.ndarray:
    """Build every configuration space of ``pop`` (:func:`_cspaces`); ``straight``: return whether each
    straight line is free."""
    out = np.zeros(pop.size if straight else 1, np.bool_)
    in_blocks(_cspaces, pop.size, *kernel_args(pop), grid_args(grid_of(pop.arena)), out, per_thread=16)
    return out


def parts(pops: dict[str, Population], repeats: int, difficulty: bool) -> list[dict]:
    """Time each costly part of the evaluation alone on the decoded populations ``pops``."""
    found: dict[str, Callable[[Population], object]] = {
        "outside term": metrics.elements_outside,
        "configuration space": cspaces,
        "solvability (reach)": lambda pop: reach(pop, grid_of(pop.arena)),
    }
    if difficulty:
        found["difficulty (survey)"] = survey
    rows = next(iter(pops.values())).size
    straight = {f"{name}_straight_pct": 100 * float(cspaces(pop, straight=True).mean()) for name, pop in pops.items()}
    return [
        compare(what, rows, interleaved({name: partial(part, pop) for name, pop in pops.items()}, repeats, 1))
        | (straight if what == "configuration space" else {})
        for what, part in found.items()
    ]


def one_off(paths: dict[str, Path], repeats: int) -> list[dict]:
    """Per arena: the median seconds of loading its spec (reading the map) and of building its grid."""
    out = []
    for name, path in paths.items():
        arena = mazegen.load(path).arena

        def grid(arena: Arena = arena) -> Grid:
            base_cells.cache_clear()  # unpack the map's cells again, as a fresh process does
            return Grid.from_arena(arena)

        built = grid()
        out.append(
            {
                "arena": name,
                "load_s": median_seconds(partial(mazegen.load, path), repeats=repeats),
                "grid_s": median_seconds(grid, repeats=repeats),
                "cells": f"{built.cols} × {built.rows}",
                "wall_cells": int(unpack(built.base, built.cols).sum()),
            }
        )
    return out


def measure(folder: Path, populations: list[int], repeats: int) -> tuple[list[dict], list[dict]]:
    """Time the full evaluations and, on the largest population, their parts; the one-off costs."""
    paths = write_specs(folder)
    timed = []
    for variant in TERMS:
        problems = {name: load_problem(paths[variant, name], folder) for name in ARENAS}
        for rows in populations:
            row, pops = evaluations(problems, rows, repeats)
            timed.append({"variant": variant, **row})
            print(f"  {variant:10} {rows:6,} {row['overhead_pct']:+6.1f} %", flush=True)
        timed += [{"variant": variant, **row} for row in parts(pops, repeats, variant == "difficulty")]
    return timed, one_off({name: paths["solvable", name] for name in ARENAS}, repeats)


COLUMNS = [
    ("variant", "fitness", "s"),
    ("what", "timed", "s"),
    ("individuals", "individuals", ","),
    ("map_valid_pct", "valid % map", ".1f"),
    ("empty_valid_pct", "valid % empty", ".1f"),
    ("map_s", "map s", ".4f"),
    ("empty_s", "empty s", ".4f"),
    ("map_per_s", "map individuals/s", ",.0f"),
    ("empty_per_s", "empty individuals/s", ",.0f"),
    ("ratio", "map/empty", ".3f"),
    ("overhead_pct", "overhead %", "+.1f"),
    ("map_straight_pct", "straight line free % map", ".1f"),
    ("empty_straight_pct", "straight line free % empty", ".1f"),
]
ONE_OFF_COLUMNS = [
    ("arena", "arena", "s"),
    ("load_s", "load the spec s", ".3f"),
    ("grid_s", "Grid.from_arena s", ".4f"),
    ("cells", "grid cells", "s"),
    ("wall_cells", "wall cells in the grid", ","),
]


def main() -> None:
    """Measure, print the tables, write the CSV."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--populations", type=int, nargs="+", default=[1_000, 5_000])
    parser.add_argument("--repeats", type=int, default=9, help="timed calls per figure (median; >= 7)")
    args = parser.parse_args()
    print(
        f"base map at populations {args.populations}, median of {args.repeats}, {thread_count()} threads, "
        f"load average {os.getloadavg()[0]:.2f}"
    )
    with tempfile.TemporaryDirectory() as folder:
        timed, one_off = measure(Path(folder), sorted(args.populations), args.repeats)
    print("\n### Static evaluation, map against empty arena (100 × 100 m, grid 400 × 400)\n")
    print(markdown_table(timed, COLUMNS))
    print("\n### One-off per arena (median)\n")
    print(markdown_table(one_off, ONE_OFF_COLUMNS))
    path = BENCHMARKS / "base_map.csv"
    keys = dict.fromkeys(key for row in timed for key in row)
    write_csv(path, [{key: row.get(key) for key in keys} for row in timed])
    print(f"\nwrote {path.relative_to(ROOT)}; load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
