"""The worked plug-in package of examples/plugins, installed for real (pip, offline) into an
environment of its own, and used through every command: its library imported by name, its metric
changing which floors win, its policy driven, its format exported."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import EXAMPLES

PACKAGE = EXAMPLES / "plugins"
SMALL = ["--population", "60", "--generations", "3", "-q"]


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> dict[str, str]:
    """The environment of a Python that has the plug-in package installed besides this one's
    packages: pip installs a copy (so that the build leaves the checkout clean) into a folder of
    its own, which leads the search path."""
    root = tmp_path_factory.mktemp("plugins")
    source = shutil.copytree(PACKAGE, root / "source")
    install = [
        sys.executable,
        "-m",
        "pip",
        "install",
        "-q",
        "--no-deps",
        "--no-build-isolation",
        "--no-index",
    ]
    subprocess.run(
        [*install, "--target", root / "site", source], check=True, capture_output=True, timeout=300
    )
    return {
        **os.environ,
        "PYTHONPATH": os.pathsep.join(filter(None, [str(root / "site"), os.environ.get("PYTHONPATH")])),
    }


def mazegen(env: dict[str, str], *arguments: str | Path, cwd: Path) -> subprocess.CompletedProcess:
    command = [sys.executable, "-m", "mazegen", *map(str, arguments)]
    done = subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr
    return done


@pytest.fixture(scope="module")
def runs(installed, tmp_path_factory) -> Path:
    """The example spec run with its metric and without it."""
    folder = tmp_path_factory.mktemp("warehouse")
    spec = (PACKAGE / "warehouse.maze").read_text(encoding="utf-8")
    (folder / "docked.maze").write_text(spec, encoding="utf-8")
    plain = "\n".join(line for line in spec.splitlines() if "dock_clearance" not in line)
    (folder / "plain.maze").write_text(plain + "\n", encoding="utf-8")
    for name in ("docked", "plain"):
        mazegen(installed, "run", f"{name}.maze", "-o", name, *SMALL, cwd=folder)
    return folder


def test_every_plugin_is_listed_with_its_package(installed, tmp_path):
    listed = [
        json.loads(line) for line in mazegen(installed, "plugins", "--json", cwd=tmp_path).stdout.splitlines()
    ]
    ours = {(row["kind"], row["name"]) for row in listed if row["origin"] == "mazegen-warehouse 1.0"}
    assert ours == {
        ("libraries", "warehouse"),
        ("metrics", "dock_clearance"),
        ("controllers", "cautious"),
        ("exporters", "layout-csv"),
    }


def test_its_library_is_imported_by_name_only_where_it_is_installed(installed, tmp_path):
    spec = PACKAGE / "warehouse.maze"
    assert mazegen(installed, "check", spec, cwd=tmp_path).stdout.strip().endswith("warehouse.maze: OK")
    lacking = subprocess.run(
        [sys.executable, "-m", "mazegen", "check", spec], capture_output=True, text=True, cwd=tmp_path
    )
    assert lacking.returncode != 0 and lacking.stderr.count("\n") == 1
    assert "unknown library 'warehouse'" in lacking.stderr


def test_its_metric_changes_which_floors_win(runs):
    docked = json.loads((runs / "docked" / "run-01" / "best-01.json").read_text(encoding="utf-8"))
    plain = json.loads((runs / "plain" / "run-01" / "best-01.json").read_text(encoding="utf-8"))
    assert "dock_clearance" in docked["terms"] and "dock_clearance" not in plain["terms"]
    assert docked["elements"] != plain["elements"]


def test_its_metric_scores_saved_scenarios(installed, runs):
    scored = mazegen(installed, "score", "docked.maze", "docked/run-01/best-01.json", cwd=runs).stdout
    assert "dock_clearance" in scored


def test_its_policy_drives(installed, runs):
    done = mazegen(installed, "drive", "docked", "--controller", "cautious", "--json", cwd=runs)
    rows = [json.loads(line) for line in done.stdout.splitlines()]
    assert rows and {row["controller"] for row in rows} == {"cautious"}
    assert all(row["outcome"] in ("arrived", "collision", "timeout", "no path") for row in rows)


def test_its_format_exports(installed, runs, tmp_path):
    out = tmp_path / "csv"
    mazegen(installed, "export", "docked", "--format", "layout-csv", "-o", out, "--scale", "0.01", cwd=runs)
    tables = sorted((tmp_path / "csv").glob("run-01/best-*.csv"))
    assert tables
    header, *rows = tables[0].read_text(encoding="utf-8").splitlines()
    assert header == "type,class,x_m,y_m,width_m,depth_m,rotation_deg"
    assert rows and all(row.split(",")[0] in ("shelfRack", "pallet", "forkliftBay") for row in rows)
