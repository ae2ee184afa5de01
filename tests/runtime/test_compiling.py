"""The note a command gives when numba compiles kernels: once, and only when something compiles."""

from __future__ import annotations

from numba import njit

from mazegen.runtime.compiling import compile_note, noting_compiles


def test_the_note_is_said_once_however_many_kernels_compile() -> None:
    said: list[str] = []
    with noting_compiles(said.append, "drive", 15):
        njit(lambda x: x + 1)(1)
        njit(lambda x: x * 2.0)(1.0)
    assert said == [compile_note("drive", 15)]


def test_nothing_is_said_when_nothing_compiles() -> None:
    kernel = njit(lambda x: x - 1)
    kernel(1)  # compiled before the block
    said: list[str] = []
    with noting_compiles(said.append, "run", 20):
        assert kernel(2) == 1
    assert said == []


def test_the_note_ends_with_its_block() -> None:
    said: list[str] = []
    with noting_compiles(said.append, "score", 15):
        pass
    njit(lambda x: x + 3)(1)
    assert said == []


def test_the_note_names_the_work_and_its_figure() -> None:
    note = compile_note("drive", 15)
    assert "drive" in note and "15 s" in note and "\n" not in note


def test_each_bundled_controller_leaves_the_kernel_a_run_looks_for_in_the_cache():
    # A controller inlined into the loop leaves no cache file of its own: every run of a spec driving
    # it would then say it compiles, and compile ahead, however warm the cache.
    from pathlib import Path

    import numba
    import numpy as np

    from mazegen.runtime import CONTROLLER_KERNELS
    from mazegen.runtime.simulation import drive
    from mazegen.spec import robot_for
    from tests.runtime.floors import ARENA, population, random_floors

    floors = population(ARENA, random_floors(np.random.default_rng(1), 4, ARENA))
    for name in CONTROLLER_KERNELS:
        drive(floors, robot=robot_for(ARENA), controller=name)
    folder = Path(numba.config.CACHE_DIR)
    missing = [k for k in CONTROLLER_KERNELS.values() if not any(folder.rglob(f"{k}-*.nbi"))]
    assert missing == []
