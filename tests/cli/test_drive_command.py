"""`mazegen drive` as a user runs it: outputs, JSON, the documents and pictures of -o, floors without a
path reported before driving, unknown controllers and bad files.

The simulator is replaced by :class:`tests.runtime.fake_drive.FakeDrive` (``straight`` collides,
every other controller arrives), so these tests see what the command does with what a drive gives.
"""

from __future__ import annotations

import dataclasses
import json
import math
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import jsonschema
import numpy as np
import pytest
from click.testing import CliRunner

import mazegen
import mazegen.runtime.simulation as simulation
from mazegen.cli.main import main
from mazegen.errors import MazeError
from mazegen.runtime.documents._scenario import arena_document, read_document
from mazegen.spec import robot_for
from tests.conftest import EXAMPLES, ROOT
from tests.runtime.fake_drive import fake_drive

SCHEMA = jsonschema.Draft202012Validator(json.loads((ROOT / "docs" / "scenario.schema.json").read_text()))
OPEN = [{"type": "router", "x": 700, "y": 300, "size": 30}]
WALL = [{"type": "productionLine", "x": 700, "y": 525, "width": 1400, "depth": 80, "rotation": 0}]
"""A production line across the whole floor: no path from start to goal."""


def hand_floor(path: Path, elements: list[dict]) -> Path:
    document = {"format": "mazegen-scenario", "version": 1, "scenario": "factory", "elements": elements}
    path.write_text(json.dumps(document), encoding="utf-8")
    return path


@pytest.fixture
def suite(tmp_path) -> Path:
    """A suite-like folder of examples/factory.maze: its spec.json and three floors, the second walled."""
    folder = tmp_path / "suite"
    folder.mkdir()
    (folder / "spec.json").write_text(mazegen.load(EXAMPLES / "factory.maze").to_json(), encoding="utf-8")
    for number, elements in enumerate([OPEN, WALL, []], start=1):
        hand_floor(folder / f"scenario-{number:02d}.json", elements)
    return folder


def invoke(*args: str):
    return CliRunner().invoke(main, ["drive", *args], catch_exceptions=False)


def test_each_scenario_and_controller_is_a_row_then_each_controller_is_summed_up(suite, monkeypatch):
    fake = fake_drive(monkeypatch)
    result = invoke(str(suite), "--controller", "straight", "-c", "dwa")
    assert result.exit_code == 0, result.output
    # one batch call per controller, over the floors with a path (the first and third)
    assert [(name, indices) for name, indices, _ in fake.calls] == [("straight", [0, 2]), ("dwa", [0, 2])]
    rows = [line.split() for line in result.stdout.splitlines()]
    heading = rows[0]
    assert heading[:4] == ["file", "controller", "outcome", "time"] and "closest" in heading
    table = {(row[0].rsplit("/", 1)[-1], row[1]): row[2:] for row in rows[1:7]}
    assert table[("scenario-01.json", "straight")][0] == "collision"
    assert (
        table[("scenario-01.json", "dwa")][:1] == ["arrived"]
        and table[("scenario-01.json", "dwa")][-1] == "0.4"
    )
    assert table[("scenario-02.json", "dwa")] == ["no", "path"]  # nothing driven, no numbers
    summary = {row[0]: row[1:] for row in rows[9:]}
    assert rows[7] == [] and rows[8] == ["controller", "driven", "arrived", "success", "mean", "score"]
    assert summary == {"straight": ["2", "0", "0", "0"], "dwa": ["2", "2", "1", "0.4"]}


def test_a_floor_without_a_path_is_said_before_driving_and_not_driven(suite, monkeypatch):
    fake = fake_drive(monkeypatch)
    result = invoke(str(suite), "-c", "dwa")
    lines = result.stderr.splitlines()
    walled = str(suite / "scenario-02.json")
    assert lines[0] == (
        f"{walled}: no path for a robot of radius 25 cm from start (60, 60) to goal (1340, 990): not driven"
    )
    assert lines[1] == "driving dwa" and all(1 not in indices for _, indices, _ in fake.calls)


