"""Throughput of each numba kernel at population 50,000, and how a generation's time scales.

Usage:
    python benchmarks/kernels.py                      # everything, about a minute
    python benchmarks/kernels.py --quick              # populations up to 20,000
    python benchmarks/kernels.py --repeats 9 --no-plot

Part 1 times every population-wide kernel (median of ``--repeats`` calls after three warm-up calls),
with all numba threads and with one, on a random and on an evolved population (15 generations) of
``examples/table1/exp8.maze`` (flat grammar, size-limit fitness), of exp8 with an overlap penalty
added, and of ``examples/factory.maze`` (nested grammar, overlap and outside penalties), and checks
the engine's targets. Part 2 times one generation (``evaluate_cached`` with a fresh cache and
workspace, then ``breed``) of exp8 against population (genome 32) and against genome length
(population 20,000), and fits a line through each curve.

Writes ``benchmarks/kernels.csv``, ``benchmarks/scaling.csv`` and ``benchmarks/kernels.png``.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np
from common import BENCHMARKS, ROOT, markdown_table, median_seconds, peak_rss_mb, write_csv

import mazegen
from mazegen.generator.build import build
from mazegen.runtime import metrics
from mazegen.runtime.engine import _breeding as breeding
from mazegen.runtime.engine import _evolution as evolution
from mazegen.runtime.engine._cache import EvaluationCache, genome_hashes
from mazegen.runtime.engine._mapping import PopulationMap
from mazegen.runtime.engine._operators import random_codons, random_genes
from mazegen.runtime.engine._placement import placement_params
from mazegen.runtime.engine._population import Population
from mazegen.runtime.engine._problem import Problem, Workspace
from mazegen.runtime.threads import thread_count, threads
from mazegen.spec import FitnessTerm

EXP8 = ROOT / "examples" / "table1" / "exp8.maze"
# Spec name -> (file, fitness terms added). exp8's fitness has no overlap term, so its evolved
# scenarios pile up overlapping bars; the variant evolves under factory's overlap penalty.
SPECS: dict[str, tuple[Path, tuple[FitnessTerm, ...]]] = {
    "exp8": (EXP8, ()),
    "exp8 + overlap": (EXP8, (FitnessTerm("overlap", 0.5),)),
    "factory": (ROOT / "examples" / "factory.maze", ()),
}
SCALING_SPEC = "exp8"
POPULATION = 50_000
QUICK_LIMIT = 20_000
EVOLVED_GENERATIONS = 15
SIZE_LIMIT = 500.0
SCALING_POPULATIONS = (1_000, 2_000, 5_000, 10_000, 20_000, 50_000, 100_000)
SCALING_GENOMES = (32, 64, 128, 256)
GENOME_POPULATION = 20_000
# Untimed calls before each median. One is not enough for kernels that allocate tens of MB: on this
# VM the first few 64 MB allocations of a process can take ~10x longer (apparently the kernel
# finding fresh huge pages), which once made a median of five calls 8x too slow.
WARMUP = 3


@dataclass(frozen=True)
class Sample:
    """A population of genomes with what the kernels read: its mapping, decoding and fitness."""

    codons: np.ndarray
    genes: np.ndarray
    mapped: PopulationMap
    population: Population
    fitness: np.ndarray

    @classmethod
    def of(cls, problem: Problem, codons: np.ndarray, genes: np.ndarray) -> Sample:
        """Decode and evaluate ``codons`` and ``genes`` (fresh arrays, no workspace)."""
        evaluation = problem.evaluate(codons, genes)
        return cls(codons, genes, evaluation.mapped, evaluation.population, evaluation.fitness)

    @property
    def rows(self) -> int:
        """Number of individuals."""
        return int(self.codons.shape[0])


def load_problem(name: str, genome: int | None = None) -> Problem:
    """Build spec ``name`` of :data:`SPECS` in a temporary folder and load it.

    Args:
        name: A key of :data:`SPECS`.
        genome: Codons per genome and element slots, when not the spec's.
    """
    path, extra = SPECS[name]
    spec = mazegen.load(path)
    spec = dataclasses.replace(spec, fitness=spec.fitness + extra)
    if genome is not None:
        scenario = dataclasses.replace(spec.scenario, max_elements=genome)
        spec = dataclasses.replace(spec, scenario=scenario).with_evolution(genome=genome)
    with tempfile.TemporaryDirectory() as folder:
        build(spec, Path(folder))
        return Problem.from_build_dir(Path(folder))


def random_sample(problem: Problem, rows: int, rng: np.random.Generator) -> Sample:
    """Uniform random genomes."""
    settings = problem.spec.evolution
    codons = random_codons(rng, rows, settings.genome, settings.codon_max)
    return Sample.of(problem, codons, random_genes(rng, rows, problem.slots))


def evolved_sample(problem: Problem, rows: int, rng: np.random.Generator) -> Sample:
    """The last generation of a run of ``EVOLVED_GENERATIONS`` generations with the spec's operators."""
    settings = dataclasses.replace(problem.spec.evolution, population=rows, generations=EVOLVED_GENERATIONS)
    result = evolution.evolve(problem, settings, rng)
    return Sample.of(problem, result.codons, result.genes)


