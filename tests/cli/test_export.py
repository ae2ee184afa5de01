"""`mazegen export` and `mazegen report` as a user runs them."""

from __future__ import annotations

import dataclasses
import json
import re
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

import mazegen
from mazegen.cli.main import main
from mazegen.export_formats import BUNDLED, OPTIONS
from mazegen.runtime.exporters._batch import export_plan
from mazegen.runtime.exporters._floor import ExportOptions
from tests.conftest import EXAMPLES
from tests.runtime.floors import floor_file

SUFFIXES = {
    "ros": {".pgm", ".yaml"},
    "gazebo": {".sdf"},
    "irsim": {".yaml"},
    "movingai": {".map", ".scen"},
    "json": {".json"},
    "svg": {".svg"},
    "png": {".png"},
}


def invoke(*args: str):
    return CliRunner().invoke(main, list(args), catch_exceptions=False)


def files(directory: Path) -> dict[str, bytes]:
    return {
        str(p.relative_to(directory)): p.read_bytes() for p in sorted(directory.rglob("*")) if p.is_file()
    }


def test_every_format_has_a_row_whose_writer_and_options_exist():
    assert list(BUNDLED) == list(SUFFIXES)
    assert tuple(field.name for field in dataclasses.fields(ExportOptions)) == OPTIONS
    for row in BUNDLED.values():
        assert callable(row.load_writer()) and set(row.options) <= set(OPTIONS) and row.summary


@pytest.mark.parametrize("fmt", list(BUNDLED))
def test_a_run_directory_exports_every_best_scenario_the_same_way_twice(factory_run, tmp_path, fmt):
    out = tmp_path / "out"
    result = invoke("export", str(factory_run), "--format", fmt, "-o", str(out))
    assert result.exit_code == 0, result.output
    written = files(out)
    names = {f"{run}/best-{rank:02d}{suffix}" for run in ("run-01", "run-02") for rank in range(1, 5)
             for suffix in SUFFIXES[fmt]}  # fmt: skip
    assert set(written) == names
    assert result.output == f"wrote {len(names)} files to {out}\n"
    again = invoke("export", str(factory_run), "--format", fmt, "-o", str(out), "--force")
    assert again.exit_code == 0 and files(out) == written


def test_one_scenario_exports_beside_itself_by_default(factory_run, tmp_path):
    run = tmp_path / "run"
    shutil.copytree(factory_run, run)
    scenario = run / "run-01" / "best-02.json"
    assert invoke("export", str(scenario), "-f", "ros").exit_code == 0
    assert sorted(p.name for p in (run / "run-01" / "exports" / "ros").iterdir()) == [
        "best-02.pgm",
        "best-02.yaml",
    ]
    assert invoke("export", str(run), "-f", "movingai").exit_code == 0
    assert (run / "exports" / "movingai" / "run-02" / "best-04.scen").is_file()


def test_a_hand_drawn_floor_exports_with_its_spec(tmp_path):
    path = floor_file(
        tmp_path / "floor.json", {"type": "productionLine", "x": 700, "y": 525, "width": 500, "depth": 80}
    )
    without = invoke("export", str(path), "-f", "svg")
    assert without.exit_code == 1
    assert (
        without.stderr.strip()
        == f"{path}: the scenario's elements have no 'parts': give --spec SPEC.maze to compute them"
    )
    result = invoke(
        "export", str(path), "-f", "json", "--spec", str(EXAMPLES / "factory.maze"), "-o", str(tmp_path)
    )
    assert result.exit_code == 1 and "already exists" in result.stderr  # it would replace the floor itself
    result = invoke("export", str(path), "-f", "json", "--spec", str(EXAMPLES / "factory.maze"))
    assert result.exit_code == 0, result.output
    document = json.loads((tmp_path / "exports" / "json" / "floor.json").read_text())
    assert document["elements"][0]["parts"] and document["metrics"]["solvable"] and len(document["path"]) >= 2


HALL = """import manufacturing
arena hall { map "warehouse.yaml" cm  start (60, 60)  goal (355, 230)  robot radius 20  grid 5 }
scenario hall on hall { elements cobot, router  max elements 8 }
fitness { count  solvable required }
"""
"""An arena on examples/maps/warehouse.yaml."""


