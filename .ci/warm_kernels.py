"""Compile, on the core a test run leaves idle, the kernels its tests reach after the first minutes:
the homotopy classes, every bundled controller's drive and the learning environment. numba caches
what it compiles (the cache is keyed on the runtime's sources), so a test that reaches a kernel this
compiled first loads it instead of compiling it. ``.ci/run`` starts it beside the tests and ends it by
its id; it writes nothing but the kernel cache."""

from __future__ import annotations

import math

import numpy as np

import mazegen
from mazegen.controllers import BUNDLED
from mazegen.gym import FloorVectorEnv, population_levels
from mazegen.runtime.engine import Population
from mazegen.runtime.geometry import ElementTable, grid_of
from mazegen.runtime.navigation import class_counts, floor_topology
from mazegen.runtime.simulation import drive

FLOORS = (
    [("vwall", 350, 300, 100, 100, 0), ("vwall", 650, 300, 100, 100, 0)],
    [("cobot", 500, 250, 60, 60, 30), ("hwall", 300, 450, 200, 20, 0), ("router", 700, 150, 40, 40, 0)],
)
"""Two floors of the factory example's elements: two obstacles in a row; three of three kinds."""


def floors(spec: mazegen.Spec) -> Population:
    types = spec.scenario_elements
    names = [kind.name for kind in types]
    ids = np.full((len(FLOORS), 3), -1, np.int32)
    params = np.zeros((len(FLOORS), 3, 5))
    for i, elements in enumerate(FLOORS):
        for k, (name, x, y, width, depth, degrees) in enumerate(elements):
            ids[i, k] = names.index(name)
            params[i, k] = (x, y, width, depth, math.radians(degrees))
    count = np.array([len(elements) for elements in FLOORS], np.int32)
    return Population(
        ids, count, lambda: params, np.ones(len(FLOORS), bool), ElementTable.from_types(types), spec.arena
    )


def main() -> None:
    spec = mazegen.load("examples/factory.maze")
    population = floors(spec)
    grid = grid_of(population.arena)
    floor_topology(population, grid, 0)
    class_counts(population, grid)
    robot = spec.robot_or_default
    for name in sorted(BUNDLED, key=lambda name: name != "movebase"):  # the largest first
        drive(population, robot=robot, controller=name)
    levels = population_levels(population, robot, np.arange(2), np.zeros(2, np.int64), "factory")
    for beams in (0, 64):
        env = FloorVectorEnv(2, levels=levels, beams=beams, waypoint=1.0)
        env.reset(seed=0)
        env.step(env.expert_actions("straight"))


if __name__ == "__main__":
    main()
