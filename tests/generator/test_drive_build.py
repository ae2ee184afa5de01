"""Generated fitness modules of specs that drive a robot: who is driven, what each term reads."""

from __future__ import annotations

import re

import pytest

from mazegen.dsl.loader import load_spec
from mazegen.generator.build import build, render_artifacts
from tests.conftest import ROOT
from tests.drive_fakes import DRIVE_SPEC
from tests.generator.test_build import assert_ruff_clean

DRIVING = (
    DRIVE_SPEC
    + """
robot { drive best 0.25 }
fitness {
    count
    solvable required
    controller dwa fails weight 2
    controller dwa time 2..4
    controller my.package:policy clearance
    controllers dwa, purepursuit disagree weight 0.5
}
"""
)


@pytest.fixture(autouse=True)
def _policy_module(tmp_path, monkeypatch):
    """``my.package``, the module of the policy DRIVING names: a spec names only policies it finds."""
    (tmp_path / "my").mkdir()
    (tmp_path / "my" / "package.py").write_text("def policy(observations): ...\n")
    monkeypatch.syspath_prepend(str(tmp_path))


def test_drive_terms_choose_who_is_driven_after_the_static_terms(write_spec):
    fitness = render_artifacts(load_spec(write_spec(DRIVING)))["fitness.py"]
    static = fitness.index("'count': 1.0 * metrics.element_count(pop)")
    choose = fitness.index("driven = metrics.drive_selection(pop, scores, rejected(pop), 0.25)")
    first_drive = fitness.index("metrics.drive_fails(pop, 'dwa', driven)")
    assert static < choose < first_drive
    assert "'dwa_fails': 2.0 * np.nan_to_num(" in fitness  # a reward; undriven: no credit
    assert "metrics.drive_time(pop, 'dwa', driven), 2.0, 4.0" in fitness
    assert "metrics.drive_clearance(pop, 'my.package:policy', driven)" in fitness
    assert "'dwa_purepursuit_disagree': 0.5 * np.nan_to_num(" in fitness
    assert "metrics.drive_disagree(pop, 'dwa', 'purepursuit', driven)" in fitness


def test_drive_all_is_written_as_a_fraction_of_one(write_spec):
    text = DRIVING.replace("drive best 0.25", "drive all")
    fitness = render_artifacts(load_spec(write_spec(text)))["fitness.py"]
    assert "drive_selection(pop, scores, rejected(pop), 1.0)" in fitness
    assert "every individual not rejected" in fitness


def test_a_spec_without_drive_terms_drives_nothing(write_spec):
    fitness = render_artifacts(load_spec(write_spec(DRIVE_SPEC + "robot { drive all }\n")))["fitness.py"]
    assert "drive" not in fitness
    assert "    return {\n" in fitness


def test_generated_drive_code_compiles_and_passes_ruff(write_spec, tmp_path):
    build(load_spec(write_spec(DRIVING)), tmp_path)
    compile((tmp_path / "fitness.py").read_text(), "fitness.py", "exec")
    assert_ruff_clean(tmp_path / "fitness.py")


def test_the_docs_show_the_code_generated_for_their_driving_spec(tmp_path):
    page = (ROOT / "docs" / "language.md").read_text(encoding="utf-8")
    spec = re.search(r"```maze file=driven.maze\n(.*?)```", page, re.S)
    shown = re.search(r"the generated `fitness.py` reads:\n\n```python fragment\n(.*?)```", page, re.S)
    assert spec is not None and shown is not None
    (tmp_path / "driven.maze").write_text(spec.group(1), encoding="utf-8")
    assert shown.group(1) in render_artifacts(load_spec(tmp_path / "driven.maze"))["fitness.py"]
