"""Occupancy maps imported as scenario documents: the free space comes back cell for cell."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import numpy as np
import pytest
import shapely
from click.testing import CliRunner

from mazegen.cli.main import main
from mazegen.errors import MazeError
from mazegen.maps import wall_rectangles
from mazegen.maps._files import read_map_yaml, read_pgm
from mazegen.maps._occupancy import BARN_MARGIN, read_occupancy_map
from mazegen.runtime.documents._floor import load_floor
from mazegen.runtime.documents._import import ImportedMap
from tests.conftest import EXAMPLES, ROOT

MAP_YAML = "resolution: 1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
BARN = ROOT.parent / "shared" / "anchors" / "barn" / "barn-train.json"


def imported(source: Path, out: Path, *options: str) -> list[Path]:
    """``mazegen import SOURCE -o OUT OPTIONS``: the scenario files written."""
    result = CliRunner().invoke(main, ["import", str(source), "-o", str(out), *options])
    assert result.exit_code == 0, result.output
    return sorted(out.glob("scenario-*.json"))


def part_cells(document: dict, cell: float, rows: int, cols: int) -> np.ndarray:
    """Cells whose centre lies inside an element's part: the document's walls rasterised independently."""
    parts = shapely.union_all([shapely.Polygon(p) for e in document["elements"] for p in e["parts"]])
    r, c = np.mgrid[0:rows, 0:cols]
    return shapely.contains_xy(parts, (c + 0.5) * cell, (r + 0.5) * cell)


def floor_cells(path: Path) -> np.ndarray:
    """The imported floor's obstacle cells, row 0 the lowest, checked two ways: by the engine's
    rasterisation and by the parts' geometry."""
    floor = load_floor(path)
    occupied, grid = floor.occupancy()
    assert np.array_equal(occupied, part_cells(floor.document, grid.cell, grid.rows, grid.cols))
    return occupied


@pytest.mark.parametrize("seed", range(5))
def test_walls_are_exactly_the_obstacle_cells(seed):
    occupied = np.random.default_rng(seed).random((23, 31)) < 0.4
    covered = np.zeros_like(occupied, dtype=int)
    rectangles = wall_rectangles(occupied)
    for first_row, last_row, first_col, last_col in rectangles:
        covered[first_row : last_row + 1, first_col : last_col + 1] += 1
    assert np.array_equal(covered, occupied.astype(int))  # each obstacle cell once, nothing else
    runs = np.count_nonzero(np.diff(np.pad(occupied, ((0, 0), (1, 0))).astype(int), axis=1) == 1)
    assert len(rectangles) < runs  # runs of equal columns merge


def test_a_block_is_one_wall():
    occupied = np.zeros((9, 9), dtype=bool)
    occupied[2:7, 1:4] = True
    occupied[0, :] = True
    assert wall_rectangles(occupied) == [(0, 0, 0, 8), (2, 6, 1, 3)]


def test_a_grid_imports_to_exactly_its_cells(tmp_path):
    rows = ["#########", "#..#....#", "#..#.##.#", "#.......#", "#########"]
    (tmp_path / "grid.txt").write_text("\n".join(rows) + "\n")
    [path] = imported(tmp_path / "grid.txt", tmp_path / "out", "--start", "1.5,1.5", "--goal", "7.5,3.5")
    expected = np.array([[char == "#" for char in row] for row in rows])[::-1]  # the first line is the top
    assert np.array_equal(floor_cells(path), expected)
    document = json.loads(path.read_text())
    jsonschema.validate(document, json.loads((ROOT / "docs" / "scenario.schema.json").read_text()))
    assert document["arena"]["width"] == 9.0 and document["arena"]["unit"] == "m"
    assert document["metrics"]["solvable"]


def test_an_npy_grid_takes_its_resolution(tmp_path):
    grid = np.zeros((8, 8), dtype=np.int8)
    grid[0, :] = grid[-1, :] = 1
    grid[2:4, 3] = 7  # nonzero is an obstacle
    np.save(tmp_path / "g.npy", grid)
    [path] = imported(
        tmp_path / "g.npy",
        tmp_path / "out",
        "--resolution",
        "0.25",
        "--start",
        "0.3,0.6",
        "--goal",
        "1.6,0.6",
    )
    assert np.array_equal(floor_cells(path), grid[::-1] != 0)
    assert json.loads(path.read_text())["arena"]["width"] == 2.0