SAMPLES: dict[str, Callable[[Problem, int, np.random.Generator], Sample]] = {
    "random": random_sample,
    "evolved": evolved_sample,
}


def describe(sample: Sample) -> dict:
    """Mean elements, valid share, distinct genomes and best fitness of a population."""
    valid = sample.population.valid
    return {
        "mean_elements": float(sample.population.n_elements.mean()),
        "valid_pct": 100 * float(valid.mean()),
        "distinct_pct": 100 * np.unique(genome_hashes(sample.codons, sample.genes)).size / sample.rows,
        "best": float(sample.fitness[valid].max()),
    }


def mapping(problem: Problem, codons: np.ndarray, out: PopulationMap | None = None) -> PopulationMap:
    """The problem's mapping of ``codons``, into ``out`` when given."""
    return problem.map(codons, numbers=problem.reads_numbers, out=out)


def map_decode_overlap(problem: Problem, sample: Sample, workspace: Workspace) -> np.ndarray:
    """Map into the workspace, decode placements into it, count overlapping pairs."""
    return metrics.overlapping_pairs(problem.decode(sample.codons, sample.genes, workspace)[1])


def ga_step(selection: str, problem: Problem, sample: Sample) -> Callable[[], None]:
    """One ``breed`` of ``sample`` with the spec's operators and ``selection``, into kept arrays."""
    settings = dataclasses.replace(problem.spec.evolution, population=sample.rows, selection=selection)
    out = (np.empty_like(sample.codons), np.empty_like(sample.genes))
    return partial(
        breeding.breed,
        np.random.default_rng(2),
        sample.codons,
        sample.genes,
        sample.fitness,
        settings,
        out,
        problem.usage(sample.codons),  # the crossover within the used codons reads it
        problem.usage,
    )


# Kernel name -> a zero-argument call of it on a problem's sample.
KERNELS: dict[str, Callable[[Problem, Sample], Callable[[], object]]] = {
    "mapping, fresh arrays": lambda p, s: partial(mapping, p, s.codons),
    "mapping, reuse out=": lambda p, s: partial(mapping, p, s.codons, mapping(p, s.codons)),
    "placement decoding, fresh arrays": lambda p, s: partial(
        placement_params, s.mapped, s.genes, p.ranges, p.table, None
    ),
    "placement decoding, reuse out=": lambda p, s: partial(
        placement_params, s.mapped, s.genes, p.ranges, p.table, None, np.empty_like(s.population.params)
    ),
    "overlap": lambda p, s: partial(metrics.overlapping_pairs, s.population),
    "outside": lambda p, s: partial(metrics.elements_outside, s.population),
    "size limit": lambda p, s: partial(metrics.elements_over_size, s.population, SIZE_LIMIT),
    "genome hash": lambda p, s: partial(genome_hashes, s.codons, s.genes),
    "full evaluation": lambda p, s: partial(p.evaluate, s.codons, s.genes, Workspace()),
    "map + decode + overlap": lambda p, s: partial(map_decode_overlap, p, s, Workspace()),
    "GA step, truncation": partial(ga_step, "truncation"),
    "GA step, tournament": partial(ga_step, "tournament"),
}


