"""IR-SIM, an independent simulator, as the oracle of MazeGen's: the same floors (exported with
``--format irsim``), the same commands, and the same outcome on at least 95 % of the floors, every
disagreement explained by how IR-SIM's check differs, confirmed with exact geometry (shapely).

IR-SIM moves the robot by the same forward-Euler step but decides a collision only at the end of
each step, with the robot's disc drawn as a polygon inscribed in it, and an arrival only at the end
of each step. MazeGen's simulator checks the whole segment each step drives (the swept disc, and
the segment's closest approach to the goal). So MazeGen can see a contact or an arrival that IR-SIM
cannot; never the reverse.
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import numpy as np
import pytest
import shapely

from mazegen.runtime.simulation import NO_PATH, OUTCOMES, drive
from mazegen.spec import robot_for
from tests.runtime.floors import ARENA, population
from tests.runtime.simulation.irsim_replay import (
    METRES,
    disc_sides,
    drive_recording,
    export_world,
    floor_parts,
    inscribed,
    make,
    oracle_floors,
    replay,
)

pytest.importorskip("irsim", reason="ir-sim is in the test extra")

FLOORS = 100
"""Random floors made; those MazeGen finds a path on are driven (at least 50 of them)."""


def contact_within_step(obstacles, start: np.ndarray, end: np.ndarray, radius: float) -> bool:
    """MazeGen's collision, which IR-SIM cannot see: the step's swept disc touches an obstacle, while
    IR-SIM's polygonal disc at the step's end does not (the exact disc is clear of the obstacles by
    more than the polygon is inset from it)."""
    segment = (
        shapely.LineString([start[:2], end[:2]]) if np.any(start[:2] != end[:2]) else shapely.Point(end[:2])
    )
    swept = shapely.distance(segment, obstacles)
    at_end = shapely.distance(shapely.Point(end[:2]), obstacles)
    return bool(swept <= radius * (1 + 1e-12) and at_end > inscribed(radius))


def goal_within_step(goal, start: np.ndarray, end: np.ndarray, tolerance: float) -> bool:
    """MazeGen's arrival, which IR-SIM cannot see: the step's segment comes within the goal
    tolerance, while its end, the only point IR-SIM checks, does not."""
    segment = shapely.LineString([start[:2], end[:2]])
    return bool(segment.distance(goal) <= tolerance and shapely.Point(end[:2]).distance(goal) >= tolerance)


def test_irsim_agrees_with_mazegen_on_replayed_drives(tmp_path):
    floors = oracle_floors(FLOORS)
    episodes, policy = drive_recording(floors)
    commands = policy.commands
    arena = floors.arena
    radius = arena.robot_radius
    tolerance = 0.3 / METRES  # robot_for's goal tolerance, 0.3 m
    room = shapely.box(0, 0, arena.width, arena.height).exterior
    goal = shapely.Point(arena.goal)
    driven = np.flatnonzero(episodes.outcome != NO_PATH)
    assert driven.size >= 50
    assert episodes.trajectory is not None
    results, explained = Counter(), Counter()
    for m in driven.tolist():
        ours = OUTCOMES[episodes.outcome[m]]
        given = np.array(commands.get(m, []), np.float64).reshape(-1, 2)
        assert len(given) == episodes.steps[m]
        theirs = replay(export_world(floors, m, tmp_path, lidar=False), given * [METRES, 1.0])
        poses = theirs.poses / [METRES, METRES, 1.0]
        # Same kinematics: every pose both simulators reach is the same (up to the heading's wrap).
        shared = min(len(poses), episodes.steps[m] + (0 if ours == "collision" else 1))
        track = episodes.trajectory[m, :shared]
        assert np.abs(poses[:shared, :2] - track[:, :2]).max(initial=0) < 1e-6 * arena.width
        assert np.abs(np.sin(poses[:shared, 2] - track[:, 2])).max(initial=0) < 1e-9
        results[(ours, theirs.outcome)] += 1
        if ours == theirs.outcome or (ours == "timeout" and theirs.outcome == "running"):
            continue
        # A disagreement: IR-SIM ran every command MazeGen gave and saw nothing at the last step.
        assert theirs.outcome == "running" and len(poses) == len(given) + 1, (m, ours, theirs.outcome)
        start, end = poses[-2] if len(poses) > 1 else poses[-1], poses[-1]
        if ours == "collision":
            obstacles = shapely.union_all([room, *(shapely.Polygon(p) for p in floor_parts(floors, m))])
            assert contact_within_step(obstacles, start, end, radius), f"floor {m}: unexplained collision"
            explained["contact within a step"] += 1
        else:
            assert ours == "arrived" and goal_within_step(goal, start, end, tolerance), f"floor {m}"
            explained["goal within a step"] += 1
    agree = sum(
        n
        for (ours, theirs), n in results.items()
        if ours == theirs or (ours, theirs) == ("timeout", "running")
    )
    print(f"\nIR-SIM oracle: {agree}/{driven.size} agree; {dict(results)}; explained {dict(explained)}")
    assert agree >= 0.95 * driven.size
    assert sum(explained.values()) == driven.size - agree
    # The drives end in every way, so each verdict is compared.
    assert {ours for ours, _ in results} == {"arrived", "collision", "timeout"}


class Constant:
    """A policy that gives every robot the same command at every step."""

    def __init__(self, speed: float, turn: float) -> None:
        self.action = (speed, turn)

    def __call__(self, observations) -> np.ndarray:
        return np.tile(self.action, (observations.floor.size, 1))


def drive_both(elements: list[tuple], start: tuple[float, float, float], speed: float, folder: Path):
    """MazeGen's drive of one hand-made floor from ``start`` (arena units) with a constant speed,
    straight ahead, and IR-SIM's replay of as many steps of it."""
    floors = population(ARENA, [elements])
    episodes = drive(
        floors, robot=robot_for(ARENA), controller=Constant(speed, 0.0), starts=np.array([start]), record=True
    )
    commands = np.array([[speed * METRES, 0.0]] * int(episodes.steps[0]))
    world = export_world(floors, 0, folder, lidar=False)
    theirs = replay(world, commands, np.array(start) * [METRES, METRES, 1.0])
    return floors, episodes, theirs


