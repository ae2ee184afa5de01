"""Driving robots through floors: a batched, exact, deterministic simulator and its controllers.

One robot per floor, all stepping in lockstep inside numba kernels: unicycle kinematics with
speed, turn-rate and acceleration limits; collisions decided on the elements' exact convex parts
along each step's motion; a 2D lidar cast against the same geometry. See docs/simulation.md.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.simulation._drive import (
        DriveRequest,
        compile_loop,
        compile_set_up,
        drive,
        drive_many,
    )
    from mazegen.runtime.simulation._episodes import (
        ARRIVED,
        COLLISION,
        NO_PATH,
        OUTCOMES,
        TIMEOUT,
        Episodes,
        barn_score,
    )
    from mazegen.runtime.simulation._levels import LevelRows, level_rows
    from mazegen.runtime.simulation._lidar import beam_angles
    from mazegen.runtime.simulation._policy import Observations
    from mazegen.runtime.simulation._slots import REWARD_TERMS, Slots

__all__ = [
    "ARRIVED",
    "COLLISION",
    "NO_PATH",
    "OUTCOMES",
    "REWARD_TERMS",
    "TIMEOUT",
    "DriveRequest",
    "Episodes",
    "LevelRows",
    "Observations",
    "Slots",
    "barn_score",
    "beam_angles",
    "compile_loop",
    "compile_set_up",
    "drive",
    "drive_many",
    "level_rows",
]

__getattr__ = lazy_names(
    __name__,
    {
        "_drive": ["compile_loop", "compile_set_up", "drive", "drive_many", "DriveRequest"],
        "_episodes": ["ARRIVED", "barn_score", "COLLISION", "Episodes", "NO_PATH", "OUTCOMES", "TIMEOUT"],
        "_levels": ["LevelRows", "level_rows"],
        "_lidar": ["beam_angles"],
        "_policy": ["Observations"],
        "_slots": ["REWARD_TERMS", "Slots"],
    },
)
