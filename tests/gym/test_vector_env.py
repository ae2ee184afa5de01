"""FloorVectorEnv: what it steps is drive's episode, its autoreset modes, masked and explicit resets,
seeds, reward and the errors of a caller's mistakes."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

from mazegen.errors import MazeError
from mazegen.gym import FloorVectorEnv, LevelPool, Levels, Reward, population_levels
from mazegen.runtime.simulation import ARRIVED, drive
from mazegen.spec import robot_for
from tests.runtime.floors import ARENA, ZIGZAG, population

FLOORS = [
    ZIGZAG,
    [],
    [("cobot", 300, 120, 60, 60, 30)],
    [("vwall", 500, 300, 20, 300, 0)],
    [("router", 400, 400, 80, 80, 10), ("hwall", 700, 200, 300, 20, 0)],
]


def levels_and_floors(beams: int = 36, footprint=None) -> tuple[Levels, object, object]:
    floors = population(ARENA, FLOORS)
    robot = robot_for(ARENA, beams=beams, footprint=footprint)
    rows = np.arange(len(FLOORS))
    return population_levels(floors, robot, rows, np.zeros(len(rows), np.int64), "hall"), floors, robot


def first_episodes(env: FloorVectorEnv, controller: str) -> tuple[list[np.ndarray], np.ndarray, np.ndarray]:
    """Poses of every robot, start included, driven by ``controller`` until every first episode has
    ended, and each first episode's steps and outcome."""
    poses = [env.slots.pose.copy()]
    steps = np.full(env.num_envs, -1)
    outcome = np.full(env.num_envs, -1)
    while (steps < 0).any():
        _, _, terminated, truncated, info = env.step(env.expert_actions(controller))
        poses.append(env.slots.pose.copy())
        ending = (terminated | truncated) & (steps < 0)
        steps[ending] = len(poses) - 1
        outcome[ending] = info["outcome"][ending]
    return poses, steps, outcome


@pytest.mark.parametrize(
    ("controller", "footprint"),
    [("straight", None), ("vfh", None), ("straight", (60.0, 30.0))],
    ids=["straight", "vfh", "straight-box"],
)
def test_driven_by_a_bundled_controllers_actions_it_gives_drives_trajectories(controller, footprint):
    levels, floors, robot = levels_and_floors(footprint=footprint)
    env = FloorVectorEnv(len(levels), levels=levels, beams=36)
    env.reset(seed=0, options={"levels": levels})
    poses, steps, outcome = first_episodes(env, controller)
    episodes = drive(floors, robot=robot, controller=controller, record=True)
    assert episodes.trajectory is not None
    np.testing.assert_array_equal(steps, episodes.steps)
    np.testing.assert_array_equal(outcome, episodes.outcome)
    for k in range(len(levels)):
        mine = np.array([pose[k] for pose in poses[: steps[k] + 1]])
        np.testing.assert_array_equal(mine, episodes.trajectory[k, : steps[k] + 1])


def test_next_step_autoreset_starts_a_level_of_the_source_on_the_step_after_the_end():
    levels, _, _ = levels_and_floors(beams=0)
    env = FloorVectorEnv(3, levels=levels, beams=0)
    env.reset(seed=1)
    ended_at = None
    for t in range(400):
        _, reward, terminated, truncated, info = env.step(env.expert_actions("straight"))
        if (terminated | truncated).any():
            ended_at = t
            break
    assert ended_at is not None
    first = int(np.flatnonzero(terminated | truncated)[0])
    observation, reward, terminated, truncated, info = env.step(env.expert_actions("straight"))
    assert reward[first] == 0.0 and not terminated[first] and not truncated[first]
    assert info["outcome"][first] == -1 and info["level"][first] in set(levels.ids.tolist())
    np.testing.assert_array_equal(observation["velocity"][first], [0.0, 0.0])
    row = int(np.flatnonzero(levels.ids == info["level"][first])[0])
    start, goal = levels.rows.start[row], levels.rows.goal[row]
    assert observation["goal"][first, 0] == pytest.approx(np.hypot(*(goal - start[:2])))


def test_same_step_autoreset_returns_the_new_levels_start_and_the_final_observation_in_info():
    levels, _, _ = levels_and_floors(beams=0)
    env = FloorVectorEnv(2, levels=levels, beams=0, autoreset_mode=AutoresetMode.SAME_STEP)
    env.reset(seed=2)
    for _ in range(400):
        observation, _, terminated, truncated, info = env.step(env.expert_actions("straight"))
        ended = terminated | truncated
        if ended.any():
            break
    k = int(np.flatnonzero(ended)[0])
    assert info["_final_obs"][k] and info["_final_info"][k]
    assert info["final_info"]["outcome"][k] in (0, 1, 2)
    assert info["outcome"][k] == -1  # the new episode's
    np.testing.assert_array_equal(observation["velocity"][k], [0.0, 0.0])
    assert not np.array_equal(info["final_obs"]["goal"][k], observation["goal"][k])


