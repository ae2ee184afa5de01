"""A first run or drive compiles its kernels on two cores at once, and waits about a third less.

numba compiles a kernel the first time it is called, one after another on one core:
about a minute for a run on this project's machine, most of it before the first
generation. When no kernel is cached yet, :func:`compile_kernels` splits that work in
two before the runs start: a helper process compiles the path kernels (solvability, then
the path search and difficulty metrics that every scenario file is measured with, and the
simulator's episode loops when the spec drives a robot), while
this process compiles the rest (mapping, placement, geometry, hashing, breeding) and
then evolves a tiny population, which compiles what the spec's fitness calls besides.
A first drive splits likewise (:func:`compile_drive_kernels`): the helper sets up a drive
(paths, parts, starts, fields or costmaps) while this process compiles the episode loop.
Both write to the kernel cache, from which the runs and drives load them, here or in their workers.

Compiling is a matter of types, not values, so the helper works on two empty floors.
Nothing here changes a result: it only fills the cache sooner.
"""

from __future__ import annotations

import contextlib
import dataclasses
import multiprocessing.connection
import signal
import sys
import threading
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from mazegen.fitness_terms import reads_survey
from mazegen.runtime import metrics
from mazegen.runtime.engine import (
    PLACEMENT_GENES,
    Population,
    Problem,
    Workspace,
    breed,
    evolve,
    genome_hashes,
    random_codons,
    random_genes,
)
from mazegen.runtime.geometry import ElementTable, grid_of, world_vertices
from mazegen.runtime.navigation import navigation_of, paths_of, reach, survey
from mazegen.runtime.runs._executors import die_with_launcher, process_context
from mazegen.spec import Spec

TINY = 8
"""Individuals of the population that compiles the kernels."""


def compile_kernels(problem: Problem) -> None:
    """Compile the kernels ``problem``'s runs call, in a helper process and in this one at once.

    Worth calling only when :func:`mazegen.runtime.kernels_cached` says nothing is cached,
    and only from a program whose main module a new process may import (the ``mazegen``
    command, or a script that guards its work with ``if __name__ == "__main__"``).

    Raises:
        MazeError: when the spec's fitness module fails, as the run would.
    """
    _beside(KernelHelper(compile_path_kernels, problem.spec), compile_evolution_kernels, problem)


def compile_drive_kernels(spec: Spec, controllers: Sequence[str]) -> None:
    """Compile what a first drive of bundled ``controllers`` over floors of ``spec`` calls: the episode
    loop of each here, the set-up of a drive (paths, parts, starts, fields or costmaps) in a helper
    process meanwhile. Worth calling, as :func:`compile_kernels` is, when the loops are not cached.

    Raises:
        MazeError: for an unknown controller, as the drive would.
    """
    _beside(KernelHelper(_compile_set_ups, spec, tuple(controllers)), _compile_loops, spec, controllers)


def _beside(helper: KernelHelper, work: Callable[..., None], *args: Any) -> None:
    """``work(*args)`` here while ``helper`` compiles; waits for the helper."""
    try:
        work(*args)
    except BaseException:
        helper.stop()  # the error (or Ctrl-C) is this process's to report
        raise
    finally:
        helper.join()


def _compile_loops(spec: Spec, controllers: Sequence[str]) -> None:
    from mazegen.runtime.simulation import compile_loop

    floors, robot = empty_floors(spec), spec.robot_or_default
    for name in controllers:
        compile_loop(floors, robot, name)


def _compile_set_ups(spec: Spec, controllers: tuple[str, ...]) -> None:
    from mazegen.runtime.simulation import compile_set_up

    # Which floors have a path, which a drive of scenario files asks first: on floors of their own, as
    # floors measured so reuse the measured lengths and would leave the path kernel a drive may call.
    navigation_of(empty_floors(spec))
    floors, robot = empty_floors(spec), spec.robot_or_default
    for name in controllers:
        compile_set_up(floors, robot, name)


