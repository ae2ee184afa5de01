"""A floor of several tasks in its documents, its drives and its exports: every task listed with its
measures, driven on its own, and written where navigation tools read tasks."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest
import yaml
from click.testing import CliRunner

import mazegen
from mazegen.cli.main import main
from mazegen.runtime.documents import Floor, completed_document, load_floor, read_document, with_drives
from mazegen.runtime.exporters import ExportOptions
from mazegen.runtime.exporters._movingai import movingai_files
from mazegen.runtime.exporters._ros import ros_files
from tests.conftest import ROOT

SPEC = """
element box { shape square size 40..80 }
arena floor {
    size 1000 x 800 cm  robot radius 20
    station dock (100, 100) heading 90
    station line (900, 700)
    station store (900, 100) heading 180
    task dock -> line
    task line -> store
    tasks 2 seed 4 min distance 3 m
}
scenario s on floor { elements box  max elements 6 }
fitness { count  overlap reject  solvable required  difficulty target medium tasks worst }
evolution { population 40  generations 2  genome 16  seed 1  best 2 }
"""
SCHEMA = jsonschema.Draft202012Validator(json.loads((ROOT / "docs" / "scenario.schema.json").read_text()))


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("tasks")
    (folder / "tasks.maze").write_text(SPEC)
    out = folder / "run"
    mazegen.run(folder / "tasks.maze", out_dir=out, catalog=False)
    return out


def test_a_document_lists_every_task_with_its_measures_and_passes_the_schema(run_dir):
    document = read_document(run_dir / "run-01" / "best-01.json")
    SCHEMA.validate(document)
    arena = document["arena"]
    names = [task["name"] for task in arena["tasks"]]
    assert names == ["dock -> line", "line -> store", "drawn 3", "drawn 4"]
    assert [task["name"] for task in document["tasks"]] == names
    assert arena["tasks"][0]["start_heading"] == 90.0 and arena["tasks"][1]["goal_heading"] == 180.0
    assert (arena["start"], arena["goal"]) == (arena["tasks"][0]["start"], arena["tasks"][0]["goal"])
    assert document["path"] == document["tasks"][0]["path"]
    every = [task["metrics"] for task in document["tasks"]]
    assert document["metrics"]["solvable"] == all(m["solvable"] for m in every)
    if document["metrics"]["solvable"]:
        mean = sum(m["difficulty"] for m in every) / len(every)
        assert document["metrics"]["difficulty"] == pytest.approx(mean, abs=1e-3)


def test_a_completed_document_measures_each_task_again_the_same(run_dir):
    path = run_dir / "run-01" / "best-01.json"
    document = read_document(path)
    spec = mazegen.load(run_dir.parent / "tasks.maze")
    bare = {
        "elements": [{k: e[k] for k in ("type", "x", "y", "size", "rotation")} for e in document["elements"]]
    }
    again = completed_document(spec, {**document, **bare}, str(path))
    assert again["tasks"] == document["tasks"] and again["metrics"] == document["metrics"]


def test_drive_drives_every_task_and_writes_each_into_its_entry(run_dir, tmp_path):
    out = tmp_path / "driven"
    result = CliRunner().invoke(
        main, ["drive", str(run_dir / "run-01" / "best-01.json"), "--controller", "straight", "-o", str(out)]
    )
    assert result.exit_code == 0, result.output
    document = read_document(out / "best-01.json")
    SCHEMA.validate(document)
    assert all("straight" in task["drive"] for task in document["tasks"])
    first = document["tasks"][0]["drive"]["straight"]
    # The robot starts at the dock's heading, 90 degrees, not facing its path.
    assert first["outcome"] != "no path" and first["trajectory"][0][2] == 90.0
    assert document.get("drive", {}) == {}
    assert result.output.count(" straight ") >= 4  # one row per task
    # Another controller driven later keeps the first one's entries.
    from mazegen.runtime.documents import Drive

    extra = Drive("f", "dwa", "timeout", 1.0, 1.0, 0.1, 2.0, 0.0, False, None, (), task="drawn 3")
    merged = with_drives(document, [extra])
    assert set(merged["tasks"][2]["drive"]) == {"straight", "dwa"}
    assert set(merged["tasks"][0]["drive"]) == {"straight"}


def test_score_lists_each_task(run_dir):
    result = CliRunner().invoke(
        main,
        [
            "score",
            str(run_dir.parent / "tasks.maze"),
            str(run_dir / "run-01" / "best-01.json"),
            "--json",
        ],
    )
    assert result.exit_code == 0, result.output
    record = json.loads(result.output.splitlines()[-1])
    assert [task["name"] for task in record["tasks"]] == [
        "dock -> line",
        "line -> store",
        "drawn 3",
        "drawn 4",
    ]


def test_exports_write_a_scen_line_and_a_pose_per_task(run_dir):
    floor: Floor = load_floor(run_dir / "run-01" / "best-01.json")
    document = floor.document
    scen = movingai_files(floor, ExportOptions())["best-01.scen"].decode().splitlines()
    solvable = [task["metrics"]["solvable"] for task in document["tasks"]]
    assert scen[0] == "version 1" and len(scen) == 1 + sum(solvable)
    files = ros_files(floor, ExportOptions())
    tasks = yaml.safe_load(files["best-01.tasks.yaml"])["tasks"]
    assert [task["name"] for task in tasks] == [task["name"] for task in document["arena"]["tasks"]]
    first = tasks[0]
    assert (first["start"]["x"], first["start"]["y"]) == (1.0, 1.0)  # (100, 100) cm, the arena's corner at 0
    assert first["start"]["yaw"] == pytest.approx(1.5707963, abs=1e-6) and first["goal"]["yaw"] is None
    for entry, task in zip(tasks, document["tasks"]):
        length = task["metrics"]["path_length"]
        assert entry["optimal_length"] == (None if length is None else pytest.approx(length / 100, abs=1e-6))


@pytest.mark.parametrize(
    ("key", "entry", "message"),
    [
        ("tasks", {"start": [100, 100], "goal": [900, 700]}, "arena.tasks[0]: 'name' is missing"),
        ("stations", {"name": "dock"}, "arena.stations[0]: 'point' is missing"),
    ],
)
def test_a_document_task_or_station_without_its_fields_is_one_located_line(run_dir, key, entry, message):
    from mazegen.errors import MazeError
    from mazegen.runtime.documents._task import task_spec

    spec = mazegen.load(run_dir.parent / "tasks.maze")
    document = read_document(run_dir / "run-01" / "best-01.json")
    document["arena"][key] = [entry]
    with pytest.raises(MazeError, match=message.replace("[", r"\[").replace("]", r"\]")) as caught:
        task_spec(spec, document, "floor.json")
    assert caught.value.filename == "floor.json" and "\n" not in str(caught.value)
