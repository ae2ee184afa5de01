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


def floor_code(population, index: int) -> int:
    """A number made of the floor in row ``index`` (its elements' placements), so that the same floor
    fares the same in any population, at any row."""
    placed = population.params[index, : population.n_elements[index]]
    return int(abs(placed.sum()) * 7) % 1000


def outcome_of(population, index: int) -> int:
    """A made-up outcome of a floor (the same for every controller but ``straight``, which fails
    where the others arrive)."""
    return (ARRIVED, COLLISION, ARRIVED, TIMEOUT)[floor_code(population, index) % 4]


def has_path(population, index: int) -> bool:
    """Whether the fake finds a path on a floor: not on every fifth."""
    return floor_code(population, index) % 5 != 4


@dataclass
class FakeDrive:
    """Records each call: the controller's name and the rows driven; episodes follow :func:`outcome_of`."""

    calls: list[tuple[str, np.ndarray]] = field(default_factory=list)

    def __call__(self, population, *, robot, controller, indices=None, **options) -> Episodes:
        name = controller.name
        rows = np.flatnonzero(population.valid) if indices is None else np.asarray(indices, dtype=np.int64)
        self.calls.append((name, rows.copy()))
        outcome = np.array([outcome_of(population, int(i)) for i in rows], dtype=np.int8)
        if name == "straight":
            outcome = np.where(outcome == ARRIVED, COLLISION, ARRIVED).astype(np.int8)
        n = rows.size
        optimal = np.array([10.0 if has_path(population, int(i)) else np.nan for i in rows])
        return Episodes(
            controller=name,
            outcome=outcome,
            time=np.full(n, 25.0),
            distance=np.full(n, 12.5),
            clearance=np.array([float(floor_code(population, int(i))) for i in rows]),
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
    from mazegen.runtime.engine._problem import Problem

    (folder / "spec.maze").write_text(text, encoding="utf-8")
    build(load_spec(folder / "spec.maze"), folder / "build")
    return Problem.from_build_dir(folder / "build")
