"""drive(): episodes end as documented, controllers succeed and fail where they should, and a drive
is the same whatever the thread count."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from mazegen.errors import MazeError
from mazegen.runtime.simulation import ARRIVED, COLLISION, NO_PATH, OUTCOMES, drive
from mazegen.runtime.threads import CORES, threads
from mazegen.spec import Arena, ControllerSpec, robot_for
from tests.conftest import EXAMPLES
from tests.runtime.floors import ARENA, ZIGZAG, population, random_floors

CORRIDOR = Arena("corridor", 1000, 600, "cm", (100, 300), (900, 300), 20, 10)
"""Start and goal on one horizontal line through the middle."""
U_TRAP = [("vwall", 600, 300, 20, 220, 0), ("hwall", 520, 200, 180, 20, 0), ("hwall", 520, 400, 180, 20, 0)]
"""A cup open toward the start, across the straight line to the goal."""
BUNDLED = ("straight", "purepursuit")


def test_in_an_empty_arena_the_robot_arrives_in_the_optimal_time_within_one_step():
    arena = Arena("open", 1000, 600, "cm", (100, 100), (900, 500), 20, 10)
    robot = robot_for(arena, goal_tolerance=1e-3)
    for name in BUNDLED:
        episodes = drive(population(arena, [[]]), robot=robot, controller=name)
        assert OUTCOMES[episodes.outcome[0]] == "arrived", name
        assert episodes.optimal_time[0] == pytest.approx(math.dist(arena.start, arena.goal) / robot.max_speed)
        assert abs(episodes.time[0] - episodes.optimal_time[0]) <= robot.step, name
        assert episodes.distance[0] == pytest.approx(
            math.dist(arena.start, arena.goal), abs=robot.max_speed * robot.step
        )


def test_a_wall_across_the_floor_fails_every_controller():
    floors = population(CORRIDOR, [[("vwall", 500, 300, 20, 600, 0)]])
    for name in (*BUNDLED, "dwa", "vfh"):
        episodes = drive(floors, robot=robot_for(CORRIDOR), controller=name)
        assert (
            episodes.outcome[0] == NO_PATH and np.isnan(episodes.optimal_time[0]) and episodes.steps[0] == 0
        )
        assert episodes.failed[0] and episodes.score()[0] == 0.0


def test_straight_fails_behind_a_u_shaped_trap_while_purepursuit_and_dwa_arrive():
    floors = population(CORRIDOR, [U_TRAP])
    robot = robot_for(CORRIDOR)
    assert drive(floors, robot=robot, controller="straight").outcome[0] != ARRIVED
    assert drive(floors, robot=robot, controller="purepursuit").outcome[0] == ARRIVED
    assert drive(floors, robot=robot, controller="dwa").outcome[0] == ARRIVED


def test_a_robot_whose_contacts_continue_stops_short_of_the_cup_and_drives_on():
    floors = population(CORRIDOR, [U_TRAP])
    ended = drive(floors, robot=robot_for(CORRIDOR), controller="straight", record=True)
    robot = robot_for(CORRIDOR, contact="continue")
    carried = drive(floors, robot=robot, controller="straight", record=True)
    assert ended.outcome[0] == COLLISION and ended.contacts[0] == 1
    assert OUTCOMES[carried.outcome[0]] == "timeout" and carried.stuck[0] and carried.contacts[0] > 1
    np.testing.assert_array_equal(carried.collision[0], ended.collision[0])
    assert carried.steps[0] > ended.steps[0] and carried.clearance[0] == 0.0
    cup = shapely.union_all(
        [shapely.box(x - w / 2, y - d / 2, x + w / 2, y + d / 2) for _, x, y, w, d, _ in U_TRAP]
    )
    poses = carried.trajectory[0][~np.isnan(carried.trajectory[0][:, 0])]
    assert min(cup.distance(shapely.Point(x, y)) for x, y, _ in poses) > CORRIDOR.robot_radius


def test_purepursuit_arrives_along_a_zigzag_and_keeps_clear():
    episodes = drive(population(ARENA, [ZIGZAG]), robot=robot_for(ARENA), controller="purepursuit")
    assert episodes.outcome[0] == ARRIVED and episodes.clearance[0] > 0
    assert episodes.time[0] < 4 * episodes.optimal_time[0]


def test_a_thin_wall_stops_a_fast_robot_whose_poses_alone_would_clear_it():
    # 100 cm a step: the poses at x = 430 and 530 are both more than a radius from the 2 cm wall.
    arena = Arena("corridor", 1000, 600, "cm", (130, 300), (900, 300), 20, 10)
    robot = robot_for(arena, max_speed=1000.0, accel=1e6, goal_tolerance=1.0)
    floors = population(arena, [[("vwall", 500, 225, 2, 450, 0)]])
    episodes = drive(floors, robot=robot, controller="straight")
    assert episodes.outcome[0] == COLLISION
    np.testing.assert_allclose(episodes.collision[0], [499 - 20, 300])
    assert episodes.clearance[0] == 0.0


def test_recorded_trajectories_start_at_the_start_and_end_with_the_episode():
    floors = population(ARENA, [[], ZIGZAG])
    episodes = drive(floors, robot=robot_for(ARENA), controller="straight", record=True)
    poses = episodes.trajectory
    assert poses is not None
    for m in range(2):
        steps = episodes.steps[m]
        np.testing.assert_allclose(poses[m, 0, :2], ARENA.start)
        assert np.isfinite(poses[m, : steps + 1]).all() and np.isnan(poses[m, steps + 1 :]).all()
        track = np.linalg.norm(np.diff(poses[m, : steps + 1, :2], axis=0), axis=1).sum()
        if episodes.outcome[m] == ARRIVED:
            assert track == pytest.approx(episodes.distance[m])


def test_starts_and_indices_choose_the_floors_and_poses():
    floors = population(ARENA, [ZIGZAG, []])
    start = np.array([[900.0, 500.0, 0.0]])
    episodes = drive(
        floors, robot=robot_for(ARENA), controller="straight", indices=np.array([1]), starts=start
    )
    assert episodes.size == 1 and episodes.outcome[0] == ARRIVED
    assert episodes.time[0] < 2.0  # 50 cm from the goal
    with pytest.raises(MazeError, match="starts must be 1 finite"):
        drive(
            floors,
            robot=robot_for(ARENA),
            controller="straight",
            indices=np.array([1]),
            starts=np.zeros((2, 3)),
        )


def test_a_drive_is_the_same_whatever_the_thread_count():
    floors = population(ARENA, random_floors(np.random.default_rng(5), 60, ARENA))
    robot = robot_for(ARENA)
    for name in BUNDLED:
        with threads(1):
            one = drive(floors, robot=robot, controller=name, record=True)
        with threads(CORES):
            many = drive(floors, robot=robot, controller=name, record=True)
        for field in (
            "outcome",
            "time",
            "distance",
            "clearance",
            "optimal_time",
            "steps",
            "collision",
            "stuck",
            "trajectory",
        ):
            np.testing.assert_array_equal(getattr(one, field), getattr(many, field), err_msg=field)
        assert len(set(one.outcome)) > 1  # the floors are not all alike


@pytest.mark.parametrize(
    ("controller", "message"),
    [
        ("nosuch", "unknown controller 'nosuch': not bundled"),
        (
            ControllerSpec("straight", (("gain", 1.0),)),
            "controller straight has no parameter 'gain' (it has heading_gain",
        ),
        (
            ControllerSpec("straight", (("turn_in_place", 9.0),)),
            "controller straight's turn_in_place must be within [0, 3.15] rad",
        ),
        (ControllerSpec("nosuch.module:policy", (("x", 1.0),)), "is a user's policy: it takes no parameters"),
        ("nosuch_module_xyz:policy", "controller nosuch_module_xyz:policy: cannot load it (No module named"),
        ("math:pi", "controller math:pi is not callable"),
        (":x", "a policy's path reads package.module:name, got ':x'"),
        (".x:y", "a policy's path reads package.module:name, got '.x:y'"),
        ("x..y:z", "a policy's path reads package.module:name, got 'x..y:z'"),
        ("math:", "a policy's path reads package.module:name, got 'math:'"),
    ],
)
def test_a_bad_controller_is_one_line(controller, message):
    with pytest.raises(MazeError) as raised:
        drive(population(ARENA, [[]]), robot=robot_for(ARENA), controller=controller)
    assert message in str(raised.value) and "\n" not in str(raised.value)


def test_lengths_set_in_the_spec_are_in_arena_units():
    from mazegen.runtime.simulation._choice import bundled_params

    defaults = bundled_params("purepursuit", (), ARENA)
    assert defaults[0] == pytest.approx(60.0)  # 0.6 m in cm
    changed = bundled_params("purepursuit", (("lookahead", 45.0),), ARENA)
    assert changed[0] == 45.0 and (changed[1:] == defaults[1:]).all()


@pytest.mark.parametrize("controller", ["straight", "purepursuit", "dwa", "vfh", "movebase"])
def test_the_loop_compiled_without_floors_has_the_types_a_drive_of_scenario_files_gives_it(
    controller, factory_run, monkeypatch
):
    # A first drive compiles its loop ahead (runs/_warmup.py) with compile_loop: a loop of other types
    # would be compiled again by the drive itself, which would then wait as long as before.
    import numba

    import mazegen
    import mazegen.runtime.simulation._loop as loop
    from mazegen.runtime.runs._warmup import empty_floors
    from mazegen.runtime.simulation import compile_loop

    types: list[tuple] = []
    loop_in_blocks = loop.in_blocks

    def recorded(kernel, count, *args, **options):
        types.append(tuple(numba.typeof(arg) for arg in args))
        return loop_in_blocks(kernel, count, *args, **options)

    monkeypatch.setattr(loop, "in_blocks", recorded)
    spec = mazegen.load(EXAMPLES / "factory.maze")
    compile_loop(empty_floors(spec), spec.robot_or_default, controller)
    assert len(types) == 1
    mazegen.drive(factory_run, controller)
    assert len(types) >= 2 and all(found == types[0] for found in types[1:])