def test_replay_moves_the_robot_by_forward_euler(tmp_path):
    """The harness on hand-made commands: IR-SIM's poses are the forward-Euler unicycle's."""
    floors = population(ARENA, [[]])
    world = export_world(floors, 0, tmp_path, lidar=False)
    # within the acceleration window (1 m/s and 2 rad/s a step), which IR-SIM applies as MazeGen does
    commands = np.array([[0.5, 0.0]] * 3 + [[0.4, 1.0]] * 5 + [[0.0, -0.8]] * 2)
    result = replay(world, commands)
    (sx, sy), (gx, gy) = ARENA.start, ARENA.goal
    x, y, theta = sx * METRES, sy * METRES, float(np.arctan2(gy - sy, gx - sx))
    expected = [(x, y, theta)]
    for v, w in commands:
        x, y, theta = x + v * np.cos(theta) * 0.1, y + v * np.sin(theta) * 0.1, theta + w * 0.1
        expected.append((x, y, theta))
    assert result.outcome == "running"
    assert result.poses[:, :2] == pytest.approx(np.array(expected)[:, :2], abs=1e-9)
    assert np.sin(result.poses[:, 2] - np.array(expected)[:, 2]) == pytest.approx(0, abs=1e-9)


def test_replay_stops_at_irsims_collision_and_arrival(tmp_path):
    floors = population(ARENA, [[]])
    world = export_world(floors, 0, tmp_path, lidar=False)
    into_the_wall = replay(world, np.array([[0.0, -np.pi / 4 / 0.1 / 5]] * 5 + [[0.5, 0.0]] * 400))
    assert into_the_wall.outcome == "collision"
    # The wall is the arena's south edge: the robot's centre is within its radius of y = 0.
    assert into_the_wall.poses[-1, 1] <= ARENA.robot_radius * METRES + 0.05
    assert into_the_wall.poses[-2, 1] > ARENA.robot_radius * METRES
    _, episodes, to_goal = drive_both([], (ARENA.goal[0] - 100, ARENA.goal[1], 0.0), 50.0, tmp_path)
    assert OUTCOMES[episodes.outcome[0]] == to_goal.outcome == "arrived"
    assert len(to_goal.poses) == episodes.steps[0] + 1


