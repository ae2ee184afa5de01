"""Drive a controller over floors of a population: one robot per floor, one :class:`Episodes`.

:func:`drive` sets the drive up (:func:`mazegen.runtime.simulation._setup.set_up`: every robot at
its start), runs the episodes to their ends (the compiled loop of a bundled controller, a step
between calls of a user's policy otherwise) and returns what came of them.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from mazegen.controllers import FIELDS
from mazegen.runtime.engine.population import Population
from mazegen.runtime.simulation._episodes import Episodes
from mazegen.runtime.simulation._fields import floor_fields
from mazegen.runtime.simulation._loop import run_bundled
from mazegen.runtime.simulation._policy import run_policy
from mazegen.runtime.simulation._setup import set_up
from mazegen.runtime.simulation._state import DriveState
from mazegen.spec import ControllerSpec, Robot


def drive(
    population: Population,
    *,
    robot: Robot,
    controller: str | ControllerSpec | Callable[[Any], Any],
    indices: np.ndarray | None = None,
    starts: np.ndarray | None = None,
    record: bool = False,
) -> Episodes:
    """Drive ``controller`` over the floors ``indices`` of ``population`` (default: every valid one).

    Args:
        population: The floors.
        robot: The robot's limits, lidar and timeouts (:func:`mazegen.spec.robot_for`).
        controller: A bundled controller's name, a spec's :class:`ControllerSpec`, a dotted path
            ``package.module:name`` or entry point name of a user's policy, or the policy itself.
        indices: Which individuals to drive, in this order.
        starts: ``float64[M, 3]`` start pose ``(x, y, theta)`` per driven floor; default the arena's
            start, heading toward the goal.
        record: Keep every pose (:attr:`Episodes.trajectory`).

    Nothing is drawn at random: the same floors, robot, controller and starts give the same
    episodes (perturbed starts are the caller's, drawn from its own seeded generator).

    Raises:
        MazeError: an unknown controller or parameter, or a user's policy that fails.
    """
    state = set_up(
        population, robot=robot, controller=controller, indices=indices, starts=starts, record=record
    )
    if len(state.rows):  # (no floors: nothing to compile)
        _run_to_the_end(state)
    return state.episodes()


def _run_to_the_end(state: DriveState) -> None:
    """Run every episode of ``state`` to its end, with the loop its controller needs."""
    choice = state.choice
    if choice.policy is not None:
        run_policy(state, choice.policy)
    elif FIELDS in choice.reads:
        _run_with_fields(state)
    else:
        run_bundled(state, _NO_FIELDS)


_NO_FIELDS = (np.full((1, 1, 1), np.inf, np.float32), np.zeros((1, 1, 1), np.float32), np.zeros(5))
"""The fields of controllers that read none: one 1×1 dummy shared by every floor."""


FIELD_CHUNK = 1024
"""Floors whose fields are built and driven at a time: the fields of a 128 × 128 grid take 128 kB
a floor, so a drive over many floors holds a chunk's, not all of them."""


def _run_with_fields(state: DriveState) -> None:
    """Drive chunk after chunk of floors, each with the fields of its floors."""
    for a in range(0, len(state.rows), FIELD_CHUNK):
        part = state.part(a, min(a + FIELD_CHUNK, len(state.rows)))
        run_bundled(part, floor_fields(state.population, state.robot, part.rows))
