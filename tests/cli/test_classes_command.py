"""`mazegen classes` and `mazegen.classes` as a user runs them: floors grouped into the tests they make,
with and without a controller, JSON, bad files, and the classes the catalog keeps.

Drives go through :class:`tests.runtime.fake_drive.FakeDrive` (``straight`` collides, every other
controller arrives by the straight line), so these tests see what the command does with a drive.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

import mazegen
from mazegen.cli.main import main
from tests.cli.test_drive_command import WALL, hand_floor
from tests.conftest import EXAMPLES
from tests.runtime.fake_drive import fake_drive

ON_ROUTE = [{"type": "productionLine", "x": 700, "y": 525, "width": 300, "depth": 80, "rotation": 126}]
"""A production line across the middle of the start-goal diagonal: two ways round it."""
FURTHER_ON = [{"type": "productionLine", "x": 900, "y": 672, "width": 300, "depth": 80, "rotation": 126}]
"""The same line moved along the diagonal: the same test."""


@pytest.fixture
def floors(tmp_path) -> Path:
    """A suite-like folder of examples/factory.maze: two floors one test, an open one, a walled one."""
    folder = tmp_path / "floors"
    folder.mkdir()
    (folder / "spec.json").write_text(mazegen.load(EXAMPLES / "factory.maze").to_json(), encoding="utf-8")
    for number, elements in enumerate([ON_ROUTE, [], FURTHER_ON, WALL], start=1):
        hand_floor(folder / f"scenario-{number:02d}.json", elements)
    return folder


def invoke(*args: str):
    return CliRunner().invoke(main, ["classes", *args], catch_exceptions=False)


def test_floors_with_the_same_ways_round_the_same_obstacles_are_one_test(floors):
    result = invoke(str(floors), "--json")
    assert result.exit_code == 0, result.output
    found = json.loads(result.output)
    signatures = {Path(f["file"]).name: f["signature"] for f in found["floors"]}
    assert signatures == {
        "scenario-01.json": "2:L,R",
        "scenario-02.json": "1:",
        "scenario-03.json": "2:L,R",
        "scenario-04.json": "0:",
    }
    groups = {g["key"]: [Path(file).name for file in g["files"]] for g in found["groups"]}
    assert groups == {"2:L,R": ["scenario-01.json", "scenario-03.json"], "0:": ["scenario-04.json"],
                      "1:": ["scenario-02.json"]}  # fmt: skip
    assert found["groups"][0]["representative"].endswith("scenario-01.json")  # the largest group first
    first = found["floors"][0]["tasks"][0]["classes"]
    assert [c["length"] for c in first] == sorted(c["length"] for c in first)
    assert all(c["narrowest"] > 0 for c in first)


def test_the_table_names_each_floor_and_counts_the_tests(floors):
    result = invoke(str(floors))
    assert result.exit_code == 0, result.output
    assert "3 distinct tests among 4 floors" in result.output
    assert result.output.count("scenario-0") >= 4 + 3  # a row per floor, a representative per group


def test_a_controller_splits_floors_by_its_outcome_and_trajectory_class(floors, monkeypatch):
    fake_drive(monkeypatch)
    result = invoke(str(floors), "--controller", "straight", "-c", "dwa", "--json")
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    found = json.loads(lines[-1])
    first = found["floors"][0]
    outcomes = {(d["controller"], d["outcome"], d["class"]) for d in first["drives"]}
    straight_class = first["tasks"][0]["classes"]
    assert ("straight", "collision", None) in outcomes
    [dwa] = [d for d in first["drives"] if d["controller"] == "dwa"]
    assert dwa["outcome"] == "arrived" and dwa["class"] in {c["signature"] for c in straight_class}
    assert any("no path" in line and "scenario-04" in line for line in lines)  # said, not driven
    [key] = [g["key"] for g in found["groups"] if g["representative"] == first["file"]]
    assert key == f"2:L,R | straight collision | dwa arrived {dwa['class']}"


def test_a_file_that_cannot_be_read_is_one_line_and_the_others_are_classified(floors):
    (floors / "scenario-05.json").write_text("{not json")
    result = invoke(str(floors))
    assert result.exit_code == 1
    assert "scenario-05.json" in result.output and "Traceback" not in result.output
    assert "3 distinct tests among 4 floors" in result.output


def test_limits_out_of_bounds_are_one_line(floors):
    result = invoke(str(floors), "--max-classes", "0")
    assert result.exit_code != 0 and "--max-classes must be from 1 to 64" in result.output


def test_the_api_takes_folders_and_documents(floors):
    found = mazegen.classes(floors)
    assert [floor.signature for floor in found.floors] == ["2:L,R", "1:", "2:L,R", "0:"]
    spec = mazegen.load(EXAMPLES / "factory.maze")
    document = json.loads((floors / "scenario-01.json").read_text())
    [alone] = mazegen.classes(document, spec=spec, max_classes=1).floors
    assert alone.signature == "1:" and alone.count == 1


def test_the_catalog_keeps_each_scenarios_classes(factory_run, tmp_path):
    """A copy of a run of two runs, four best scenarios each: the first run's classes recorded by
    ``classes``, the second's found by ``scenarios`` when a condition names them, once."""
    shutil.copytree(factory_run.parent, tmp_path / "runs")
    run, catalog = tmp_path / "runs" / factory_run.name, str(tmp_path / "runs" / "catalog.sqlite")
    assert invoke(str(run / "run-01")).exit_code == 0  # records the first run's
    query = ["scenarios", "--catalog", catalog, "--where", "classes>=1", "--sort", "classes"]
    listed = CliRunner().invoke(main, query, catch_exceptions=False)
    assert listed.exit_code == 0, listed.output
    assert "finding the homotopy classes of 4 scenarios" in listed.output  # the second run's, once
    assert listed.output.count("best-0") == 8
    again = CliRunner().invoke(main, ["scenarios", "--catalog", catalog, "--where", "classes>=1", "--paths"])
    assert "finding" not in again.output
    paths = again.output.splitlines()
    assert len(paths) == 8 and all(Path(line).is_file() for line in paths)
    none = CliRunner().invoke(main, ["scenarios", "--catalog", catalog, "--where", "classes>=99", "--paths"])
    assert none.output.strip() == ""


