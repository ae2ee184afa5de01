"""ROS map exports read back the way nav2's map_server reads them."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import shapely
import yaml

import mazegen
from mazegen.errors import MazeError
from mazegen.runtime.documents._floor import load_floor
from mazegen.runtime.exporters._floor import ExportOptions
from mazegen.runtime.exporters._ros import FREE_THRESH, OCCUPIED_THRESH, ros_files
from mazegen.runtime.geometry._cspace import grid_of
from mazegen.runtime.navigation._paths import free_cells
from tests.conftest import EXAMPLES
from tests.runtime.floors import floor_file

OCCUPIED, FREE, UNKNOWN = 100, 0, -1


def read_pgm(path: Path) -> np.ndarray:
    """Pixels of a binary PGM (P5, 8 bits), top row first; header comments allowed."""
    data = path.read_bytes()
    fields: list[bytes] = []
    at = 0
    while len(fields) < 4:
        while data[at : at + 1].isspace():
            at += 1
        if data[at : at + 1] == b"#":
            at = data.index(b"\n", at) + 1
            continue
        end = at
        while not data[end : end + 1].isspace():
            end += 1
        fields.append(data[at:end])
        at = end
    magic, width, height, maxval = fields[0], int(fields[1]), int(fields[2]), int(fields[3])
    assert magic == b"P5" and maxval == 255
    pixels = np.frombuffer(data, np.uint8, count=width * height, offset=at + 1)
    return pixels.reshape(height, width)


def load_map(yaml_path: Path) -> tuple[np.ndarray, dict]:
    """An occupancy grid as nav2's map_server builds it from a YAML file (trinary mode).

    Returns:
        ``int8[height, width]`` with row 0 the map's lowest row (100, 0 or -1), and the YAML.
    """
    meta = yaml.safe_load(yaml_path.read_text(encoding="utf-8"))
    assert meta.get("mode", "trinary") == "trinary"
    pixels = read_pgm(yaml_path.parent / meta["image"]).astype(np.float64)
    shade = pixels / 255.0
    occ = shade if meta["negate"] else 1.0 - shade
    cells = np.where(
        meta["occupied_thresh"] < occ, OCCUPIED, np.where(occ < meta["free_thresh"], FREE, UNKNOWN)
    )
    # map_server stores image row y at map row height - y - 1.
    return cells[::-1].astype(np.int8), meta


def export(floor, tmp_path: Path, options: ExportOptions | None = None) -> Path:
    for name, data in ros_files(floor, options or ExportOptions()).items():
        (tmp_path / name).write_bytes(data)
    return tmp_path / f"{floor.name}.yaml"


def element_cells(document: dict, cell: float, rows: int, cols: int) -> tuple[np.ndarray, np.ndarray]:
    """Exact geometry: cells an element covers with some area, and cells it touches at all."""
    parts = [shapely.Polygon(part) for element in document["elements"] for part in element["parts"]]
    union = shapely.union_all(parts)
    r, c = np.mgrid[0:rows, 0:cols]
    boxes = shapely.box(c * cell, r * cell, (c + 1) * cell, (r + 1) * cell)
    covered = shapely.area(shapely.intersection(boxes, union)) > 1e-6 * cell * cell
    touched = shapely.intersects(boxes, union.buffer(1e-6 * cell))
    return covered, touched


def test_round_trip_gives_the_engines_occupancy(factory_run, tmp_path):
    spec = mazegen.load(EXAMPLES / "factory.maze")
    scenarios = sorted(factory_run.glob("run-*/best-*.json"))
    assert len(scenarios) == 8
    for path in scenarios:
        floor = load_floor(path)
        occupied, grid = floor.occupancy()
        loaded, meta = load_map(export(floor, tmp_path))
        assert meta["resolution"] == pytest.approx(spec.arena.cell / 100)
        assert meta["origin"] == [pytest.approx(-meta["resolution"]), pytest.approx(-meta["resolution"]), 0.0]
        assert loaded.shape == (grid.rows + 2, grid.cols + 2)
        assert UNKNOWN not in loaded
        # Each engine cell, found through the map's origin and resolution, holds the engine's value.
        rows, cols = np.mgrid[0 : grid.rows, 0 : grid.cols]
        x = (cols + 0.5) * grid.cell / 100
        y = (rows + 0.5) * grid.cell / 100
        map_col = np.floor((x - meta["origin"][0]) / meta["resolution"]).astype(int)
        map_row = np.floor((y - meta["origin"][1]) / meta["resolution"]).astype(int)
        assert np.array_equal(loaded[map_row, map_col] == OCCUPIED, occupied)
        frame = np.ones(loaded.shape, bool)
        frame[1:-1, 1:-1] = False
        assert (loaded[frame] == OCCUPIED).all()
        # The engine's occupancy is the elements' footprint: every covered cell, only touched ones.
        covered, touched = element_cells(floor.document, grid.cell, grid.rows, grid.cols)
        assert occupied[covered].all()
        assert not (occupied & ~touched).any()
        # The robot's configuration space never reaches into an occupied cell.
        robot_free = free_cells(floor.population, grid_of(spec.arena), 0)
        assert not (robot_free & occupied).any()
        assert occupied.any() and robot_free.sum() < (~occupied).sum()


def test_thresholds_read_unknown_as_unknown(tmp_path):
    """205 (unknown), 254 (free) and 0 (occupied) survive a reload with the written thresholds."""
    (tmp_path / "m.pgm").write_bytes(b"P5\n# three pixels\n3 1\n255\n" + bytes([205, 254, 0]))
    (tmp_path / "m.yaml").write_text(
        "image: m.pgm\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
        f"occupied_thresh: {OCCUPIED_THRESH}\nfree_thresh: {FREE_THRESH}\n"
    )
    loaded, _ = load_map(tmp_path / "m.yaml")
    assert loaded.tolist() == [[UNKNOWN, FREE, OCCUPIED]]


FLOOR_CM = {"type": "hwall", "x": 700, "y": 500, "width": 400, "depth": 20, "rotation": 30}


def hand_floor(tmp_path: Path, name: str, scale: float) -> Path:
    element = {
        key: value * scale if key in ("x", "y", "width", "depth") else value
        for key, value in FLOOR_CM.items()
    }
    return floor_file(tmp_path / f"{name}.json", element)


def test_metres_whatever_the_unit(tmp_path, write_spec):
    """The same floor drawn in cm and in mm gives the same map, in metres."""
    millimetres = write_spec(
        "import manufacturing\n"
        "arena floor { size 14000 x 10500 mm  start (600, 600)  goal (13400, 9900)\n"
        "    robot radius 250  grid 125 }\n"
        "scenario factory on floor { elements hwall }\nfitness { count }\n"
    )
    in_cm = load_floor(hand_floor(tmp_path, "cm", 1), mazegen.load(EXAMPLES / "factory.maze"))
    in_mm = load_floor(hand_floor(tmp_path, "mm", 10), mazegen.load(millimetres))
    cm_map, cm_meta = load_map(export(in_cm, tmp_path))
    mm_map, mm_meta = load_map(export(in_mm, tmp_path))
    assert cm_meta["resolution"] == mm_meta["resolution"] == 0.125
    assert np.array_equal(cm_map, mm_map) and (cm_map[1:-1, 1:-1] == OCCUPIED).sum() > 30
    assert "start [0.6, 0.6], goal [13.4, 9.9], robot radius 0.25" in (tmp_path / "mm.yaml").read_text()


def test_pixels_are_centimetres_unless_scaled(tmp_path):
    spec = mazegen.load(EXAMPLES / "mazegen1.maze")
    floor = load_floor(floor_file(tmp_path / "figures.json"), spec)
    _, default = load_map(export(floor, tmp_path))
    _, scaled = load_map(export(floor, tmp_path, ExportOptions(scale=0.001)))
    assert default["resolution"] == pytest.approx(spec.arena.cell * 0.01)
    assert scaled["resolution"] == pytest.approx(spec.arena.cell * 0.001)
    assert math.isclose(default["resolution"] / scaled["resolution"], 10)


def test_occupancy_needs_the_spec(factory_run, tmp_path):
    alone = tmp_path / "best-01.json"
    alone.write_bytes((factory_run / "run-01" / "best-01.json").read_bytes())
    floor = load_floor(alone)
    assert floor.spec is None
    with pytest.raises(MazeError, match="needs the spec the scenario was made under: give --spec"):
        ros_files(floor, ExportOptions())
