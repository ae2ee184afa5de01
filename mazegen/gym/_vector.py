"""``FloorVectorEnv``: a native Gymnasium vector environment stepping every robot in one compiled call.

Each sub-environment is a slot of :class:`mazegen.runtime.simulation.Slots`: a robot on a level
(floor, task, robot limits) drawn from the environment's level source. The source is the only place
levels come from, at ``reset`` and at every automatic reset, unless ``reset`` is given levels
explicitly (``options={"levels": ...}``). Observations, actions, reward and the autoreset modes are
those of docs/learning.md.
"""

from __future__ import annotations

import math
from dataclasses import astuple, dataclass
from typing import Any

import numpy as np
from gymnasium.spaces import Box, Dict, Space
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from mazegen.errors import MazeError
from mazegen.gym._levels import Levels
from mazegen.gym._sources import LevelPool, LevelSource, level_source
from mazegen.runtime.simulation import ARRIVED, COLLISION, REWARD_TERMS, TIMEOUT, Slots, beam_angles
from mazegen.spec import Robot

MODES = (AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP, AutoresetMode.DISABLED)
"""The autoreset modes of Gymnasium 1.x, every one of which the environment runs."""


@dataclass(frozen=True)
class Reward:
    """The weights of a step's reward (docs/learning.md): ``progress`` per metre of the way to go
    covered (the progress terms of an episode add up to its start's way to go less its end's), an
    ``arrival`` bonus, a ``collision`` penalty (each step that touches, for a robot whose contacts
    continue) and a ``time`` penalty every step."""

    progress: float = 1.0
    arrival: float = 10.0
    collision: float = 10.0
    time: float = 0.01

    def __post_init__(self) -> None:
        if not all(math.isfinite(value) for value in astuple(self)):
            raise MazeError(f"reward weights must be finite numbers, got {self}")

    @property
    def weights(self) -> np.ndarray:
        """``float64[4]`` in :data:`mazegen.runtime.simulation.REWARD_TERMS` order."""
        return np.array([getattr(self, term) for term in REWARD_TERMS], np.float64)


