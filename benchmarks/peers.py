"""MazeGen against the alogos GE library on the paper's Figure 1 task: individuals evaluated per second.

Usage:
    python benchmarks/peers.py [--populations 1000 5000 10000] [--generations 15] [--repeats 3]
                               [--seed 1] [--csv benchmarks/peers.csv]

The task, the same for both: the grammar of the paper's Figure 1 (``examples/mazegen1.maze``),
genomes of 32 codons 0..255, fitness = number of figures in the phenotype (maximised; invalid
individuals worst), ``generations`` bred after a random generation 0, tournament selection of
size 3, crossover 0.9, per-codon int-flip mutation 0.05, no wrapping. Tournament replaces the spec's
truncation 0.1 in both because alogos' truncation picks the best ``offspring_size`` individuals and
breeds exactly that many children: it cannot breed a whole population from the best 10%.

Where alogos cannot match MazeGen:

* crossover: alogos' only GE crossover swaps two equal-length segments and is always applied;
  MazeGen cuts once with probability 0.9;
* elitism: MazeGen keeps its best individual; alogos' generational model (``non_overlapping``
  with pass-through truncation of survivors) keeps none;
* MazeGen also evolves 5 placement genes per element slot (32 slots), mutated at the same rate;
  alogos has only the codons;
* both skip repeated work: MazeGen evaluates each genome (codons + placement genes) once per
  run, alogos maps each distinct genotype once per generation and scores each distinct phenotype
  once per generation (its LRU caches and database are off). The table reports both counts.

Per repeat, alogos and MazeGen run one after the other with the same seed (``seed + repeat``), so
machine noise hits both. Timed: building the EA and running it for alogos, ``mazegen.run`` on a
build directory for MazeGen (loading the build, evolving, picking the best scenarios); the grammar
is parsed (alogos) or the spec built (MazeGen) once beforehand. Individuals per second is
population × (generations + 1) / median seconds.
"""

from __future__ import annotations

import argparse
import random
import re
import statistics
import tempfile
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import Any

import alogos
from alogos.systems import ge
from common import BENCHMARKS, ROOT, markdown_table, write_csv

import mazegen
from mazegen.spec import FIRST_OPERATORS

SPEC = ROOT / "examples" / "mazegen1.maze"
BNF = """\
<scenario> ::= angle | square | eshape | lshape | <composedFigures>
<composedFigures> ::= angle(<scenario>) | square(<scenario>) | eshape(<scenario>) | lshape(<scenario>)
"""
FIGURE = re.compile(r"\b(?:angle|square|eshape|lshape)\b")
GENOME = 32
TOURNAMENT = 3
CROSSOVER = 0.9
MUTATION = 0.05
TARGET_RATIO = 100

COLUMNS = [
    ("population", "population", ","),
    ("generations", "generations", "d"),
    ("repeats", "repeats", "d"),
    ("alogos_s", "alogos s", ".3f"),
    ("mazegen_s", "MazeGen s", ".4f"),
    ("alogos_per_s", "alogos individuals/s", ",.0f"),
    ("mazegen_per_s", "MazeGen individuals/s", ",.0f"),
    ("ratio", "MazeGen / alogos", ".1f"),
    ("alogos_best", "best alogos", ""),
    ("mazegen_best", "best MazeGen", ""),
    ("alogos_mapped", "alogos genotypes mapped", ",d"),
    ("alogos_scored", "alogos phenotypes scored", ",d"),
    ("mazegen_evaluated", "MazeGen genomes evaluated", ",d"),
]


class FigureCount:
    """alogos' objective: the number of figure names in a phenotype, counting its calls."""

    def __init__(self) -> None:
        self.calls = 0

    def __call__(self, phenotype: str) -> int:
        self.calls += 1
        return len(FIGURE.findall(phenotype))


def timed(action: Callable[[], Any]) -> tuple[float, Any]:
    """Wall seconds of one call of ``action`` and what it returned."""
    started = time.perf_counter()
    result = action()
    return time.perf_counter() - started, result


def alogos_ea(
    grammar: alogos.Grammar, objective: FigureCount, population: int, generations: int
) -> alogos.EvolutionaryAlgorithm:
    """alogos' GE on the Figure 1 task with the settings above (``benchmarks/quality.py`` steps it)."""
    return alogos.EvolutionaryAlgorithm(
        grammar,
        objective,
        "max",
        system="ge",
        population_size=population,
        offspring_size=population,
        max_generations=generations + 1,  # alogos counts the random generation 0
        genotype_length=GENOME,
        codon_size=8,
        max_wraps=0,
        init_pop_unique_phenotypes=False,  # MazeGen starts from plain random genomes
        generation_model="non_overlapping",
        parent_selection_operator="tournament",
        parent_selection_tournament_size=TOURNAMENT,
        survivor_selection_operator="truncation",  # keeps all offspring: their number is the population
        mutation_int_replacement_probability=MUTATION,
        gen_to_phe_cache_lookup_on=False,
        phe_to_fit_cache_lookup_on=False,
        database_on=False,
    )


