"""examples/learning/train.py runs end to end: both curricula train, and every controller is driven over
held-out floors (in miniature: its figures are the example's README's, from a full run)."""

from __future__ import annotations

import json
import runpy

from tests.conftest import EXAMPLES


def test_the_learning_example_trains_both_curricula_and_compares_them_on_held_out_floors(tmp_path):
    train = runpy.run_path(str(EXAMPLES / "learning" / "train.py"))["main"]
    arguments = [
        "--iterations",
        "1",
        "--candidates",
        "2",
        "--levels",
        "2",
        "--held-out",
        "8",
        "--training-suites",
        "1",
        "--suite-iterations",
        "2",
        "--out",
        str(tmp_path),
    ]
    rows = train(arguments)
    names = [row["controller"] for row in rows]
    assert names == ["straight", "purepursuit", "ES, uniform", "ES, prioritised"]
    assert all(0.0 <= row["success"] <= 1.0 and 0.0 <= row["score"] <= 0.5 for row in rows)
    saved = json.loads((tmp_path / "results.json").read_text())
    assert saved["held_out"] == rows and len(saved["training"]["prioritised"]) == 1
    assert (tmp_path / "policies.npz").is_file()
