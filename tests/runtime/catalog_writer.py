"""A process that fills a catalog, for the concurrent-writers test; it imports neither NumPy nor numba,
so several start in a moment."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from mazegen.runtime.catalog._catalog import Catalog


def write_experiments(path: str, writer: int, count: int) -> None:
    """Record ``count`` experiments of two runs, three scenarios each, in a few transactions apiece."""
    catalog = Catalog.open(Path(path), create=True)
    counts = {"evaluations": 10, "mean": 1.0, "median": 1.0, "invalid": 0, "unique": 10, "cache_hits": 0}
    stats = tuple(SimpleNamespace(generation=g, best=float(g), seconds=0.01, **counts) for g in range(5))
    result = SimpleNamespace(stats=stats)  # what the catalog reads of a RunResult
    metrics = {"solvable": True, "difficulty": float(writer)}
    document = {
        "fitness": 4.0,
        "elements": [{}] * 4,
        "valid": True,
        "phenotype": "a",
        "terms": {},
        "metrics": metrics,
    }
    for number in range(count):
        run_dir = Path(path).parent / f"w{writer}-{number}"
        settings = {"seed": number, "runs": 2, "population": 10, "generations": 4}
        record = {"scenario": f"w{writer}", "source": "-", "evolution": settings}
        experiment = catalog.start_experiment(
            run_dir=run_dir, record=record, sweep=None, executor="x", resumed=False
        )
        for run in (1, 2):
            catalog.record_run(experiment, run, result, (document,) * 3, run_dir / f"run-0{run}")  # type: ignore[arg-type]
        catalog.finish_experiment(experiment, status="finished")
    catalog.close()
