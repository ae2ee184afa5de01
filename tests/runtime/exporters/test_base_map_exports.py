"""Floors built on a map: every export and picture holds the map's walls, checked against the map's
own cells (a hand-made map_server map: unknown cells, either ``negate``, an origin away from zero)."""

from __future__ import annotations

import io
import json
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import shapely
import yaml
from PIL import Image

import mazegen
from mazegen.errors import MazeError
from mazegen.maps import base_cells, read_occupancy_map
from mazegen.runtime.documents._floor import Floor, load_floor
from mazegen.runtime.exporters._documents import png_files, svg_files
from mazegen.runtime.exporters._floor import ExportOptions
from mazegen.runtime.exporters._gazebo import gazebo_files
from mazegen.runtime.exporters._irsim import irsim_files
from mazegen.runtime.exporters._movingai import movingai_files
from mazegen.runtime.reports._render import scenario_svg
from tests.runtime.exporters.test_export_movingai import read_map
from tests.runtime.exporters.test_export_ros import OCCUPIED, UNKNOWN, element_cells, export, load_map
from tests.runtime.floors import floor_file

MAP = [
    "################",
    "#..............#",
    "#..##.....??...#",
    "#..##.....??...#",
    "#..............#",
    "#.......####...#",
    "#..............#",
    "#.?............#",
    "#..............#",
    "#.....#........#",
    "#..............#",
    "################",
]
"""The hand-made map, top row first: ``#`` occupied, ``.`` free, ``?`` unknown; cells of 0.1 m."""
WALLS = np.array([[char == "#" for char in row] for row in reversed(MAP)])
UNKNOWN_CELLS = np.array([[char == "?" for char in row] for row in reversed(MAP)])
ORIGIN = (-3.2, 1.7)
PIXELS = {0: {"#": 0, ".": 254, "?": 205}, 1: {"#": 255, ".": 0, "?": 50}}
"""Pixel values of each cell, as map_server reads them: with ``negate 1`` the occupancy is the
pixel's shade itself, so an unknown cell (205 unnegated) is 50."""
ELEMENTS = (
    {"type": "router", "x": 76, "y": 56, "size": 30},
    {"type": "hwall", "x": 80, "y": 85, "width": 150, "depth": 12, "rotation": 15},
)
"""Placed off the cells' edges, so the cells they cover are the cells they touch."""
SVG = "{http://www.w3.org/2000/svg}"


