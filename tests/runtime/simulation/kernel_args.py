"""What a controller kernel reads, for ARENA's default robot: its parameters and the limits; and
a controller's drives on one thread and on all."""

from __future__ import annotations

import numpy as np

from mazegen.runtime.engine._population import Population
from mazegen.runtime.simulation import Episodes, drive
from mazegen.runtime.simulation._choice import bundled_params
from mazegen.runtime.simulation._state import robot_limits
from mazegen.runtime.threads import CORES, threads
from mazegen.spec import robot_for
from tests.runtime.floors import ARENA

ROBOT = robot_for(ARENA)
LIMITS = robot_limits(ROBOT, ARENA)
"""The ``limits`` array of the kernels."""


def params_of(name: str) -> np.ndarray:
    """Bundled controller ``name``'s default parameters, lengths in ARENA's unit."""
    return bundled_params(name, (), ARENA)


def on_one_thread_and_on_all(pop: Population, controller: str) -> tuple[Episodes, Episodes]:
    """``controller``'s recorded drives over ``pop`` on one thread and on every thread."""
    with threads(1):
        one = drive(pop, robot=ROBOT, controller=controller, record=True)
    with threads(CORES):
        return one, drive(pop, robot=ROBOT, controller=controller, record=True)