def map_server_files(
    folder: Path, pixels: np.ndarray, yaml: str, *, ascii_pgm: bool, maxval: int = 255
) -> Path:
    """``m.yaml`` (``yaml`` after its image line) and its PGM ``m.pgm``: P2 or P5, 8 or 16 bits."""
    height, width = pixels.shape
    if ascii_pgm:
        body = "\n".join(" ".join(str(v) for v in row) for row in pixels)
        data = f"P2\n# by hand\n{width} {height}\n{maxval}\n{body}\n".encode()
    else:
        wide = ">u2" if maxval > 255 else np.uint8
        data = f"P5\n{width} {height}\n{maxval}\n".encode() + pixels.astype(wide).tobytes()
    (folder / "m.pgm").write_bytes(data)
    (folder / "m.yaml").write_text("image: m.pgm  # beside the YAML\n" + yaml)
    return folder / "m.yaml"


@pytest.mark.parametrize(("ascii_pgm", "maxval"), [(True, 255), (False, 255), (False, 65535)])
def test_a_map_server_map_with_unknown_cells_negate_and_an_origin(tmp_path, ascii_pgm, maxval):
    # negate 1: dark is free, light occupied; the middle grey is unknown, an obstacle too.
    free, occupied, unknown = 0, maxval, maxval // 2
    pixels = np.full((8, 10), free)
    pixels[0, :] = pixels[-1, :] = occupied
    pixels[1:4, 6] = unknown
    pixels[5, 2:4] = occupied
    yaml = "resolution: 0.5\norigin: [-2.0, 3.0, 0.0]\nnegate: 1\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    source = map_server_files(tmp_path, pixels, yaml, ascii_pgm=ascii_pgm, maxval=maxval)
    # The start and goal are in the map's frame: the arena's lower-left corner is the origin.
    [path] = imported(source, tmp_path / "out", "--start", "-1.25,4.75", "--goal", "2.25,4.25")
    assert np.array_equal(floor_cells(path), (pixels != free)[::-1])
    arena = json.loads(path.read_text())["arena"]
    assert (arena["start"], arena["goal"]) == ([0.75, 1.75], [4.25, 1.25])
    assert (arena["width"], arena["height"]) == (5.0, 4.0)


@pytest.mark.parametrize(
    ("mode", "free_pixels"),
    [("trinary", [230, 254]), ("scale", [230, 254]), ("raw", [0])],
)
def test_modes_free_only_what_map_server_calls_free(tmp_path, mode, free_pixels):
    pixels = np.array([[0, 100, 190, 230, 254]])  # occupancy 1 - pixel / 255: 190 unknown, 230 free
    yaml = f"{MAP_YAML}mode: {mode}\n"
    source = map_server_files(tmp_path, pixels, yaml, ascii_pgm=True)
    found = read_occupancy_map(source).occupied[0]
    assert found.tolist() == [value not in free_pixels for value in pixels[0]]


def test_a_png_map_and_its_alpha_in_scale_mode(tmp_path):
    from PIL import Image

    rgba = np.zeros((6, 6, 4), dtype=np.uint8)
    rgba[...] = (250, 252, 254, 255)  # free: the mean of the colours is light
    rgba[0, :] = rgba[-1, :] = (0, 0, 0, 255)
    rgba[2, 3] = (250, 252, 254, 0)  # transparent: unknown in scale mode, an obstacle
    Image.fromarray(rgba, "RGBA").save(tmp_path / "m.png")
    (tmp_path / "m.yaml").write_text(f"image: m.png\n{MAP_YAML}mode: scale\n")
    expected = np.zeros((6, 6), dtype=bool)
    expected[[0, -1], :] = True
    expected[2, 3] = True
    assert np.array_equal(read_occupancy_map(tmp_path / "m.yaml").occupied, expected[::-1])
    (tmp_path / "m.yaml").write_text(f"image: m.png\n{MAP_YAML}")  # trinary: alpha does not count
    assert read_occupancy_map(tmp_path / "m.yaml").occupied.sum() == 12


def test_the_barn_worlds_path_is_free_in_the_imported_floor(tmp_path):
    if not BARN.is_file():
        pytest.skip("BARN's training file is not beside this checkout")
    worlds = {w["world"]: w for w in json.loads(BARN.read_text())["worlds"]}
    for number in (0, 3, 5, 100):
        [path] = imported(BARN, tmp_path / str(number), "--world", str(number))
        occupied = floor_cells(path)
        grid = np.array([[char == "#" for char in row] for row in worlds[number]["grid"]])
        # BARN's row is the arena's x, its column the arena's y, after a free margin.
        assert np.array_equal(occupied[BARN_MARGIN:-BARN_MARGIN].T, grid)
        assert not occupied[:BARN_MARGIN].any() and not occupied[-BARN_MARGIN:].any()
        for row, col in worlds[number]["path"]:
            assert not occupied[col + BARN_MARGIN, row]
        document = json.loads(path.read_text())
        assert document["metrics"]["solvable"]  # the 2020 timing runs' start and goal, connected
        start = document["arena"]["start"]
        timer = worlds[number]["start_goal"]["timer_2020_start_gazebo"]
        assert start == pytest.approx([timer[0] + 4.5, timer[1] - 5.1 + BARN_MARGIN * 0.15])


