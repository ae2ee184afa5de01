"""Fuzz the ``.maze`` language: every mutant is checked, and built (and run) when accepted.

    python -m tests.dsl.fuzz --mutants 5000 --seed 1 [--evolve] [--save DIR]

A mutant may be refused only with a one-line :class:`MazeError`; anything else (another
exception, a message over several lines, a mutant that takes longer than the time limit) is a
failure. Mutants run in worker processes this module starts and ends; a worker that overruns the
limit is killed (the mutant counts as a hang) and replaced. The tests run it small
(tests/dsl/test_fuzz.py); the issue's large run is the command above.
"""

from __future__ import annotations

import argparse
import multiprocessing
import shutil
import sys
import tempfile
import time
import traceback
from collections import Counter
from dataclasses import dataclass, field
from multiprocessing.connection import Connection, wait
from pathlib import Path
from typing import Any

from tests.dsl.mutants import ROOT, SOURCES, Mutant, mutant

ACCEPTED, REJECTED, LATE = "accepted", "rejected", "refused after check"
TRACEBACK, MULTILINE, HANG = "traceback", "message over several lines", "hang"
FAILURES = (TRACEBACK, MULTILINE, HANG)


@dataclass
class Summary:
    """What a fuzzing session found: outcomes counted, and every failure with its mutant."""

    mutants: int = 0
    outcomes: Counter = field(default_factory=Counter)
    failures: list[tuple[Mutant, str, str]] = field(default_factory=list)
    seconds: float = 0.0

    def lines(self) -> list[str]:
        counts = ", ".join(f"{kind} {self.outcomes[kind]}" for kind in (ACCEPTED, REJECTED, LATE, *FAILURES))
        return [f"{self.mutants} mutants in {self.seconds:.0f} s: {counts}"] + [
            f"  mutant {m.index} of {m.source.name} ({', '.join(m.mutations)}): {kind}: {detail[-300:]!r}"
            for m, kind, detail in self.failures
        ]


def _examine(path: Path, build_dir: Path, evolve: bool) -> tuple[str, str]:
    """Check the mutant at ``path``; build an accepted spec, and run it when ``evolve``."""
    from mazegen import api
    from mazegen.dsl.loader import check_file, load_spec, parse_file
    from mazegen.errors import MazeError
    from mazegen.generator.build import build

    try:
        check_file(path)
    except MazeError as error:
        return (MULTILINE, str(error)) if "\n" in str(error) else (REJECTED, str(error))
    if not any(type(d).__name__ == "ScenarioDecl" for d in parse_file(path).model.declarations):
        return ACCEPTED, "a library"
    try:
        spec = load_spec(path)
        build(spec, build_dir)
        compile((build_dir / "fitness.py").read_text(encoding="utf-8"), "fitness.py", "exec")
        if evolve:
            api.run(build_dir, population=10, generations=1, runs=1, executor="serial", catalog=False)
    except MazeError as error:
        return (MULTILINE, str(error)) if "\n" in str(error) else (LATE, str(error))
    return ACCEPTED, spec.name


def _work(conn: Connection, folder: str, evolve: bool) -> None:
    """A worker: copies of the bundled folders, each mutant written over its file, then restored."""
    root = Path(folder)
    copies = {}
    for source in SOURCES:
        copy = root / source.parent.relative_to(ROOT)
        if not copy.exists():
            shutil.copytree(source.parent, copy, ignore=shutil.ignore_patterns("*.png", "*.json"))
        copies[source] = copy / source.name
    if evolve:  # compile (or load) the kernels before the clock starts
        _examine(copies[SOURCES[0]], root / "build", evolve)
    conn.send("ready")
    while (task := conn.recv()) is not None:
        index, source, text = task
        path = copies[source]
        path.write_text(text, encoding="utf-8")
        try:
            outcome = _examine(path, root / "build", evolve)
        except Exception:  # what the fuzzer looks for
            outcome = (TRACEBACK, traceback.format_exc())
        finally:
            path.write_text(source.read_text(encoding="utf-8"), encoding="utf-8")
            shutil.rmtree(root / "build", ignore_errors=True)
        conn.send((index, *outcome))