@pytest.fixture(scope="module")
def hall_run(tmp_path_factory) -> Path:
    """A small run of :data:`HALL` (one run, two best scenarios) in ``run`` beside the spec and its map;
    do not modify it."""
    folder = tmp_path_factory.mktemp("hall")
    for suffix in (".yaml", ".pgm"):
        shutil.copy(EXAMPLES / "maps" / f"warehouse{suffix}", folder)
    spec = mazegen.load(write(folder / "hall.maze", HALL)).with_evolution(best=2)
    mazegen.run(spec, runs=1, population=30, generations=1, out_dir=folder / "run")
    return folder


def test_a_floor_on_a_map_is_exported_and_drawn_with_its_walls_or_not_at_all(hall_run, tmp_path):
    run, spec = hall_run / "run", ["--spec", str(hall_run / "hall.maze")]
    drawn = (run / "run-01" / "best-01.svg").read_text()
    assert '<g class="walls"' in drawn  # the run's own pictures
    for fmt in BUNDLED:
        result = invoke("export", str(run), "-f", fmt, "-o", str(tmp_path / fmt))
        assert result.exit_code == 0, (fmt, result.output)
    assert '<model name="map_walls">' in (tmp_path / "gazebo" / "run-01" / "best-01.sdf").read_text()
    assert invoke("report", str(run), "-o", str(tmp_path / "report.html")).exit_code == 0
    # Taken out of its run folder, the floor names its map but has lost the map's cells.
    alone = write(tmp_path / "alone" / "best-01.json", (run / "run-01" / "best-01.json").read_text())
    needs = "needs its spec: give --spec SPEC.maze (scenarios in a run or suite directory find it there)"
    needed = {"ros": "an occupancy map", "gazebo": "a Gazebo world", "irsim": "an IR-SIM world",
              "movingai": "a grid map", "svg": "its picture", "png": "its picture"}  # fmt: skip
    for fmt, what in needed.items():
        result = invoke("export", str(alone), "-f", fmt, "-o", str(tmp_path / "out"))
        assert result.exit_code == 1
        assert result.stderr == f"{alone}: the floor is built on map 'warehouse.yaml': {what} {needs}\n"
        given = invoke("export", str(alone), "-f", fmt, "-o", str(tmp_path / "given" / fmt), *spec)
        assert given.exit_code == 0, given.output
    assert not (tmp_path / "out").exists()
    picture = tmp_path / "alone" / "best-01.svg"
    result = invoke("render", str(alone), "-o", str(picture))
    assert result.exit_code == 1 and "its picture needs its spec" in result.stderr and not picture.exists()
    assert invoke("render", str(alone), "-o", str(picture), *spec).exit_code == 0
    assert picture.read_text() == drawn
    picture.unlink()
    assert invoke("render", str(run / "run-01" / "best-01.json"), "-o", str(picture)).exit_code == 0
    assert picture.read_text() == drawn  # its spec found beside it


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def test_user_mistakes_are_one_line_errors(factory_run, tmp_path):
    alone = write(tmp_path / "alone" / "best-01.json", (factory_run / "run-01" / "best-01.json").read_text())
    other = write(tmp_path / "other.json", '{"format": "something"}')
    damaged = json.loads(alone.read_text())
    damaged["elements"][1]["x"] = "left"
    damaged = write(tmp_path / "damaged" / "best-01.json", json.dumps(damaged))
    cases = [
        (["export", str(other), "-f", "svg"], 1, f"{other}: not a scenario file"),
        (["export", str(tmp_path / "alone"), "-f", "svg"], 1, "not a run or suite directory"),
        (["export", str(damaged), "-f", "gazebo"], 1, f"{damaged}: elements[1].x: must be a number"),
        (["export", str(alone), "-f", "ros"], 1, "needs the spec the scenario was made under"),
        (["export", str(alone), "-f", "movingai", "--spec", str(EXAMPLES / "workshop.maze")], 1,
         "the arena of spec 'workshop' differs from the scenario's"),
        (["export", str(factory_run), "-f", "movingai", "--cell", "-2", "-o", str(tmp_path / "m")], 1,
         "--cell must be a positive number of arena units, got -2"),
        (["export", str(alone), "-f", "gazebo", "--scale", "0"], 1,
         "--scale must be from 1e-06 to 1000 metres per arena unit, got 0"),
        (["export", str(alone), "-f", "svg", "--cell", "25"], 1,
         "--cell does not apply to svg exports (only to ros, movingai)"),
        (["export", str(alone), "-f", "obj"], 1,
         "unknown export format 'obj' (bundled: ros, gazebo, irsim, movingai, json, svg, png)"),
        (["export", str(tmp_path / "missing.json"), "-f", "svg"], 2, "does not exist"),
        (["report", str(tmp_path / "alone")], 1, "not a run, suite or sweep folder"),
    ]  # fmt: skip
    for args, status, message in cases:
        result = invoke(*args)
        assert result.exit_code == status, (args, result.output)
        assert message in result.stderr, (args, result.stderr)
        assert "Traceback" not in result.output
        if status == 1:
            assert len(result.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "m").exists()  # nothing written when one scenario fails


