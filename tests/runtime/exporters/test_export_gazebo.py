"""Gazebo worlds: valid SDF for the simulator's own checker, one model per element, right poses and shapes."""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import mazegen
from mazegen.runtime.documents._floor import load_floor
from mazegen.runtime.exporters._floor import ExportOptions
from mazegen.runtime.exporters._gazebo import gazebo_files
from tests.conftest import EXAMPLES
from tests.runtime.floors import floor_file

CM = 0.01


def numbers(node: ET.Element | None) -> list[float]:
    assert node is not None and node.text is not None
    return [float(v) for v in node.text.split()]


def world_of(floor, tmp_path: Path) -> Path:
    ((name, data),) = gazebo_files(floor, ExportOptions()).items()
    (tmp_path / name).write_bytes(data)
    return tmp_path / name


def figures_floor(tmp_path: Path):
    """The paper's figures (bars of several parts), rotated."""
    path = floor_file(
        tmp_path / "figures.json",
        {"type": "angle", "x": 200, "y": 200, "size": 120, "rotation": 15},
        {"type": "square", "x": 600, "y": 300, "size": 80, "rotation": 45},
        {"type": "eshape", "x": 400, "y": 650, "size": 150, "rotation": 200},
        {"type": "lshape", "x": 700, "y": 700, "size": 100},
    )
    return load_floor(path, mazegen.load(EXAMPLES / "mazegen1.maze"))


def foreign_floor(tmp_path: Path):
    """A document from elsewhere: parts only, a type name SDF reserves characters of, no colour."""
    document = {
        "format": "mazegen-scenario",
        "version": 1,
        "arena": {"width": 500, "height": 400, "unit": "m", "start": [1, 1], "goal": [499, 399]},
        "elements": [
            {"type": "arm::base <1>", "x": 100, "y": 100, "parts": [[[90, 90], [110, 95], [100, 120]]]},
        ],
    }
    path = tmp_path / "foreign.json"
    path.write_text(json.dumps(document))
    return load_floor(path)


def floors(factory_run: Path, tmp_path: Path) -> list:
    runs = [load_floor(path) for path in sorted(factory_run.glob("run-*/best-*.json"))]
    return [*runs, figures_floor(tmp_path), foreign_floor(tmp_path)]


@pytest.mark.skipif(
    shutil.which("ign") is None,
    reason="`ign sdf` is not installed "
    "(Debian: libsdformat-dev ignition-tools sdformat-sdf ruby; .ci/run installs them)",
)
def test_every_world_passes_ign_sdf_check(factory_run, tmp_path):
    worlds = [world_of(floor, tmp_path) for floor in floors(factory_run, tmp_path)]
    checks = [
        subprocess.Popen(
            ["ign", "sdf", "-k", str(world)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
        )
        for world in worlds
    ]
    for world, check in zip(worlds, checks):
        out, err = check.communicate(timeout=60)
        assert check.returncode == 0 and "Valid." in out, f"{world.name}: {out}{err}"
        assert "Warning" not in err and "Error" not in err, f"{world.name}: {err}"


def local_to_world(pose: list[float], points: np.ndarray) -> np.ndarray:
    x, y, yaw = pose[0], pose[1], pose[5]
    turn = np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]])
    return points @ turn.T + (x, y)


def footprint(collision: ET.Element) -> tuple[np.ndarray, float]:
    """Corners (in the model's frame) and height of a box or polyline collision."""
    pose = numbers(collision.find("pose"))
    box = collision.find("geometry/box/size")
    if box is not None:
        length, width, height = numbers(box)
        assert pose[2] == pytest.approx(height / 2)
        half = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * (length / 2, width / 2)
        return local_to_world(pose, half), height
    polyline = collision.find("geometry/polyline")
    assert polyline is not None and pose == [0] * 6
    points = np.array([numbers(point) for point in polyline.findall("point")])
    return points, numbers(polyline.find("height"))[0]