def test_a_corner_touched_between_two_steps_is_seen_by_mazegen_only(tmp_path):
    """A square turned 45°, its lowest corner 0.5 mm inside the robot's reach at the middle of a
    step and out of reach at both ends: MazeGen's swept check collides, IR-SIM's end check does
    not, and the oracle's class says so."""
    radius, side, corner_x = ARENA.robot_radius, 30.0, 152.5
    centre_y = 300 + radius - 0.05 + side / np.sqrt(2)
    floors, episodes, theirs = drive_both(
        [("router", corner_x, centre_y, side, side, 45)], (100.0, 300.0, 0.0), 50.0, tmp_path
    )
    (part,) = floor_parts(floors, 0)
    assert part[:, 1].min() == pytest.approx(300 + radius - 0.05)
    assert OUTCOMES[episodes.outcome[0]] == "collision"
    assert theirs.outcome == "running"
    poses = theirs.poses / [METRES, METRES, 1.0]
    assert contact_within_step(shapely.Polygon(part), poses[-2], poses[-1], radius)
    # The same check on the step before, which touched nothing, does not explain anything.
    assert not contact_within_step(shapely.Polygon(part), poses[-3], poses[-2], radius)


def test_a_goal_crossed_between_two_steps_is_seen_by_mazegen_only(tmp_path):
    """The robot passes 0.1 mm inside the goal tolerance at the middle of a step, out of it at both
    ends: MazeGen arrives, IR-SIM does not."""
    tolerance = 0.3 / METRES
    gx, gy = ARENA.goal
    _, episodes, theirs = drive_both([], (gx - 5 * 20 - 2.5, gy - tolerance + 0.01, 0.0), 50.0, tmp_path)
    assert OUTCOMES[episodes.outcome[0]] == "arrived"
    assert theirs.outcome == "running"
    poses = theirs.poses / [METRES, METRES, 1.0]
    goal = shapely.Point(ARENA.goal)
    assert goal_within_step(goal, poses[-2], poses[-1], tolerance)
    assert not goal_within_step(goal, poses[-3], poses[-2], tolerance)


def test_irsims_lidar_reads_what_mazegens_reads(tmp_path):
    """The same 360 beams from the same poses against the same parts and walls: the same ranges
    (IR-SIM casts its rays on its own, analytically)."""
    floors = oracle_floors(24)
    _, policy = drive_recording(floors, scans=12)
    compared = 0
    for m, scans in sorted(policy.scans.items())[:12]:
        ours = np.array(scans)
        given = np.array(policy.commands[m][: len(scans) - 1]).reshape(-1, 2)
        theirs = replay(export_world(floors, m, tmp_path, lidar=True), given * [METRES, 1.0])
        shared = min(len(ours), len(theirs.scans))
        assert np.abs(theirs.scans[:shared] / METRES - ours[:shared]).max() < 1e-6 * floors.arena.width
        assert (ours[:shared] < robot_for(ARENA).lidar_range).any()  # the beams see something
        compared += shared
    assert compared >= 100


