"""A gap-seeking lidar policy in NumPy: a worked example of a user's controller for MazeGen.

MazeGen calls ``policy`` once per simulation step with the observations of every robot still
driving (:class:`mazegen.runtime.simulation.Observations`) and reads back one ``(v, w)`` per robot.
This one steers toward the open beam nearest the goal's bearing and slows down when the way ahead
is short. Drive it with::

    PYTHONPATH=examples/policies mazegen drive RUN_DIR --controller gap_seeking:policy

or from Python by passing ``policy`` itself as the controller (docs/simulation.md).
"""

from __future__ import annotations

import numpy as np

TURN_GAIN = 2.0
"""Turn rate per radian between the heading and the chosen gap."""
LOOK = 4.0
"""A beam is open when it reads farther than this many robot radii (or than the goal)."""


def policy(observations) -> np.ndarray:
    """``float64[n, 2]`` speed and turn rate of the ``n`` robots observed (a full-circle lidar)."""
    limits = observations.limits
    max_speed, max_turn, radius = limits[0], limits[2], limits[6]
    ranges, angles = observations.scan, observations.angles
    goal_distance = observations.goal[:, 0]
    bearing = np.arctan2(observations.goal[:, 2], observations.goal[:, 1])
    look = np.minimum(goal_distance, LOOK * radius)
    # A direction has room when every beam within the body's half-width seen from `look` is open.
    spread = 2 * np.pi / angles.size
    half = int(np.ceil(np.arcsin(min(1.0, 2.0 / LOOK)) / spread))
    open_beam = (ranges > look[:, None]).astype(np.int64)
    wrapped = np.concatenate([open_beam[:, -half:], open_beam, open_beam[:, :half]], axis=1)
    window = np.cumsum(np.pad(wrapped, ((0, 0), (1, 0))), axis=1)
    room = window[:, 2 * half + 1 :] - window[:, : -2 * half - 1] == 2 * half + 1
    off_goal = np.abs(np.angle(np.exp(1j * (angles[None, :] - bearing[:, None]))))
    choice = np.argmin(np.where(room, off_goal, np.inf), axis=1)
    trapped = ~room.any(axis=1)
    heading = np.where(trapped, np.pi / 2, angles[choice])
    ahead = np.where(np.abs(angles) <= spread * half, ranges, np.inf).min(axis=1)
    slow = np.clip((ahead - 1.5 * radius) / (LOOK * radius), 0.0, 1.0)
    speed = np.where(trapped, 0.0, max_speed * slow * np.clip(np.cos(heading), 0.0, 1.0))
    turn = np.clip(TURN_GAIN * heading, -max_turn, max_turn)
    return np.stack([speed, turn], axis=1)
