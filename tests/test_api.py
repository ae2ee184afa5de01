"""The Python API as the README shows it: every name importable, its own wording in errors."""

from __future__ import annotations

import dataclasses
import inspect
import json
from pathlib import Path

import pytest
from click.testing import CliRunner

import mazegen
from mazegen.cli.main import main
from mazegen.errors import MazeError
from tests.conftest import EXAMPLES


def test_every_public_name_resolves_and_is_listed():
    for name in mazegen.__all__:
        assert getattr(mazegen, name) is not None
    assert {"run", "resume", "sweep", "ExperimentResult", "MazeError"} <= set(mazegen.__all__)
    assert set(mazegen.__all__) <= set(dir(mazegen))
    assert not {"Any", "TYPE_CHECKING", "annotations"} & set(dir(mazegen))
    with pytest.raises(AttributeError, match="no attribute 'nosuch'"):
        mazegen.nosuch  # noqa: B018


def test_the_api_takes_settings_by_keyword():
    positional = {"load": ["path"], "build": ["spec", "out_dir"], "run": ["spec"], "resume": ["run_dir"]}
    positional["sweep"] = ["specs", "settings"]
    for name, leading in positional.items():
        parameters = inspect.signature(getattr(mazegen, name)).parameters.values()
        assert [p.name for p in parameters if p.kind is not p.KEYWORD_ONLY] == leading, name
        assert all(p.annotation is not p.empty for p in parameters), name


def test_an_existing_run_directory_is_reported_in_the_callers_words(tmp_path):
    out = tmp_path / "run"
    out.mkdir()
    (out / "something").write_text("x")
    with pytest.raises(MazeError) as raised:
        mazegen.run(EXAMPLES / "mazegen1.maze", population=10, generations=1, out_dir=out)
    assert "force=True" in str(raised.value) and "--force" not in str(raised.value)
    command = CliRunner().invoke(main, ["run", str(EXAMPLES / "mazegen1.maze"), "-o", str(out), "-q"])
    assert command.exit_code == 1
    assert "use --force" in command.stderr and "force=True" not in command.stderr


def test_an_options_name_has_one_spelling_per_caller():
    error = MazeError(f"use {mazegen.errors.option('force')} to replace it", filename="x")
    assert str(error) == "x: use force=True to replace it"
    assert error.render(command_line=True) == "x: use --force to replace it"
    with pytest.raises(KeyError):
        mazegen.errors.option("nosuch")


def test_sweep_then_resume_from_python(tmp_path):
    spec = mazegen.load(EXAMPLES / "mazegen1.maze")
    settings = {"population": [20, 30], "generations": [1]}
    cells = mazegen.sweep([spec], settings, out_dir=tmp_path / "sweep", runs=1)
    assert [path.parent for path, _ in cells] == [tmp_path / "sweep"] * 2
    assert all(isinstance(result, mazegen.ExperimentResult) and result.best[0] for _, result in cells)
    assert [result for _, result in mazegen.sweep([spec], settings, out_dir=tmp_path / "sweep")] == [None] * 2
    with pytest.raises(MazeError, match="finished: nothing to resume"):
        mazegen.resume(cells[0][0])


def test_a_sweep_too_large_is_refused_before_its_values_are_spelled_out(tmp_path):
    with pytest.raises(MazeError, match="seed: 999999999 values; a sweep has at most 10000 cells"):
        mazegen.sweep([EXAMPLES / "factory.maze"], {"seed": range(1, 10**9)}, out_dir=tmp_path)


def test_drive_takes_scenario_files_folders_and_documents(tmp_path):
    spec = mazegen.load(EXAMPLES / "factory.maze")
    router = {"type": "router", "x": 700, "y": 300, "size": 30}
    wall = {"type": "productionLine", "x": 700, "y": 525, "width": 1400, "depth": 80, "rotation": 0}
    folder = tmp_path / "floors"
    folder.mkdir()
    for number, elements in enumerate([[router], [wall]], start=1):
        document = {"format": "mazegen-scenario", "version": 1, "scenario": "factory", "elements": elements}
        (folder / f"floor-{number}.json").write_text(json.dumps(document), encoding="utf-8")
    given = {"format": "mazegen-scenario", "version": 1, "scenario": "factory", "elements": [router]}
    drives = mazegen.drive([folder, given], ["straight", "purepursuit"], spec=spec)
    assert [(Path(d.file).name, d.controller) for d in drives] == [
        (name, controller)
        for name in ("floor-1.json", "floor-2.json", "scenario 2")
        for controller in ("straight", "purepursuit")
    ]
    assert [d.outcome for d in drives[2:4]] == ["no path", "no path"]  # the wall closes the floor
    same = [dataclasses.replace(d, file="") for d in (drives[0], drives[1])]
    assert [dataclasses.replace(d, file="") for d in drives[4:]] == same  # one floor, given twice
    with pytest.raises(MazeError, match=r"^scenario 1: a scenario document needs its spec: give spec="):
        mazegen.drive(given, "straight")
