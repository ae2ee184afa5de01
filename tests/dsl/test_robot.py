"""The robot block and the drive terms: what a good spec gives the Spec."""

from __future__ import annotations

import math
import sys

import pytest

from mazegen.controllers import BUNDLED
from mazegen.dsl.loader import load_spec
from mazegen.errors import MazeError
from mazegen.spec import ControllerSpec, FitnessTerm, Spec, robot_for

HEAD = (
    "element box { shape square size 20..40 }\n"
    "arena floor { size 1000 x 800 cm start (50, 50) goal (950, 750) robot radius 20 }\n"
    "scenario s on floor { elements box }\n"
)

FULL = (
    HEAD
    + """
robot {
    speed 60  min speed 5  turn rate 90  acceleration 1000  turn acceleration 180
    step 0.05  goal tolerance 25  timeout factor 6  stuck 8  contact continue  footprint 50.8 by 43
    lidar { beams 180  fov 270  range 300 }
    drive best 0.2
    controller purepursuit { lookahead 45  rotate_to_heading 30 }
}
fitness {
    solvable required
    controller dwa fails weight 2
    controller dwa time 2..4
    controller purepursuit clearance 0..10
    controllers dwa, vfh disagree weight 0.5
}
"""
)


def test_the_robot_block_sets_limits_in_arena_units_and_angles_in_radians(write_spec):
    robot = load_spec(write_spec(FULL)).robot
    assert robot is not None
    assert (robot.max_speed, robot.min_speed, robot.accel) == (60, 5, 1000)
    assert robot.max_turn == pytest.approx(math.pi / 2)
    assert robot.turn_accel == pytest.approx(math.pi)
    assert (robot.step, robot.goal_tolerance, robot.timeout, robot.stuck) == (0.05, 25, 6, 8)
    assert robot.contact == "continue"
    assert robot.footprint == (50.8, 43.0)
    assert (robot.beams, robot.lidar_range, robot.driven) == (180, 300, 0.2)
    assert robot.fov == pytest.approx(1.5 * math.pi)


def test_controllers_are_the_blocks_then_the_terms_each_once(write_spec):
    robot = load_spec(write_spec(FULL)).robot
    assert robot is not None
    assert [c.name for c in robot.controllers] == ["purepursuit", "dwa", "vfh"]
    lookahead, heading = robot.controller("purepursuit").params
    assert lookahead == ("lookahead", 45.0)  # a length, in the arena's unit as written
    assert heading[0] == "rotate_to_heading" and heading[1] == pytest.approx(math.radians(30))
    assert robot.controller("dwa") == ControllerSpec("dwa")


def test_drive_terms_name_their_controllers_measure_and_target(write_spec):
    terms = {term.key: term for term in load_spec(write_spec(FULL)).fitness}
    assert terms["dwa_fails"] == FitnessTerm("drive", 2.0, metric="fails", controllers=("dwa",))
    assert terms["dwa_time"].target == (2.0, 4.0)
    assert terms["purepursuit_clearance"].target == (0.0, 10.0)
    assert terms["dwa_vfh_disagree"].controllers == ("dwa", "vfh")
    assert terms["dwa_vfh_disagree"].weight == 0.5


def test_drive_terms_without_a_robot_block_get_the_arenas_default_robot(write_spec):
    spec = load_spec(write_spec(HEAD + "fitness { controller straight fails }\n"))
    assert spec.robot == robot_for(spec.arena, controllers=(ControllerSpec("straight"),))
    assert spec.robot.max_speed == pytest.approx(50)  # BARN's 0.5 m/s in centimetres


def test_a_spec_that_drives_nothing_has_no_robot(write_spec):
    assert load_spec(write_spec(HEAD + "fitness { count }\n")).robot is None


def test_drive_all_drives_every_individual(write_spec):
    spec = load_spec(write_spec(HEAD + "robot { drive all }\n"))
    assert spec.robot is not None and spec.robot.driven == 1.0


