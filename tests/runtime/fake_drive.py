"""A stand-in for the simulator's ``drive`` that tests of the commands set in its place: episodes
known in advance, and a record of every call."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import click
import numpy as np

from mazegen.runtime.simulation import ARRIVED, COLLISION, Episodes

STEPS = 4
"""Poses of a fake episode: start, three between, the goal (or where it collided)."""


@dataclass
class FakeDrive:
    """``drive(...)``: every robot goes straight from start toward goal; ``straight`` collides at the
    end of its last step, any other controller arrives at 2.5 times the optimal time.

    Attributes:
        calls: ``(controller name, indices, robot)`` of every call.
    """

    calls: list[tuple[str, list[int], Any]] = field(default_factory=list)

    def __call__(self, population, *, robot, controller, indices=None, starts=None, record=False, seed=0):
        name = getattr(controller, "name", controller)
        click.echo(f"driving {name}", err=True)  # so a test sees what was said before driving
        self.calls.append((name, list(indices), robot))
        m = len(indices)
        (sx, sy), (gx, gy) = population.arena.start, population.arena.goal
        t = np.linspace(0.0, 1.0, STEPS + 1)
        trajectory = np.full((m, STEPS + 3, 3), np.nan)
        trajectory[:, : STEPS + 1, 0] = sx + t * (gx - sx)
        trajectory[:, : STEPS + 1, 1] = sy + t * (gy - sy)
        trajectory[:, : STEPS + 1, 2] = np.arctan2(gy - sy, gx - sx)
        collided = name == "straight"
        collision = np.full((m, 2), np.nan)
        if collided:
            collision[:] = trajectory[:, STEPS, :2]
        length = float(np.hypot(gx - sx, gy - sy))
        optimal = np.full(m, length / robot.max_speed)
        return Episodes(
            controller=name,
            outcome=np.full(m, COLLISION if collided else ARRIVED, np.int8),
            time=optimal * 2.5,
            distance=np.full(m, length),
            clearance=np.full(m, 0.0 if collided else 12.34567),
            optimal_time=optimal,
            steps=np.full(m, STEPS, np.int32),
            collision=collision,
            stuck=np.zeros(m, bool),
            trajectory=trajectory if record else None,
        )

    def many(self, requests, *, record=False) -> list[Episodes]:
        """``drive_many(...)``: each request as :meth:`__call__` drives it, a call each."""
        return [
            self(r.population, robot=r.robot, controller=r.controller, indices=r.indices, record=record)
            for r in requests
        ]


def fake_drive(monkeypatch) -> FakeDrive:
    """Put a :class:`FakeDrive` in place of the simulator's ``drive`` and return it."""
    import mazegen.runtime.simulation as simulation

    fake = FakeDrive()
    monkeypatch.setattr(simulation, "drive", fake, raising=False)
    monkeypatch.setattr(simulation, "drive_many", fake.many, raising=False)
    return fake