def run_alogos(grammar: alogos.Grammar, population: int, generations: int, seed: int) -> dict:
    """One alogos GE run; returns its best fitness and how many mappings and scorings it did."""
    random.seed(seed)  # alogos draws from the global random module
    objective = FigureCount()
    ea = alogos_ea(grammar, objective, population, generations)
    best = ea.run()
    return {
        "best": best.fitness,
        "mapped": ea.state.num_gen_to_phe_evaluations,
        "scored": objective.calls,
    }


def run_mazegen(build_dir: Path, population: int, generations: int, seed: int) -> dict:
    """One MazeGen run; returns its best fitness and how many genomes it evaluated."""
    result = mazegen.run(build_dir, population=population, generations=generations, runs=1, seed=seed)
    run = result.runs[0]
    return {"best": float(run.fitness.max()), "evaluated": sum(row.evaluations for row in run.stats)}


def compare(
    grammar: alogos.Grammar, build_dir: Path, population: int, generations: int, repeats: int, seed: int
) -> dict:
    """Interleaved repeats of both libraries at one population size, summarised as one table row."""
    alogos_runs, mazegen_runs = [], []
    for repeat in range(repeats):
        alogos_runs.append(timed(partial(run_alogos, grammar, population, generations, seed + repeat)))
        mazegen_runs.append(timed(partial(run_mazegen, build_dir, population, generations, seed + repeat)))
    alogos_s = statistics.median(seconds for seconds, _ in alogos_runs)
    mazegen_s = statistics.median(seconds for seconds, _ in mazegen_runs)
    individuals = population * (generations + 1)

    def bests(runs: list[tuple[float, dict]]) -> str:
        return " / ".join(f"{out['best']:g}" for _, out in runs)

    def median_count(runs: list[tuple[float, dict]], key: str) -> int:
        return round(statistics.median(out[key] for _, out in runs))

    return {
        "population": population,
        "generations": generations,
        "repeats": repeats,
        "alogos_s": alogos_s,
        "mazegen_s": mazegen_s,
        "alogos_per_s": individuals / alogos_s,
        "mazegen_per_s": individuals / mazegen_s,
        "ratio": alogos_s / mazegen_s,
        "alogos_best": bests(alogos_runs),
        "mazegen_best": bests(mazegen_runs),
        "alogos_mapped": median_count(alogos_runs, "mapped"),
        "alogos_scored": median_count(alogos_runs, "scored"),
        "mazegen_evaluated": median_count(mazegen_runs, "evaluated"),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--populations", type=int, nargs="+", default=[1000, 5000, 10000])
    parser.add_argument("--generations", type=int, default=15)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--seed", type=int, default=1, help="repeat r of both libraries uses seed + r")
    parser.add_argument("--csv", type=Path, default=BENCHMARKS / "peers.csv")
    parser.add_argument(
        "--first-operators",
        action="store_true",
        help="MazeGen with the operators that were its default before (one-point crossover and mutation "
        "within the whole genome), whose evolved genomes use fewer codons",
    )
    args = parser.parse_args()

    # alogos' EA maps genotypes without passing its parameters, so only the module default
    # stops wrapping (it is 3); the max_wraps=0 given to the EA reaches the initial population only.
    ge.default_parameters.max_wraps = 0
    grammar = alogos.Grammar(bnf_text=BNF)
    operators = FIRST_OPERATORS if args.first_operators else {}
    spec = mazegen.load(SPEC).with_evolution(
        selection="tournament", tournament=TOURNAMENT, crossover=CROSSOVER, mutation=MUTATION, **operators
    )
    with tempfile.TemporaryDirectory(prefix="mazegen-peers-") as temp:
        build_dir = Path(temp)
        mazegen.build(spec, build_dir)
        # Untimed small runs: load numba's compiled kernels and warm both libraries' code paths.
        run_alogos(grammar, 50, 1, args.seed)
        run_mazegen(build_dir, 50, 1, args.seed)
        rows = [
            compare(grammar, build_dir, population, args.generations, args.repeats, args.seed)
            for population in args.populations
        ]
    print(markdown_table(rows, COLUMNS))
    print("\nindividuals/s = population × (generations + 1) / median wall seconds of a whole run")
    for row in rows:
        verdict = "PASS" if row["ratio"] >= TARGET_RATIO else "FAIL"
        print(f"{verdict}  population {row['population']:,}: {row['ratio']:.0f}× (target ≥ {TARGET_RATIO}×)")
    write_csv(args.csv, rows)


if __name__ == "__main__":
    main()
