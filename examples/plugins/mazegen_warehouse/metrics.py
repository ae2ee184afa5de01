"""A measure of a floor as a metric plug-in: how much room the nearest element leaves the dock."""

from __future__ import annotations

import numpy as np

ROOM = 5.0
"""Metres beyond which more room counts for nothing."""


def dock_clearance(floors, x: float = 0.0, y: float = 0.0) -> np.ndarray:
    """Distance in metres, at most :data:`ROOM`, from the dock at ``(x, y)`` (arena units) to the
    nearest element's bounding box; a floor without elements leaves the dock all the room."""
    box = floors.bounds  # float64[N, K, 4], NaN in empty slots
    dx = np.maximum(np.maximum(box[..., 0] - x, x - box[..., 2]), 0.0)  # NaN in empty slots
    dy = np.maximum(np.maximum(box[..., 1] - y, y - box[..., 3]), 0.0)
    nearest = np.fmin.reduce(np.hypot(dx, dy), axis=1, initial=np.inf)  # fmin skips NaN
    return np.minimum(nearest * floors.metres_per_unit, ROOM)