class KernelHelper:
    """A helper process that compiles kernels by calling ``work(*args)`` (a module-level function).

    Stopped, it exits through Python, so that its locks are released (a killed process leaves
    the resource tracker to warn of a leaked semaphore, after the command's one-line error).
    It ends with this process too, should this one be killed outright.
    """

    def __init__(self, work: Callable[..., None], *args: Any) -> None:
        context = process_context()
        self._ready, ready = context.Pipe(duplex=False)
        self._process = context.Process(target=_compile_quietly, args=(work, args, ready), daemon=True)
        self._process.start()
        ready.close()  # the helper's copy is the one that tells

    def stop(self) -> None:
        """Stop compiling: once the helper's handler is in place (or the helper gone), a SIGTERM."""
        try:
            multiprocessing.connection.wait([self._ready, self._process.sentinel])
        finally:
            self._process.terminate()
            self.join()

    def join(self) -> None:
        """Wait for the helper to end."""
        self._process.join()
        self._ready.close()

    @property
    def exitcode(self) -> int | None:
        """0 when it compiled to the end, 1 when stopped, ``None`` while it runs."""
        return self._process.exitcode


def _compile_quietly(
    work: Callable[..., None], args: tuple, ready: multiprocessing.connection.Connection
) -> None:
    """``work(*args)`` in the helper, which leaves Ctrl-C to the command.

    It compiles on a thread of its own while this main thread waits, so a SIGTERM's handler
    always runs here, where its ``SystemExit`` ends the process: on the compiling thread it could
    run inside one of llvmlite's callbacks into Python, which swallow exceptions (compiling
    would go on, to exit code 0). Ready is said once the handler is in place."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, lambda number, frame: sys.exit(1))
    die_with_launcher()
    compiling = threading.Thread(target=_compile_or_not, args=(work, args), daemon=True)
    compiling.start()
    ready.send_bytes(b"stoppable")
    ready.close()
    compiling.join()


def _compile_or_not(work: Callable[..., None], args: tuple) -> None:
    with contextlib.suppress(Exception):  # best effort: whatever is not cached, the runs compile
        work(*args)


def compile_path_kernels(spec: Spec) -> None:
    """Compile solvability, then the path search and difficulty metrics (and the paths' corners), then
    the simulator when the spec drives a robot, on two empty floors of ``spec``."""
    floors = empty_floors(spec)
    if not reads_survey(spec):  # else the survey answers solvability too
        reach(floors, grid_of(spec.arena))  # first: the evolution in the other process needs it soonest
    survey(floors)
    paths_of(floors, grid_of(spec.arena))  # the corners every scenario file records
    drive_once(spec, floors)


def empty_floors(spec: Spec) -> Population:
    """Two floors of ``spec`` without elements: what the kernels are compiled on."""
    slots = spec.scenario.max_elements
    params = np.zeros((2, slots, PLACEMENT_GENES))
    return Population(
        element_ids=np.full((2, slots), -1, np.int32),
        n_elements=np.zeros(2, np.int32),
        placement=lambda: params,
        valid=np.ones(2, np.bool_),
        table=ElementTable.from_types(spec.scenario_elements),
        arena=spec.arena,
    )


def drive_once(spec: Spec, floors: Population) -> None:
    """Drive each controller the spec's drive terms name over ``floors``: the simulator's kernels,
    which its every generation calls. A spec without drive terms loads none of the simulator."""
    if not spec.drive_controllers:
        return
    from mazegen.runtime import simulation

    robot = spec.robot_or_default
    for name in spec.drive_controllers:
        simulation.drive(floors, robot=robot, controller=robot.controller(name))


def compile_evolution_kernels(problem: Problem) -> None:
    """Compile mapping, placement, geometry, hashing and breeding, then evolve a tiny population."""
    settings = dataclasses.replace(problem.spec.evolution, population=TINY, generations=1)
    rng = np.random.default_rng(0)
    codons = random_codons(rng, TINY, settings.genome, settings.codon_max)
    genes = random_genes(rng, TINY, problem.slots)
    _, floors = problem.decode(codons, genes, Workspace())
    metrics.overlapping_pairs(floors)
    metrics.elements_outside(floors)
    metrics.elements_over_size(floors, 1.0)
    world_vertices(problem.table, np.zeros(1, np.int32), np.zeros((1, PLACEMENT_GENES)))
    genome_hashes(codons, genes)
    spare = (np.empty_like(codons), np.empty_like(genes))
    breed(rng, codons, genes, np.zeros(TINY), settings, spare, map_usage=problem.usage)  # the spec's own
    # Last, when the helper has most likely cached solvability: whatever else the fitness calls.
    evolve(problem, settings, rng)
