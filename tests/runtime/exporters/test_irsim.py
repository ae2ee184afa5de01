"""IR-SIM worlds: every example's floors load in IR-SIM itself with their obstacles and robot as
written, from any folder; options that do not apply are refused."""

from __future__ import annotations

import dataclasses
import json
import math
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely import affinity

import mazegen
from mazegen.errors import MazeError, MazeNote
from mazegen.export_formats import BUNDLED
from mazegen.maps import wall_boxes
from mazegen.runtime.documents._floor import Floor, load_floor
from mazegen.runtime.exporters._floor import ExportOptions
from mazegen.runtime.exporters._irsim import floor_robot, irsim_files
from mazegen.runtime.simulation._lidar import beam_angles
from mazegen.spec import Spec, robot_for
from tests.conftest import EXAMPLES
from tests.runtime.floors import floor_file

irsim = pytest.importorskip("irsim", reason="ir-sim is in the test extra")

SPECS = sorted([*EXAMPLES.glob("*.maze"), *EXAMPLES.glob("table1/exp*.maze")])  # canvas.maze: an import


def world_of(floor: Floor, folder: Path, options: ExportOptions | None = None) -> Path:
    ((name, data),) = irsim_files(floor, options or ExportOptions()).items()
    (folder / name).write_bytes(data)
    return folder / name


def make(path: Path):
    return irsim.make(str(path), headless=True, log_level="ERROR")


def hand_floor(spec: Spec, folder: Path) -> Floor:
    """One element of each of the spec's types, spread along the arena's diagonal."""
    arena, kinds = spec.arena, spec.scenario_elements
    elements = []
    for k, kind in enumerate(kinds):
        share = (k + 1) / (len(kinds) + 1)
        element = {"type": kind.name, "x": arena.width * share, "y": arena.height * (1 - share)}
        size = sum(kind.size) / 2
        if kind.size2 is None:
            element["size"] = size
        else:
            element |= {"width": size, "depth": sum(kind.size2) / 2}
        elements.append(element | {"rotation": kind.rotations[k % len(kind.rotations)]})
    return load_floor(floor_file(folder / f"{spec.name}.json", *elements), spec)


def check_world(env, floor: Floor, metres: float) -> None:
    """IR-SIM holds every part (as the same polygon), the walls of the floor's map (tested on their own in
    test_base_map_exports.py) and the four walls, and the robot as written."""
    arena = floor.arena
    parts = [np.asarray(part) * metres for element in floor.document["elements"] for part in element["parts"]]
    base = floor.base("an IR-SIM world")
    boxes = 0 if base is None else len(wall_boxes(base))
    assert len(env.obstacle_list) == len(parts) + boxes + 4
    for obstacle, part in zip(env.obstacle_list, parts):
        assert shapely.hausdorff_distance(shapely.Polygon(part), obstacle.geometry) < 1e-6
    walls = shapely.union_all([o.geometry for o in env.obstacle_list[len(parts) + boxes :]])
    width, height = arena["width"] * metres, arena["height"] * metres
    inside = shapely.box(0, 0, width, height)
    assert walls.intersection(inside).area == pytest.approx(0, abs=1e-9)
    assert walls.union(inside).convex_hull.area > inside.area  # walls surround the arena
    for x, y in (
        (-1e-6, height / 2),
        (width + 1e-6, height / 2),
        (width / 2, -1e-6),
        (width / 2, height + 1e-6),
    ):
        assert walls.contains(shapely.Point(x, y))
    (sx, sy), (gx, gy) = arena["start"], arena["goal"]
    heading = math.atan2(gy - sy, gx - sx)
    robot = env.robot
    assert robot.state[:3, 0] == pytest.approx([sx * metres, sy * metres, heading], abs=1e-8)
    assert np.ravel(robot.goal)[:2] == pytest.approx([gx * metres, gy * metres], abs=1e-8)
    assert robot.radius == pytest.approx(arena["robot_radius"] * metres)
    limits = floor_robot(floor)
    assert robot.vel_max[:, 0] == pytest.approx([limits.max_speed * metres, limits.max_turn])
    assert robot.vel_min[:, 0] == pytest.approx([limits.min_speed * metres, -limits.max_turn])
    assert np.ravel(robot.info.acce) == pytest.approx([limits.accel * metres, limits.turn_accel])
    assert robot.goal_threshold == pytest.approx(limits.goal_tolerance * metres)
    assert not robot.collision
    if limits.beams == 0:
        return
    (lidar,) = robot.sensors
    assert lidar.number == limits.beams and lidar.range_max == pytest.approx(limits.lidar_range * metres)
    # the beams point where the simulator's do: IR-SIM's angles turned by the sensor's mount
    directions = lidar.angle_list + lidar.offset[2, 0]
    assert directions == pytest.approx(beam_angles(limits.beams, limits.fov), abs=1e-8)  # nine decimals


@pytest.mark.parametrize("spec_path", SPECS, ids=[p.stem for p in SPECS])
def test_every_examples_floor_loads_as_written(spec_path, tmp_path):
    floor = hand_floor(mazegen.load(spec_path), tmp_path)
    metres = {"cm": 0.01, "mm": 0.001, "m": 1.0, "px": 0.01}[floor.arena["unit"]]
    check_world(make(world_of(floor, tmp_path)), floor, metres)


def test_every_best_scenario_of_a_run_loads_as_written(factory_run, tmp_path):
    paths = sorted(factory_run.glob("run-*/best-*.json"))
    assert paths
    for path in paths:
        floor = load_floor(path)
        check_world(make(world_of(floor, tmp_path)), floor, 0.01)