def test_a_ros_map_is_made_on_the_cells_asked_for(factory_run, tmp_path):
    """``--cell`` sets the ROS map's resolution as it does the MovingAI map's (it was ignored)."""
    for cell, out in ((None, tmp_path / "default"), ("25", tmp_path / "coarse")):
        extra = [] if cell is None else ["--cell", cell]
        assert invoke("export", str(factory_run), "-f", "ros", "-o", str(out), *extra).exit_code == 0
    default, coarse = (d / "run-01" / "best-01" for d in (tmp_path / "default", tmp_path / "coarse"))
    assert "resolution: 0.125\n" in default.with_suffix(".yaml").read_text()  # the spec's grid 12.5 cm
    assert "resolution: 0.25\n" in coarse.with_suffix(".yaml").read_text()
    # 1400 x 1050 cm on cells of 25 cm, framed by one cell on each side
    assert coarse.with_suffix(".pgm").read_bytes().startswith(b"P5\n58 44\n255\n")
    assert default.with_suffix(".pgm").read_bytes().startswith(b"P5\n114 86\n255\n")


def test_existing_exports_are_kept_without_force(factory_run, tmp_path):
    out = tmp_path / "out"
    assert invoke("export", str(factory_run), "-f", "svg", "-o", str(out)).exit_code == 0
    mark = out / "run-02" / "best-03.svg"
    mark.write_text("mine")
    result = invoke("export", str(factory_run), "-f", "svg", "-o", str(out))
    assert result.exit_code == 1 and "already exists (use --force" in result.stderr
    assert mark.read_text() == "mine"


def test_report_writes_one_page_and_keeps_an_existing_one(factory_run, tmp_path):
    page = tmp_path / "report.html"
    result = invoke("report", str(factory_run), "-o", str(page))
    assert result.exit_code == 0 and result.output == f"wrote {page}\n"
    text = page.read_text()
    assert text.startswith("<!DOCTYPE html>") and text.count("<figure>") == 2  # the best of each run
    page.write_text("mine")
    refused = invoke("report", str(factory_run), "-o", str(page))
    assert refused.exit_code == 1 and "already exists" in refused.stderr and page.read_text() == "mine"
    assert invoke("report", str(factory_run), "-o", str(page), "--force").exit_code == 0
    assert page.read_text() == text


HOSTILE_STEM = "we--ird\x01\t\n <&]]>\x7f"


@pytest.mark.parametrize("fmt", list(BUNDLED))
def test_a_hostile_file_name_gives_files_that_parse(factory_run, tmp_path, fmt):
    source = tmp_path / f"{HOSTILE_STEM}.json"
    shutil.copy(factory_run / "run-01" / "best-01.json", source)
    out = tmp_path / "out"
    result = invoke(
        "export", str(source), "-f", fmt, "-o", str(out), "--spec", str(EXAMPLES / "factory.maze")
    )
    assert result.exit_code == 0, result.output
    written = {path.name: path.read_bytes() for path in out.iterdir()}
    assert all(name.isprintable() and " " not in name for name in written), sorted(written)
    for name, data in written.items():
        if name.endswith((".sdf", ".svg")):
            ET.fromstring(data)  # well-formed XML
        elif name.endswith(".yaml"):
            document = yaml.safe_load(data)
            assert document["image"] in written if fmt == "ros" else document["obstacle"]
        elif name.endswith(".scen"):
            problem = data.decode("utf-8").splitlines()[1].split("\t")
            assert len(problem) == 9 and problem[1] in written
        elif name.endswith(".json"):
            assert json.loads(data)["elements"]


