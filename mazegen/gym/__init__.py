"""Learning on MazeGen's floors: a native Gymnasium vector environment, a single-floor environment
registered as ``mazegen/Floor-v0``, level sources and the curriculum's interface (docs/learning.md).

Needs Gymnasium: ``pip install "mazegen[gym]"``. Importing this package registers the environment.
"""

from typing import TYPE_CHECKING

try:
    import gymnasium
except ImportError as error:  # pragma: no cover - the extra not installed
    raise ImportError('mazegen.gym needs Gymnasium: pip install "mazegen[gym]"') from error

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.gym._curriculum import (
        LevelMutator,
        LevelSampler,
        controller_failure,
        duplicates,
        max_monte_carlo,
        positive_value_loss,
    )
    from mazegen.gym._levels import Levels
    from mazegen.gym._single import FloorEnv
    from mazegen.gym._sources import (
        TRAINING_SPEC,
        LevelPool,
        LevelSource,
        SpecLevels,
        file_levels,
        level_source,
        population_levels,
    )
    from mazegen.gym._vector import MODES, FloorVectorEnv, Reward

__all__ = [
    "MODES",
    "TRAINING_SPEC",
    "FloorEnv",
    "FloorVectorEnv",
    "LevelMutator",
    "LevelPool",
    "LevelSampler",
    "LevelSource",
    "Levels",
    "Reward",
    "SpecLevels",
    "controller_failure",
    "duplicates",
    "file_levels",
    "level_source",
    "max_monte_carlo",
    "population_levels",
    "positive_value_loss",
]

__getattr__ = lazy_names(
    __name__,
    {
        "_curriculum": [
            "controller_failure",
            "duplicates",
            "LevelMutator",
            "LevelSampler",
            "max_monte_carlo",
            "positive_value_loss",
        ],
        "_levels": ["Levels"],
        "_single": ["FloorEnv"],
        "_sources": [
            "file_levels",
            "level_source",
            "LevelPool",
            "LevelSource",
            "population_levels",
            "SpecLevels",
            "TRAINING_SPEC",
        ],
        "_vector": ["FloorVectorEnv", "MODES", "Reward"],
    },
)

ENV_ID = "mazegen/Floor-v0"
"""The single-floor environment's id for ``gymnasium.make`` (and ``gymnasium.make_vec``, which gives
the native vector environment)."""

if ENV_ID not in gymnasium.registry:
    gymnasium.register(
        id=ENV_ID,
        entry_point="mazegen.gym._single:FloorEnv",
        vector_entry_point="mazegen.gym._vector:FloorVectorEnv",
    )
