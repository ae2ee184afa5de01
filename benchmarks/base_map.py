"""Static evaluation on a 2,000 × 2,000-cell base map against an empty arena of the same size (issue 28).

Usage:
    python benchmarks/base_map.py                 # populations 1,000 and 5,000, median of 9 (~4 min)
    python benchmarks/base_map.py --repeats 7 --populations 1000

Writes, in a temporary folder, two map_server maps of 2,000 × 2,000 cells at 5 cm (100 × 100 m): ``hall``
(outer walls with unknown cells outside them, a lattice of pillars, long internal walls with doors,
shelving) and ``bare`` (its outer walls alone); and specs identical but for the arena (``map "hall.yaml"
m``, ``map "bare.yaml" m`` or ``size 100 x 100 m``; the same start, goal, robot radius and 25 cm grid,
400 × 400 cells), with their elements in metres and ``outside reject`` in every fitness, in two variants:
``solvable`` (count, overlap, outside, solvable) and ``difficulty`` (the same plus a difficulty target).

The same random genomes are evaluated on every arena (mapping, decoding, every term, into a kept
workspace, all threads), the arenas interleaved and their order reversed every round, after three untimed
calls each; medians of wall and CPU time. Then, on the largest population, the parts of the evaluation a
map touches, each alone (the outside term, the configuration space, the solvability search); and the
one-off costs per arena: loading the spec (reading the map) and building the grid. Prints Markdown
tables and writes ``benchmarks/base_map.csv``.
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
from mazegen.runtime.navigation._paths import kernel_args
from mazegen.runtime.threads import in_blocks, thread_count
from mazegen.spec import Arena

CELLS, RESOLUTION = 2_000, 0.05
FREE, OCCUPIED, UNKNOWN = 254, 0, 205
WARMUP = 3  # untimed calls of each full evaluation: numba compiles on the first; kernels.py on fresh pages
ARENAS = {"hall": 'map "hall.yaml" m', "bare": 'map "bare.yaml" m', "empty": "size 100 x 100 m"}
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


def hall_pixels(*, interior: bool) -> np.ndarray:
    """The map's pixels, top row first: a hall of 97.6 × 97.6 m in 100 × 100 m, unknown outside;
    ``interior``: pillars, internal walls with doors and shelving (else the bare outer walls)."""

    def at(metres: float) -> int:
        return round(metres / RESOLUTION)

    cells = np.full((CELLS, CELLS), FREE, dtype=np.uint8)  # row 0 the lowest (y up) until the flip

    def block(x0: float, y0: float, x1: float, y1: float, value: int = OCCUPIED) -> None:
        cells[at(y0) : at(y1), at(x0) : at(x1)] = value

    block(0, 0, 100, 100, UNKNOWN)  # outside the hall: never seen by the mapping robot
    block(1.0, 1.0, 99.0, 99.0)  # the outer walls, 20 cm thick
    block(1.2, 1.2, 98.8, 98.8, FREE)
    if interior:
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
    """The maps (binary PGM and YAML) and a spec per (variant, arena) in ``folder``."""
    for name, interior in (("hall", True), ("bare", False)):
        pixels = hall_pixels(interior=interior).tobytes()
        (folder / f"{name}.pgm").write_bytes(f"P5\n{CELLS} {CELLS}\n255\n".encode() + pixels)
        (folder / f"{name}.yaml").write_text(
            f"image: {name}.pgm\nmode: trinary\nresolution: {RESOLUTION}\norigin: [0.0, 0.0, 0.0]\n"
            "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
        )
    paths = {}
    for variant, terms in TERMS.items():
        for name, arena in ARENAS.items():
            paths[variant, name] = folder / f"{variant}-{name}.maze"
            paths[variant, name].write_text(SPEC.format(arena=arena, terms=terms))
    return paths


def interleaved(actions: dict[str, Callable[[], object]], repeats: int, warmup: int = WARMUP) -> dict:
    """Median wall and CPU seconds of each action (the process's CPU time: all its threads, none of
    another process's), the actions called in turn, their order reversed every round."""
    names = list(actions)
    for _ in range(warmup):
        for name in names:
            actions[name]()
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in names}
    for round_ in range(repeats):
        for name in names if round_ % 2 == 0 else names[::-1]:
            wall, cpu = time.perf_counter(), time.process_time()
            actions[name]()
            times[name].append((time.perf_counter() - wall, time.process_time() - cpu))
    return {name: tuple(statistics.median(each) for each in zip(*values)) for name, values in times.items()}


