"""The worked warehouse (examples/warehouse.maze), checked as a plant engineer would, with shapely and
the map's own cells rather than MazeGen's geometry: on 1,000 evolved floors no element overlaps a
keep-clear zone or stands on the hall's walls, every run of racks is one line of equal racks equally
spaced, and every task has a path. Its picture in the README is its run's best floor."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
import yaml
from shapely.geometry import Polygon, box

import mazegen
from tests.conftest import EXAMPLES, ROOT

FLOORS = 1000


def _map_walls(folder) -> shapely.Geometry:
    """The hall's blocked cells (occupied or unknown, trinary) as one shape in the arena's frame, read
    from the PGM and YAML directly."""
    meta = yaml.safe_load((folder / "hall.yaml").read_text())
    data = (folder / meta["image"]).read_bytes()
    fields, rest = [], data
    while len(fields) < 4:  # magic, width, height, maxval; comments skipped
        line, rest = rest.split(b"\n", 1)
        if not line.startswith(b"#"):
            fields += line.split()
    cols, rows = int(fields[1]), int(fields[2])
    pixels = np.frombuffer(rest[: cols * rows], np.uint8).reshape(rows, cols)[::-1]  # row 0 lowest
    occupancy = (255 - pixels) / 255.0
    blocked = occupancy > meta["free_thresh"]  # occupied, and unknown (205) blocked
    cell = meta["resolution"]
    cells = [box(c * cell, r * cell, (c + 1) * cell, (r + 1) * cell) for r, c in zip(*np.nonzero(blocked))]
    return shapely.union_all(cells)


@pytest.fixture(scope="module")
def floors():
    """1,000 evolved floors: the distinct valid floors of the final populations of twelve runs of the
    example (seeds 1..12), as scenario documents."""
    spec = mazegen.load(EXAMPLES / "warehouse.maze")
    result = mazegen.run(spec.with_evolution(best=1000), runs=12, catalog=False)
    found = [document for run in result.best for document in run]
    assert len(found) >= FLOORS
    return spec, found[:FLOORS]


def test_no_element_is_on_the_walls_or_in_a_clear_zone_and_every_task_has_a_path(floors):
    spec, found = floors
    walls = _map_walls(EXAMPLES / "maps")
    hall = box(0, 0, spec.arena.width, spec.arena.height)
    clear = [Polygon(zone.outline) for zone in spec.arena.zones if zone.rule == "clear"]
    for shape in (walls, *clear):
        shapely.prepare(shape)
    for document in found:
        for element in document["elements"]:
            shape = shapely.union_all([Polygon(part) for part in element["parts"]])
            assert hall.covers(shape)
            for area in (walls, *clear):  # touching is fine, overlapping is not
                assert not area.intersects(shape) or shape.intersection(area).area < 1e-9, element
        assert [task["metrics"]["solvable"] for task in document["tasks"]] == [True] * len(spec.arena.tasks)


def _runs(elements: list[dict]) -> dict[tuple[str, int], list[dict]]:
    """The members of each row of a floor, in their order along it."""
    runs: dict[tuple[str, int], list[dict]] = {}
    for element in elements:
        if "row" in element:
            runs.setdefault((element["row"]["name"], element["row"]["index"]), []).append(element)
    return {key: sorted(members, key=lambda e: e["row"]["member"]) for key, members in runs.items()}


def test_every_run_of_racks_is_a_line_of_equal_racks_equally_spaced(floors):
    _, found = floors
    counted = 0
    for document in found:
        runs = _runs(document["elements"])
        assert len(runs) >= 2  # 'at least 2 rackRun'
        for members in runs.values():
            assert 2 <= len(members) <= 4
            first = members[0]
            assert all(
                (m["width"], m["depth"], m["rotation"]) == (first["width"], first["depth"], first["rotation"])
                for m in members
            )
            assert first["rotation"] in (0.0, 90.0)  # square to the walls
            along = np.array([np.cos(np.radians(first["rotation"])), np.sin(np.radians(first["rotation"]))])
            steps = np.diff([[m["x"], m["y"]] for m in members], axis=0)
            across = steps @ np.array([-along[1], along[0]])
            assert np.abs(across).max() < 2e-4  # one line (documents keep 4 decimals)
            lengths = steps @ along
            assert np.ptp(lengths) < 3e-4  # equal gaps
            gap = lengths[0] - first["width"]
            assert 0.1 - 3e-4 <= gap <= 0.3 + 3e-4  # 'spacing 0.1..0.3'
            counted += 1
    assert counted >= 2 * len(found)


def test_the_readme_picture_is_the_examples_best_floor(tmp_path):
    """docs/images/warehouse.svg, which the README shows, is what the example's own run draws."""
    from mazegen.runtime.reports import render_file

    result = mazegen.run(EXAMPLES / "warehouse.maze", catalog=False)
    render_file(
        result.best[0][0], tmp_path / "best.svg", base=mazegen.load(EXAMPLES / "warehouse.maze").arena.base
    )
    assert (tmp_path / "best.svg").read_bytes() == (ROOT / "docs" / "images" / "warehouse.svg").read_bytes()
