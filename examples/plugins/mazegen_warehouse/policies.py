"""A controller as a policy plug-in: face the goal, then drive, slower where the way ahead is short."""

from __future__ import annotations

import numpy as np

TURN_GAIN = 2.0
"""Turn rate per radian between the heading and the goal's bearing."""
CAUTION = 6.0
"""Full speed only when the beams ahead read farther than this many robot radii."""


def cautious(observations) -> np.ndarray:
    """``float64[n, 2]`` speed and turn rate of the ``n`` robots observed."""
    max_speed, radius = observations.limits[0], observations.limits[6]
    bearing = np.arctan2(observations.goal[:, 2], observations.goal[:, 1])
    ahead = np.abs(observations.angles) < 0.3
    room = observations.scan[:, ahead].min(axis=1) if ahead.any() else np.full(len(bearing), np.inf)
    speed = max_speed * np.clip(room / (CAUTION * radius), 0.0, 1.0)
    speed = np.where(np.abs(bearing) < 0.6, speed, 0.0)
    return np.stack([speed, TURN_GAIN * bearing], axis=1)