def recovered_commands(track: np.ndarray, step: float) -> np.ndarray:
    """The ``(v, w)`` each step applied, from consecutive poses of a forward-Euler track: the move
    along the heading over the step, and the turn over the step."""
    move = np.diff(track[:, :2], axis=0)
    heading = track[:-1, 2]
    v = (move[:, 0] * np.cos(heading) + move[:, 1] * np.sin(heading)) / step
    return np.column_stack([v, np.diff(track[:, 2]) / step])


@pytest.mark.parametrize("controller", ["straight", "purepursuit", "dwa", "vfh"])
def test_irsim_replays_the_bundled_controllers(controller, tmp_path):
    """Each bundled controller's drives, their commands recovered from the recorded poses, replayed
    in IR-SIM: the same poses, no contact IR-SIM sees before MazeGen's, the same arrivals; and every
    contact MazeGen reports lies at the robot's radius from a part or a wall (shapely)."""
    floors = oracle_floors(40)
    robot = robot_for(floors.arena)
    episodes = drive(floors, robot=robot, controller=controller, record=True)
    assert episodes.trajectory is not None
    room = shapely.box(0, 0, floors.arena.width, floors.arena.height).exterior
    radius, agree, driven = floors.arena.robot_radius, 0, 0
    for m in np.flatnonzero(episodes.outcome != NO_PATH).tolist():
        ours, steps = OUTCOMES[episodes.outcome[m]], int(episodes.steps[m])
        track = episodes.trajectory[m, : steps + 1]
        # a collision leaves the robot at the start of its last step: that step's command is lost
        given = recovered_commands(track[:-1] if ours == "collision" else track, robot.step)
        theirs = replay(export_world(floors, m, tmp_path, lidar=False), given * [METRES, 1.0])
        poses = theirs.poses / [METRES, METRES, 1.0]
        assert np.abs(poses[:, :2] - track[: len(poses), :2]).max() < 1e-6 * floors.arena.width
        driven += 1
        if ours == "collision":
            contact = shapely.Point(episodes.collision[m])
            obstacles = shapely.union_all([room, *(shapely.Polygon(p) for p in floor_parts(floors, m))])
            assert shapely.distance(contact, obstacles) == pytest.approx(radius, abs=1e-6 * radius)
            agree += theirs.outcome == "running"  # nothing before MazeGen's contact
        elif ours == "arrived":
            agree += theirs.outcome == "arrived" or goal_within_step(
                shapely.Point(floors.arena.goal), poses[-2], poses[-1], 0.3 / METRES
            )
        else:
            agree += theirs.outcome == "running"
    assert driven >= 20 and agree == driven


def test_a_contact_within_irsims_polygon_inset_is_seen_by_mazegen_only(tmp_path):
    """The robot ends a step 0.1 mm inside its reach of the east wall, heading so that a side of
    IR-SIM's polygonal disc (not a corner) faces the wall: the disc touches, the polygon inscribed
    in it does not."""
    radius, heading = ARENA.robot_radius, np.pi / disc_sides()
    end_x = ARENA.width - radius + 0.01
    start = (end_x - 10 * 5.0 * np.cos(heading), 300.0, heading)  # ten steps of 5 cm
    floors, episodes, theirs = drive_both([], start, 50.0, tmp_path)
    assert OUTCOMES[episodes.outcome[0]] == "collision" and episodes.steps[0] == 10
    assert theirs.outcome == "running"
    poses = theirs.poses / [METRES, METRES, 1.0]
    assert poses[-1, 0] == pytest.approx(end_x)
    walls = shapely.box(0, 0, ARENA.width, ARENA.height).exterior
    assert contact_within_step(walls, poses[-2], poses[-1], radius)
    # With its own geometry, IR-SIM agrees that its polygon misses the wall by the inset.
    env = make(export_world(floors, 0, tmp_path, lidar=False))
    env.robot.set_state((poses[-1] * [METRES, METRES, 1.0]).reshape(3, 1))
    assert not any(env.robot.check_collision(obstacle) for obstacle in env.obstacle_list)