def time_threads(action: Callable[[], object], repeats: int) -> tuple[float, float]:
    """Median seconds of ``action`` with all the kernels' threads, then with one."""
    parallel = median_seconds(action, repeats=repeats, warmup=WARMUP)
    with threads(1):
        return parallel, median_seconds(action, repeats=repeats, warmup=WARMUP)


def measure_kernels(population: int, repeats: int) -> tuple[list[dict], list[dict]]:
    """Describe each spec's random and evolved populations and time every kernel on them."""
    described, timed = [], []
    for spec_name in SPECS:
        problem = load_problem(spec_name)
        for kind, make in SAMPLES.items():
            sample = make(problem, population, np.random.default_rng(1))
            described.append({"spec": spec_name, "population": kind, "rows": sample.rows, **describe(sample)})
            for kernel, call in KERNELS.items():
                parallel, single = time_threads(call(problem, sample), repeats)
                timed.append(
                    {
                        "spec": spec_name,
                        "population": kind,
                        "kernel": kernel,
                        "rows": sample.rows,
                        "ms": 1e3 * parallel,
                        "per_s": sample.rows / parallel,
                        "ms_1t": 1e3 * single,
                        "per_s_1t": sample.rows / single,
                        "speedup": single / parallel,
                    }
                )
                print(f"  {spec_name:14} {kind:8} {kernel:30} {1e3 * parallel:8.2f} ms", flush=True)
    return described, timed


POPULATION_COLUMNS = [
    ("spec", "spec", "s"),
    ("population", "population", "s"),
    ("rows", "individuals", ","),
    ("mean_elements", "mean elements", ".2f"),
    ("valid_pct", "valid %", ".1f"),
    ("distinct_pct", "distinct genomes %", ".1f"),
    ("best", "best fitness", "g"),
]
KERNEL_VALUES = [
    ("ms", "ms", ".2f"),
    ("per_s", "M/s", ",.2f"),
    ("per_s_1t", "1 thread M/s", ",.2f"),
    ("speedup", "speed-up", ".2f"),
]


def kernel_table(timed: list[dict], spec: str) -> str:
    """One spec's kernels as rows, random and evolved populations side by side (rates in millions/s)."""
    wide: dict[str, dict] = {}
    for row in timed:
        if row["spec"] == spec:
            cells = wide.setdefault(row["kernel"], {"kernel": row["kernel"]})
            for key, _, _ in KERNEL_VALUES:
                scale = 1e-6 if key.startswith("per_s") else 1.0
                cells[f"{row['population']}_{key}"] = row[key] * scale
    columns = [("kernel", "kernel", "s")] + [
        (f"{kind}_{key}", f"{kind} {heading}", spec_format)
        for kind in SAMPLES
        for key, heading, spec_format in KERNEL_VALUES
    ]
    return markdown_table(list(wide.values()), columns)


@dataclass(frozen=True)
class Target:
    """A figure the engine should reach: ``per_s`` at least ``bound``, or ``ms`` at most ``bound``."""

    text: str
    key: str
    bound: float
    cases: tuple[tuple[str, str, str], ...]  # (spec, population, kernel)

    def lines(self, timed: list[dict]) -> list[str]:
        """One PASS or FAIL line per case."""
        found = {(row["spec"], row["population"], row["kernel"]): row for row in timed}
        lines = []
        for case in self.cases:
            value = found[case][self.key]
            passed = value >= self.bound if self.key == "per_s" else value <= self.bound
            shown = f"{value / 1e6:.2f} M/s" if self.key == "per_s" else f"{value:.2f} ms"
            lines.append(f"{'PASS' if passed else 'FAIL'}  {self.text}: {' / '.join(case)} = {shown}")
        return lines


TARGETS = (
    Target(
        "mapping >= 5 M genomes/s on a random population",
        "per_s",
        5e6,
        tuple((spec, "random", "mapping, fresh arrays") for spec in ("exp8", "factory")),
    ),
    Target(
        "map + decode + overlap >= 1 M evaluations/s on an evolved population",
        "per_s",
        1e6,
        tuple((spec, "evolved", "map + decode + overlap") for spec in ("factory", "exp8 + overlap")),
    ),
    Target(
        "one GA step <= 20 ms",
        "ms",
        20.0,
        tuple(
            (spec, "evolved", f"GA step, {selection}")
            for spec in SPECS
            for selection in ("truncation", "tournament")
        ),
    ),
)


