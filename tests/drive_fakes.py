"""A stand-in for the simulator's ``drive`` that records what it is asked to drive, so the language's
drive terms are tested whatever the simulator does (and before it exists)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mazegen.runtime.simulation import ARRIVED, COLLISION, TIMEOUT, Episodes

DRIVE_SPEC = """
element box { shape square size 20..60 }
arena floor { size 1000 x 800 cm start (50, 50) goal (950, 750) robot radius 20 }
scenario s on floor { elements box max elements 6 }
"""


def outcome_of(index: int) -> int:
    """A made-up outcome of the floor in row ``index`` of a population (the same for every
    controller but ``straight``, which fails where the others arrive)."""
    return (ARRIVED, COLLISION, ARRIVED, TIMEOUT)[index % 4]


@dataclass
class FakeDrive:
    """Records each call: the controller's name and the rows driven; episodes follow :func:`outcome_of`."""

    calls: list[tuple[str, np.ndarray]] = field(default_factory=list)

    def __call__(self, population, *, robot, controller, indices=None, **options) -> Episodes:
        name = controller.name
        rows = np.asarray(indices, dtype=np.int64)
        self.calls.append((name, rows.copy()))
        outcome = np.array([outcome_of(int(i)) for i in rows], dtype=np.int8)
        if name == "straight":
            outcome = np.where(outcome == ARRIVED, COLLISION, ARRIVED).astype(np.int8)
        n = rows.size
        optimal = np.where(rows % 5 == 4, np.nan, 10.0)  # every fifth floor has no path
        return Episodes(
            controller=name,
            outcome=outcome,
            time=np.full(n, 25.0),
            distance=np.full(n, 12.5),
            clearance=rows.astype(np.float64),
            optimal_time=optimal,
            steps=np.full(n, 250, dtype=np.int32),
            collision=np.full((n, 2), np.nan),
            stuck=np.zeros(n, dtype=bool),
        )

    def episodes(self, controller: str) -> int:
        """Episodes driven of ``controller`` so far."""
        return sum(rows.size for name, rows in self.calls if name == controller)


def build_problem(text: str, folder: Path):
    """The built problem of a spec ``text`` (written in ``folder``)."""
    from mazegen.dsl.loader import load_spec
    from mazegen.generator.build import build
    from mazegen.runtime.engine.problem import Problem

    (folder / "spec.maze").write_text(text, encoding="utf-8")
    build(load_spec(folder / "spec.maze"), folder / "build")
    return Problem.from_build_dir(folder / "build")
