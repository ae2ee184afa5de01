"""What a finished experiment prints, and the command line of a generated ``experiment.py``."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from mazegen.errors import MazeError
from mazegen.runtime.documents import RunDirectory
from mazegen.runtime.runs._experiment import Experiment, default_run_dir
from mazegen.runtime.runs._launcher import ExperimentResult, Job, RunsInterrupted, run_jobs
from mazegen.runtime.runs._progress import reporter_for
from mazegen.runtime.runs._rejections import why_no_scenario
from mazegen.text import printable


def summary_lines(outcome: ExperimentResult) -> list[str]:
    """One line per run: best fitness and its phenotype, or why it found no valid scenario."""
    lines = []
    for number, documents in enumerate(outcome.best, start=1):
        if documents:
            top = documents[0]
            lines.append(
                f"run {number}: best fitness {top['fitness']:g}, {len(top['elements'])} elements: "
                f"{printable(top['phenotype'])}"  # the grammar's text: control characters too
            )
            continue
        why = [] if outcome.run_dir is None else why_no_scenario(outcome.run_dir, number)
        lines.append(f"run {number}: no valid scenario" + (f"; {why[0]}" if why else ""))
        lines += why[1:]
    return lines


NO_SCENARIO = "no run produced a valid scenario (see why above)"
"""The error of an experiment that ends without a scenario (its run directory is whole)."""


def closing_lines(outcome: ExperimentResult, run_dir: Path) -> list[str]:
    """Where the results went: the run directory, its pictures, and the command of its report page."""
    shown = printable(str(run_dir))
    lines = [f"wrote {shown}"]
    if any(outcome.best):
        pictures = printable(str(RunDirectory(run_dir).pictures))
        lines += [
            f"pictures: {pictures} (as PNG: mazegen export {shown} --format png)",
            f"one page of settings, pictures and plots: mazegen report {shown}",
        ]
    return lines


def main(build_dir: Path, argv: list[str] | None = None) -> int:
    """Command line of a generated ``experiment.py``: runs on the local cores, like ``mazegen run``."""
    parser = argparse.ArgumentParser(description=f"Run the MazeGen experiment in {build_dir}.")
    parser.add_argument("--seed", type=int)
    parser.add_argument("--runs", type=int)
    parser.add_argument("--population", type=int)
    parser.add_argument("--generations", type=int)
    parser.add_argument("-o", "--out", type=Path, help="run directory (default runs/<name>-seed<seed>)")
    parser.add_argument("--force", action="store_true", help="replace an existing run directory")
    parser.add_argument("--workers", type=int, help="worker processes (default: the cores)")
    parser.add_argument("--checkpoint-every", type=int, help="generations between checkpoints (0: none)")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    reporter = reporter_for(quiet=args.quiet)
    try:
        experiment = Experiment.from_build_dir(build_dir).with_settings(
            seed=args.seed, runs=args.runs, population=args.population, generations=args.generations
        )
        out = args.out or default_run_dir(experiment.problem.spec)
        [outcome] = run_jobs(
            [Job(experiment, out, force=args.force)],
            executor="local",
            workers=args.workers,
            checkpoint_every=args.checkpoint_every,
            reporter=reporter,
        )
    except MazeError as error:
        print(error.render(command_line=True), file=sys.stderr)
        return 1
    except RunsInterrupted:
        print(f"interrupted; continue with: mazegen resume {printable(str(out))}", file=sys.stderr)
        return 130
    finally:
        reporter.close()
    for line in [*summary_lines(outcome), *closing_lines(outcome, out)]:
        print(line)
    if not any(outcome.best):
        print(NO_SCENARIO, file=sys.stderr)
        return 1
    return 0