def test_json_is_one_object_per_scenario_and_controller(suite, monkeypatch):
    fake_drive(monkeypatch)
    result = invoke(str(suite), "-c", "straight,dwa", "--json")
    assert result.exit_code == 0
    records = [json.loads(line) for line in result.stdout.splitlines()]
    assert [(Path(r["file"]).name, r["controller"]) for r in records] == [
        (f"scenario-0{n}.json", name) for n in (1, 2, 3) for name in ("straight", "dwa")
    ]
    crash, arrival, walled = records[0], records[1], records[2]
    assert crash["outcome"] == "collision" and crash["collision"] == [1340.0, 990.0] and crash["score"] == 0
    assert arrival["outcome"] == "arrived" and arrival["score"] == 0.4 and arrival["clearance"] == 12.3457
    assert arrival["time"] == pytest.approx(2.5 * arrival["optimal_time"], abs=1e-3)
    assert walled["outcome"] == "no path" and walled["optimal_time"] is None and "trajectory" not in walled


def test_out_writes_driven_documents_and_pictures_that_the_reader_and_the_schema_accept(
    suite, tmp_path, monkeypatch
):
    fake_drive(monkeypatch)
    before = {path.name: path.read_bytes() for path in suite.iterdir()}
    out = tmp_path / "driven"
    result = invoke(str(suite), "-c", "straight", "-c", "dwa", "-o", str(out))
    assert result.exit_code == 0, result.output
    assert {path.name: path.read_bytes() for path in suite.iterdir()} == before  # inputs untouched
    document = read_document(out / "scenario-01.json")
    assert list(SCHEMA.iter_errors(document)) == []
    straight, dwa = document["drive"]["straight"], document["drive"]["dwa"]
    assert straight["outcome"] == "collision" and straight["collision"] == [1340.0, 990.0]
    heading = round(math.degrees(math.atan2(990 - 60, 1340 - 60)), 4)  # degrees, as documents write angles
    assert straight["trajectory"][0] == [60.0, 60.0, heading] and len(straight["trajectory"]) == 5
    assert dwa["collision"] is None and dwa["outcome"] == "arrived"
    walled = read_document(out / "scenario-02.json")["drive"]["dwa"]
    assert walled["outcome"] == "no path" and walled["trajectory"] == []
    svg = ET.parse(out / "scenario-01.svg").getroot()
    assert len(svg.findall(".//{http://www.w3.org/2000/svg}polyline")) == 3  # the path and two drives


def test_out_into_the_source_folder_adds_the_drive_in_place_and_keeps_earlier_drives(
    factory_run, tmp_path, monkeypatch
):
    fake_drive(monkeypatch)
    run = tmp_path / "run"
    shutil.copytree(factory_run, run)
    assert invoke(str(run), "-c", "straight", "-o", str(run)).exit_code == 0
    assert invoke(str(run), "-c", "dwa", "-o", str(run)).exit_code == 0
    for path in sorted(run.glob("run-*/best-*.json")):
        original = read_document(factory_run / path.relative_to(run))
        driven = read_document(path)
        assert set(driven["drive"]) == {"straight", "dwa"}
        assert {key: value for key, value in driven.items() if key != "drive"} == original
        assert "straight: collision" in path.with_suffix(".svg").read_text()


def test_the_robot_is_the_specs_when_it_has_one(suite, monkeypatch):
    fake = fake_drive(monkeypatch)
    spec = mazegen.load(EXAMPLES / "factory.maze")
    robot = robot_for(spec.arena, max_speed=20.0)
    (suite / "spec.json").write_text(dataclasses.replace(spec, robot=robot).to_json(), encoding="utf-8")
    assert invoke(str(suite), "-c", "dwa").exit_code == 0
    assert fake.calls[0][2] == robot
    (suite / "spec.json").write_text(spec.to_json(), encoding="utf-8")
    assert invoke(str(suite), "-c", "dwa").exit_code == 0
    assert fake.calls[1][2] == robot_for(spec.arena)


def test_an_unknown_controller_is_one_line_naming_the_known_ones_before_anything_is_read(
    tmp_path, monkeypatch
):
    fake = fake_drive(monkeypatch)
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    result = invoke(str(bad), "-c", "dwa", "-c", "dwb")
    assert result.exit_code == 2 and fake.calls == []
    assert result.stderr.splitlines() == [
        "unknown controller 'dwb': known are dwa, movebase, purepursuit, straight, vfh, or a user's policy "
        "as package.module:name"
    ]
    for given in ([], ["-c", ","]):  # no controller at all: one line, exit status 1
        result = invoke(str(bad), *given)
        assert (
            result.exit_code == 1 and len(result.stderr.splitlines()) == 1 and "--controller" in result.stderr
        )


