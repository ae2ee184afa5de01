"""What driving a batch of floors returns: one episode per floor, and BARN's score of it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

ARRIVED, COLLISION, TIMEOUT, NO_PATH = 0, 1, 2, 3
OUTCOMES = ("arrived", "collision", "timeout", "no path")
"""Outcome names by code: within the goal tolerance, touched an obstacle or the arena wall, out
of time (including an early stop for lack of progress), or not driven because MazeGen finds no
path from start to goal on the floor (its optimal time is NaN)."""


@dataclass(frozen=True)
class Episodes:
    """N episodes, one per floor, all driven by one controller.

    Attributes:
        controller: The controller's name.
        outcome: ``int8[N]`` codes of :data:`OUTCOMES`.
        time: ``float64[N]`` seconds driven until the episode ended.
        distance: ``float64[N]`` length of the robot's track, in arena units.
        clearance: ``float64[N]`` closest approach of the robot's edge to an obstacle or the arena
            wall over the episode (0 at a collision).
        optimal_time: ``float64[N]`` the optimal path's length over the robot's top speed (BARN's
            OT), NaN where no path exists.
        steps: ``int32[N]`` simulation steps taken.
        collision: ``float64[N, 2]`` where the robot's centre was at its first contact, NaN without one.
        stuck: ``bool[N]`` timeouts that ended early for lack of progress.
        contacts: ``int32[N]`` steps that touched an obstacle or the arena wall: 1 for a collision, any
            number for a robot whose contacts continue (``collision`` then holds the first's).
        trajectory: ``float64[N, T, 3]`` poses ``(x, y, theta)`` at every step up to ``steps``
            (NaN after), when recorded; else None.
    """

    controller: str
    outcome: np.ndarray
    time: np.ndarray
    distance: np.ndarray
    clearance: np.ndarray
    optimal_time: np.ndarray
    steps: np.ndarray
    collision: np.ndarray
    stuck: np.ndarray
    trajectory: np.ndarray | None = None
    contacts: np.ndarray | None = None

    @property
    def size(self) -> int:
        """Number of episodes."""
        return int(self.outcome.shape[0])

    @property
    def failed(self) -> np.ndarray:
        """``bool[N]``: collided, timed out or had no path."""
        return self.outcome != ARRIVED

    def time_ratio(self, failed_as: float) -> np.ndarray:
        """Time over the optimal time (BARN's AT / OT), a failure counting as ``failed_as`` (the
        robot's timeout factor: the longest an episode may last); NaN where no path exists."""
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(self.failed, failed_as, self.time / self.optimal_time)

    def score(self) -> np.ndarray:
        """The BARN challenge's score of each episode (see :func:`barn_score`)."""
        return barn_score(self.outcome == ARRIVED, self.time, self.optimal_time)


def barn_score(success: np.ndarray, actual_time: np.ndarray, optimal_time: np.ndarray) -> np.ndarray:
    """``1[success] × OT / clip(AT, 2·OT, 8·OT)``, the BARN challenge's score of a run: 0 for a
    failure, at most 0.5 for a run as fast as the optimal time allows."""
    ot = np.asarray(optimal_time, np.float64)
    at = np.clip(np.asarray(actual_time, np.float64), 2 * ot, 8 * ot)
    with np.errstate(invalid="ignore", divide="ignore"):
        score = np.where(np.asarray(success, bool), ot / at, 0.0)
    return np.nan_to_num(score, nan=0.0)