def test_an_exported_ros_map_imports_to_the_same_free_space(factory_run, tmp_path):
    for best in sorted(factory_run.glob("run-*/best-0[12].json")):
        folder = tmp_path / best.parent.name / best.stem
        exports = folder / "ros"
        result = CliRunner().invoke(main, ["export", str(best), "--format", "ros", "-o", str(exports)])
        assert result.exit_code == 0, result.output
        source = exports / f"{best.stem}.yaml"
        document = json.loads(best.read_text())
        start, goal = (",".join(str(v / 100) for v in document["arena"][end]) for end in ("start", "goal"))
        [path] = imported(source, folder / "in", "--start", start, "--goal", goal, "--robot-radius", "0.25")
        values = read_map_yaml(source)
        pixels, _ = read_pgm(exports / values["image"])
        assert np.array_equal(floor_cells(path), (pixels == 0)[::-1])  # the frame included
        assert json.loads(path.read_text())["arena"]["start"] == pytest.approx(
            [v / 100 + values["resolution"] for v in document["arena"]["start"]]
        )


def test_tasks_are_drawn_connected_and_reproducible(tmp_path):
    source = EXAMPLES / "maps" / "rooms.txt"
    first = imported(source, tmp_path / "a", "--tasks", "5", "--seed", "3", "--resolution", "0.5")
    again = imported(source, tmp_path / "b", "--tasks", "5", "--seed", "3", "--resolution", "0.5")
    assert len(first) == 5
    assert [p.read_bytes() for p in first] == [p.read_bytes() for p in again]
    assert (tmp_path / "a" / "spec.json").read_bytes().replace(b"/a/", b"/b/") == (
        tmp_path / "b" / "spec.json"
    ).read_bytes()
    documents = [json.loads(p.read_text()) for p in first]
    assert all(d["metrics"]["solvable"] for d in documents)
    assert len({tuple(d["arena"]["start"] + d["arena"]["goal"]) for d in documents}) > 1


def test_a_rotated_map_is_refused(tmp_path):
    yaml = MAP_YAML.replace("[0, 0, 0]", "[0, 0, 0.5]")
    source = map_server_files(tmp_path, np.zeros((4, 4), int), yaml, ascii_pgm=True)
    with pytest.raises(MazeError, match=r"origin yaw 0\.5 is not 0"):
        read_occupancy_map(source)


@pytest.mark.parametrize("radius", [0.0, 0.3, 0.55, 1.2])
def test_where_the_robot_may_stand_is_the_engines_configuration_space(tmp_path, radius):
    grid = np.random.default_rng(4).random((20, 26)) < 0.15
    grid[[0, -1], :] = grid[:, [0, -1]] = True
    np.save(tmp_path / "g.npy", grid)
    [path] = imported(tmp_path / "g.npy", tmp_path / "out", "--tasks", "1", "--robot-radius", str(radius))
    free, _ = load_floor(path).configuration_space(None)
    expected = ImportedMap(read_occupancy_map(tmp_path / "g.npy"), radius).robot_free
    assert np.array_equal(free, expected)


def test_drawn_tasks_start_and_stop_where_the_robots_disc_touches_no_wall(tmp_path):
    # 0.5 m cells, a 0.3 m robot: a cell beside an obstacle has its centre 0.5 m from the obstacle's
    # centre (clear for the engine's disc) but 0.25 m from its edge (a touch for the simulator).
    paths = imported(
        EXAMPLES / "maps" / "rooms.txt", tmp_path / "out", "--tasks", "30", "--resolution", "0.5"
    )
    for path in paths:
        document = json.loads(path.read_text())
        walls = shapely.union_all(
            [shapely.Polygon(part) for e in document["elements"] for part in e["parts"]]
        )
        for label in ("start", "goal"):
            point = shapely.Point(document["arena"][label])
            assert walls.distance(point) > document["arena"]["robot_radius"], (path, label)