def test_a_bad_file_is_one_line_and_skipped_and_the_others_are_driven_with_exit_status_1(suite, monkeypatch):
    fake = fake_drive(monkeypatch)
    (suite / "scenario-04.json").write_text('{"format": "mazegen-scenario", "version": 2}')
    hand_floor(suite / "scenario-05.json", [{"type": "ruoter", "x": 1, "y": 1, "size": 3}])
    result = invoke(str(suite), "-c", "dwa", "--json")
    assert result.exit_code == 1
    errors = [line for line in result.stderr.splitlines() if not line.startswith("driving")]
    assert errors[:2] == [
        f"{suite / 'scenario-04.json'}: unsupported scenario version 2 (this MazeGen reads 1)",
        f"{suite / 'scenario-05.json'}: elements[0].type: 'ruoter' is not an element of scenario 'factory' "
        "(cobot, router, vwall, hwall, productionLine)",
    ]
    assert errors[2].endswith(
        "scenario-02.json: no path for a robot of radius 25 cm from start (60, 60) to goal "
        "(1340, 990): not driven"
    )
    assert len(result.stdout.splitlines()) == 3 and fake.calls[0][1] == [0, 2]


def test_a_lone_scenario_without_its_spec_says_to_give_one(tmp_path, monkeypatch):
    fake_drive(monkeypatch)
    floor = hand_floor(tmp_path / "floor.json", OPEN)
    result = invoke(str(floor), "-c", "dwa")
    assert result.exit_code == 1 and result.stderr.startswith(f"{floor}: ") and "--spec" in result.stderr
    assert len(result.stderr.splitlines()) == 1
    assert invoke(str(floor), "-c", "dwa", "--spec", str(EXAMPLES / "factory.maze")).exit_code == 0


def test_the_simulator_drives_the_floors_end_to_end(suite, tmp_path):
    """No fake: ``straight`` crosses an open floor and hits a production line across its way."""
    across = {"type": "productionLine", "x": 700, "y": 525, "width": 300, "depth": 80, "rotation": 36}
    hand_floor(suite / "scenario-03.json", [across])  # on the straight line from start to goal
    out = tmp_path / "driven"
    result = invoke(str(suite), "-c", "straight", "--json", "-o", str(out))
    assert result.exit_code == 0, result.output
    records = {Path(r["file"]).name: r for r in map(json.loads, result.stdout.splitlines())}
    assert [records[f"scenario-0{n}.json"]["outcome"] for n in (1, 2, 3)] == [
        "arrived",
        "no path",
        "collision",
    ]
    arrived, crashed = records["scenario-01.json"], records["scenario-03.json"]
    assert arrived["score"] == 0.5 and arrived["collision"] is None and arrived["clearance"] > 0
    assert crashed["score"] == 0 and crashed["clearance"] == 0 and crashed["distance"] < arrived["distance"]
    document = read_document(out / "scenario-03.json")
    assert list(SCHEMA.iter_errors(document)) == []
    trajectory = document["drive"]["straight"]["trajectory"]
    assert trajectory[0][:2] == [60.0, 60.0] and math.dist(trajectory[-1][:2], crashed["collision"]) < 50