TWO_TASKS = """
import manufacturing
arena floor {
    size 1400 x 1050 cm  robot radius 25  grid 12.5
    station west (100, 525)  station east (1300, 525)  station south (700, 100)
    task west -> east
    task west -> south
}
scenario factory on floor { elements cobot, router, vwall, hwall, productionLine  max elements 8 }
fitness { count  solvable required }
evolution { population 10  generations 1  genome 32 }
"""


def test_a_floor_of_several_tasks_has_a_canonical_class_per_task(tmp_path, write_spec):
    """A line across the middle: two ways round it from west to east; the way south passes it by."""
    spec = mazegen.load(write_spec(TWO_TASKS))
    line = {"type": "productionLine", "x": 700, "y": 600, "width": 400, "depth": 80, "rotation": 90}
    document = {"format": "mazegen-scenario", "version": 1, "scenario": "factory", "elements": [line]}
    [floor] = mazegen.classes(document, spec=spec).floors
    assert [name for name, _ in floor.tasks] == ["west -> east", "west -> south"]
    east, south = (top for _, top in floor.tasks)
    assert east.signature == "2:L,R" and south.signature == "1:"  # going round above is too far
    assert floor.signature == f"{east.signature};{south.signature}"
    assert floor.count == len(east.classes) + len(south.classes)


def test_the_same_floors_give_the_same_bytes_in_another_process(floors):
    """The classes are computed in the calling process, from the floors alone: a second process,
    with its own kernels loaded, prints them byte for byte."""
    import subprocess
    import sys

    here = invoke(str(floors), "--json").output
    command = [sys.executable, "-m", "mazegen", "classes", str(floors), "--json"]
    there = subprocess.run(command, capture_output=True, text=True, check=True).stdout
    assert here == there
