"""The calibration's published figures follow from its saved floors and data (docs/difficulty.md,
"Calibration"; README.md).

``benchmarks/calibration.py`` drives the saved floors and writes the saved data; driving takes
minutes, so here the floors' metrics are measured again and every figure the pages quote is
recomputed from the data's measured times, then looked for in the pages' text.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import mazegen
from mazegen.runtime.documents._scenario import population_from_documents
from mazegen.runtime.geometry._elements import ElementTable
from mazegen.runtime.navigation._calibration import (
    TARGET_CONTROLLERS,
    VERSION_1_LEVELS,
    CalibrationFloors,
    arrivals,
    controller_agreement,
    correlations,
    data_scores,
    read_calibration,
)
from mazegen.runtime.navigation._difficulty import HARDNESS, METRICS, WEIGHTS, survey
from tests.conftest import EXAMPLES, ROOT

DATA = ROOT / "tests" / "runtime" / "navigation" / "calibration_data.csv"
FLOORS = DATA.with_name("calibration_floors.json")


def page(name: str) -> str:
    """A page's text with every run of white space one space (the figures wrap anywhere)."""
    return " ".join((ROOT / name).read_text(encoding="utf-8").split())


def signed(value: float) -> str:
    """``value`` to 2 decimals with the pages' minus sign."""
    return f"{value:.2f}".replace("-", "−")


def span(values: list[float]) -> str:
    """The pages' way of quoting several figures: one when they round alike, else lowest–highest."""
    low, high = f"{min(values):.2f}", f"{max(values):.2f}"
    return low if low == high else f"{low}–{high}"


def percent(share: float) -> str:
    return f"{100 * share:.0f} %"


@pytest.fixture(scope="module")
def saved() -> CalibrationFloors:
    return CalibrationFloors.read(FLOORS)


@pytest.fixture(scope="module")
def data() -> list[dict[str, float | str]]:
    return read_calibration(DATA)


@pytest.fixture(scope="module")
def figures(saved, data) -> list[dict[str, float | str]]:
    """The table of ρ and held-out R² per controller, then for their mean."""
    return correlations(data, saved.seed)


def test_the_saved_data_holds_the_metrics_of_the_saved_floors(saved, data):
    """Floor by floor, in order, the data's metrics are the saved floors' (to its 10 digits)."""
    measured = []
    for name in dict.fromkeys(floor["spec"] for floor in saved.floors):
        spec = mazegen.load(EXAMPLES / f"{name}.maze")
        documents = [(name, floor) for floor in saved.floors if floor["spec"] == name]
        population = population_from_documents(
            spec, ElementTable.from_types(spec.scenario_elements), documents
        )
        measured += [(name, spec.arena.robot_radius, row) for row in survey(population).table]
    assert [(name, scale) for name, scale, _ in measured] == [(row["spec"], row["scale"]) for row in data]
    table = np.array([[row[metric] for metric in METRICS] for row in data])
    assert np.allclose(np.array([row for *_, row in measured]), table, rtol=1e-9, atol=1e-12)


def test_the_docs_table_is_what_the_saved_data_gives(figures):
    """Every cell of docs/difficulty.md's table of ρ and held-out R² per controller."""
    text = (ROOT / "docs" / "difficulty.md").read_text(encoding="utf-8")
    lines = re.search(r"^\| Controller \| ρ v1 .*?(?=\n\n)", text, re.M | re.S)
    assert lines, "docs/difficulty.md has no table of ρ per controller"
    heading, _, *rows = (line.strip("|").split("|") for line in lines.group(0).splitlines())
    keys = [cell.strip().replace("ρ ", "rho_").replace("R² ", "r2_").replace(" ", "_") for cell in heading]
    stated = {
        cells[0].strip(): {key: cell.strip().strip("*") for key, cell in zip(keys[1:], cells[1:])}
        for cells in rows
    }
    expected = {
        "mean of the four" if row["controller"] == "mean" else str(row["controller"]): {
            key: signed(float(row[key])) for key in keys[1:]
        }
        for row in figures
    }
    assert stated == expected