def test_disabled_autoreset_refuses_to_step_an_ended_sub_environment_and_resets_only_the_masked():
    levels, _, _ = levels_and_floors(beams=0)
    env = FloorVectorEnv(2, levels=levels, beams=0, autoreset_mode="disabled")
    env.reset(seed=0, options={"levels": levels.take([0, 1])})  # straight hits the zig-zag's wall first
    while True:
        _, _, terminated, truncated, _ = env.step(env.expert_actions("straight"))
        if terminated[0] or truncated[0]:
            break
    assert not (terminated[1] or truncated[1])
    with pytest.raises(MazeError, match=r"sub-environments \[0\] have ended"):
        env.step(np.zeros((2, 2)))
    kept = env.slots.pose[1].copy()
    mask = np.array([True, False])
    _observation, info = env.reset(options={"reset_mask": mask, "levels": levels.take([3])})
    assert info["level"][0] == levels.ids[3] and info["outcome"][0] == -1
    np.testing.assert_array_equal(env.slots.pose[1], kept)
    env.step(env.expert_actions("straight"))


def test_explicit_levels_are_played_and_the_same_seed_gives_the_same_episodes():
    levels, _, _ = levels_and_floors(beams=8)
    chosen = levels.take([4, 2, 0])
    env = FloorVectorEnv(3, levels=levels, beams=8)
    _, info = env.reset(options={"levels": chosen})
    assert info["level"].tolist() == chosen.ids.tolist()
    assert info["hash"].tolist() == chosen.hashes.tolist()

    def episodes(seed: int) -> list:
        env = FloorVectorEnv(3, levels=LevelPool(levels), beams=8)
        observation, info = env.reset(seed=seed)
        record = [observation["scan"].tobytes(), info["level"].tolist()]
        actions = np.random.default_rng(seed).uniform([0, -1], [60, 1], size=(300, 3, 2))
        for a in actions:
            observation, reward, _terminated, _truncated, info = env.step(a)
            record += [observation["scan"].tobytes(), reward.tobytes(), info["level"].tolist()]
        return record

    assert episodes(7) == episodes(7)
    assert episodes(7) != episodes(8)


def test_the_progress_terms_add_up_to_the_way_covered_and_arrival_is_paid_once():
    levels, _, _ = levels_and_floors(beams=0)
    open_floor = levels.take([1])
    weights = Reward(progress=1, arrival=7, collision=0, time=0)
    env = FloorVectorEnv(1, levels=open_floor, beams=0, reward=weights)
    env.reset(options={"levels": open_floor})
    start_to_go = open_floor.rows.optimal_time[0] * open_floor.rows.limits[0, 0]  # the path's length
    total, rewards = 0.0, []
    while True:
        _, reward, terminated, truncated, info = env.step(env.expert_actions("straight"))
        total += reward[0]
        rewards.append(reward[0])
        if terminated[0] or truncated[0]:
            break
    assert info["outcome"][0] == ARRIVED
    left = env.slots.to_go[0]
    scale = open_floor.rows.scale[0]
    assert total == pytest.approx((start_to_go - left) * scale + 7)
    assert rewards[-1] > 7 > max(rewards[:-1])


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ({"num_envs": 0}, "num_envs must be a positive integer"),
        ({"beams": -1}, "beams must be an integer >= 0"),
        ({"autoreset_mode": "sometimes"}, "autoreset_mode must be one of"),
        ({"levels": 42}, "levels must be a spec, files, Levels"),
    ],
)
def test_a_callers_mistake_in_building_it_is_one_line(arguments, message):
    levels, _, _ = levels_and_floors(beams=0)
    with pytest.raises(MazeError, match=message):
        FloorVectorEnv(**({"levels": levels} | arguments))


