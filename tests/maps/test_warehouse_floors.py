"""The worked warehouse (examples/warehouse.maze), checked as a plant engineer would, with shapely and
the map's own cells rather than MazeGen's geometry: on 1,000 evolved floors no element overlaps a
keep-clear zone or stands on the hall's walls, and every task has a path."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
import yaml
from shapely.geometry import Polygon, box

import mazegen
from mazegen.runtime.documents._scenario import element_documents
from mazegen.runtime.engine._problem import Problem
from mazegen.runtime.navigation import reach_of
from tests.conftest import EXAMPLES

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
def floors(tmp_path_factory):
    """The valid floors of the final populations of four short runs of the example, 1,000 of them."""
    spec = mazegen.load(EXAMPLES / "warehouse.maze")
    build = tmp_path_factory.mktemp("warehouse") / "build"
    mazegen.build(spec, build)
    problem = Problem.from_build_dir(build)
    result = mazegen.run(spec, runs=4, population=500, generations=3, catalog=False)
    found = []
    for run in result.runs:
        evaluation = problem.evaluate(run.codons, run.genes)
        keep = np.flatnonzero(np.isfinite(evaluation.fitness))
        found += [(evaluation.population, int(i)) for i in keep]
    assert len(found) >= FLOORS
    return spec, found[:FLOORS]


def test_no_element_is_on_the_walls_or_in_a_clear_zone_and_every_task_has_a_path(floors):
    spec, found = floors
    walls = _map_walls(EXAMPLES / "maps")
    hall = box(0, 0, spec.arena.width, spec.arena.height)
    clear = [Polygon(zone.outline) for zone in spec.arena.zones if zone.rule == "clear"]
    for shape in (walls, *clear):
        shapely.prepare(shape)
    for population, index in found:
        for element in element_documents(spec, population, index):
            shape = shapely.union_all([Polygon(part) for part in element["parts"]])
            assert hall.covers(shape)
            for area in (walls, *clear):  # touching is fine, overlapping is not
                assert not area.intersects(shape) or shape.intersection(area).area < 1e-9, element
        assert bool(reach_of(population).solvable[index])  # every one of the three tasks
