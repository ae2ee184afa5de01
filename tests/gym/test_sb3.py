"""The Stable-Baselines3 adapter: SB3's VecEnv conventions, and PPO training on it. Runs only where
stable-baselines3 (and PyTorch) is installed: MazeGen does not depend on either."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")

from stable_baselines3 import PPO

from mazegen.gym import TRAINING_SPEC, SpecLevels
from mazegen.gym.sb3 import FloorSB3VecEnv


@pytest.fixture(scope="module")
def levels():
    return SpecLevels(TRAINING_SPEC, batch=32).sample(np.random.default_rng(0), 6)


def test_an_ended_episode_gives_sb3_its_terminal_observation_and_truncation_flag(levels):
    env = FloorSB3VecEnv(num_envs=3, levels=levels, beams=0)
    env.seed(4)
    observation = env.reset()
    assert observation["goal"].shape == (3, 3)
    for _ in range(2000):
        env.step_async(np.tile([50.0, 0.4], (3, 1)))  # circles: collisions and timeouts
        observation, reward, done, infos = env.step_wait()
        if done.any():
            break
    k = int(np.flatnonzero(done)[0])
    assert reward.dtype == np.float32 and infos[k]["outcome"] in (1, 2)
    assert infos[k]["TimeLimit.truncated"] == (infos[k]["outcome"] == 2)
    assert not np.array_equal(infos[k]["terminal_observation"]["goal"], observation["goal"][k])
    np.testing.assert_array_equal(observation["velocity"][k], [0.0, 0.0])  # the new episode's start


def test_ppo_trains_on_it(levels):
    env = FloorSB3VecEnv(num_envs=4, levels=levels, beams=16)
    model = PPO("MultiInputPolicy", env, n_steps=32, batch_size=64, n_epochs=1, seed=0, device="cpu")
    model.learn(total_timesteps=256)
    actions, _ = model.predict(env.reset(), deterministic=True)
    assert actions.shape == (4, 2) and env.action_space.contains(actions[0].astype(np.float64))