def generation_seconds(problem: Problem, sample: Sample, repeats: int) -> float:
    """Median time of one generation: ``evaluate_cached`` with a fresh cache and workspace, then ``breed``."""
    settings = dataclasses.replace(problem.spec.evolution, population=sample.rows)
    rng = np.random.default_rng(3)
    out = (np.empty_like(sample.codons), np.empty_like(sample.genes))

    def generation() -> None:
        evaluated = evolution.evaluate_cached(
            problem, sample.codons, sample.genes, EvaluationCache(), Workspace()
        )
        breeding.breed(
            rng, sample.codons, sample.genes, evaluated.fitness, settings, out, evaluated.usage, problem.usage
        )

    return median_seconds(generation, repeats=repeats, warmup=WARMUP)


def scaling_point(axis: str, problem: Problem, sample: Sample, repeats: int) -> dict:
    """One point of a scaling curve: time per generation and per individual of ``sample``."""
    seconds = generation_seconds(problem, sample, repeats)
    point = {
        "axis": axis,
        "population": sample.rows,
        "genome": problem.spec.evolution.genome,
        "ms": 1e3 * seconds,
        "us_per_individual": 1e6 * seconds / sample.rows,
        **describe(sample),
    }
    print(
        f"  {axis:10} population {sample.rows:>7,} genome {point['genome']:>3}: {point['ms']:8.2f} ms",
        flush=True,
    )
    return point


def measure_scaling(limit: int | None, genome_rows: int, repeats: int) -> list[dict]:
    """Time per generation of exp8 against population and against genome length.

    The population curve uses nested subsets of one evolved population of the largest size, so
    every point has the same kind of individuals; the genome curve evolves a population per length.

    Args:
        limit: Largest population of the population curve (``None``: all of them).
        genome_rows: Population of the genome-length curve.
        repeats: Timed generations per point (median).
    """
    populations = [n for n in SCALING_POPULATIONS if limit is None or n <= limit]
    problem = load_problem(SCALING_SPEC)
    largest = evolved_sample(problem, populations[-1], np.random.default_rng(1))
    order = np.random.default_rng(4).permutation(largest.rows)
    points = [
        scaling_point(
            "population", problem, Sample.of(problem, largest.codons[rows], largest.genes[rows]), repeats
        )
        for rows in (np.sort(order[:n]) for n in populations)
    ]
    for genome in SCALING_GENOMES:
        problem = load_problem(SCALING_SPEC, genome)
        points.append(
            scaling_point(
                "genome", problem, evolved_sample(problem, genome_rows, np.random.default_rng(1)), repeats
            )
        )
    return points


def fit_line(sizes: np.ndarray, seconds: np.ndarray) -> dict:
    """Least-squares line through the points, its R², the log-log slope and the per-unit time ratio."""
    slope, intercept = np.polyfit(sizes, seconds, 1)
    residual = seconds - (slope * sizes + intercept)
    return {
        "slope": slope,
        "intercept": intercept,
        "r2": 1 - float(residual @ residual) / float(((seconds - seconds.mean()) ** 2).sum()),
        "exponent": float(np.polyfit(np.log(sizes), np.log(seconds), 1)[0]),
        "ratio": (seconds[-1] / sizes[-1]) / (seconds[0] / sizes[0]),
    }


SCALING_AXES = ("population", "genome")  # each curve varies the column of its name
SCALING_COLUMNS = [
    ("population", "population", ","),
    ("genome", "genome", "d"),
    ("ms", "ms / generation", ".2f"),
    ("us_per_individual", "µs / individual", ".3f"),
    ("mean_elements", "mean elements", ".2f"),
    ("distinct_pct", "distinct genomes %", ".1f"),
]


def curves(points: list[dict]) -> dict[str, tuple[np.ndarray, np.ndarray, dict]]:
    """Sizes, seconds and line fit of each scaling curve."""
    fitted = {}
    for axis in SCALING_AXES:
        chosen = [p for p in points if p["axis"] == axis]
        sizes = np.array([p[axis] for p in chosen], dtype=np.float64)
        seconds = np.array([p["ms"] / 1e3 for p in chosen])
        fitted[axis] = (sizes, seconds, fit_line(sizes, seconds))
    return fitted


