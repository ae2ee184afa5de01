"""The curriculum's interface: the mutator, the comparator, the prioritised level sampler with jaxued's
semantics, and the scores that feed it."""

from __future__ import annotations

import numpy as np
import pytest

from mazegen.errors import MazeError
from mazegen.gym import (
    TRAINING_SPEC,
    FloorVectorEnv,
    LevelMutator,
    Levels,
    LevelSampler,
    SpecLevels,
    controller_failure,
    duplicates,
    max_monte_carlo,
    positive_value_loss,
)


@pytest.fixture(scope="module")
def generator() -> SpecLevels:
    return SpecLevels(TRAINING_SPEC, batch=64)


@pytest.fixture(scope="module")
def levels(generator):
    return generator.sample(np.random.default_rng(11), 12)


def test_mutated_levels_are_valid_floors_of_the_spec_near_their_parents(generator, levels):
    mutator = LevelMutator(generator, rate=0.05)
    children = mutator.mutate(np.random.default_rng(3), levels, 10)
    assert len(children) == 10 and children.has_genomes and children.spec == "training"
    _, population = generator.problem.decode(children.codons, children.genes)
    assert population.valid.all() and np.isfinite(children.rows.optimal_time).all()
    parents = {tuple(c) for c in levels.codons.tolist()}
    changed = [tuple(c) not in parents for c in children.codons.tolist()]
    assert sum(changed) >= 8  # a rate of 0.05 over 32 codons and 12 x 5 genes leaves few unchanged
    same = mutator.mutate(np.random.default_rng(3), levels, 10)
    assert same.hashes.tolist() == children.hashes.tolist()


def test_only_levels_with_genomes_of_its_spec_mutate(generator, levels):
    bare = Levels(levels.rows, levels.ids, levels.hashes, levels.difficulty, levels.task, "training")
    with pytest.raises(MazeError, match="only levels with genomes of spec training"):
        LevelMutator(generator).mutate(np.random.default_rng(0), bare, 2)


def test_duplicates_are_levels_met_before(levels):
    doubled = levels.take([0, 1, 0, 2, 1])
    np.testing.assert_array_equal(duplicates(doubled), [False, False, True, False, True])
    np.testing.assert_array_equal(duplicates(levels.take([3, 4]), against=levels.take([4])), [False, True])


def test_rank_prioritisation_mixes_rank_and_staleness_as_plr_does(levels):
    sampler = LevelSampler(capacity=4, staleness_coef=0.25, temperature=0.5)
    sampler.insert(levels.take([0, 1, 2]), np.array([0.3, 0.9, 0.1]))
    ranks = np.array([2.0, 1.0, 3.0])
    by_score = ranks ** (-1 / 0.5) / (ranks ** (-1 / 0.5)).sum()
    stale = 3 - np.array([1.0, 2.0, 3.0])  # episodes since each was seen: inserted at 1, 2, 3
    np.testing.assert_allclose(sampler.weights(), 0.75 * by_score + 0.25 * stale / stale.sum())
    index, replayed = sampler.sample_replay_levels(np.random.default_rng(0), 50)
    assert set(replayed.hashes.tolist()) <= set(levels.hashes[:3].tolist())
    assert np.bincount(index, minlength=3).argmax() == 1  # the best score is drawn most


def test_a_full_buffer_keeps_the_best_scores_and_a_duplicate_only_updates_its_score(levels):
    sampler = LevelSampler(capacity=2, prioritization="topk", topk_k=1, staleness_coef=0.0)
    sampler.insert(levels.take([0, 1]), np.array([0.5, 0.2]))
    where = sampler.insert(levels.take([2, 3]), np.array([0.1, 0.7]))
    np.testing.assert_array_equal(where, [-1, 1])  # 0.1 beats nothing held; 0.7 replaces 0.2
    assert sampler.levels is not None and sampler.levels.hashes.tolist() == levels.hashes[[0, 3]].tolist()
    np.testing.assert_array_equal(sampler.weights(), [0.0, 1.0])
    assert sampler.insert(levels.take([0]), 0.9).tolist() == [0] and sampler.size == 2
    sampler.update(np.array([1]), np.array([0.05]))
    np.testing.assert_array_equal(sampler.weights(), [1.0, 0.0])


def test_an_environment_fed_by_the_sampler_plays_replays_and_fresh_levels(generator, levels):
    sampler = LevelSampler(capacity=4, replay_prob=0.5, minimum_fill_ratio=0.5, generator=generator)
    sampler.insert(levels.take([0, 1]), np.array([1.0, 2.0]))
    env = FloorVectorEnv(6, levels=sampler, beams=0, seed=0)
    _, info = env.reset(seed=5)
    held = set(levels.ids[:2].tolist())
    played = info["level"].tolist()
    assert any(level in held for level in played) and any(level not in held for level in played)
    assert sampler.size == 4  # fresh levels went into the buffer
    np.testing.assert_array_equal(sampler.index_of(levels.hashes[[1, 5]]), [1, -1])


def test_regret_estimates_match_hand_worked_rollouts():
    rewards = np.array([[1.0], [0.0], [2.0]])
    values = np.array([[0.5], [1.0], [0.0]])
    dones = np.array([[0.0], [1.0], [0.0]])
    gamma, lam = 0.5, 1.0
    # t=2: delta = 2 + 0.5*1.0 - 0 = 2.5; t=1 (done): delta = 0 - 1 = -1; t=0: 1 + 0.5*1 - 0.5 = 1,
    # advantage 1 + 0.5*(-1) = 0.5. Positive parts: 2.5, 0, 0.5.
    loss = positive_value_loss(rewards, values, dones, np.array([1.0]), gamma=gamma, lam=lam)
    np.testing.assert_allclose(loss, [(2.5 + 0.0 + 0.5) / 3])
    returns = np.array([[1.5], [0.0], [2.5]])
    np.testing.assert_allclose(max_monte_carlo(returns, values, np.array([3.0])), [3.0 - 0.5])


def test_a_bundled_controllers_failure_scores_the_levels(levels):
    failed = controller_failure(levels, "straight", beams=0)
    env = FloorVectorEnv(len(levels), levels=levels, beams=0, autoreset_mode="same_step")
    env.reset(options={"levels": levels})
    ended = np.full(len(levels), -1)
    while (ended < 0).any():
        _, _, terminated, truncated, info = env.step(env.expert_actions("straight"))
        done = (terminated | truncated) & (ended < 0)
        if done.any():
            ended[done] = info["final_info"]["outcome"][done]
    np.testing.assert_array_equal(failed, (ended != 0).astype(float))


def test_an_update_of_a_level_not_held_is_one_line(levels):
    sampler = LevelSampler(capacity=2)
    sampler.insert(levels.take([0]), 0.5)
    with pytest.raises(MazeError, match=r"buffer indices within \[0, 1\) and one score each"):
        sampler.update(np.array([1]), np.array([0.3]))
    with pytest.raises(MazeError, match="one score each"):
        sampler.update(np.array([0, 0]), np.array([0.3, 0.2, 0.1]))
    sampler.update(np.array([0]), 0.75)
    assert sampler.scores.tolist() == [0.75]
