"""``FloorEnv``: one robot on one level at a time, the ``gymnasium.Env`` registered as
``mazegen/Floor-v0``; a :class:`~mazegen.gym._vector.FloorVectorEnv` of one sub-environment underneath,
so that both step alike."""

from __future__ import annotations

import math
from typing import Any

import gymnasium
import numpy as np
from gymnasium.vector import AutoresetMode

from mazegen.gym._vector import FloorVectorEnv, Reward
from mazegen.spec import Robot


class FloorEnv(gymnasium.Env):
    """One robot on a level drawn from ``levels`` at every ``reset``; the arguments are
    :class:`~mazegen.gym._vector.FloorVectorEnv`'s. ``reset(options={"levels": ...})`` takes one level."""

    metadata: dict[str, Any] = {"render_modes": []}  # noqa: RUF012 - Gymnasium declares it so

    def __init__(
        self,
        *,
        levels: Any = None,
        robot: Robot | None = None,
        reward: Reward | None = None,
        beams: int = 360,
        fov: float = 2 * math.pi,
        waypoint: float | None = None,
        seed: int | None = None,
    ) -> None:
        self.vector = FloorVectorEnv(
            1, levels=levels, robot=robot, reward=reward, beams=beams, fov=fov, waypoint=waypoint,
            autoreset_mode=AutoresetMode.DISABLED, seed=seed,
        )  # fmt: skip
        self.observation_space = self.vector.single_observation_space
        self.action_space = self.vector.single_action_space

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """A new episode on a level drawn from the source (``seed`` reseeds it), or ``options["levels"]``."""
        super().reset(seed=seed)
        observation, info = self.vector.reset(seed=seed, options=options)
        return _first(observation), _first(info)

    def step(self, action: Any) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        """One step by the action ``(v, w)``."""
        observation, reward, terminated, truncated, info = self.vector.step(
            np.asarray(action, np.float64)[None]
        )
        return _first(observation), float(reward[0]), bool(terminated[0]), bool(truncated[0]), _first(info)


def _first(batch: dict[str, Any]) -> dict[str, Any]:
    """The first sub-environment's entries of a batch of observations or infos (masks left out)."""
    return {key: values[0] for key, values in batch.items() if not key.startswith("_")}
