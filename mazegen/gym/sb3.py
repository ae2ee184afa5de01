"""``FloorSB3VecEnv``: the vector environment behind Stable-Baselines3's ``VecEnv`` interface, so that
SB3's algorithms (``PPO("MultiInputPolicy", env)``) train on MazeGen's floors without N wrapped
single environments. Needs ``stable-baselines3`` (and PyTorch), which MazeGen does not install."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from gymnasium.vector import AutoresetMode

try:
    from stable_baselines3.common.vec_env import VecEnv
except ImportError as error:  # pragma: no cover - the library not installed
    raise ImportError("FloorSB3VecEnv needs Stable-Baselines3: pip install stable-baselines3") from error

from mazegen.errors import MazeError
from mazegen.gym._vector import FloorVectorEnv

INFO_KEYS = ("level", "hash", "difficulty", "task", "outcome")
"""What each sub-environment's info holds, as ``FloorVectorEnv`` gives it."""


class FloorSB3VecEnv(VecEnv):
    """SB3's ``VecEnv`` over a ``FloorVectorEnv`` in ``SAME_STEP`` autoreset mode (SB3's own convention):
    an ended episode's last observation is ``info["terminal_observation"]``, a timeout is flagged
    ``info["TimeLimit.truncated"]``, and ``seed(s)`` then ``reset()`` reseeds the level draws.

    Args:
        env: The environment (its mode must be ``SAME_STEP``); default one made from ``kwargs``.
        kwargs: ``FloorVectorEnv``'s arguments, when ``env`` is not given.
    """

    def __init__(self, env: FloorVectorEnv | None = None, **kwargs: Any) -> None:
        self.env = env or FloorVectorEnv(**kwargs, autoreset_mode=AutoresetMode.SAME_STEP)
        if self.env.autoreset_mode is not AutoresetMode.SAME_STEP:
            raise MazeError(
                "Stable-Baselines3 resets an ended episode in the same step: use autoreset mode SAME_STEP"
            )
        super().__init__(self.env.num_envs, self.env.single_observation_space, self.env.single_action_space)
        self._actions = np.zeros((self.num_envs, 2))

    def reset(self) -> dict[str, np.ndarray]:
        """New episodes everywhere; the seed of the last ``seed()`` call reseeds the level draws."""
        seed = self._seeds[0] if self._seeds else None
        observation, _ = self.env.reset(seed=seed)
        self._reset_seeds()
        self._reset_options()
        return observation

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.asarray(actions, np.float64).reshape(self.num_envs, 2)

    def step_wait(self) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, list[dict[str, Any]]]:
        observation, reward, terminated, truncated, info = self.env.step(self._actions)
        done = terminated | truncated
        ended = info.get("final_info", info)
        infos = [{key: info[key][i] for key in INFO_KEYS} for i in range(self.num_envs)]
        for i in np.flatnonzero(done).tolist():
            infos[i] |= {key: ended[key][i] for key in INFO_KEYS}
            infos[i]["terminal_observation"] = {key: value[i] for key, value in info["final_obs"].items()}
            infos[i]["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
        return observation, reward.astype(np.float32), done, infos

    def close(self) -> None:
        """Nothing to release: the robots live in this process."""

    def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
        return [getattr(self.env, attr_name)] * len(self._indices(indices))

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
        setattr(self.env, attr_name, value)

    def env_method(
        self, method_name: str, *method_args: Any, indices: Any = None, **method_kwargs: Any
    ) -> list[Any]:
        return [getattr(self.env, method_name)(*method_args, **method_kwargs) for _ in self._indices(indices)]

    def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:
        return [False] * len(self._indices(indices))

    def _indices(self, indices: Any) -> Sequence[int]:
        if indices is None:
            return range(self.num_envs)
        return [indices] if isinstance(indices, int) else list(indices)
