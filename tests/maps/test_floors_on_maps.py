"""Floors evolved and driven on a base map: no element on its walls, paths around them, robots stopped
by them."""

from __future__ import annotations

import json

import numpy as np
import shapely
from shapely.geometry import Polygon, box

import mazegen
from mazegen.maps import read_occupancy_map
from tests.map_files import hall_pixels, hall_spec, write_map


def _walls(yaml, cell: float):
    """The map's own blocked cells as shapely squares, arena units (``cell`` per map cell)."""
    occupied = read_occupancy_map(yaml).occupied
    return shapely.union_all(
        [box(c * cell, r * cell, (c + 1) * cell, (r + 1) * cell) for r, c in np.argwhere(occupied)]
    )


def test_evolved_floors_keep_off_the_walls_and_go_through_the_gap(tmp_path):
    yaml = write_map(tmp_path, hall_pixels())
    (tmp_path / "spec.maze").write_text(hall_spec())
    spec = mazegen.load(tmp_path / "spec.maze")
    assert any(term.kind == "outside" and term.reject for term in spec.fitness)  # added: the spec has none
    out = tmp_path / "run"
    mazegen.run(spec, out_dir=out)
    walls = _walls(yaml, 10.0)
    files = sorted(out.glob("run-*/best-*.json"))
    assert files
    for file in files:
        document = json.loads(file.read_text())
        assert document["arena"]["map"]["source"] == "hall.yaml"
        for element in document["elements"]:
            outline = shapely.union_all([Polygon(part) for part in element["parts"]])
            assert outline.intersection(walls).area == 0, (file, element)
        path = document["path"]
        assert document["metrics"]["solvable"] and path is not None
        assert max(y for _, y in path) > 200  # the wall's gap is at the top: the path goes round
        route = shapely.LineString(path)
        assert route.distance(walls) > 0  # and never through a wall


def test_straight_drives_into_the_wall_between_start_and_goal(tmp_path):
    write_map(tmp_path, hall_pixels())
    (tmp_path / "spec.maze").write_text(hall_spec())
    spec = mazegen.load(tmp_path / "spec.maze")
    document = {
        "format": "mazegen-scenario",
        "version": 1,
        "arena": {"start": [60, 60], "goal": [340, 60]},
        "elements": [],
    }
    [drive] = mazegen.drive(document, "straight", spec=spec)
    assert drive.outcome == "collision"
    x, y = drive.collision
    assert abs(x - 185) < 1 and abs(y - 60) < 1  # its disc (15) against the wall of column 20 (x 200)
    [around] = mazegen.drive(document, "dwa", spec=spec)  # round the wall, through its gap
    assert around.outcome == "arrived"


def test_the_warehouse_examples_floors_keep_its_zones_and_walls():
    """examples/warehouse.maze: every floor written keeps its aisles clear, its racks in their storage
    areas, only bays and pallets in the yard, nothing on the hall's walls, and is solvable (shapely on
    the map's own cells and the zones as written, not MazeGen's geometry)."""
    from tests.conftest import EXAMPLES

    spec = mazegen.load(EXAMPLES / "warehouse.maze").with_evolution(best=40)
    result = mazegen.run(spec, runs=1, population=300, generations=3)
    documents = result.best[0]
    assert len(documents) >= 20
    walls = _walls(EXAMPLES / "maps" / "hall.yaml", 0.1)
    zones = [(zone, Polygon(zone.outline)) for zone in spec.arena.zones]
    assert {zone.rule for zone, _ in zones} == {"clear", "accepts", "holds"}
    racks = 0
    for document in documents:
        assert document["metrics"]["solvable"]
        for element in document["elements"]:
            outline = shapely.union_all([Polygon(part) for part in element["parts"]])
            assert outline.intersection(walls).area == 0
            for zone, area in zones:
                if zone.rule == "clear" or (zone.rule == "accepts" and element["type"] not in zone.types):
                    assert outline.intersection(area).area < 1e-6, (zone.name, element)
            holding = [area for zone, area in zones if zone.rule == "holds" and element["type"] in zone.types]
            if holding:
                racks += 1
                assert any(area.buffer(1e-5).covers(outline) for area in holding), element
    assert racks > 0


def test_a_first_run_on_a_map_with_zones_waits_for_their_kernels(tmp_path):
    """The kernels a run of a spec on a map with zones names are those its run leaves in the cache
    (so a first run's compile note covers them)."""
    from pathlib import Path

    import numba

    from mazegen.runtime import ARENA_KERNELS, EVERY_RUN_KERNELS, run_kernels

    write_map(tmp_path, hall_pixels())
    zone = "zone lane rect (250, 100) (390, 160) keep clear"
    (tmp_path / "spec.maze").write_text(hall_spec(extra=zone))
    spec = mazegen.load(tmp_path / "spec.maze")
    assert run_kernels(spec) == EVERY_RUN_KERNELS + ARENA_KERNELS
    (tmp_path / "plain.maze").write_text(hall_spec().replace('map "hall.yaml" cm', "size 400 x 300 cm"))
    assert run_kernels(mazegen.load(tmp_path / "plain.maze")) == EVERY_RUN_KERNELS
    mazegen.run(spec, out_dir=tmp_path / "run", catalog=False)
    for kernel in run_kernels(spec):
        assert any(Path(numba.config.CACHE_DIR).rglob(f"{kernel}-*.nbi")), kernel