def compare(head: dict, rows: int, seconds: dict[str, tuple[float, float]], extra: dict[str, dict]) -> list:
    """A row per arena: its wall seconds and rate, its ratio to the empty arena and the overhead, in wall
    and in CPU time."""
    (empty, empty_cpu) = seconds["empty"]
    return [
        {
            **head,
            "individuals": rows,
            "arena": name,
            **extra.get(name, {}),
            "s": wall,
            "per_s": rows / wall,
            "ratio": wall / empty,
            "overhead_pct": 100 * (wall / empty - 1),
            "cpu_s": cpu,
            "cpu_overhead_pct": 100 * (cpu / empty_cpu - 1),
        }
        for name, (wall, cpu) in seconds.items()
    ]


def evaluations(problems: dict[str, Problem], rows: int, repeats: int) -> tuple[list[dict], dict]:
    """Time the full evaluation of ``rows`` random genomes on each arena; the rows and the populations."""
    rng = np.random.default_rng(rows)
    settings = problems["empty"].spec.evolution
    codons = random_codons(rng, rows, settings.genome, settings.codon_max)
    genes = random_genes(rng, rows, problems["empty"].slots)
    done = {name: problem.evaluate(codons, genes) for name, problem in problems.items()}
    extra = {name: {"valid_pct": 100 * float(np.isfinite(e.fitness).mean())} for name, e in done.items()}
    actions = {name: partial(p.evaluate, codons, genes, Workspace()) for name, p in problems.items()}
    rows_ = compare({"timed": "full evaluation"}, rows, interleaved(actions, repeats), extra)
    return rows_, {name: evaluation.population for name, evaluation in done.items()}


@njit(nogil=True)
def _cspaces(first, last, shapes, ids, n_el, params, valid, grid, straight):  # pragma: no cover - compiled
    """The configuration space of individuals ``first`` to ``last - 1`` alone (occupancy, the base's
    walls ORed in, the disc dilation), as the searches build it; with ``straight`` of size 1, no more,
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


def parts(pops: dict[str, Population], repeats: int) -> list[dict]:
    """Time each part of the solvable variant's evaluation that reads the map alone, on ``pops``."""
    found: dict[str, Callable[[Population], object]] = {
        "outside term": metrics.elements_outside,
        "configuration space": cspaces,
        "solvability (reach)": lambda pop: reach(pop, grid_of(pop.arena)),
    }
    straight = {n: {"straight_pct": 100 * float(cspaces(p, straight=True).mean())} for n, p in pops.items()}
    rows = []
    for what, part in found.items():
        seconds = interleaved({name: partial(part, pop) for name, pop in pops.items()}, repeats, 1)
        rows += compare({"timed": what}, pops["empty"].size, seconds, straight)
    return rows


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
        problems = {}
        for name in ARENAS:  # each spec built into a folder of its own, and loaded
            mazegen.build(paths[variant, name], folder / f"build-{variant}-{name}")
            problems[name] = Problem.from_build_dir(folder / f"build-{variant}-{name}")
        for rows in populations:
            found, pops = evaluations(problems, rows, repeats)
            timed += [{"fitness": variant, **row} for row in found]
            overheads = ", ".join(f"{row['arena']} {row['overhead_pct']:+.1f} %" for row in found)
            print(f"  {variant:10} {rows:6,}: {overheads}", flush=True)
        if variant == "solvable":
            timed += [{"fitness": variant, **row} for row in parts(pops, repeats)]
    return timed, one_off({name: paths["solvable", name] for name in ARENAS}, repeats)


COLUMNS = [
    ("fitness", "fitness", "s"),
    ("timed", "timed", "s"),
    ("individuals", "individuals", ","),
    ("arena", "arena", "s"),
    ("valid_pct", "valid %", ".1f"),
    ("straight_pct", "straight line free %", ".1f"),
    ("s", "s", ".4f"),
    ("per_s", "individuals/s", ",.0f"),
    ("ratio", "× empty", ".3f"),
    ("overhead_pct", "overhead %", "+.1f"),
    ("cpu_s", "CPU s", ".4f"),
    ("cpu_overhead_pct", "CPU overhead %", "+.1f"),
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
        timed, one_off_rows = measure(Path(folder), sorted(args.populations), args.repeats)
    print("\n### Static evaluation on each arena (100 × 100 m, grid 400 × 400), against the empty one\n")
    print(markdown_table(timed, COLUMNS))
    print("\n### One-off per arena (median)\n")
    print(markdown_table(one_off_rows, ONE_OFF_COLUMNS))
    path = BENCHMARKS / "base_map.csv"
    keys = dict.fromkeys(key for row in timed for key in row)
    write_csv(path, [{key: row.get(key) for key in keys} for row in timed])
    print(f"\nwrote {path.relative_to(ROOT)}; load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
