"""Compiling the kernels ahead of a first run, on two processes at once."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

from tests.conftest import EXAMPLES

FIRST_RUN = textwrap.dedent(
    """
    import sys
    from pathlib import Path

    def main():
        import mazegen
        from mazegen.runtime import kernels_cached
        from mazegen.runtime.engine._problem import Problem
        from mazegen.runtime.runs._warmup import compile_kernels

        cache, build = Path(sys.argv[1]), Path(sys.argv[2])
        mazegen.build(mazegen.load(sys.argv[3]), build)
        assert not kernels_cached()
        compile_kernels(Problem.from_build_dir(build))
        assert kernels_cached()  # the kernels it looks for are named as numba files them
        compiled = {path.name for path in cache.rglob("*.nb*")}
        mazegen.run(build, population=30, generations=2, runs=1, executor="serial")
        # the run, its scenario documents and their metrics included, loaded every kernel it called
        print(sorted({path.name for path in cache.rglob("*.nb*")} - compiled))

    if __name__ == "__main__":  # the helper process imports this module again
        main()
    """
)


def first_compile(tmp_path, script: str, *args: str) -> str:
    """Run ``script`` with an empty kernel cache (its first argument, before ``args``); its output."""
    path = tmp_path / "first.py"
    path.write_text(script)
    cache = tmp_path / "cache"
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    done = subprocess.run(
        [sys.executable, str(path), str(cache), *args], capture_output=True, text=True, env=env, timeout=900, check=False
    )
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


def test_a_run_after_compiling_ahead_compiles_nothing(tmp_path):
    assert (
        first_compile(tmp_path, FIRST_RUN, str(tmp_path / "build"), str(EXAMPLES / "workshop.maze")) == "[]"
    )
    cache = tmp_path / "cache"
    # Both processes compiled: the path kernels in the helper, the evolution's here.
    names = {path.name.split("-")[0] for path in cache.rglob("*.nbi")}
    assert {"_difficulty._survey_all", "_connectivity._reach_all", "_mapping._map_all"} <= names


STOPPED_HELPER = textwrap.dedent(
    """
    import sys

    def main():
        import mazegen
        from mazegen.runtime.runs._warmup import KernelHelper, compile_path_kernels

        # the cache is empty: it compiles for long
        helper = KernelHelper(compile_path_kernels, mazegen.load(sys.argv[1]))
        helper.stop()  # at once, as compile_kernels does when the command fails early or is interrupted
        print(helper.exitcode)

    if __name__ == "__main__":
        main()
    """
)


def test_a_helper_stopped_at_once_exits_through_python(tmp_path):
    # Killed outright, the helper would leave a semaphore behind, and the resource tracker would
    # warn of it after the command's one-line error. Stopped before its handler is in place, it
    # would be killed; stopped while numba calls back into Python, its exit would be swallowed.
    script = tmp_path / "stopped.py"
    script.write_text(STOPPED_HELPER)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    args = [sys.executable, str(script), str(EXAMPLES / "factory.maze")]
    done = subprocess.run(args, capture_output=True, text=True, env=env, timeout=300, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "1"  # sys.exit(1) from its handler, not -15 for a kill nor 0 for done
    assert done.stderr == ""


FIRST_DRIVE = textwrap.dedent(
    """
    import sys
    from pathlib import Path

    def main():
        import mazegen
        from mazegen.runtime import simulation
        from mazegen.runtime.runs import compile_drive_kernels
        from mazegen.runtime.runs._warmup import empty_floors

        cache, spec = Path(sys.argv[1]), mazegen.load(sys.argv[2])
        compile_drive_kernels(spec, ["straight"])
        compiled = {path.name for path in cache.rglob("*.nb*")}
        episodes = simulation.drive(empty_floors(spec), robot=spec.robot_or_default, controller="straight")
        print(episodes.outcome.tolist(), sorted({path.name for path in cache.rglob("*.nb*")} - compiled))

    if __name__ == "__main__":
        main()
    """
)


def test_a_drive_after_compiling_ahead_compiles_nothing(tmp_path):
    # both empty floors driven to arrival, from the cache alone
    assert first_compile(tmp_path, FIRST_DRIVE, str(EXAMPLES / "factory.maze")) == "[0, 0] []"
    names = {path.name.split("-")[0] for path in (tmp_path / "cache").rglob("*.nbi")}
    assert {"_loop.run_all", "_step.begin_all", "_paths._navigate_all"} <= names  # the loop, the set-up