def test_a_file_name_no_encoding_can_write_exports_that_parse(factory_run, tmp_path):
    source = tmp_path / "best\udcff\x1b[2J.json"  # a byte that is not UTF-8, and a terminal escape
    shutil.copy(factory_run / "run-01" / "best-01.json", source)
    spec = mazegen.load(EXAMPLES / "factory.maze")
    for fmt in ("gazebo", "ros", "movingai"):
        files = export_plan(source, BUNDLED[fmt], tmp_path / fmt, spec=spec)
        assert {path.name for path in files} <= {f"best__[2J{suffix}" for suffix in SUFFIXES[fmt]}
        for path, data in files.items():
            if path.suffix == ".sdf":
                ET.fromstring(data)
            elif path.suffix == ".yaml":
                assert yaml.safe_load(data)["image"] == "best__[2J.pgm"
            elif path.suffix == ".scen":
                assert data.decode("utf-8").splitlines()[1].split("\t")[1] == "best__[2J.map"


def webots_files(floor, options):
    """A plug-in's writer: one text file per scenario, named after it."""
    return {f"{floor.name}.wbt": f"# {floor.name} at {options.scale} m per unit\n"}


webots_files.options = ("scale",)


def test_a_registered_format_exports_like_a_bundled_one(factory_run, tmp_path, register_plugins):
    register_plugins("exporters", {"webots": webots_files})
    out = tmp_path / "out"
    result = invoke("export", str(factory_run), "-f", "webots", "--scale", "0.5", "-o", str(out))
    assert result.exit_code == 0, result.output
    assert files(out)["run-02/best-03.wbt"] == b"# best-03 at 0.5 m per unit\n"
    assert len(files(out)) == 8


def _raises(floor, options):
    raise RuntimeError("no Webots here")


def _one_name(floor, options):
    return {"world.wbt": b""}


WEBOTS = "exporter plug-in 'webots' of fake-plugins 1.0"

PLUGIN_MISTAKES = [
    (_raises, f"{WEBOTS} fails (RuntimeError: no Webots here)"),
    (lambda floor, options: [b""], f"{WEBOTS} returns list, not a dict of file names to bytes or str"),
    (
        lambda floor, options: {"../up.wbt": b""},
        f"{WEBOTS} returns the file name '../up.wbt': a file's name, not a path",
    ),
    (
        lambda floor, options: {"..": b""},
        f"{WEBOTS} returns the file name '..': a file's name, not a path",
    ),
    (
        lambda floor, options: {"a.wbt": 3},
        f"{WEBOTS} returns int for 'a.wbt', not bytes or UTF-8 text",
    ),
    (
        lambda floor, options: {"a.wbt": "\ud800"},
        f"{WEBOTS} returns str for 'a.wbt', not bytes or UTF-8 text",
    ),
    (
        _one_name,
        f"{WEBOTS} writes 'world.wbt' for another scenario too "
        "(name each file after the scenario: floor.name)",
    ),
]


@pytest.mark.parametrize(
    ("writer", "message"),
    PLUGIN_MISTAKES,
    ids=["raises", "list", "path", "dot-dot", "int", "surrogate", "one-name"],
)
def test_a_plugin_writers_mistake_is_one_line_naming_it_and_nothing_is_written(
    factory_run, tmp_path, register_plugins, writer, message
):
    register_plugins("exporters", {"webots": writer})
    out = tmp_path / "out"
    result = invoke("export", str(factory_run), "-f", "webots", "-o", str(out))
    assert result.exit_code == 1
    (line,) = result.stderr.splitlines()
    assert line.startswith(str(factory_run / "run-01")) and line.endswith(message), line
    assert not out.exists()


def test_a_plugin_of_a_bundled_name_is_not_used_and_a_note_says_so(factory_run, tmp_path, register_plugins):
    register_plugins("exporters", {"svg": _raises})
    result = invoke("export", str(factory_run), "-f", "svg", "-o", str(tmp_path / "out"))
    assert result.exit_code == 0, result.output
    assert (
        result.stderr
        == "note: exporter plug-in 'svg' of fake-plugins 1.0 is not used: 'svg' is a bundled format\n"
    )
    assert (tmp_path / "out" / "run-01" / "best-01.svg").is_file()


def test_docs_list_every_format_as_its_row_says():
    """docs/exports.md's table of formats is the table of :data:`BUNDLED`: name, options, summary."""
    page = (Path(__file__).resolve().parents[2] / "docs" / "exports.md").read_text(encoding="utf-8")
    listed = re.findall(r"^\| `(\w+)` \| (.*) \| (.*) \|$", page, flags=re.M)
    expected = [
        (row.name, ", ".join(f"`--{option}`" for option in row.options) or "none", row.summary)
        for row in BUNDLED.values()
    ]
    assert listed == expected
    for name in BUNDLED:
        assert re.search(rf"^## .*`{name}`", page, flags=re.M), f"docs/exports.md has no section on {name}"
