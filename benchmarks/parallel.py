"""Many runs at once: Table 1's experiment 7 (15 runs) on one and two local workers and on a Dask cluster.

Usage:
    python benchmarks/parallel.py [--runs 15] [--repeats 3] [--experiment 7] [--no-dask]

Every configuration runs the same experiment into a run directory, as ``mazegen run``
does (best scenarios, drawings, final populations, statistics, the catalog), and the
script checks that all of them wrote the same files. Workers run one numba thread
each. "warm" executors are started once and reused across repeats, as a sweep or an
existing Dask cluster is; "cold" ones are started inside the timing, as one
``mazegen run`` command starts its workers. Repeats go round all configurations
in turn, so that other jobs on the machine slow them alike. Prints a Markdown table, the speed-up of
two workers over one, the Dask overhead against local processes, and the load
average; writes ``benchmarks/parallel.csv``.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import statistics
import tempfile
import time
from collections.abc import Callable
from contextlib import ExitStack
from pathlib import Path

from common import BENCHMARKS, ROOT, markdown_table, write_csv

import mazegen
from mazegen.runtime.runs._executors import Executor, LocalExecutor, SerialExecutor
from mazegen.runtime.runs._experiment import Experiment
from mazegen.runtime.runs._launcher import Job, launch

DASK = "dask, 2 workers, warm"


def digest(directory: Path) -> str:
    """One hash of every file of a run directory but its timings."""
    hasher = hashlib.sha256()
    for path in sorted(directory.rglob("*")):
        if path.is_file() and path.name != "timing.csv":
            hasher.update(str(path.relative_to(directory)).encode() + path.read_bytes())
    return hasher.hexdigest()


def timed_launch(experiment: Experiment, out: Path, executor: Executor | Callable[[], Executor]) -> float:
    """Seconds to run every run of ``experiment`` and write ``out`` (as `mazegen run` does: the
    populations go to the files only), on ``executor`` or on a new one."""
    started = time.perf_counter()
    if isinstance(executor, Executor):
        launch([Job(experiment, out, force=True)], executor=executor, keep_populations=False)
    else:
        with executor() as made:
            launch([Job(experiment, out, force=True)], executor=made, keep_populations=False)
    return time.perf_counter() - started


def measure(
    configurations: dict[str, Executor | Callable[[], Executor]],
    experiment: Experiment,
    out: Path,
    repeats: int,
) -> list[dict]:
    """Median seconds of each configuration; repeats go round the configurations, so that a
    neighbour's load falls on all of them alike. Warm executors run once untimed first."""
    for executor in configurations.values():
        if isinstance(executor, Executor):
            timed_launch(experiment, out, executor)  # workers import the runtime and load the kernels
    times: dict[str, list[float]] = {name: [] for name in configurations}
    digests = {}
    for _ in range(repeats):
        for name, executor in configurations.items():
            times[name].append(timed_launch(experiment, out, executor))
            digests[name] = digest(out)
            print(f"{name}: {times[name][-1]:.2f} s", flush=True)
    runs = experiment.problem.spec.evolution.runs
    rows = []
    for name, spent in times.items():
        seconds = statistics.median(spent)
        rows.append(
            {"configuration": name, "seconds": seconds, "runs_per_s": runs / seconds, "files": digests[name]}
        )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--experiment", type=int, default=7)
    parser.add_argument("--runs", type=int, default=15)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--no-dask", action="store_true", help="skip the Dask LocalCluster")
    parser.add_argument("--csv", type=Path, default=BENCHMARKS / "parallel.csv")
    args = parser.parse_args()
    load_before = os.getloadavg()
    spec = mazegen.load(ROOT / "examples" / "table1" / f"exp{args.experiment}.maze")
    with tempfile.TemporaryDirectory(prefix="mazegen-parallel-") as temp:
        build = Path(temp) / "build"
        mazegen.build(spec, build)
        experiment = Experiment.from_build_dir(build).with_settings(runs=args.runs)
        mazegen.run(build, runs=1, population=50, generations=1)  # load the kernels in this process
        out = Path(temp) / "run"

        def local(workers: int) -> Callable[[], Executor]:
            return lambda: LocalExecutor(workers=workers, threads_per_worker=1)

        with ExitStack() as stack:
            configurations: dict[str, Executor | Callable[[], Executor]] = {
                "serial, this process, all threads": SerialExecutor(),
                "local, 1 worker, warm": stack.enter_context(local(1)()),
                "local, 2 workers, warm": stack.enter_context(local(2)()),
                "local, 1 worker, cold": local(1),
                "local, 2 workers, cold": local(2),
            }
            if not args.no_dask:
                configurations[DASK] = stack.enter_context(dask_executor(stack))
            rows = measure(configurations, experiment, out, args.repeats)
    load_after = os.getloadavg()
    identical = len({row.pop("files") for row in rows}) == 1
    print()
    columns = [
        ("configuration", "configuration", "s"),
        ("seconds", "median s", ".2f"),
        ("runs_per_s", "runs/s", ".2f"),
    ]
    print(markdown_table(rows, columns))
    by_name = {row["configuration"]: row["seconds"] for row in rows}
    warm = by_name["local, 1 worker, warm"] / by_name["local, 2 workers, warm"]
    cold = by_name["local, 1 worker, cold"] / by_name["local, 2 workers, cold"]
    print(f"\nspeed-up of 2 local workers over 1: {warm:.2f}x warm, {cold:.2f}x cold (target >= 1.7x)")
    if DASK in by_name:
        overhead = by_name[DASK] / by_name["local, 2 workers, warm"] - 1
        print(
            f"Dask LocalCluster against local processes (2 workers, warm): {overhead:+.1%} (target <= +10%)"
        )
    print(f"every configuration wrote the same files: {'yes' if identical else 'NO'}")
    before, after = (" ".join(f"{value:.2f}" for value in load) for load in (load_before, load_after))
    print(f"load average (1, 5, 15 min): before {before}, after {after}")
    write_csv(args.csv, rows)


def dask_executor(stack: ExitStack) -> Executor:
    """An executor on a new Dask LocalCluster of two one-thread worker processes on loopback."""
    from distributed import LocalCluster

    from mazegen.runtime.runs._dask_executor import DaskExecutor

    cluster = stack.enter_context(
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None
        )
    )
    return DaskExecutor(scheduler=cluster.scheduler_address)


if __name__ == "__main__":
    main()
