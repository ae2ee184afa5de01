"""A user's batch policy in the loop: one Python call per step for every robot still driving.

Between calls, compiled kernels run over the robots still driving: one gathers their
:class:`~mazegen.runtime.simulation._observe.Observations` (lidar, goal in the robot frame,
velocity), the other steps them by the returned actions through the same step as the bundled
controllers (:func:`mazegen.runtime.simulation._step.step`). A policy that raises (or exits),
returns the wrong shape, numbers that are not real, or a non-finite action ends the drive with one
line naming the controller, the step and the floor.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from mazegen.errors import MazeError
from mazegen.runtime.simulation._observe import Observations, observe
from mazegen.runtime.simulation._state import ACTIVE, DriveState
from mazegen.runtime.simulation._step import record, step


def run_policy(drive: DriveState, policy: Callable[[Observations], Any]) -> None:
    """Drive every robot of ``drive`` still driving to the end of its episode with ``policy``, its
    controller, one call per step."""
    name = drive.choice.name
    active = drive.active()
    record(drive, active)
    steps = 0
    while active.size:
        actions = _actions(name, policy, observe(drive, active, steps), steps)
        step(drive, active, actions)
        steps += 1
        active = active[drive.robots.outcome[active] == ACTIVE]


def _actions(
    name: str, policy: Callable[[Observations], Any], observations: Observations, step: int
) -> np.ndarray:
    n = observations.floor.size
    where = f"controller {name} at step {step}"
    try:
        returned = np.asarray(policy(observations))
    except (Exception, SystemExit) as error:  # the user's code: any failure is theirs, said in one line
        floors = observations.floor
        raise MazeError(
            f"{where} (floors {floors[0]}{'...' if n > 1 else ''}, {n} driving) raised "
            f"{type(error).__name__}: {error}"
        ) from error
    if returned.dtype.kind not in "biuf":  # complex, text, objects: no (v, w) without a guess
        raise MazeError(
            f"{where} on floor {observations.floor[0]}: returned actions of type {returned.dtype}, "
            "expected real numbers"
        )
    actions = returned.astype(np.float64)
    if actions.shape != (n, 2):
        raise MazeError(
            f"{where} on floor {observations.floor[0]}: returned actions of shape {actions.shape}, "
            f"expected ({n}, 2): one (v, w) per robot"
        )
    bad = np.flatnonzero(~np.isfinite(actions).all(axis=1))
    if bad.size:
        raise MazeError(
            f"{where} on floor {observations.floor[bad[0]]}: returned a non-finite action {actions[bad[0]]}"
        )
    return np.ascontiguousarray(actions)
