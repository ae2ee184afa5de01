"""The BARN benchmark scripts run end to end (one broke unnoticed when a floor's navigation stopped being
measured on reading): the validation's table, and a fit's two tables, on a budget of a few drives."""

from __future__ import annotations

import re
import subprocess
import sys

import pytest

from tests.conftest import ROOT

BARN = ROOT.parent / "shared" / "anchors" / "barn" / "barn-train.json"
pytestmark = pytest.mark.skipif(not BARN.is_file(), reason="BARN's training file is not beside this checkout")

ROW = re.compile(r"^\| `(\w+)[^|]*\| (-?\d\.\d\d) \| (\d+\.\d) \| 90\.9 \| (\d+\.\d) \|", re.MULTILINE)
"""A controller's row of the protocol's table: ρ, success and agreement, BARN's success 90.9 %."""


def run(*args: str) -> str:
    done = subprocess.run(
        [sys.executable, *args], cwd=ROOT, capture_output=True, text=True, timeout=900, check=False
    )
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout


def test_the_validation_prints_each_controllers_agreement_with_barns_runs():
    out = run("benchmarks/barn_validation.py", "--controllers", "straight", "--contact", "end")
    rows = ROW.findall(out)
    assert [name for name, *_ in rows] == ["straight"]
    assert "one Gazebo DWA run against the mean of the other four: ρ 0.86" in out


def test_a_fit_on_a_small_budget_prints_the_fits_and_the_protocols_tables():
    out = run(
        "benchmarks/barn_fit.py",
        "--controller",
        "dwa",
        "--params",
        "horizon",
        "--folds",
        "2",
        "--budget",
        "1",
    )
    assert "| fitted on the others, held-out fold 2 |" in out
    rows = ROW.findall(out)
    assert [name for name, *_ in rows] == ["dwa"] * 3  # defaults, fitted on all, held out
    # A budget of one drive is the defaults: every fit keeps them, and drives as they do.
    assert len({tuple(row[1:]) for row in rows}) == 1
    assert "controller dwa { horizon 2 }" in out  # its default, 2 s
