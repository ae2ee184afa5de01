"""A user's measure of a floor as a fitness term: from a file or an installed package, in runs on
every executor, and each way it can go wrong said in one located line."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from mazegen import api
from mazegen.errors import MazeError
from mazegen.metric_plugins import metric_function
from mazegen.runtime.plugin_view import Floors
from tests.runtime.floors import ARENA, NAMES, ZIGZAG, population
from tests.runtime.rundirs import file_digests

HEAD = """\
element box { shape square size 40..120 }
arena floor { size 1000 x 800 cm start (50, 50) goal (950, 750) robot radius 20 }
scenario s on floor { elements box max elements 12 }
"""
EVOLUTION = "evolution { population 60 generations 4 genome 24 seed 3 }\n"

DOCK = '''\
import numpy as np


def dock_clearance(floors, x=500.0, y=400.0):
    """Distance from the dock at (x, y) to the nearest element's bounding box, metres (at most 5)."""
    box = floors.bounds
    dx = np.maximum(np.maximum(box[..., 0] - x, x - box[..., 2]), 0.0)  # NaN in empty slots
    dy = np.maximum(np.maximum(box[..., 1] - y, y - box[..., 3]), 0.0)
    nearest = np.fmin.reduce(np.hypot(dx, dy), axis=1, initial=np.inf)  # fmin skips NaN
    return np.minimum(nearest * floors.metres_per_unit, 5.0)