class _Worker:
    def __init__(self, context: Any, folder: Path, evolve: bool) -> None:
        folder.mkdir(parents=True)
        self.conn, child = context.Pipe()
        self.process = context.Process(target=_work, args=(child, str(folder), evolve), daemon=True)
        self.process.start()
        child.close()
        if not self.conn.poll(900) or self.conn.recv() != "ready":
            self.stop()
            raise RuntimeError("a fuzzing worker did not start")
        self.task: Mutant | None = None
        self.since = 0.0

    def give(self, task: Mutant) -> None:
        self.task, self.since = task, time.monotonic()
        self.conn.send((task.index, task.source, task.text))

    def stop(self) -> None:
        if self.process.is_alive():
            self.process.kill()
        self.process.join()
        self.conn.close()


def fuzz(
    *, mutants: int, seed: int, evolve: bool = False, workers: int = 2, timeout: float = 15.0
) -> Summary:
    """Make ``mutants`` mutants of ``seed`` and examine them in ``workers`` processes.

    Args:
        mutants: How many.
        seed: Which mutants (mutant i of seed s is always the same text).
        evolve: Also run a tiny evolution (population 10, one generation, serial) of each
            accepted spec.
        workers: Worker processes.
        timeout: Seconds a mutant may take before it counts as a hang.
    """
    summary = Summary(mutants=mutants)
    started = time.monotonic()
    context = multiprocessing.get_context("spawn")  # no threads or numba state inherited
    queue = [mutant(seed, index) for index in range(mutants)]
    queue.reverse()
    with tempfile.TemporaryDirectory(prefix="mazegen-fuzz-") as temp:
        pool: list[_Worker] = []
        made = 0

        def new_worker() -> _Worker:
            nonlocal made
            made += 1
            return _Worker(context, Path(temp) / f"worker-{made}", evolve)

        try:
            pool = [new_worker() for _ in range(max(1, min(workers, mutants)))]
            for worker in pool:
                if queue:
                    worker.give(queue.pop())
            while any(worker.task is not None for worker in pool):
                busy = [worker for worker in pool if worker.task is not None]
                deadline = min(worker.since for worker in busy) + timeout
                ready = wait([worker.conn for worker in busy], timeout=max(0.0, deadline - time.monotonic()))
                for i, worker in enumerate(pool):
                    task = worker.task
                    if task is None:
                        continue
                    if worker.conn in ready:
                        _, kind, detail = worker.conn.recv()
                    elif time.monotonic() - worker.since > timeout:
                        worker.stop()
                        worker = pool[i] = new_worker()
                        kind, detail = HANG, f"more than {timeout:g} s"
                    else:
                        continue
                    summary.outcomes[kind] += 1
                    if kind in FAILURES:
                        summary.failures.append((task, kind, detail))
                    worker.task = None
                    if queue:
                        worker.give(queue.pop())
            for worker in pool:
                worker.conn.send(None)
        finally:
            for worker in pool:
                worker.process.join(timeout=30)
                worker.stop()
    summary.failures.sort(key=lambda failure: failure[0].index)
    summary.seconds = time.monotonic() - started
    return summary


def _save(summary: Summary, folder: Path) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    for m, kind, detail in summary.failures:
        stem = f"mutant-{m.index}-{m.source.stem}"
        (folder / f"{stem}.maze").write_text(m.text, encoding="utf-8")
        (folder / f"{stem}.txt").write_text(f"{kind}\n{', '.join(m.mutations)}\n{detail}\n", encoding="utf-8")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mutants", type=int, default=5000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--timeout", type=float, default=15.0, help="seconds before a mutant is a hang")
    parser.add_argument("--evolve", action="store_true", help="also run each accepted spec briefly")
    parser.add_argument("--save", type=Path, help="write each failing mutant and its failure here")
    args = parser.parse_args(argv)
    summary = fuzz(
        mutants=args.mutants, seed=args.seed, evolve=args.evolve, workers=args.workers, timeout=args.timeout
    )
    print("\n".join(summary.lines()))
    if args.save is not None:
        _save(summary, args.save)
    return 1 if summary.failures else 0


if __name__ == "__main__":
    sys.exit(main())
