"""Shared fixtures: paths to the examples and a helper to write specs."""

from __future__ import annotations

from contextlib import nullcontext
from pathlib import Path
from types import SimpleNamespace

import pytest

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"


@pytest.fixture(autouse=True)
def _kernels_cached(monkeypatch):
    """Commands say nothing about compiling kernels, whatever the state of the cache, so that tests of
    their output do not depend on which test ran first (the notes have tests of their own)."""
    import mazegen.runtime
    import mazegen.runtime.compiling

    monkeypatch.setattr(mazegen.runtime, "kernels_cached", lambda kernels=(): True)
    monkeypatch.setattr(
        mazegen.runtime.compiling, "noting_compiles", lambda say, work, seconds: nullcontext()
    )


@pytest.fixture
def write_spec(tmp_path: Path):
    """Write ``text`` as a .maze file in a temporary directory and return its path."""

    def write(text: str, name: str = "spec.maze") -> Path:
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        return path

    return write


@pytest.fixture(scope="session")
def factory(tmp_path_factory):
    """The built problem of examples/factory.maze; do not modify it."""
    import mazegen
    from mazegen.generator.build import build
    from mazegen.runtime.engine._problem import Problem

    out = tmp_path_factory.mktemp("factory-build")
    build(mazegen.load(EXAMPLES / "factory.maze"), out)
    return Problem.from_build_dir(out)


@pytest.fixture(scope="session")
def factory_run(tmp_path_factory) -> Path:
    """A small run directory of examples/factory.maze (2 runs, 4 best scenarios each); do not modify it."""
    import mazegen

    spec = mazegen.load(EXAMPLES / "factory.maze").with_evolution(best=4)
    out = tmp_path_factory.mktemp("factory") / "run"
    mazegen.run(spec, runs=2, population=80, generations=3, out_dir=out)
    return out


@pytest.fixture(scope="session")
def small_reference(tmp_path_factory) -> dict[str, str]:
    """The file digests of a ``tests.runtime.rundirs.small_run`` never interrupted."""
    from tests.runtime.rundirs import file_digests, small_run

    out = tmp_path_factory.mktemp("small-reference") / "run"
    small_run(out)
    return file_digests(out)


@pytest.fixture
def register_plugins(monkeypatch):
    """``register_plugins(kind, {name: object})`` makes ``mazegen.plugins`` see ``object`` registered
    as ``name`` under ``kind``'s entry point group by a package ``fake-plugins 1.0``, as an installed
    package's ``pyproject.toml`` would."""
    from importlib.metadata import EntryPoint

    from mazegen import plugins

    registered: dict[str, list[EntryPoint]] = {}
    real = plugins._entry_points

    class _Registered(EntryPoint):
        def load(self):
            return self._target

        @property
        def dist(self):
            return SimpleNamespace(metadata={"Name": "fake-plugins"}, version="1.0")

    def register(kind: str, named: dict[str, object]) -> None:
        for name, target in named.items():
            point = _Registered(name, f"fake_plugins:{name}", plugins.GROUPS[kind])
            object.__setattr__(point, "_target", target)
            registered.setdefault(kind, []).append(point)

    monkeypatch.setattr(plugins, "_entry_points", lambda kind: [*real(kind), *registered.get(kind, [])])
    return register