def plot(fitted: dict[str, tuple[np.ndarray, np.ndarray, dict]], rows: int, path: Path) -> None:
    """Two log-log panels of time per generation, with the least-squares line and a ∝ size line.

    The y range is the measured one: a least-squares line with a negative intercept would
    otherwise plunge towards zero at the left edge.

    Args:
        fitted: From :func:`curves`.
        rows: Population of the genome-length curve.
        path: The PNG to write.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import LogFormatter, NullFormatter

    figure, panels = plt.subplots(1, 2, figsize=(11, 4.5))
    for panel, (axis, (sizes, seconds, fit)) in zip(panels, fitted.items()):
        ms = seconds * 1e3
        grid = np.geomspace(sizes[0], sizes[-1], 100)
        panel.loglog(sizes, ms, "o-", label="measured")
        panel.loglog(
            grid,
            (fit["slope"] * grid + fit["intercept"]) * 1e3,
            "--",
            label=f"least squares, R² {fit['r2']:.3f}",
        )
        panel.loglog(grid, ms[-1] * grid / sizes[-1], ":", color="grey", label="∝ size (through last)")
        panel.set_ylim(ms.min() / 1.5, ms.max() * 1.5)
        panel.set_xticks(sizes, [f"{size:,.0f}" for size in sizes])
        panel.xaxis.set_minor_formatter(NullFormatter())
        panel.yaxis.set_major_formatter(LogFormatter())  # plain numbers, minor ones on short ranges
        panel.yaxis.set_minor_formatter(LogFormatter(labelOnlyBase=False))
        panel.set_xlabel(
            "population (genome 32)" if axis == "population" else f"genome length (population {rows:,})"
        )
        panel.set_ylabel("ms per generation")
        panel.set_title(f"exp8: time per generation vs {axis}")
        panel.legend()
        panel.grid(True, which="both", alpha=0.3)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


def main() -> None:
    """Measure, print the tables and targets, write the CSVs and the plot."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="timed calls per figure (median)")
    parser.add_argument("--quick", action="store_true", help=f"populations up to {QUICK_LIMIT:,}")
    parser.add_argument("--no-plot", action="store_true", help="skip benchmarks/kernels.png")
    args = parser.parse_args()
    limit = QUICK_LIMIT if args.quick else None
    population = min(POPULATION, limit or POPULATION)
    genome_population = min(GENOME_POPULATION, limit or GENOME_POPULATION)

    print(
        f"kernels at population {population:,}, {thread_count()} threads, "
        f"load average {os.getloadavg()[0]:.2f}"
    )
    described, timed = measure_kernels(population, args.repeats)
    print("\nscaling")
    points = measure_scaling(limit, genome_population, args.repeats)

    print(f"\n### Populations ({population:,} individuals, evolved: {EVOLVED_GENERATIONS} generations)\n")
    print(markdown_table(described, POPULATION_COLUMNS))
    for spec in SPECS:
        print(f"\n### Kernels, {spec} (rates in millions of individuals per second)\n")
        print(kernel_table(timed, spec))
    print("\n### Targets\n")
    for target in TARGETS:
        print("\n".join(target.lines(timed)))
    fitted = curves(points)
    for axis in SCALING_AXES:
        sizes, _, fit = fitted[axis]
        print(f"\n### Time per generation vs {axis}, {SCALING_SPEC}\n")
        print(markdown_table([p for p in points if p["axis"] == axis], SCALING_COLUMNS))
        print(
            f"\nleast squares: {fit['intercept'] * 1e3:.2f} ms + {fit['slope'] * 1e6:.3f} µs × {axis}, "
            f"R² = {fit['r2']:.4f}; log-log slope {fit['exponent']:.2f}; "
            f"(time / {axis}) at {sizes[-1]:,.0f} ÷ at {sizes[0]:,.0f} = {fit['ratio']:.2f}"
        )

    write_csv(BENCHMARKS / "kernels.csv", timed)
    write_csv(BENCHMARKS / "scaling.csv", points)
    if not args.no_plot:
        plot(fitted, genome_population, BENCHMARKS / "kernels.png")
    print(f"\npeak RSS {peak_rss_mb():.0f} MB, load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