'''


def _spec(folder: Path, fitness: str) -> Path:
    (folder / "dock.py").write_text(DOCK, encoding="utf-8")
    path = folder / "spec.maze"
    path.write_text(HEAD + f"fitness {{\n    count\n    {fitness}\n}}\n" + EVOLUTION, encoding="utf-8")
    return path


def _best(path: Path, out: Path, **options) -> dict:
    result = api.run(path, out_dir=out, catalog=False, **options)
    return result.best[0][0]


def _dock_clearance(document: dict) -> float:
    """The plug-in's measure of a written scenario's squares, by hand (arena units)."""
    boxes = [(e["x"], e["y"], e["size"] / 2) for e in document["elements"]]
    return min(max(abs(x - 500) - h, abs(y - 400) - h, 0.0) for x, y, h in boxes)


def test_a_file_metric_changes_which_floors_win(tmp_path):
    plain = _best(_spec(tmp_path, "solvable required"), tmp_path / "plain")
    docked = _best(_spec(tmp_path, 'metric dock_clearance from "dock.py" weight 20'), tmp_path / "docked")
    assert docked["terms"]["dock_clearance"] > 0
    assert "dock_clearance" not in plain["terms"]
    assert docked["elements"] != plain["elements"]
    assert _dock_clearance(docked) > _dock_clearance(plain)


def test_an_installed_metric_scores_like_the_same_file(tmp_path, register_plugins):
    namespace: dict = {}
    exec(compile(DOCK, "dock.py", "exec"), namespace)
    register_plugins("metrics", {"dock_clearance": namespace["dock_clearance"]})
    by_file = _best(_spec(tmp_path, 'metric dock_clearance(x=300) from "dock.py" range 1..2'), tmp_path / "a")
    installed = _best(_spec(tmp_path, "metric dock_clearance(x=300) range 1..2"), tmp_path / "b")
    assert by_file["terms"] == installed["terms"] and by_file["elements"] == installed["elements"]


def test_a_plugin_run_writes_the_same_files_on_every_executor(tmp_path, register_plugins):
    """File plug-ins load in every worker; a worker lacking an installed plug-in's package names it."""
    distributed = pytest.importorskip("distributed")
    path = _spec(tmp_path, 'metric dock_clearance from "dock.py" penalty 3')
    api.run(path, out_dir=tmp_path / "serial", catalog=False, runs=2)
    api.run(path, out_dir=tmp_path / "local", catalog=False, runs=2, executor="local", workers=2)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None
    ) as cluster:
        dask = {"executor": "dask", "scheduler": cluster.scheduler_address}
        api.run(path, out_dir=tmp_path / "dask", catalog=False, runs=2, **dask)
        register_plugins("metrics", {"far_from_dock": lambda floors: floors.x[:, 0]})  # here, not there
        with pytest.raises(MazeError) as caught:
            api.run(
                _spec(tmp_path, "metric far_from_dock"), out_dir=tmp_path / "lacking", catalog=False, **dask
            )
    serial = file_digests(tmp_path / "serial")
    assert any("best" in name for name in serial)
    assert file_digests(tmp_path / "local") == serial
    assert file_digests(tmp_path / "dask") == serial
    assert str(caught.value).endswith(
        "metric 'far_from_dock': metric plug-in 'far_from_dock' is not installed in this environment: no "
        "package registers it under mazegen.metrics (install fake-plugins here)"
    )


def test_a_reject_term_rejects_above_its_threshold(tmp_path):
    best = _best(_spec(tmp_path, 'metric dock_clearance from "dock.py" reject above 0.5'), tmp_path / "out")
    assert "dock_clearance" not in best["terms"]
    assert _dock_clearance(best) * 0.01 <= 0.5 + 1e-9


# (name, the plug-in's body after `def bad(floors):`, the message after `spec.maze:6:5: metric 'bad': `)
BAD_PLUGINS = [
    (
        "wrong shape",
        "return np.zeros((floors.size, 2))",
        "the plug-in must return one number per floor, float64[60], got float64[60, 2]",
    ),
    ("one number", "return 1.0", "the plug-in must return one number per floor, float64[60], got float64[]"),
    (
        "text",
        "return np.array(['x'] * floors.size)",
        "the plug-in must return one number per floor, float64[60], got <U1[60]",
    ),
    (
        "NaN",
        "return np.full(floors.size, np.nan)",
        "the plug-in returned nan for floor 0 (a value must be finite)",
    ),
    ("raises", "raise KeyError('dock')", "the plug-in raised KeyError: 'dock'"),
    (
        "ragged",
        "return [[1.0], [1.0, 2.0]]",
        "the plug-in must return one number per floor, float64[60], got a list that is no array",
    ),
    (
        "writes the floors",
        "floors.x[0, 0] = 1.0",
        "the plug-in raised ValueError: assignment destination is read-only",
    ),
]


@pytest.mark.parametrize(("name", "body", "message"), BAD_PLUGINS, ids=[row[0] for row in BAD_PLUGINS])
def test_a_bad_plugin_is_one_located_line(tmp_path, name, body, message):
    (tmp_path / "bad.py").write_text(
        f"import numpy as np\n\n\ndef bad(floors):\n    {body}\n", encoding="utf-8"
    )
    path = _spec(tmp_path, 'metric bad from "bad.py"')
    with pytest.raises(MazeError) as caught:
        api.run(path, out_dir=tmp_path / "out", catalog=False)
    assert str(caught.value) == f"{caught.value.filename}:6:5: metric 'bad': {message}"
    assert caught.value.filename.endswith("spec.maze")


def test_a_machine_without_the_package_names_it():
    with pytest.raises(MazeError) as caught:
        metric_function("aisle_width", None, "mazegen-warehouse")
    assert str(caught.value) == (
        "metric plug-in 'aisle_width' is not installed in this environment: no package registers it "
        "under mazegen.metrics (install mazegen-warehouse here)"
    )


def test_the_floors_view_reads_its_population_and_cannot_write_it():
    pop = population(ARENA, [ZIGZAG, [("router", 500, 300, 30, 30, 90)], []])
    floors = Floors(pop, tuple(NAMES))
    assert floors.size == 3 and floors.slots == 2
    assert floors.count.tolist() == [2, 1, 0] and floors.count.dtype == np.int64
    assert [floors.types[t] for t in floors.type[0]] == ["vwall", "vwall"] and floors.type[1, 1] == -1
    assert floors.x[0].tolist() == [330, 660] and floors.depth[0, 0] == 450
    assert floors.rotation[1, 0] == pytest.approx(np.pi / 2)
    assert floors.bounds.shape == (3, 2, 4) and np.isnan(floors.bounds[1, 1]).all()
    assert floors.bounds[0, 0].tolist() == pytest.approx([320, 0, 340, 450])
    assert floors.solvable.tolist() == [True, True, True]
    assert floors.path_length[0] > floors.path_length[2] == pytest.approx(math.dist(ARENA.start, ARENA.goal))
    assert [path is not None for path in floors.paths] == [True, True, True]
    free = floors.free(0)
    assert free.shape == (60, 100) and free.dtype == bool and not free[20, 33] and free[50, 33]
    assert [part.shape for part in floors.outline(0, 1)] == [(4, 2)]
    assert floors.metres_per_unit == 0.01 and floors.robot_radius == 20 and floors.cell == 10
    for array in (floors.x, floors.type, floors.count, floors.valid, floors.bounds, floors.solvable):
        with pytest.raises(ValueError, match="read-only"):
            array.flat[0] = 1
    with pytest.raises(IndexError, match="floor 1 has 1 elements, not 2"):
        floors.outline(1, 1)


def test_a_plugin_term_works_in_every_command(tmp_path):
    """Resume, sweep, suite, score, drive and a build's own experiment.py all score with it."""
    from click.testing import CliRunner

    from mazegen.cli.main import main

    path = _spec(tmp_path, 'metric dock_clearance(y=600) from "dock.py" weight 5')

    def ok(*arguments: str | Path) -> str:
        done = CliRunner().invoke(main, [str(a) for a in arguments], catch_exceptions=False)
        assert done.exit_code == 0, done.output
        return done.output

    ok("run", path, "-o", tmp_path / "run", "-q")
    ok("sweep", path, "--set", "seed=1..2", "-o", tmp_path / "sweep", "-q")
    cells = sorted((tmp_path / "sweep").glob("*/run-01/best-01.json"))
    assert len(cells) == 2 and all("dock_clearance" in _terms(cell) for cell in cells)
    ok("suite", path, "--size", "4", "--iterations", "2", "--batch", "30", "-o", tmp_path / "suite", "-q")
    assert all(
        "dock_clearance" in _terms(file)
        for file in (tmp_path / "suite").glob("*.json")
        if "terms" in file.read_text()
    )
    best = tmp_path / "run" / "run-01" / "best-01.json"
    assert "dock_clearance" in ok("score", path, best)
    ok("drive", tmp_path / "run", "--controller", "straight", "-o", tmp_path / "driven")
    assert "dock_clearance" in _terms(next((tmp_path / "driven").rglob("best-01.json")))
    ok("build", path, "-o", tmp_path / "build")
    generated = subprocess.run(
        [sys.executable, "experiment.py", "-o", tmp_path / "generated"],
        cwd=tmp_path / "build",
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert generated.returncode == 0, generated.stderr
    assert "dock_clearance" in _terms(tmp_path / "generated" / "run-01" / "best-01.json")


def _terms(file: Path) -> dict:
    return json.loads(file.read_text(encoding="utf-8")).get("terms") or {}


STOPPING = """
import os

calls = 0


def interrupting(floors):
    # The dock's clearance; Ctrl-C at the STOP_AT-th call once STOP_AT is set, as a user would press it.
    global calls
    if os.environ.get("STOP_AT"):
        calls += 1
        if calls == int(os.environ["STOP_AT"]):
            raise KeyboardInterrupt
    return dock_clearance(floors)
"""


def test_a_plugin_run_resumes_as_if_never_interrupted(tmp_path, monkeypatch):
    (tmp_path / "stop.py").write_text(DOCK + STOPPING, encoding="utf-8")
    path = _spec(tmp_path, 'metric interrupting from "stop.py" weight 5')
    api.run(path, out_dir=tmp_path / "whole", catalog=False, runs=2)
    monkeypatch.setenv("STOP_AT", "7")  # in the second run: the first evaluates 5 generations
    with pytest.raises(KeyboardInterrupt):
        api.run(path, out_dir=tmp_path / "stopped", catalog=False, runs=2, checkpoint_every=1)
    monkeypatch.delenv("STOP_AT")
    api.resume(tmp_path / "stopped", catalog=False)
    assert file_digests(tmp_path / "stopped") == file_digests(tmp_path / "whole")
