"""Level sources and levels: a spec's fresh floors, scenario files, the .npz a JAX user loads, and the
single-floor environment registered for gymnasium.make."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import mazegen
from mazegen.errors import MazeError
from mazegen.gym import (
    TRAINING_SPEC,
    FloorEnv,
    FloorVectorEnv,
    Levels,
    SpecLevels,
    file_levels,
    level_source,
)
from tests.conftest import EXAMPLES


@pytest.fixture(scope="module")
def training() -> SpecLevels:
    return SpecLevels(TRAINING_SPEC, batch=64)


def test_a_specs_levels_are_valid_floors_with_a_path_and_one_seed_gives_the_same(training):
    first = training.sample(np.random.default_rng(4), 20)
    again = SpecLevels(TRAINING_SPEC, batch=64).sample(np.random.default_rng(4), 20)
    assert len(first) == 20 and first.hashes.tolist() == again.hashes.tolist()
    assert np.isfinite(first.rows.optimal_time).all() and (first.rows.path_count >= 2).all()
    assert first.has_genomes and first.spec == "training"
    _, population = training.problem.decode(first.codons, first.genes)
    assert population.valid.all()
    assert np.isfinite(first.difficulty).all()
    other = training.sample(np.random.default_rng(5), 20)
    assert set(other.hashes.tolist()).isdisjoint(first.hashes.tolist())


def test_levels_round_trip_through_one_npz_with_fixed_shapes(training, tmp_path):
    levels = training.sample(np.random.default_rng(1), 6)
    path = levels.save(tmp_path / "levels.npz")
    loaded = Levels.load(path)
    for name, array in levels.rows.arrays.items():
        np.testing.assert_array_equal(getattr(loaded.rows, name), array)
    assert loaded.ids.tolist() == levels.ids.tolist() and loaded.spec == "training"
    np.testing.assert_array_equal(loaded.codons, levels.codons)
    with np.load(path, allow_pickle=False) as data:  # what a JAX user vmaps over: one batch axis
        assert data["rows.parts"].shape[:2] == data["rows.count"].shape == (6, levels.rows.count.shape[1])
        assert data["rows.start"].shape == (6, 3)
    (tmp_path / "bad.npz").write_bytes(b"not a zip")
    with pytest.raises(MazeError, match=r"bad\.npz.*cannot read levels"):
        Levels.load(tmp_path / "bad.npz")


def test_a_runs_scenario_files_are_levels_on_their_own_start_and_goal_with_their_genomes(factory_run):
    levels = file_levels(factory_run)
    assert len(levels) >= 1 and all(level.endswith(".json") for level in levels.ids.tolist())
    assert levels.has_genomes and levels.spec == "factory"
    spec = mazegen.load(EXAMPLES / "factory.maze")
    np.testing.assert_array_equal(levels.rows.goal, np.tile(spec.arena.goal, (len(levels), 1)))
    env = FloorVectorEnv(2, levels=factory_run, beams=0)
    _, info = env.reset(seed=0)
    assert set(info["level"].tolist()) <= set(levels.ids.tolist())


def test_every_autoreset_draws_from_the_source_it_was_given():
    calls = []

    def sampler(rng, n):
        calls.append(n)
        return pool.take(rng.integers(0, len(pool), n))

    pool = SpecLevels(TRAINING_SPEC, batch=32).sample(np.random.default_rng(0), 8)
    env = FloorVectorEnv(4, levels=sampler, beams=0, seed=0)
    env.reset(seed=1)
    seen = set()
    for _ in range(600):
        _, _, _, _, info = env.step(env.expert_actions("straight"))
        seen |= set(info["level"].tolist())
    assert sum(calls) > 8 and seen <= set(pool.ids.tolist())
    with pytest.raises(MazeError, match="a level sampler asked for 4 levels returned 1 levels"):
        FloorVectorEnv(4, levels=lambda rng, n: pool.take([0]), beams=0)


def test_the_registered_single_floor_env_passes_gymnasiums_checker():
    import mazegen.gym  # noqa: F401 - registers mazegen/Floor-v0

    env = gymnasium.make("mazegen/Floor-v0")
    check_env(env.unwrapped, skip_render_check=True)
    observation, info = env.reset(seed=3)
    assert env.observation_space.contains(observation) and info["level"].startswith("training:")
    vector = gymnasium.make_vec("mazegen/Floor-v0", num_envs=3, vectorization_mode="vector_entry_point")
    assert isinstance(vector.unwrapped, FloorVectorEnv) and vector.num_envs == 3


def test_the_single_env_plays_the_level_it_is_given(training):
    levels = training.sample(np.random.default_rng(2), 2)
    env = FloorEnv(levels=levels, beams=0)
    _, info = env.reset(options={"levels": levels.take([1])})
    assert info["level"] == levels.ids[1] and info["hash"] == levels.hashes[1]
    _, reward, terminated, truncated, info = env.step(np.array([10.0, 0.0]))
    assert isinstance(reward, float) and not terminated and not truncated and info["outcome"] == -1


def test_what_a_level_source_is_made_of():
    assert isinstance(level_source(TRAINING_SPEC), SpecLevels)
    with pytest.raises(MazeError, match="levels must be a spec, files, Levels, a source or a sampler"):
        level_source(3.5)


def test_a_robot_for_levels_already_made_is_refused_not_ignored(training):
    levels = training.sample(np.random.default_rng(6), 2)
    with pytest.raises(MazeError, match="levels already made carry theirs"):
        level_source(levels, robot=training.robot)
    with pytest.raises(MazeError, match="levels already made carry theirs"):
        FloorVectorEnv(2, levels=lambda rng, n: levels, robot=training.robot, beams=0)