def test_scale_sets_the_metres(factory_run, tmp_path):
    floor = load_floor(factory_run / "run-01" / "best-01.json")
    check_world(make(world_of(floor, tmp_path, ExportOptions(scale=0.5))), floor, 0.5)


def test_a_world_loads_the_same_from_another_folder(factory_run, tmp_path):
    """Written by the CLI in one folder, loaded with another current directory: nothing it names
    is looked up relative to where IR-SIM runs."""
    out = tmp_path / "exports"
    subprocess.run(
        [sys.executable, "-m", "mazegen", "export", str(factory_run), "--format", "irsim", "-o", str(out)],
        check=True,
        capture_output=True,
    )
    world = out / "run-01" / "best-01.yaml"
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    probe = (
        "import irsim, sys\n"
        "env = irsim.make(sys.argv[1], headless=True, log_level='ERROR')\n"
        "print(len(env.obstacle_list), *env.robot.state[:3, 0])\n"
    )
    here = make(world)
    seen = subprocess.run(
        [sys.executable, "-c", probe, str(world.resolve())],
        cwd=elsewhere,
        check=True,
        capture_output=True,
        text=True,
        env={**os.environ, "MPLBACKEND": "Agg"},
    ).stdout.split()[-4:]
    assert [int(seen[0]), *map(float, seen[1:])] == pytest.approx(
        [len(here.obstacle_list), *here.robot.state[:3, 0]]
    )
    assert "obstacle_map" not in world.read_text()


def test_same_scenario_same_bytes(factory_run):
    path = factory_run / "run-02" / "best-01.json"
    assert irsim_files(load_floor(path), ExportOptions()) == irsim_files(load_floor(path), ExportOptions())


def test_cell_is_refused():
    with pytest.raises(MazeError, match="--cell does not apply to irsim exports"):
        BUNDLED["irsim"].check_options(ExportOptions(cell=5.0).given())


def test_cli_refuses_cell_and_a_floor_without_robot_radius_in_one_line(tmp_path):
    document = {
        "format": "mazegen-scenario",
        "version": 1,
        "arena": {"width": 50, "height": 40, "unit": "m", "start": [1, 1], "goal": [49, 39]},
        "elements": [{"type": "box", "x": 10, "y": 10, "parts": [[[9, 9], [11, 9], [11, 11], [9, 11]]]}],
    }
    path = tmp_path / "foreign.json"
    path.write_text(json.dumps(document))
    for extra, message in (
        (["--cell", "2"], "--cell does not apply to irsim exports"),
        ([], "an IR-SIM robot needs the arena's robot radius"),
    ):
        done = subprocess.run(
            [sys.executable, "-m", "mazegen", "export", str(path), "--format", "irsim", *extra],
            capture_output=True,
            text=True,
        )
        assert done.returncode != 0 and "Traceback" not in done.stderr
        assert done.stderr.count("\n") == 1 and message in done.stderr, done.stderr
    assert not (tmp_path / "exports").exists()


def test_the_specs_robot_block_sets_the_limits_and_the_lidar(tmp_path):
    base = mazegen.load(EXAMPLES / "factory.maze")
    robot = robot_for(base.arena, max_speed=80.0, max_turn=1.0, beams=90, fov=math.pi, lidar_range=200.0)
    floor = hand_floor(dataclasses.replace(base, robot=robot), tmp_path)
    env = make(world_of(floor, tmp_path))
    check_world(env, floor, 0.01)
    assert env.robot.vel_max[:, 0] == pytest.approx([0.8, 1.0])
    (lidar,) = env.robot.sensors
    assert lidar.number == 90 and lidar.range_max == pytest.approx(2.0)
    assert lidar.angle_list[[0, -1]] == pytest.approx([-math.pi / 2, math.pi / 2])


def test_a_robot_without_a_lidar_has_no_sensor(tmp_path):
    base = mazegen.load(EXAMPLES / "factory.maze")
    floor = hand_floor(dataclasses.replace(base, robot=robot_for(base.arena, beams=0)), tmp_path)
    assert make(world_of(floor, tmp_path)).robot.sensors == []


def test_a_robot_with_a_footprint_is_its_box_in_irsim(tmp_path):
    base = mazegen.load(EXAMPLES / "factory.maze")  # an arena in cm
    floor = hand_floor(
        dataclasses.replace(base, robot=robot_for(base.arena, footprint=(50.8, 43.0))), tmp_path
    )
    robot = make(world_of(floor, tmp_path)).robot
    (sx, sy), (gx, gy) = floor.arena["start"], floor.arena["goal"]
    heading = math.atan2(gy - sy, gx - sx)
    body = affinity.rotate(shapely.box(-0.254, -0.215, 0.254, 0.215), heading, (0, 0), use_radians=True)
    expected = affinity.translate(body, sx * 0.01, sy * 0.01)
    assert shapely.hausdorff_distance(robot.geometry, expected) < 1e-6


def test_a_robot_whose_contacts_continue_is_exported_with_a_note_that_irsim_stops_at_contact(tmp_path):
    base = mazegen.load(EXAMPLES / "factory.maze")
    (tmp_path / "end").mkdir()
    ending = hand_floor(base, tmp_path / "end")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no note for a touch that ends the episode, as IR-SIM's does
        irsim_files(ending, ExportOptions())
    carrying = hand_floor(
        dataclasses.replace(base, robot=robot_for(base.arena, contact="continue")), tmp_path
    )
    with pytest.warns(MazeNote, match="contact continue"):
        files = irsim_files(carrying, ExportOptions())
    assert b"collision_mode: stop" in next(iter(files.values()))