def same_corners(a: np.ndarray, b: np.ndarray) -> bool:
    """The same polygon, whatever vertex it starts from."""
    return len(a) == len(b) and any(np.allclose(np.roll(a, k, axis=0), b, atol=1e-5) for k in range(len(a)))


def test_one_model_per_element_at_its_pose_with_its_shape(factory_run, tmp_path):
    kinds = set()
    for floor in floors(factory_run, tmp_path):
        world = ET.parse(world_of(floor, tmp_path)).getroot().find("world")
        assert world is not None
        names = [model.get("name") for model in world.findall("model")]
        assert len(names) == len(set(names))
        models = [model for model in world.findall("model") if model.get("name", "").startswith("element_")]
        elements = floor.document["elements"]
        assert len(models) == len(elements)
        metres = 1.0 if floor.arena["unit"] == "m" else CM
        for model, element in zip(models, elements):
            assert model.findtext("static") == "true"
            pose = numbers(model.find("pose"))
            rotation = math.radians(element.get("rotation", 0))
            expected = [element["x"] * metres, element["y"] * metres, 0, 0, 0, rotation]
            assert pose == pytest.approx(expected, abs=1e-6)
            collisions = model.findall("link/collision")
            assert len(collisions) == len(model.findall("link/visual")) == len(element["parts"])
            for collision, part in zip(collisions, element["parts"]):
                corners, height = footprint(collision)
                assert same_corners(local_to_world(pose, corners), np.array(part) * metres)
                assert height == pytest.approx(element.get("height", 100) * metres)
        kinds |= {c.tag for m in models for c in m.iterfind("link/collision/geometry/*")}
    assert kinds == {"box", "polyline"}


def test_world_is_enclosed_and_marks_start_and_goal(factory_run, tmp_path):
    floor = load_floor(factory_run / "run-01" / "best-01.json")
    world = ET.parse(world_of(floor, tmp_path)).getroot().find("world")
    assert world is not None
    arena = floor.arena
    width, depth = arena["width"] * CM, arena["height"] * CM
    walls = world.find("model[@name='arena_walls']")
    assert walls is not None
    bounds = {}
    for collision in walls.findall("link/collision"):
        corners, _ = footprint(collision)
        bounds[collision.get("name")] = (corners.min(axis=0), corners.max(axis=0))
    # Four walls along the whole of each side, their inner faces on the arena's edges.
    (south_lo, south_hi), (north_lo, north_hi) = bounds["south_collision"], bounds["north_collision"]
    (west_lo, west_hi), (east_lo, east_hi) = bounds["west_collision"], bounds["east_collision"]
    assert south_hi[1] == pytest.approx(0) and north_lo[1] == pytest.approx(depth)
    assert west_hi[0] == pytest.approx(0) and east_lo[0] == pytest.approx(width)
    for lo, hi in ((south_lo, south_hi), (north_lo, north_hi)):
        assert lo[0] <= 0 and hi[0] >= width
    for lo, hi in ((west_lo, west_hi), (east_lo, east_hi)):
        assert lo[1] <= 0 and hi[1] >= depth
    for name in ("start", "goal"):
        marker = world.find(f"model[@name='{name}']")
        assert marker is not None and marker.find("link/collision") is None
        assert numbers(marker.find("pose"))[:2] == pytest.approx([v * CM for v in arena[name]])


def test_names_keep_only_letters_digits_and_underscores(tmp_path):
    world = ET.parse(world_of(foreign_floor(tmp_path), tmp_path)).getroot().find("world")
    assert world is not None
    assert [m.get("name") for m in world.findall("model")][-1] == "element_01_arm__base__1_"


def test_same_scenario_same_bytes(factory_run):
    path = factory_run / "run-02" / "best-01.json"
    assert gazebo_files(load_floor(path), ExportOptions()) == gazebo_files(load_floor(path), ExportOptions())
