"""Plug-ins registered by installed packages, as ``mazegen.plugins`` finds and loads them."""

import json
import re
import subprocess
import sys
from importlib.metadata import EntryPoint

import pytest
from click.testing import CliRunner

import mazegen
from mazegen import plugins
from mazegen.cli.main import main
from mazegen.errors import MazeError, MazeNote


def test_a_registered_plugin_is_found_with_its_package(register_plugins):
    register_plugins("metrics", {"dock_clearance": len})
    (found,) = [p for p in plugins.installed("metrics") if p.name == "dock_clearance"]
    assert found.origin == "fake-plugins 1.0"
    assert plugins.find("metrics", "dock_clearance").load() is len
    assert plugins.find("metrics", "no_such_metric") is None
    assert "dock_clearance" in plugins.names("metrics")


def test_a_name_two_packages_register_is_refused(register_plugins):
    register_plugins("exporters", {"webots": len})
    register_plugins("exporters", {"webots": abs})
    with pytest.raises(MazeError, match=r"'webots' is registered by more than one package"):
        plugins.find("exporters", "webots")


def test_a_plugin_that_fails_to_import_is_one_line(monkeypatch):
    broken = EntryPoint("broken", "no_such_module_anywhere:thing", plugins.GROUPS["metrics"])
    monkeypatch.setattr(plugins, "_entry_points", lambda kind: [broken] if kind == "metrics" else [])
    with pytest.raises(MazeError, match=r"metric plug-in 'broken' of .* fails to load .*ModuleNotFoundError"):
        plugins.find("metrics", "broken").load()


LIBRARY = "element crate { shape square size 20..40 colour '#8b5a2b' }\n"
SPEC = (
    "import {library}\n"
    "arena floor {{ size 1000 x 800 cm start (50, 50) goal (950, 750) robot radius 20 }}\n"
    "scenario s on floor {{ elements {element} }}\n"
)


def test_a_registered_library_is_imported_by_name(tmp_path, register_plugins):
    library = tmp_path / "site" / "warehouse.maze"
    library.parent.mkdir()
    library.write_text(LIBRARY)
    register_plugins("libraries", {"warehouse": library})
    spec = tmp_path / "spec.maze"
    spec.write_text(SPEC.format(library="warehouse", element="crate"))
    assert [element.name for element in mazegen.load(spec).elements] == ["crate"]
    result = CliRunner().invoke(main, ["check", str(spec)])
    assert result.exit_code == 0 and result.stderr == "", result.output


def test_a_bundled_library_wins_over_a_registered_one_and_a_note_says_so(tmp_path, register_plugins):
    library = tmp_path / "figures.maze"
    library.write_text(LIBRARY)
    register_plugins("libraries", {"figures": str(library)})
    spec = tmp_path / "spec.maze"
    spec.write_text(SPEC.format(library="figures", element="square"))
    note = f"{spec}:1:1: library plug-in 'figures' of fake-plugins 1.0 is not used: 'figures' is a bundled "
    note += "library"
    with pytest.warns(MazeNote, match=re.escape(note)):
        assert [element.name for element in mazegen.load(spec).elements] == ["square"]
    result = CliRunner().invoke(main, ["check", str(spec)])
    assert result.exit_code == 0, result.output
    assert result.stderr == f"note: {note}\n"


def test_plugins_lists_the_bundled_and_the_registered_of_each_kind(register_plugins):
    register_plugins("exporters", {"webots": len})
    register_plugins("libraries", {"warehouse": "/srv/warehouse.maze"})
    result = CliRunner().invoke(main, ["plugins", "--json"])
    assert result.exit_code == 0, result.output
    rows = [json.loads(line) for line in result.output.splitlines()]
    assert {row["kind"] for row in rows} == set(plugins.GROUPS)
    webots = {"kind": "exporters", "name": "webots", "value": "fake_plugins:webots"}
    assert {**webots, "origin": "fake-plugins 1.0", "bundled": False} in rows
    bundled = {(row["kind"], row["name"]) for row in rows if row["bundled"]}
    assert {("exporters", "ros"), ("libraries", "figures"), ("controllers", "dwa")} <= bundled
    assert {("metrics", "tortuosity")} <= bundled
    table = CliRunner().invoke(main, ["plugins"]).output.splitlines()
    assert table[0].split() == ["kind", "name", "value", "origin"]
    assert "libraries warehouse fake_plugins:warehouse fake-plugins 1.0" in [
        " ".join(line.split()) for line in table
    ]


def test_plugins_imports_neither_the_runtime_nor_a_plugin():
    probe = (
        "import sys; from click.testing import CliRunner; from mazegen.cli.main import main;"
        "assert CliRunner().invoke(main, ['plugins']).output.startswith('kind');"
        "print(any(m.startswith(('numba', 'mazegen.runtime')) for m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"