def write_map(folder: Path, negate: int) -> None:
    rows, cols = len(MAP), len(MAP[0])
    pixels = bytes(PIXELS[negate][char] for row in MAP for char in row)
    (folder / "hand.pgm").write_bytes(f"P5\n{cols} {rows}\n255\n".encode("ascii") + pixels)
    (folder / "hand.yaml").write_text(
        f"image: hand.pgm\nmode: trinary\nresolution: 0.1\norigin: [{ORIGIN[0]}, {ORIGIN[1]}, 0.0]\n"
        f"negate: {negate}\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )


def spec_file(path: Path, source: str, *, shift: float = 0.0, unknown: str = "", grid: float = 10) -> Path:
    """A spec of an arena on the map ``source`` (cm), its start and goal ``shift`` from (25, 25) and
    (135, 95)."""
    start, goal = (25 + shift, 25 + shift), (135 + shift, 95 + shift)
    path.write_text(
        f'import manufacturing\narena hall {{ map "{source}" cm {unknown}\n'
        f"    start {start} goal {goal} robot radius 10 grid {grid} }}\n"
        "scenario hall on hall { elements router, hwall  max elements 8 }\nfitness { count }\n"
    )
    return path


def hall(folder: Path, negate: int = 0, unknown: str = "", grid: float = 10) -> mazegen.Spec:
    write_map(folder, negate)
    return mazegen.load(spec_file(folder / "hall.maze", "hand.yaml", unknown=unknown, grid=grid))


def floor_on(spec: mazegen.Spec, path: Path, *elements: dict) -> Floor:
    return load_floor(floor_file(path, *elements), spec)


def cell_boxes(blocked: np.ndarray, cell: float) -> shapely.Geometry:
    rows, cols = np.nonzero(blocked)
    return shapely.union_all(shapely.box(cols * cell, rows * cell, (cols + 1) * cell, (rows + 1) * cell))


def assert_cover_exactly(boxes: list[shapely.Geometry], blocked: np.ndarray, cell: float) -> None:
    """Disjoint boxes whose union is the blocked cells: fewer boxes than cells, areas adding up."""
    area = blocked.sum() * cell * cell
    union = shapely.union_all(boxes)
    assert 0 < len(boxes) < blocked.sum()
    assert sum(box.area for box in boxes) == pytest.approx(area)
    assert union.area == pytest.approx(area)
    assert union.symmetric_difference(cell_boxes(blocked, cell)).area < 1e-6 * area


@pytest.mark.parametrize("negate", [0, 1])
@pytest.mark.parametrize("unknown", ["", "unknown blocked", "unknown free"])
def test_the_grid_sees_the_maps_cells(tmp_path, negate, unknown):
    spec = hall(tmp_path, negate, unknown)
    blocked = WALLS if unknown == "unknown free" else WALLS | UNKNOWN_CELLS
    base = spec.arena.base
    assert base is not None
    assert (base.rows, base.cols, base.origin) == (12, 16, ORIGIN) and base.resolution == pytest.approx(10)
    assert np.array_equal(base_cells(base), blocked)
    floor = floor_on(spec, tmp_path / "empty.json")
    occupied, _ = floor.occupancy()
    assert np.array_equal(occupied, blocked)
    # The robot's configuration space (MovingAI's map): no blocked cell's centre within the radius
    # of a free cell's centre, nor the arena's edge.
    files = movingai_files(floor, ExportOptions())
    passable = read_map(files["empty.map"].decode())[::-1]
    r, c = np.mgrid[0:12, 0:16]
    y, x = (r + 0.5) * 10, (c + 0.5) * 10
    near = np.zeros_like(blocked)
    for row, col in zip(*np.nonzero(blocked)):
        near |= (x - (col + 0.5) * 10) ** 2 + (y - (row + 0.5) * 10) ** 2 <= 10**2 + 1e-9
    edge = (x < 10) | (x > 150) | (y < 10) | (y > 110)
    assert np.array_equal(passable, ~(near | edge))


@pytest.mark.parametrize("negate", [0, 1])
@pytest.mark.parametrize("cell", [None, 5.0])
def test_the_ros_map_is_the_base_and_the_elements_cell_for_cell(tmp_path, negate, cell):
    spec = hall(tmp_path, negate)
    floor = floor_on(spec, tmp_path / "floor.json", *ELEMENTS)
    loaded, meta = load_map(export(floor, tmp_path, ExportOptions(cell=cell)))
    step = cell or 10.0
    split = round(10 / step)  # export cells per map cell along a side
    base = np.kron(WALLS | UNKNOWN_CELLS, np.ones((split, split), dtype=bool))
    covered, touched = element_cells(floor.document, step, *base.shape)
    assert np.array_equal(covered, touched) and covered.any() and (covered & ~base).any()
    assert loaded.shape == (base.shape[0] + 2, base.shape[1] + 2) and UNKNOWN not in loaded
    assert np.array_equal(loaded[1:-1, 1:-1] == OCCUPIED, base | covered)
    frame = np.ones(loaded.shape, dtype=bool)
    frame[1:-1, 1:-1] = False
    assert (loaded[frame] == OCCUPIED).all()
    # The map lies where the user's map lies: the frame's cell below and left of its origin.
    metres = step / 100
    assert meta["resolution"] == pytest.approx(metres)
    assert meta["origin"] == [pytest.approx(ORIGIN[0] - metres), pytest.approx(ORIGIN[1] - metres), 0.0]
    text = (tmp_path / "floor.yaml").read_text()
    assert '# built on map "hand.yaml"' in text and "start [-2.95, 1.95], goal [-1.85, 2.65]" in text
    # A scale other than the map's scales the map about its frame's origin, as it scales the floor.
    _, scaled = load_map(export(floor, tmp_path, ExportOptions(cell=cell, scale=0.001)))
    corner = [ORIGIN[0] / 10 - step / 1000, ORIGIN[1] / 10 - step / 1000]
    assert scaled["origin"] == [pytest.approx(corner[0]), pytest.approx(corner[1]), 0.0]


def test_a_map_mazegen_wrote_gives_back_the_same_free_space(tmp_path):
    spec = hall(tmp_path, negate=1)
    (tmp_path / "first").mkdir()
    router = ELEMENTS[0]  # the wall would be on the new arena's goal
    written_yaml = export(floor_on(spec, tmp_path / "floor.json", router), tmp_path / "first")
    written = read_occupancy_map(written_yaml)
    # The exported map as the base of a new arena, its start and goal where they were in the map frame.
    again = mazegen.load(spec_file(tmp_path / "again.maze", "first/floor.yaml", shift=10))
    base = again.arena.base
    assert base is not None and base.origin == pytest.approx(np.subtract(ORIGIN, 0.1))
    assert np.array_equal(base_cells(base), written.occupied)
    empty = floor_on(again, tmp_path / "empty.json")
    assert np.array_equal(empty.occupancy()[0], written.occupied)
    (tmp_path / "second").mkdir()
    second = read_occupancy_map(export(empty, tmp_path / "second"))
    assert np.array_equal(second.occupied[1:-1, 1:-1], written.occupied)
    assert second.origin == pytest.approx(np.subtract(written.origin, 0.1))
    assert not second.unknown.any()


def test_worlds_extrude_the_maps_walls_as_merged_boxes(tmp_path):
    spec = hall(tmp_path)
    floor = floor_on(spec, tmp_path / "floor.json", *ELEMENTS)
    blocked = WALLS | UNKNOWN_CELLS
    sdf = gazebo_files(floor, ExportOptions())["floor.sdf"].decode()
    assert 'on map "hand.yaml": (x, y) here is (x -3.2, y +1.7) in its frame' in sdf
    (model,) = [m for m in ET.fromstring(sdf).iter("model") if m.get("name") == "map_walls"]
    boxes = []
    for collision in model.iter("collision"):
        x, y, z = (float(v) for v in (collision.findtext("pose") or "").split()[:3])
        length, width, height = (float(v) for v in (collision.findtext("geometry/box/size") or "").split())
        assert height == pytest.approx(2.5) and z == pytest.approx(height / 2)  # the walls' height
        boxes.append(shapely.box(x - length / 2, y - width / 2, x + length / 2, y + width / 2))
    assert_cover_exactly(boxes, blocked, 0.1)
    world = yaml.safe_load(irsim_files(floor, ExportOptions())["floor.yaml"])
    boxes = []
    for obstacle in world["obstacle"]:
        if obstacle["name"].startswith("map_wall_"):
            shape, (x, y, yaw) = obstacle["shape"], obstacle["state"]
            assert shape["name"] == "rectangle" and yaw == 0
            half = (shape["length"] / 2, shape["width"] / 2)
            boxes.append(shapely.box(x - half[0], y - half[1], x + half[0], y + half[1]))
    assert_cover_exactly(boxes, blocked, 0.1)


def test_a_picture_of_a_floor_on_a_map_shows_its_walls_under_the_elements(tmp_path):
    spec = hall(tmp_path)
    floor = floor_on(spec, tmp_path / "floor.json", *ELEMENTS)
    root = ET.fromstring(svg_files(floor, ExportOptions())["floor.svg"])
    groups = {g.get("class"): g for g in root.iter(f"{SVG}g")}
    assert list(groups).index("walls") < list(groups).index("elements")
    frame = next(root.iter(f"{SVG}clipPath")).find(f"{SVG}rect")
    assert frame is not None
    left, top, width = (float(frame.get(key, "")) for key in ("x", "y", "width"))
    k = width / 160  # pixels per arena unit
    boxes = []
    for rect in groups["walls"].iter(f"{SVG}rect"):
        x, y, w, h = (float(rect.get(key, "")) for key in ("x", "y", "width", "height"))
        assert rect.get("fill") == "#3d3d3d"
        # Back to arena units (the picture's y runs down), to a tenth: pixels are written to 0.01.
        x0, x1 = round((x - left) / k, 1), round((x + w - left) / k, 1)
        y0, y1 = round(120 - (y + h - top) / k, 1), round(120 - (y - top) / k, 1)
        boxes.append(shapely.box(x0, y0, x1, y1))
    assert_cover_exactly(boxes, WALLS | UNKNOWN_CELLS, 10)
    assert any("map hand.yaml" in (text.text or "") for text in root.iter(f"{SVG}text"))  # the legend
    # The PNG shows the same: a wall cell's centre (row 9, column 3) is the walls' grey.
    image = Image.open(io.BytesIO(png_files(floor, ExportOptions())["floor.png"])).convert("RGB")
    assert image.getpixel((round(left + 35 * k), round(top + (120 - 95) * k))) == (61, 61, 61)


def test_a_picture_needs_the_map_the_floor_is_built_on(tmp_path):
    spec = hall(tmp_path)
    document = floor_on(spec, tmp_path / "floor.json", *ELEMENTS).document
    with pytest.raises(
        MazeError, match=r"^the floor is built on map 'hand.yaml': its picture needs its spec"
    ):
        scenario_svg(document)
    other = tmp_path / "other"
    other.mkdir()
    assert spec.arena.base is not None
    unknown_free = hall(other, unknown="unknown free").arena.base
    with pytest.raises(MazeError, match=r"the floor is built on map 'hand.yaml' .*; the spec's map is"):
        scenario_svg(document, base=unknown_free)
    plain = {**document, "arena": {k: v for k, v in document["arena"].items() if k != "map"}}
    with pytest.raises(MazeError, match=r"the floor is built on no map; the spec's map is 'hand\.yaml'"):
        scenario_svg(plain, base=spec.arena.base)


@pytest.mark.parametrize(
    ("files", "what"),
    [
        (gazebo_files, "a Gazebo world"),
        (irsim_files, "an IR-SIM world"),
        (svg_files, "its picture"),
        (png_files, "its picture"),
    ],
)
def test_a_floor_on_a_map_without_its_spec_is_one_line_error(tmp_path, files, what):
    spec = hall(tmp_path)
    document = floor_on(spec, tmp_path / "floor.json", *ELEMENTS).document
    alone = tmp_path / "alone" / "floor.json"
    alone.parent.mkdir()
    alone.write_text(json.dumps(document))
    floor = load_floor(alone)
    assert floor.spec is None
    with pytest.raises(
        MazeError, match=f": the floor is built on map 'hand.yaml': {what} needs its spec: give --spec"
    ):
        files(floor, ExportOptions())


def test_a_floor_drawn_by_hand_is_on_its_specs_map_and_a_written_one_names_its_map(tmp_path):
    spec = hall(tmp_path)
    drawn = tmp_path / "drawn.json"
    drawn.write_text(
        json.dumps(
            {
                "format": "mazegen-scenario",
                "version": 1,
                "arena": {"start": [45, 25], "goal": [135, 95]},  # its own task alone
                "elements": [ELEMENTS[0]],
            }
        )
    )
    document = load_floor(drawn, spec).document
    assert document["arena"]["map"]["source"] == "hand.yaml" and document["arena"]["start"] == [45, 25]
    unmapped = tmp_path / "unmapped.json"
    unmapped.write_text(
        json.dumps({**document, "arena": {k: v for k, v in document["arena"].items() if k != "map"}})
    )
    with pytest.raises(
        MazeError, match=r"map 'hand\.yaml' \(cells [0-9a-f]{16}\) in the spec, none in the scenario"
    ):
        load_floor(unmapped, spec)