def test_the_pages_quote_the_figures_the_saved_data_gives(saved, data, figures):
    """Each figure README.md and docs/difficulty.md quote in their text, looked for in it."""
    mean, dwa = figures[-1], figures[TARGET_CONTROLLERS.index("dwa")]
    weight = dict(zip(HARDNESS, WEIGHTS))
    arrived = arrivals(data)
    agree = controller_agreement(data)
    version_1 = data_scores(data, 1)
    version_2 = data_scores(data, 2)
    levels = [(version_1 >= low) & (version_1 < high) for low, high in VERSION_1_LEVELS.values()]
    floors = len(data)
    claims = {
        "README.md": [
            f"over {floors} floors, {len(TARGET_CONTROLLERS)} controllers and {saved.starts} perturbed "
            f"starts each, it ranks floors by measured traversal difficulty at Spearman ρ "
            f"{mean['rho_v2']:.2f} and explains {percent(mean['r2_refit'])} of it on held-out floors",
        ],
        "docs/difficulty.md": [
            "version 1's old levels ("
            + ", ".join(f"{low:.0f}..{high:.0f}" for low, high in VERSION_1_LEVELS.values())
            + ", set from",
            "hold version 2 medians of {:.0f}, {:.0f} and {:.0f}".format(
                *(np.median(version_2[inside]) for inside in levels)
            ),
            f"**Floors**: {floors}, from",
            f"spread over version 1's {version_1.min():.1f}..{version_1.max():.1f} as evenly as the pool "
            "allows: {} below 10, {} from 10 to 25, {} above".format(
                *(int(inside.sum()) for inside in levels)
            ),
            f"from {saved.starts} seeded perturbed starts per floor",
            f"{floors * saved.starts * len(TARGET_CONTROLLERS):,} episodes; arrivals: "
            + ", ".join(f"{name} {percent(share)}" for name, share in arrived.items()),
            f"version 2 itself, fitted on all {floors} floors, reaches {mean['r2_v2']:.2f} on the mean",
            f"version 1 already ranks floors better (ρ {mean['rho_v1']:.2f} against the mean) and explains "
            f"{mean['r2_v1']:.2f} held out; version 2 raises ρ to {mean['rho_v2']:.2f} and held-out R² to "
            f"**{mean['r2_refit']:.2f}**",
            f"tortuosity (weight {weight['tortuosity']:.2f}, ρ {mean['rho_tortuosity']:.2f}) and dispersion "
            f"({weight['dispersion']:.2f}, ρ {mean['rho_dispersion']:.2f}), then the narrowest passage "
            f"({weight['narrowest']:.2f})",
            "rank floors nearly as well (|ρ| "
            + span([abs(mean[f"rho_{name}"]) for name in ("clearance", "visibility", "dimension")])
            + ")",
            f"`dwa` arrives on {percent(arrived['dwa'])} of the starts",
            f"(ρ {dwa['rho_v2']:.2f}, yet R² {dwa['r2_v2']:.2f} to {dwa['r2_refit']:.2f})",
            "the controllers' measured difficulties agree at ρ "
            + span([agree["straight", "dwa"], agree["straight", "purepursuit"]])
            + " (straight with dwa or purepursuit) to "
            + span([rho for pair, rho in agree.items() if "vfh" in pair])
            + f" (vfh with the others); only dwa and purepursuit, which both follow MazeGen's path, agree "
            f"closely ({agree['dwa', 'purepursuit']:.2f})",
        ],
    }
    missing = [
        f"{name}: {claim}" for name, quoted in claims.items() for claim in quoted if claim not in page(name)
    ]
    assert not missing, "the saved data give, but the pages do not say:\n" + "\n".join(missing)