def test_the_robot_survives_spec_json(write_spec):
    spec = load_spec(write_spec(FULL))
    again = Spec.from_json(spec.to_json())
    assert again == spec and again.robot.footprint == (50.8, 43.0)
    disc = load_spec(write_spec(HEAD + "robot { }\n"))
    assert "footprint" not in disc.to_json() and Spec.from_json(disc.to_json()) == disc  # as before boxes
    assert again.robot is not None and again.robot.controllers[0].params == spec.robot.controllers[0].params


def test_a_policys_module_is_found_not_imported(write_spec, tmp_path, monkeypatch):
    (tmp_path / "my").mkdir()
    (tmp_path / "my" / "pkg.py").write_text("raise RuntimeError('imported when read')\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    spec = load_spec(write_spec(HEAD + "fitness { controllers my.pkg:policy, dwa disagree }\n"))
    assert spec.fitness[0].key == "my_pkg_policy_dwa_disagree"
    assert spec.robot is not None and spec.robot.controllers[0] == ControllerSpec("my.pkg:policy")


def test_a_policys_module_is_found_in_the_current_folder(write_spec, tmp_path, monkeypatch):
    """As ``python -m`` finds it, though the ``mazegen`` command's path holds its script's folder."""
    (tmp_path / "here_policy.py").write_text("def policy(observations): ...\n")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "path", [entry for entry in sys.path if entry not in ("", str(tmp_path))])
    spec = load_spec(write_spec(HEAD + "robot { controller here_policy:policy { } }\n"))
    assert spec.robot is not None and spec.robot.controllers == (ControllerSpec("here_policy:policy"),)


def test_a_controller_a_package_registers_is_known(write_spec, register_plugins):
    path = write_spec(HEAD + "fitness { controller mpc fails }\n")
    with pytest.raises(MazeError, match="unknown controller 'mpc'"):
        load_spec(path)
    register_plugins("controllers", {"mpc": lambda observations: None})
    assert load_spec(path).robot.controllers == (ControllerSpec("mpc"),)


@pytest.mark.parametrize("name", sorted(BUNDLED))
def test_every_bundled_parameter_at_its_default_is_accepted(write_spec, name):
    """The defaults of the table, written in the spec's units (metres here), pass their own bounds."""
    arena = "arena floor { size 20 x 16 m start (1, 1) goal (19, 15) robot radius 0.25 }\n"
    written = []
    for parameter in BUNDLED[name].parameters:
        value = math.degrees(parameter.default) if parameter.unit in ("rad", "rad/s") else parameter.default
        written.append(f"{parameter.name} {value:.6f}".rstrip("0").rstrip("."))
    in_metres = HEAD.replace(HEAD.splitlines()[1], arena.strip()).replace("size 20..40", "size 0.2..0.4")
    text = in_metres + f"robot {{ controller {name} {{ {' '.join(written)} }} }}\n"
    robot = load_spec(write_spec(text)).robot
    assert robot is not None
    assert [key for key, _ in robot.controller(name).params] == [p.name for p in BUNDLED[name].parameters]


NO_RADIUS = HEAD.replace(" robot radius 20", "")


@pytest.mark.parametrize("tail", ["robot { }\n", "fitness { controller dwa fails }\n"])
def test_an_arena_in_cm_without_a_robot_radius_drives_the_default_robot(write_spec, tail):
    """Only a px arena is sized by its robot: a cm one without a radius has the Jackal's limits in cm."""
    from mazegen.runtime.simulation._choice import bundled_params

    spec = load_spec(write_spec(NO_RADIUS + tail))
    assert spec.arena.robot_radius == 0
    assert spec.robot_or_default.max_speed == pytest.approx(50)  # BARN's 0.5 m/s in centimetres
    assert bundled_params("dwa", (), spec.arena)[6] == pytest.approx(30)  # inflation 0.3 m
