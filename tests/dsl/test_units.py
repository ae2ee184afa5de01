"""Lengths in their units: a file's ``units`` converts its elements into the arena's unit, so a spec in
cm and the same spec in m give the same floors, scaled."""

from __future__ import annotations

import numpy as np
import pytest

import mazegen
from mazegen.errors import MazeError

LIBRARY = """units cm
element rack { shape rect size 200..400 x 80..110 rotation 0, 90 height 300 }
element bay { shape bars (0, 0)-(0, 2) (0, 0)-(1, 0) thickness 20 size 100..200 }
"""

SPEC = """import "lib.maze"
arena hall { size WIDTH x HEIGHT UNIT start (S, S) goal (GX, GY) robot radius R grid G
             zone lane rect (0, LANE0) (WIDTH, LANE1) keep clear }
scenario s on hall { elements rack, bay max elements 8 }
fitness { count overlap reject solvable required }
evolution { population 80 generations 3 genome 24 seed 5 }
"""


def _spec(unit: str, scale: float) -> str:
    numbers = {"WIDTH": 2000, "HEIGHT": 1500, "S": 100, "GX": 1900, "GY": 1400, "R": 25, "G": 12.5}
    numbers |= {"LANE0": 700, "LANE1": 800}
    text = SPEC.replace("UNIT", unit)
    for key in sorted(numbers, key=len, reverse=True):
        text = text.replace(key, f"{numbers[key] * scale:g}")
    return text


def _corners(document: dict) -> np.ndarray:
    return np.array([p for e in document["elements"] for part in e["parts"] for p in part])


def test_a_spec_in_cm_and_in_m_give_the_same_floors_scaled(write_spec):
    write_spec(LIBRARY, "lib.maze")
    in_cm = mazegen.load(write_spec(_spec("cm", 1.0), "cm.maze"))
    in_m = mazegen.load(write_spec(_spec("m", 0.01), "m.maze"))
    assert in_m.scenario_elements[0].size == pytest.approx((2.0, 4.0))
    assert in_m.scenario_elements[1].parts[0].offset[0][0] == pytest.approx(
        in_cm.scenario_elements[1].parts[0].offset[0][0] / 100
    )
    assert in_m.scenario_elements[0].height == pytest.approx(3.0)
    floors_cm = mazegen.run(in_cm, runs=1, catalog=False).best[0]
    floors_m = mazegen.run(in_m, runs=1, catalog=False).best[0]
    assert len(floors_cm) == len(floors_m) >= 3
    for a, b in zip(floors_cm, floors_m):
        assert [e["type"] for e in a["elements"]] == [e["type"] for e in b["elements"]]
        np.testing.assert_allclose(_corners(a) / 100, _corners(b), atol=2e-4)
        assert a["fitness"] == b["fitness"]


def test_a_library_in_metres_cannot_go_into_a_pixel_arena(write_spec):
    write_spec(LIBRARY, "lib.maze")
    path = write_spec(_spec("px", 1.0), "px.maze")
    with pytest.raises(MazeError) as caught:
        mazegen.load(path)
    assert str(caught.value).endswith(
        "lib.maze:1:1: this file's lengths are in cm and arena 'hall' is in px: px has no size in metres "
        "to convert by (give both in mm, cm or m, or drop 'units')"
    )
