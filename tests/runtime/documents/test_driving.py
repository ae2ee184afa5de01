"""What a drive gives, as documents and commands show it: fabricated episodes in, rounded drives out."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mazegen.runtime.documents._driving import episode_drive, not_driven, summaries, with_drives
from mazegen.runtime.simulation import ARRIVED, COLLISION, NO_PATH, TIMEOUT, Episodes

NAN = float("nan")


def episodes(outcomes: list[int], trajectory: np.ndarray) -> Episodes:
    m = len(outcomes)
    collision = np.full((m, 2), NAN)
    collision[[k for k, o in enumerate(outcomes) if o == COLLISION]] = (3.123456, 4.0)
    return Episodes(
        controller="dwa",
        outcome=np.array(outcomes, np.int8),
        time=np.full(m, 12.345678),
        distance=np.full(m, 6.000049),
        clearance=np.full(m, -1e-12),  # a contact a rounding below zero
        optimal_time=np.array([5.0] * (m - 1) + [NAN]),
        steps=np.full(m, 2, np.int32),
        collision=collision,
        stuck=np.array([o == TIMEOUT for o in outcomes]),
        trajectory=trajectory,
    )


def test_an_episode_is_rounded_as_documents_are_with_headings_in_degrees_and_no_padding():
    poses = np.full((3, 4, 3), NAN)
    poses[:, :3] = [[1.000049, 2.0, 0.0], [1.5, 2.0, -0.1], [2.0, 2.0, 2 * math.pi - 1e-9]]
    ran = episodes([COLLISION, ARRIVED, NO_PATH], poses)
    scores = ran.score()
    crash, arrival, none = (episode_drive(f"f{k}.json", ran, k, scores) for k in range(3))
    assert crash.trajectory == ((1.0, 2.0, 0.0), (1.5, 2.0, 354.2704), (2.0, 2.0, 0.0))  # 0 <= heading < 360
    assert crash.collision == (3.1235, 4.0) and crash.outcome == "collision" and crash.score == 0
    assert crash.clearance == 0.0 and math.copysign(1, crash.clearance) == 1  # no -0.0 in a document
    assert arrival.collision is None and arrival.score == pytest.approx(5 / 12.3457, abs=1e-4)
    assert (arrival.time, arrival.distance, arrival.optimal_time) == (12.3457, 6.0, 5.0)
    assert none == not_driven("f2.json", "dwa") and none.section()["trajectory"] == []


def test_success_and_mean_score_count_the_floors_driven_only():
    drives = [[episode_drive("a", ran, 0, ran.score())] for ran in [episodes([ARRIVED, ARRIVED], None)]]
    drives += [[not_driven("b", "dwa")], [not_driven("c", "dwa")]]
    (summary,) = summaries(drives, ["dwa"])
    assert (summary.driven, summary.arrived, summary.success) == (1, 1, 1.0)
    assert summary.mean_score == drives[0][0].score > 0
    (nothing,) = summaries(drives[1:], ["dwa"])
    assert nothing.success is None and nothing.mean_score is None


def test_driving_again_replaces_that_controllers_entry_and_keeps_the_others():
    document = {"format": "mazegen-scenario", "drive": {"straight": {"outcome": "arrived"}}}
    driven = with_drives(document, [not_driven("f", "dwa")])
    assert list(driven["drive"]) == ["straight", "dwa"] and document["drive"] == {
        "straight": {"outcome": "arrived"}
    }
    again = with_drives(driven, [not_driven("f", "straight")])
    assert again["drive"]["straight"]["outcome"] == "no path"


def test_a_robot_whose_contacts_continue_says_how_many_steps_touched_and_the_documents_accept_it():
    import json

    import jsonschema

    from mazegen.runtime.documents._scenario_rules import check_document
    from tests.conftest import ROOT

    ran = episodes([TIMEOUT, COLLISION, ARRIVED], None)
    first_touch = np.where(np.array([[True], [True], [False]]), ran.collision[1], NAN)  # the timeout's too
    ran = Episodes(**{**ran.__dict__, "contacts": np.array([7, 1, 0], np.int32), "collision": first_touch})
    touched, crashed, clean = (episode_drive("f.json", ran, k, ran.score()) for k in range(3))
    assert touched.section()["contacts"] == 7 and touched.collision is not None
    assert "7 steps touching" in touched.line("m")
    assert "contacts" not in crashed.section() and "contacts" not in clean.section()  # as before contacts
    section = {"drive": {"dwa": touched.section()}}
    check_document(section, "f.json")
    schema = json.loads((ROOT / "docs" / "scenario.schema.json").read_text())
    jsonschema.validate(section["drive"]["dwa"], {**schema["$defs"]["drive"], "$defs": schema["$defs"]})
    with pytest.raises(Exception, match="contacts"):
        check_document({"drive": {"dwa": {**touched.section(), "contacts": 0}}}, "f.json")