def test_score_prints_the_drive_of_each_controller_asked_for(suite, monkeypatch):
    fake = fake_drive(monkeypatch)
    spec, floor = str(EXAMPLES / "factory.maze"), str(suite / "scenario-01.json")
    result = CliRunner().invoke(main, ["score", spec, floor, "-c", "straight,dwa"], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[-2].startswith("drive straight\tcollision, ") and lines[-2].endswith("score 0")
    assert lines[-1].startswith("drive dwa\tarrived, ") and "closest 12.3 cm" in lines[-1]
    walled = str(suite / "scenario-02.json")
    result = CliRunner().invoke(
        main, ["score", spec, floor, walled, "-c", "dwa", "--json"], catch_exceptions=False
    )
    records = [json.loads(line) for line in result.stdout.splitlines()]
    assert [r["drive"]["dwa"]["outcome"] for r in records] == ["arrived", "no path"]
    assert "trajectory" not in records[0]["drive"]["dwa"]
    table = (
        CliRunner().invoke(main, ["score", spec, floor, walled, "-c", "dwa"], catch_exceptions=False).stdout
    )
    assert table.splitlines()[0].endswith("drive dwa") and table.splitlines()[2].endswith("no path")
    calls = len(fake.calls)
    plain = CliRunner().invoke(main, ["score", spec, floor], catch_exceptions=False)
    assert "drive" not in plain.stdout and len(fake.calls) == calls  # the factory spec names no controller


def test_score_drives_the_controllers_the_spec_names_by_default():
    from mazegen.runtime.documents._driving import spec_controllers
    from mazegen.spec import ControllerSpec, FitnessTerm

    spec = mazegen.load(EXAMPLES / "factory.maze")
    assert spec_controllers(spec) == []
    robot = robot_for(spec.arena, controllers=(ControllerSpec("purepursuit", (("lookahead", 50.0),)),))
    terms = (FitnessTerm("drive", metric="disagree", controllers=("dwa", "purepursuit")),)
    named = dataclasses.replace(spec, robot=robot, fitness=spec.fitness + terms)
    assert spec_controllers(named) == ["purepursuit", "dwa"]


def test_score_refuses_an_unknown_controller_in_one_line(suite):
    spec, floor = str(EXAMPLES / "factory.maze"), str(suite / "scenario-01.json")
    result = CliRunner().invoke(main, ["score", spec, floor, "-c", "nope"], catch_exceptions=False)
    assert result.exit_code == 2 and len(result.stderr.splitlines()) == 1 and "'nope'" in result.stderr


def test_a_drive_that_compiles_says_so_once_and_one_that_does_not_says_nothing(suite, monkeypatch):
    from numba import njit

    from mazegen.runtime.compiling import DRIVE_SECONDS, compile_note
    from mazegen.runtime.documents import _driving

    monkeypatch.undo()  # the real note, not the tests' silence (conftest)
    real_drive = _driving.drive_batches

    def drive_compiling(batches, names):  # as a drive whose controller was never compiled would
        njit(lambda x: x + 1)(1)
        njit(lambda x: x + 2)(1)
        return real_drive(batches, names)

    invoke(str(suite / "scenario-01.json"), "-c", "straight", "--json")  # compiles what is not cached
    quiet = invoke(str(suite / "scenario-01.json"), "-c", "straight", "--json")
    monkeypatch.setattr(_driving, "drive_batches", drive_compiling)
    noted = invoke(str(suite / "scenario-01.json"), "-c", "straight", "--json")
    assert quiet.exit_code == 0 and noted.exit_code == 0 and quiet.stdout == noted.stdout
    assert compile_note("drive", DRIVE_SECONDS) not in quiet.stderr
    assert noted.stderr.count(compile_note("drive", DRIVE_SECONDS)) == 1


def test_a_run_whose_arena_gives_no_robot_radius_drives_the_default_robot(suite, monkeypatch):
    fake = fake_drive(monkeypatch)
    spec = mazegen.load(EXAMPLES / "factory.maze")
    pointlike = dataclasses.replace(spec, arena=dataclasses.replace(spec.arena, robot_radius=0.0))
    (suite / "spec.json").write_text(pointlike.to_json(), encoding="utf-8")
    result = invoke(str(suite), "-c", "dwa", "--json")
    assert result.exit_code == 0, result.output
    assert fake.calls[0][2] == robot_for(pointlike.arena) and fake.calls[0][2].max_speed == 50


def test_a_px_arena_without_a_robot_radius_is_one_line_per_file_and_nothing_is_driven(suite, monkeypatch):
    fake = fake_drive(monkeypatch)
    spec = mazegen.load(EXAMPLES / "factory.maze")
    canvas = dataclasses.replace(spec, arena=dataclasses.replace(spec.arena, unit="px", robot_radius=0.0))
    (suite / "spec.json").write_text(canvas.to_json(), encoding="utf-8")
    result = invoke(str(suite), "-c", "dwa")
    assert result.exit_code == 1 and fake.calls == [] and result.stdout == ""
    assert result.stderr.splitlines() == [
        f"{suite / f'scenario-0{n}.json'}: arena 'floor' is in px with no robot radius: give it one "
        "('robot radius 25'), which sizes the driven robot"
        for n in (1, 2, 3)
    ]


def test_score_of_a_px_arena_without_a_robot_radius_names_the_spec(tmp_path, monkeypatch):
    fake = fake_drive(monkeypatch)
    spec = tmp_path / "canvas.maze"
    spec.write_text(
        "element box { shape square size 20..40 }\n"
        "arena canvas { size 900 x 900 px start (50, 50) goal (850, 850) }\n"
        "scenario s on canvas { elements box }\n",
        encoding="utf-8",
    )
    floor = tmp_path / "floor.json"
    floor.write_text(
        json.dumps({"format": "mazegen-scenario", "version": 1, "scenario": "s", "elements": []})
    )
    result = CliRunner().invoke(main, ["score", str(spec), str(floor), "-c", "dwa"], catch_exceptions=False)
    assert result.exit_code == 1 and fake.calls == []
    assert result.stderr.splitlines() == [
        f"{spec}: arena 'canvas' is in px with no robot radius: give it one ('robot radius 25'), "
        "which sizes the driven robot"
    ]


def test_a_drive_with_a_non_finite_number_writes_no_file_and_says_which_field(suite, monkeypatch):
    fake = fake_drive(monkeypatch)
    import mazegen.runtime.simulation as simulation

    def broken(*args, **kwargs):
        return [
            dataclasses.replace(episodes, time=np.where(np.arange(episodes.time.size) == 1, np.nan, 1.0))
            for episodes in fake.many(*args, **kwargs)
        ]

    monkeypatch.setattr(simulation, "drive_many", broken)
    before = {path.name: path.read_bytes() for path in suite.iterdir()}
    result = invoke(str(suite), "-c", "dwa", "-o", str(suite))  # in place
    assert result.exit_code == 1
    assert result.stderr.splitlines()[-1] == (
        f"{suite / 'scenario-03.json'}: drive.dwa.time is nan: a scenario file holds finite numbers only"
    )
    assert {path.name: path.read_bytes() for path in suite.iterdir()} == before


@pytest.mark.parametrize("name", [":x", ":", ".x:y", "x..y:z", "x:y:z", "math:"])
def test_a_malformed_policy_path_is_one_line_before_anything_is_read(tmp_path, monkeypatch, name):
    fake = fake_drive(monkeypatch)
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    for command in (["drive", str(bad)], ["score", str(EXAMPLES / "factory.maze"), str(bad)]):
        result = CliRunner().invoke(main, [*command, "-c", f"dwa,{name}"], catch_exceptions=False)
        assert result.exit_code == 2 and fake.calls == []
        assert result.stderr.splitlines() == [f"a policy's path reads package.module:name, got '{name}'"]


def with_arena(path: Path, elements: list[dict], **changes) -> Path:
    """A floor whose ``arena`` is the factory spec's with ``changes``."""
    from mazegen.runtime.documents._scenario import arena_document

    arena = {**arena_document(mazegen.load(EXAMPLES / "factory.maze")), **changes}
    document = {"format": "mazegen-scenario", "version": 1, "scenario": "factory", "elements": elements}
    path.write_text(json.dumps({**document, "arena": arena}), encoding="utf-8")
    return path


def test_a_floor_with_its_own_start_and_goal_is_driven_on_them_with_a_note(suite, monkeypatch):
    fake = fake_drive(monkeypatch)
    spec = str(EXAMPLES / "factory.maze")
    moved = with_arena(suite / "scenario-01.json", OPEN, start=[100, 120], goal=[1300, 900])
    note = (
        f"{moved}: driven with its own start (100, 120) and goal (1300, 900), not the spec's "
        "start (60, 60) and goal (1340, 990)"
    )
    for args in ([str(moved), "--spec", spec], [str(moved)], [str(suite)]):  # given, or found beside it
        result = invoke(*args, "-c", "dwa", "--json")
        assert result.exit_code == 0, result.output
        assert note in result.stderr.splitlines()
        record = json.loads(result.stdout.splitlines()[0])
        assert record["file"] == str(moved) and record["outcome"] == "arrived"
        # the fake drives from start to goal: 50 cm/s over the straight line between the floor's own
        assert record["optimal_time"] == pytest.approx(math.dist((100, 120), (1300, 900)) / 50, abs=1e-3)
    assert [indices for _, indices, _ in fake.calls] == [[0], [0], [0], [1]]  # its own batch, then the rest
    assert "own start" not in invoke(str(suite / "scenario-03.json"), "-c", "dwa").stderr
    score = CliRunner().invoke(main, ["score", spec, str(moved)], catch_exceptions=False)
    assert f"{moved}: scored with its own start (100, 120)" in score.stderr  # the same note


def test_a_floor_whose_arena_differs_otherwise_is_refused_saying_what_differs(
    suite, factory_run, tmp_path, monkeypatch
):
    fake = fake_drive(monkeypatch)
    wider = with_arena(suite / "scenario-01.json", OPEN, width=1500, unit="mm", start=[100, 120])
    differs = (
        "the arena of spec 'factory' differs from the scenario's: width 1400 in the spec, 1500 in the "
        "scenario; unit 'cm' in the spec, 'mm' in the scenario"
    )
    given = invoke(str(wider), "-c", "dwa", "--spec", str(EXAMPLES / "factory.maze"))
    assert given.exit_code == 1 and fake.calls == []
    assert given.stderr.splitlines() == [f"{wider}: {differs}"]
    run = tmp_path / "run"
    shutil.copytree(factory_run, run)
    best = run / "run-01" / "best-01.json"
    document = json.loads(best.read_text())
    best.write_text(json.dumps({**document, "arena": {**document["arena"], "width": 1500, "unit": "mm"}}))
    found = invoke(str(run), "-c", "dwa", "--json")  # its spec is the run's, beside it
    assert (
        found.exit_code == 1
        and len(found.stdout.splitlines()) == len(list(run.glob("run-*/best-*.json"))) - 1
    )
    assert (
        f"{best}: driving needs the spec the scenario was made under: {differs}" in found.stderr.splitlines()
    )


def test_out_holds_the_folder_so_a_second_drive_into_it_is_refused_and_loses_nothing(
    factory_run, tmp_path, monkeypatch
):
    from mazegen.runtime.runs import _locks as locks
    from mazegen.runtime.runs._results import RunDirectoryWriter

    if locks.fcntl is None:
        pytest.skip("folders are locked with flock")
    fake = fake_drive(monkeypatch)
    run = tmp_path / "run"
    shutil.copytree(factory_run, run)
    before = {path: path.read_bytes() for path in run.rglob("*") if path.is_file()}
    held = RunDirectoryWriter(run)
    held.lock()  # another mazegen process (a drive, a resume) writing there now
    refused = invoke(str(run), "-c", "dwa", "-o", str(run))
    held.close()
    assert refused.exit_code == 1 and fake.calls == []
    assert refused.stderr.splitlines() == [f"{run}: this folder is in use by another mazegen process"]
    assert {path: path.read_bytes() for path in run.rglob("*") if path.is_file()} == before

    def another_drive_meanwhile(*args, **kwargs):  # while this drive reads, drives and writes
        with pytest.raises(MazeError, match="in use by another mazegen process"):
            RunDirectoryWriter(run).lock()
        return fake(*args, **kwargs)

    monkeypatch.setattr(simulation, "drive", another_drive_meanwhile)
    assert invoke(str(run), "-c", "straight", "-o", str(run)).exit_code == 0
    assert invoke(str(run), "-c", "dwa", "-o", str(run)).exit_code == 0  # free again once it ended
    for path in run.glob("run-*/best-*.json"):
        assert set(read_document(path)["drive"]) == {"straight", "dwa"}


def test_file_names_are_printed_escaped(suite, tmp_path, monkeypatch):
    fake_drive(monkeypatch)
    weird = "we\x1b]0;TITLE\x07ird"  # printed raw, it would retitle the terminal
    floor = hand_floor(tmp_path / f"{weird}.json", WALL)
    driven = invoke(str(floor), "-c", "dwa", "--spec", str(EXAMPLES / "factory.maze"))
    written = invoke(str(suite), "-c", "dwa", "-o", str(tmp_path / weird))
    assert driven.exit_code == written.exit_code == 0 and (tmp_path / weird / "scenario-01.json").is_file()
    for output in (driven.stdout, driven.stderr, written.stderr):  # the table, no path, wrote
        assert "\x1b" not in output and "\x07" not in output
        assert "we\\x1b]0;TITLE\\x07ird" in output, output


def _suite_of(folder: Path, spec: Path, floors: list[list[dict]], scenario: str) -> Path:
    """A suite-like folder of ``spec``: its spec.json and one scenario file per floor."""
    folder.mkdir()
    (folder / "spec.json").write_text(mazegen.load(spec).to_json(), encoding="utf-8")
    for number, elements in enumerate(floors, start=1):
        document = {"format": "mazegen-scenario", "version": 1, "scenario": scenario, "elements": elements}
        (folder / f"scenario-{number:02d}.json").write_text(json.dumps(document), encoding="utf-8")
    return folder


def test_floors_of_several_specs_and_sources_drive_as_each_alone(tmp_path):
    """Suites of two specs, a floor on its own start and goal, and a plain folder of files, in one
    command: each floor's episodes are those of driving it alone (the real simulator)."""
    factory = _suite_of(tmp_path / "factory", EXAMPLES / "factory.maze", [OPEN, []], "factory")
    figures = [{"type": "square", "x": 450, "y": 450, "size": 100}]
    drawn = _suite_of(tmp_path / "drawn", EXAMPLES / "mazegen1.maze", [figures, []], "mazegen1")
    moved = json.loads((factory / "scenario-01.json").read_text())
    arena = arena_document(mazegen.load(EXAMPLES / "factory.maze"))
    (factory / "scenario-03.json").write_text(
        json.dumps({**moved, "arena": {**arena, "start": [100, 900], "goal": [1300, 100]}}), encoding="utf-8"
    )  # its own task: a batch of its own
    assert invoke(str(drawn), "-c", "straight", "-o", str(tmp_path / "written")).exit_code == 0
    loose = tmp_path / "loose"  # any folder: its scenario files, of the spec beside them
    loose.mkdir()
    shutil.copy(drawn / "spec.json", loose / "spec.json")
    shutil.copy(tmp_path / "written" / "scenario-02.json", loose / "copied.json")
    sources = [factory, drawn, loose]
    together = invoke(*map(str, sources), "--controller", "straight,purepursuit", "--json")
    assert together.exit_code == 0, together.output
    rows = [json.loads(line) for line in together.stdout.splitlines()]
    assert len(rows) == 6 * 2
    alone = []
    for file in [*sorted(factory.glob("scenario-*.json")), *sorted(drawn.glob("scenario-*.json"))]:
        result = invoke(str(file), "--controller", "straight,purepursuit", "--json")
        alone += [json.loads(line) for line in result.stdout.splitlines()]
    by_file = {(row["file"], row["controller"]): row for row in rows}
    for row in alone:
        assert by_file[(row["file"], row["controller"])] == row
    copied = [row for row in rows if row["file"].endswith("copied.json")]
    twin = [by_file[(str(drawn / "scenario-02.json"), name)] for name in ("straight", "purepursuit")]
    assert [row["outcome"] for row in copied] == [row["outcome"] for row in twin]


def test_two_sources_that_would_write_one_file_are_refused_before_any_is_written(suite, tmp_path):
    other = tmp_path / "other"
    shutil.copytree(suite, other)
    out = tmp_path / "out"
    result = invoke(
        str(suite / "scenario-01.json"), str(other / "scenario-01.json"), "-c", "straight", "-o", str(out)
    )
    assert result.exit_code == 1
    first, second = suite / "scenario-01.json", other / "scenario-01.json"
    assert result.stderr == (
        f"{out / 'scenario-01.json'}: {second} and {first} would both be written to this file: "
        "drive them into different folders\n"
    )
    assert not list(out.rglob("*.json"))
    assert invoke(str(suite), str(other), "-c", "straight", "-o", str(out)).exit_code == 0  # one folder each
    assert sorted(path.relative_to(out).as_posix() for path in out.rglob("*.json")) == [
        f"{folder}/scenario-{number:02d}.json" for folder in ("other", "suite") for number in (1, 2, 3)
    ]


def test_a_first_drive_compiles_its_bundled_controllers_ahead_and_a_later_one_does_not(suite, monkeypatch):
    import mazegen.runtime
    import mazegen.runtime.runs as runs

    fake_drive(monkeypatch)
    ahead: list[tuple] = []
    monkeypatch.setattr(runs, "compile_drive_kernels", lambda spec, names: ahead.append((spec.name, names)))
    monkeypatch.setattr(mazegen.runtime, "kernels_cached", lambda kernels=(): False)
    monkeypatch.syspath_prepend(str(EXAMPLES / "policies"))
    assert invoke(str(suite), "-c", "dwa", "-c", "gap_seeking:policy", "-c", "vfh").exit_code == 0
    assert ahead == [("factory", ["dwa", "vfh"])]  # a user's policy is not compiled ahead
    monkeypatch.setattr(mazegen.runtime, "kernels_cached", lambda kernels=(): True)
    assert invoke(str(suite), "-c", "dwa").exit_code == 0
    assert len(ahead) == 1