class FloorVectorEnv(VectorEnv):
    """``num_envs`` robots, each on a level of its own, stepped together in compiled kernels.

    Args:
        num_envs: Sub-environments.
        levels: The level source (:func:`mazegen.gym.level_source`): None for fresh floors of the
            bundled training spec, a spec or ``.maze`` path, scenario files or folders, a ``.npz`` of
            levels, :class:`Levels`, anything with ``sample(rng, n)``, or a function ``(rng, n)``.
        robot: The robot of every level drawn from a spec or files (default each spec's).
        reward: The reward's weights.
        beams: Lidar beams over ``fov`` radians centred on the heading (0: no lidar and no ``scan``).
        fov: The lidar's field of view.
        waypoint: Metres ahead along the level's path of the ``waypoint`` observed (None: not observed).
        autoreset_mode: One of :data:`MODES` (Gymnasium's ``AutoresetMode``), default ``NEXT_STEP``.
        seed: Seeds the draw of the levels made to size the spaces; ``reset(seed=...)`` seeds the rest.
    """

    metadata: dict[str, Any] = {  # noqa: RUF012 - Gymnasium declares it so
        "autoreset_mode": AutoresetMode.NEXT_STEP,
        "autoreset_modes": MODES,
        "render_modes": [],
    }

    def __init__(
        self,
        num_envs: int = 64,
        *,
        levels: Any = None,
        robot: Robot | None = None,
        reward: Reward | None = None,
        beams: int = 360,
        fov: float = 2 * math.pi,
        waypoint: float | None = None,
        autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
        seed: int | None = None,
    ) -> None:
        if not isinstance(num_envs, int) or num_envs < 1:
            raise MazeError(f"num_envs must be a positive integer, got {num_envs!r}")
        if not isinstance(beams, int) or beams < 0 or not 0 < fov <= 2 * math.pi:
            raise MazeError(f"beams must be an integer >= 0 and fov within (0, 2 pi], got {beams!r}, {fov!r}")
        if waypoint is not None and not (isinstance(waypoint, int | float) and 0 < waypoint < math.inf):
            raise MazeError(f"waypoint must be a positive number of metres, got {waypoint!r}")
        mode = _mode(autoreset_mode)
        self.num_envs = num_envs
        self.autoreset_mode = mode
        self.metadata = {**type(self).metadata, "autoreset_mode": mode}
        self.source: LevelSource = level_source(levels, robot=robot)
        self.reward_weights = (reward or Reward()).weights
        self._rng = np.random.default_rng(seed)
        self.slots = Slots(num_envs, beam_angles(beams, fov), waypoint=waypoint or 0.0)
        self.playing = {key: np.empty(num_envs, object) for key in ("level", "hash", "task")}
        self.playing["difficulty"] = np.full(num_envs, np.nan)
        self._ended = np.zeros(num_envs, np.bool_)
        self._play(np.arange(num_envs))
        limits = self.slots.levels.limits
        low = np.array([limits[:, 1].min(), -limits[:, 2].max()])
        high = np.array([limits[:, 0].max(), limits[:, 2].max()])
        self.single_action_space = Box(low, high, dtype=np.float64)
        goal = Box(np.array([0.0, -1.0, -1.0]), np.array([np.inf, 1.0, 1.0]), dtype=np.float64)
        observed: dict[str, Space[Any]] = {"goal": goal}
        if beams:
            observed["scan"] = Box(0.0, np.inf, (beams,), np.float64)
        if waypoint:
            observed["waypoint"] = goal
        observed["velocity"] = Box(-np.inf, np.inf, (2,), np.float64)
        self.single_observation_space = Dict(observed)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.observation_space = batch_space(self.single_observation_space, num_envs)

    def reset(
        self, *, seed: int | list[int] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """Start new episodes: every sub-environment's, or those of ``options["reset_mask"]``, on levels
        drawn from the source (``seed`` reseeds its generator) or on ``options["levels"]``, one per
        sub-environment reset."""
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        options = dict(options or {})
        mask = options.pop("reset_mask", None)
        chosen = options.pop("levels", None)
        if options:
            raise MazeError(
                f"reset takes the options levels and reset_mask, got {', '.join(map(str, options))}"
            )
        where = np.arange(self.num_envs) if mask is None else np.flatnonzero(_mask(mask, self.num_envs))
        if chosen is not None and (not isinstance(chosen, Levels) or len(chosen) != where.size):
            raise MazeError(
                f"options['levels'] must be Levels, one for each of the {where.size} sub-environments reset"
            )
        self._play(where, chosen)
        self._ended[where] = False
        return self._observation(), self._info()

    def step(
        self, actions: Any
    ) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """Step every sub-environment by its action ``(v, w)`` (docs/learning.md: the autoreset modes)."""
        commands = np.asarray(actions, dtype=np.float64)
        if commands.shape != (self.num_envs, 2) or not np.isfinite(commands).all():
            raise MazeError(f"actions must be {self.num_envs} finite (v, w) rows, got shape {commands.shape}")
        mode = self.autoreset_mode
        waiting = self._ended.copy()
        if mode is AutoresetMode.DISABLED and waiting.any():
            raise MazeError(
                f"sub-environments {np.flatnonzero(waiting).tolist()} have ended: reset them "
                "(options={'reset_mask': ...}) before stepping, in autoreset mode DISABLED"
            )
        reward = self.slots.step(commands, self.reward_weights).copy()
        outcome = self.slots.robots.outcome
        terminated = (outcome == ARRIVED) | (outcome == COLLISION)
        truncated = outcome == TIMEOUT
        if mode is AutoresetMode.NEXT_STEP:
            terminated &= ~waiting
            truncated &= ~waiting
            reward[waiting] = 0.0
            if waiting.any():
                self._play(np.flatnonzero(waiting))
        ended = terminated | truncated
        info = self._info()
        if mode is AutoresetMode.SAME_STEP and ended.any():
            info |= {
                "final_obs": self._observation(),
                "_final_obs": ended.copy(),
                "_final_info": ended.copy(),
            }
            info["final_info"] = self._info()
            self._play(np.flatnonzero(ended))
            info |= self._info()
        else:
            self._ended = ended
        return self._observation(), reward, terminated, truncated, info

    def expert_actions(self, controller: str = "straight") -> np.ndarray:
        """``float64[num_envs, 2]``: the command bundled ``controller`` (default parameters) would give
        each robot now: ``straight``, or ``vfh`` with the lidar (controllers reading MazeGen's path or
        fields are not offered: nothing builds those per sub-environment)."""
        return self.slots.commands(controller)

    def _play(self, where: np.ndarray, levels: Levels | None = None) -> None:
        """Sub-environments ``where`` start episodes on ``levels``, by default levels drawn from the source
        (from a fixed pool, loaded straight from it: the same levels, without copying them first)."""
        rows = None
        if levels is None and isinstance(self.source, LevelPool):
            levels, rows = self.source.levels, self.source.draw(self._rng, where.size)
        elif levels is None:
            levels = self.source.sample(self._rng, where.size)
        self.slots.load(where, levels.rows, rows)
        for key, values in (("level", levels.ids), ("hash", levels.hashes), ("task", levels.task)):
            self.playing[key][where] = values if rows is None else values[rows]
        self.playing["difficulty"][where] = levels.difficulty if rows is None else levels.difficulty[rows]

    def _observation(self) -> dict[str, np.ndarray]:
        slots = self.slots
        seen = {"goal": slots.to_goal.copy(), "velocity": slots.velocity}
        if len(slots.angles):
            seen["scan"] = slots.ranges.copy()
        if slots.waypoint:
            seen["waypoint"] = slots.to_waypoint.copy()
        return seen

    def _info(self) -> dict[str, Any]:
        """Each sub-environment's level (id, hash, difficulty, task) and its episode's outcome
        (:data:`mazegen.runtime.simulation.OUTCOMES`' codes, -1 while it runs)."""
        found = {key: values.copy() for key, values in self.playing.items()}
        found["outcome"] = self.slots.robots.outcome.astype(np.int64)
        everywhere = np.ones(self.num_envs, np.bool_)
        return found | {f"_{key}": everywhere for key in found}


def _mode(given: AutoresetMode | str) -> AutoresetMode:
    """``given`` as Gymnasium's AutoresetMode: the enum, its value (``"NextStep"``) or its name."""
    for mode in MODES:
        if given in (mode, mode.value) or (isinstance(given, str) and given.upper() == mode.name):
            return mode
    names = ", ".join(mode.name.lower() for mode in MODES)
    raise MazeError(f"autoreset_mode must be one of {names} (Gymnasium's AutoresetMode), got {given!r}")


def _mask(mask: Any, n: int) -> np.ndarray:
    found = np.asarray(mask)
    if found.shape != (n,) or found.dtype != np.bool_ or not found.any():
        raise MazeError(f"options['reset_mask'] must be {n} booleans, at least one True")
    return found
