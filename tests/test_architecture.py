"""The layering of docs/architecture.md holds: import-linter's contracts, and no import cycle."""

from __future__ import annotations

import ast
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from tests.conftest import ROOT

LINT = (
    "import sys; from importlinter.cli import lint_imports; "
    "sys.exit(lint_imports(config_filename='pyproject.toml', no_cache=True, no_logo=True))"
)


def lint_imports(checkout: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(checkout)}
    return subprocess.run([sys.executable, "-c", LINT], cwd=checkout, env=env, capture_output=True, text=True)


def test_the_import_contracts_hold():
    done = lint_imports(ROOT)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "0 broken" in done.stdout


def test_a_wrong_way_import_breaks_a_contract(tmp_path):
    shutil.copytree(ROOT / "mazegen", tmp_path / "mazegen", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path)
    population = tmp_path / "mazegen" / "runtime" / "engine" / "_population.py"
    population.write_text(
        population.read_text() + "\n\ndef _late():\n    import mazegen.runtime.runs._launcher\n"
    )
    done = lint_imports(tmp_path)
    assert done.returncode != 0
    assert "Layers: each imports only those below it" in done.stdout
    assert "mazegen.runtime.engine._population -> mazegen.runtime.runs._launcher" in done.stdout


def test_an_import_of_another_rooms_module_breaks_a_contract(tmp_path):
    """Rooms meet at their ``__init__``: a module of another room is private to it."""
    shutil.copytree(ROOT / "mazegen", tmp_path / "mazegen", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path)
    metrics = tmp_path / "mazegen" / "runtime" / "metrics.py"
    metrics.write_text(
        metrics.read_text() + "\n\ndef _reach():\n    import mazegen.runtime.navigation._paths\n"
    )
    done = lint_imports(tmp_path)
    assert done.returncode != 0
    assert "A room's modules are private" in done.stdout and "BROKEN" in done.stdout
    assert "mazegen.runtime.metrics -> mazegen.runtime.navigation._paths" in done.stdout


def imports_of(package: Path) -> dict[str, set[str]]:
    """Each module of ``package`` and the modules of it that it imports, anywhere in its code
    (functions and ``TYPE_CHECKING`` blocks too)."""
    modules = {}
    for path in package.rglob("*.py"):
        parts = list(path.relative_to(package.parent).with_suffix("").parts)
        modules[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        here = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
        targets = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                targets |= {alias.name for alias in node.names}
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    base = ".".join(here[: len(here) - node.level + 1] + ([base] if base else []))
                # "from package import module" imports that module (a parent package runs first anyway)
                named = {f"{base}.{alias.name}" for alias in node.names}
                targets |= named if named <= modules.keys() else named | {base}
        graph[name] = {target for target in targets if target in modules and target != name}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[set[str]]:
    """The groups of modules that import each other, directly or not (Tarjan's components)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[set[str]] = []

    def visit(module: str) -> None:
        index[module] = low[module] = len(index)
        stack.append(module)
        for target in graph[module]:
            if target not in index:
                visit(target)
                low[module] = min(low[module], low[target])
            elif target in stack:
                low[module] = min(low[module], index[target])
        if low[module] == index[module]:
            group = set()
            while not group or module not in group:
                group.add(stack.pop())
            if len(group) > 1:
                found.append(group)

    for module in graph:
        if module not in index:
            visit(module)
    return found


def test_no_module_imports_itself_through_others():
    assert cycles(imports_of(ROOT / "mazegen")) == []


def test_a_cycle_through_a_function_level_import_is_found(tmp_path):
    package = tmp_path / "pkg"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "a.py").write_text("from pkg.b import helper\n")
    (package / "b.py").write_text("def helper():\n    from . import c\n")
    (package / "c.py").write_text("def late():\n    import pkg.a\n")
    assert cycles(imports_of(package)) == [{"pkg.a", "pkg.b", "pkg.c"}]


ROOMS = (
    "engine",
    "geometry",
    "navigation",
    "simulation",
    "documents",
    "reports",
    "exporters",
    "runs",
    "catalog",
    "campaigns",
)


def test_each_room_states_its_public_names_and_each_resolves():
    import importlib

    for room in ROOMS:
        package = importlib.import_module(f"mazegen.runtime.{room}")
        assert len(set(package.__all__)) == len(package.__all__), room  # ruff (RUF022) keeps the order
        for name in package.__all__:
            home = getattr(
                getattr(package, name), "__module__", f"mazegen.runtime.{room}."
            )  # constants have none
            assert home.startswith(f"mazegen.runtime.{room}."), (room, name)


def test_a_module_of_a_room_imports_only_what_it_needs():
    """A room's public names load on first use: a run does not pay for the reports' matplotlib."""
    probe = "import sys, mazegen.runtime.runs._launcher; print('matplotlib' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"


def _recipes() -> dict[str, list[str]]:
    """Each recipe of docs/architecture.md's "What goes where" by its title, with its files."""
    page = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    section = page[page.index("## What goes where") : page.index("## Threads")]
    recipes = {}
    for bullet in re.split(r"\n- ", section)[1:]:
        title = re.match(r"\*\*(.+?)\*\*", bullet)
        files = bullet.split("Files:", 1)
        assert title and len(files) == 2, f"a recipe without its files: {bullet[:60]}"
        recipes[title.group(1)] = re.findall(r"`([^`]+)`", files[1])
    return recipes


def test_every_recipe_names_files_that_exist():
    for title, files in _recipes().items():
        assert files, title
        for name in files:
            known = ROOT / name.split("NAME")[0].rpartition("/")[0]  # a new file's place: where it goes
            assert known.exists(), f"{title}: {name}"


def test_each_recipe_names_where_its_kind_is_registered():
    """The table a new kind joins, and the files derived from the code that reads it."""
    from mazegen import controllers, export_formats, fitness_terms
    from mazegen.cli import main
    from mazegen.dsl.metamodel import GRAMMAR_FILE
    from mazegen.runtime import metrics
    from mazegen.runtime.simulation import _loop

    def relative(module_file: str | Path) -> str:
        return Path(module_file).resolve().relative_to(ROOT).as_posix()

    needed = {
        "A fitness term": [fitness_terms.__file__, GRAMMAR_FILE, metrics.__file__, ROOT / "docs/language.md"],
        "An exporter": [export_formats.__file__, ROOT / "docs/exports.md"],
        "A command": [main.__file__],
        "A new controller": [controllers.__file__, _loop.__file__, ROOT / "docs/simulation.md"],
        "A new room": [ROOT / "pyproject.toml", Path(__file__)],
    }
    recipes = _recipes()
    assert set(needed) == set(recipes)
    for title, files in needed.items():
        for file in files:
            assert relative(file) in recipes[title], f"{title} does not name {relative(file)}"