def test_a_callers_mistake_in_stepping_or_resetting_it_is_one_line():
    levels, _, _ = levels_and_floors(beams=0)
    env = FloorVectorEnv(2, levels=levels, beams=0)
    env.reset(seed=0)
    with pytest.raises(MazeError, match="actions must be 2 finite"):
        env.step(np.zeros((3, 2)))
    with pytest.raises(MazeError, match="actions must be 2 finite"):
        env.step(np.array([[np.nan, 0], [0, 0]]))
    with pytest.raises(MazeError, match="reset takes the options levels and reset_mask"):
        env.reset(options={"level": levels})
    with pytest.raises(MazeError, match="one for each of the 2 sub-environments"):
        env.reset(options={"levels": levels.take([0])})
    with pytest.raises(MazeError, match="reset_mask"):
        env.reset(options={"reset_mask": np.zeros(2, bool)})
    with pytest.raises(MazeError, match="commands come from straight or vfh"):
        env.expert_actions("dwa")


def reference_waypoint(pose: np.ndarray, path: np.ndarray, ahead: float) -> np.ndarray:
    """Plain NumPy: the path's point ``ahead`` beyond its point nearest ``pose``, in the robot's frame."""
    starts, ends = path[:-1], path[1:]
    edges = ends - starts
    along, squared = np.einsum("ij,ij->i", pose[:2] - starts, edges), np.einsum("ij,ij->i", edges, edges)
    t = np.clip(np.divide(along, squared, out=np.zeros_like(along), where=squared > 0), 0, 1)  # 0 on a point
    near = starts + t[:, None] * edges
    k = int(np.argmin(np.linalg.norm(near - pose[:2], axis=1)))
    polyline = np.vstack([near[k], path[k + 1 :]])
    lengths = np.linalg.norm(np.diff(polyline, axis=0), axis=1)
    walked = np.concatenate([[0.0], np.cumsum(lengths)])
    if ahead >= walked[-1]:
        point = path[-1]
    else:
        j = int(np.searchsorted(walked, ahead, side="right")) - 1
        point = polyline[j] + (ahead - walked[j]) / lengths[j] * (polyline[j + 1] - polyline[j])
    offset = point - pose[:2]
    bearing = np.arctan2(offset[1], offset[0]) - pose[2]
    return np.array([np.hypot(*offset), np.cos(bearing), np.sin(bearing)])


def test_the_waypoint_is_the_point_of_the_path_ahead_of_the_nearest_one():
    levels, _, _ = levels_and_floors(beams=0)
    zigzag = levels.take(np.zeros(30, np.int64))
    rng = np.random.default_rng(3)
    starts = np.column_stack(
        [rng.uniform(0, ARENA.width, 30), rng.uniform(0, ARENA.height, 30), rng.uniform(-3, 3, 30)]
    )
    zigzag.rows.start[:] = starts
    env = FloorVectorEnv(30, levels=zigzag, beams=0, waypoint=1.5)
    observation, _ = env.reset(options={"levels": zigzag})
    path = zigzag.rows.path[0, : zigzag.rows.path_count[0]]
    ahead = 1.5 / zigzag.rows.scale[0]
    assert len(path) >= 4  # the zig-zag's corners
    for k in range(30):
        np.testing.assert_allclose(
            observation["waypoint"][k], reference_waypoint(starts[k], path, ahead), atol=1e-9
        )
    with pytest.raises(MazeError, match="waypoint must be a positive number of metres"):
        FloorVectorEnv(2, levels=levels, beams=0, waypoint=-1.0)


def test_a_levels_path_keeps_the_plan_margin_clear_where_it_can_and_is_as_long_as_mazegens():
    import shapely

    from mazegen.runtime.geometry import grid_of
    from mazegen.runtime.simulation._levels import PLAN_MARGIN
    from mazegen.runtime.simulation._paths import floor_paths

    floors = population(ARENA, [ZIGZAG])  # gaps of 150 cm: room for the margin on both sides
    level = population_levels(
        floors, robot_for(ARENA, beams=0), np.zeros(1, np.int64), np.zeros(1, np.int64), "hall"
    )
    walls = shapely.union_all(
        [shapely.box(x - w / 2, y - d / 2, x + w / 2, y + d / 2) for _, x, y, w, d, _ in ZIGZAG]
    )
    mazegens = floor_paths(floors, np.zeros(1, np.int64), margin=None)  # its length
    touching = floor_paths(floors, np.zeros(1, np.int64), margin=0.0)  # and its corners
    cell, radius = grid_of(ARENA).cell, ARENA.robot_radius
    kept = shapely.LineString(level.rows.path[0, : level.rows.path_count[0]]).distance(walls)
    grazing = shapely.LineString(touching.corners[0, : touching.count[0]]).distance(walls)
    assert kept >= radius + PLAN_MARGIN * 100 - cell  # cm
    assert grazing <= radius + cell < kept
    assert level.rows.optimal_time[0] * level.rows.limits[0, 0] == pytest.approx(mazegens.length[0])
