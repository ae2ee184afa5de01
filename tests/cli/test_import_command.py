"""``mazegen import``: imported floors drive, export and score like any floor; mistakes are one line."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from mazegen.cli.main import main
from tests.conftest import EXAMPLES

WAREHOUSE = str(EXAMPLES / "maps" / "warehouse.yaml")
ROOMS = str(EXAMPLES / "maps" / "rooms.txt")
TASK = ["--start", "-1.5,-1.0", "--goal", "1.55,1.0"]


def test_an_imported_map_drives_exports_and_scores(tmp_path):
    runner = CliRunner()
    out = tmp_path / "warehouse"
    result = runner.invoke(main, ["import", WAREHOUSE, *TASK, "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert result.stdout == f"wrote 1 scenario of 9 walls and their spec to {out}\n"
    assert sorted(p.name for p in out.iterdir()) == ["scenario-01.json", "spec.json", "warehouse.maze"]
    drive = runner.invoke(main, ["drive", str(out), "--controller", "straight", "--json"])
    assert drive.exit_code == 0, drive.output
    assert json.loads(drive.stdout.splitlines()[0])["outcome"] in ("arrived", "collision", "timeout")
    for fmt in ("ros", "gazebo", "irsim"):
        export = runner.invoke(main, ["export", str(out), "--format", fmt, "-o", str(tmp_path / fmt)])
        assert export.exit_code == 0, export.output
    score = runner.invoke(main, ["score", str(out / "warehouse.maze"), str(out / "scenario-01.json")])
    assert score.exit_code == 0, score.output
    assert "solvable\tyes" in score.stdout


def test_an_import_does_not_replace_files_without_force(tmp_path):
    runner = CliRunner()
    arguments = ["import", ROOMS, "--tasks", "2", "-o", str(tmp_path)]
    assert runner.invoke(main, arguments).exit_code == 0
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    again = runner.invoke(main, [*arguments, "--seed", "9"])
    assert again.exit_code == 1 and "already exists (use --force" in again.stderr
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before


def _write(folder, name: str, text: str) -> str:
    (folder / name).write_text(text)
    return str(folder / name)


def _map(folder, yaml: str, image: bytes) -> str:
    """A map_server YAML and its image ``m.pgm``."""
    (folder / "m.pgm").write_bytes(image)
    return _write(folder, "m.yaml", "image: m.pgm\n" + yaml)


BARN_FILE = json.dumps({"worlds": [{"world": 4, "grid": ["...."] * 4}]})
MAP_YAML = "resolution: 1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"

BAD_IMPORTS = [
    (
        lambda d: [str(d / "missing.yaml"), "--tasks", "1"],
        "missing.yaml: cannot read map: No such file or directory",
    ),
    (
        lambda d: [_write(d, "m.yaml", "image: m.pgm\nresolution: [1\n"), "--tasks", "1"],
        "m.yaml:2: 'resolution' must be a list of numbers",
    ),
    (
        lambda d: [_map(d, MAP_YAML, b"P5\n4 4\n255\nabc"), "--tasks", "1"],
        "m.pgm: image size mismatch: the header says 4 x 4 = 16 pixels, the file holds 3",
    ),
    (
        lambda d: [_write(d, "m.yaml", "image: m.png\n" + MAP_YAML.replace("[0, 0, 0]", "[0, 0, 1.5]"))],
        "m.yaml: origin yaw 1.5 is not 0: MazeGen's arenas are not rotated (rotate the map first)",
    ),
    (
        lambda d: [WAREHOUSE, "--start", "-5,0", "--goal", "1,1"],
        "start (-5, 0) is outside the map, which spans x -2..2, y -1.5..1.5 (map frame)",
    ),
    (
        lambda d: [WAREHOUSE, "--start", "-1.5,-1.0", "--goal", "-0.95,0.5"],
        "goal (-0.95, 0.5) is on an obstacle: cell (column 10, row 19 from the bottom)",
    ),
    (
        lambda d: [WAREHOUSE, "--start", "-1.5,-1.0", "--goal", "-0.75,0.5"],
        "goal (-0.75, 0.5) is nearer an obstacle than the robot radius 0.3 m: "
        "cell (column 12, row 19 from the bottom)",
    ),
    (
        lambda d: [
            _write(d, "two.txt", "#######\n#..#..#\n#..#..#\n#######\n"),
            *("--start", "1.5,1.5", "--goal", "4.5,1.5", "--robot-radius", "0.2"),
        ],
        "start (1.5, 1.5) and goal (4.5, 1.5) are not connected for a robot of radius 0.2 m",
    ),
    (
        lambda d: [_write(d, "full.txt", "####\n####\n####\n####\n"), "--tasks", "2"],
        "no two free cells are connected for a robot of radius 0.3 m: no task can be drawn "
        "(give a smaller --robot-radius)",
    ),
    (
        lambda d: [_write(d, "g.txt", "..x.\n"), "--tasks", "1"],
        ("g.txt:1:3: 'x' is not a cell: write 0 or . for free, 1 or # for an obstacle"),
    ),
    (
        lambda d: [_write(d, "g.txt", "....\n...\n"), "--tasks", "1"],
        "g.txt:2: a row of 3 cells, the first row has 4",
    ),
    (lambda d: [WAREHOUSE], "warehouse.yaml: give --start X,Y and --goal X,Y, or --tasks N"),
    (lambda d: [WAREHOUSE, "--start", "0,0"], "--start and --goal go together"),
    (
        lambda d: [WAREHOUSE, "--start", "a,b", "--goal", "0,0"],
        "--start must be X,Y (two numbers in metres), got 'a,b'",
    ),
    (
        lambda d: [WAREHOUSE, "--tasks", "1", "--start", "0,0", "--goal", "1,1"],
        "--tasks draws starts and goals: give it or --start and --goal, not both",
    ),
    (
        lambda d: [WAREHOUSE, "--tasks", "1", "--resolution", "1"],
        "warehouse.yaml: --resolution is for .npy and .txt grids: this map gives its own",
    ),
    (
        lambda d: [ROOMS, "--tasks", "1", "--resolution", "0.001"],
        "--resolution must be from 0.01 to 1000 metres per cell, got 0.001",
    ),
    (
        lambda d: [str(EXAMPLES / "maps" / "warehouse.pgm"), "--tasks", "1"],
        "warehouse.pgm: unknown map format '.pgm': "
        "give a map_server .yaml, a .npy or .txt grid, or BARN's .json",
    ),
    (
        lambda d: [_write(d, "barn.json", BARN_FILE)],
        "barn.json: a file of 1 BARN worlds: choose one with --world N (worlds 4)",
    ),
    (
        lambda d: [_write(d, "barn.json", BARN_FILE), "--world", "5"],
        "barn.json: no world 5 in this file (worlds 4)",
    ),
]
"""Mistakes, each given to ``mazegen import`` in a folder of its own, and the one line it prints (after
the folder of the file it names)."""


@pytest.mark.parametrize(("arguments", "message"), BAD_IMPORTS, ids=[m[:40] for _, m in BAD_IMPORTS])
def test_mistakes_are_one_line_and_write_nothing(tmp_path, arguments, message):
    given = arguments(tmp_path)
    result = CliRunner().invoke(main, ["import", *given, "-o", str(tmp_path / "out")])
    assert not isinstance(result.exception, Exception), result.exception
    assert result.exit_code == 1, result.output
    lines = result.stderr.splitlines()
    assert len(lines) == 1, lines
    assert lines[0] in (message, f"{tmp_path}/{message}", f"{EXAMPLES}/maps/{message}")
    assert not (tmp_path / "out").exists()
