"""A user's batch policy: the observations it gets, how it is named, how its failures are said, and
the worked example in examples/policies."""

from __future__ import annotations

import math
import sys
import warnings

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

from mazegen.errors import MazeError
from mazegen.runtime.geometry._elements import world_parts
from mazegen.runtime.simulation import ARRIVED, Observations, drive
from mazegen.spec import robot_for
from tests.conftest import EXAMPLES
from tests.runtime.floors import ARENA, ZIGZAG, population
from tests.runtime.simulation.worlds import reference_range

SIZE = (ARENA.width, ARENA.height)


class Recorder:
    """Drives at half speed, turning gently, and keeps a copy of everything it is shown."""

    def __init__(self) -> None:
        self.seen: list[Observations] = []

    def __call__(self, observations: Observations) -> np.ndarray:
        self.seen.append(observations)
        n = observations.floor.size
        return np.tile([observations.limits[0] / 2, 0.2], (n, 1))


def test_a_policy_gets_the_documented_observations():
    floors = population(ARENA, [ZIGZAG, [], [("cobot", 300, 120, 60, 60, 30)]])
    robot = robot_for(ARENA, beams=24)
    recorder = Recorder()
    indices = np.array([2, 0, 1])
    episodes = drive(floors, robot=robot, controller=recorder, indices=indices, record=True)
    poses = episodes.trajectory
    assert poses is not None and episodes.controller == "Recorder"
    outlines = [
        shapely.union_all(
            [
                Polygon(p)
                for k in range(floors.n_elements[i])
                for p in world_parts(floors.table, floors.element_ids[i, k], floors.params[i, k])
            ]
        )
        for i in indices
    ]
    for step, seen in enumerate(recorder.seen[:40]):
        assert seen.step == step
        driving = np.flatnonzero(episodes.steps > step)
        np.testing.assert_array_equal(seen.floor, indices[driving])
        assert seen.scan.shape == (driving.size, 24) and seen.goal.shape == (driving.size, 3)
        np.testing.assert_allclose(seen.angles, -math.pi + 2 * math.pi / 24 * np.arange(24))
        expected_velocity = [0.0, 0.0] if step == 0 else [robot.max_speed / 2, 0.2]
        np.testing.assert_allclose(seen.velocity, np.tile(expected_velocity, (driving.size, 1)))
        for row, m in enumerate(driving):
            x, y, theta = poses[m, step]
            gx, gy = ARENA.goal
            bearing = math.atan2(gy - y, gx - x) - theta
            np.testing.assert_allclose(
                seen.goal[row], [math.hypot(gx - x, gy - y), math.cos(bearing), math.sin(bearing)]
            )
            expected = [
                reference_range(outlines[m], x, y, theta + a, robot.lidar_range, SIZE) for a in seen.angles
            ]
            np.testing.assert_allclose(seen.scan[row], expected, atol=1e-7)
    np.testing.assert_allclose(
        recorder.seen[0].limits[[0, 2, 6]], [robot.max_speed, robot.max_turn, ARENA.robot_radius]
    )


def raises(observations):
    raise ValueError("no idea where to go")


def exits(observations):
    raise SystemExit(3)


@pytest.mark.parametrize(
    ("policy", "message"),
    [
        (
            raises,
            r"^controller raises at step 0 \(floors 0\.\.\., 2 driving\) raised ValueError: "
            r"no idea where to go$",
        ),
        (
            lambda o: np.zeros((o.floor.size, 3)),
            r"^controller <lambda> at step 0 on floor 0: returned actions of shape \(2, 3\)",
        ),
        (
            lambda o: np.where(o.floor[:, None] == 1, np.nan, 1.0) * np.ones((1, 2)),
            r"^controller <lambda> at step 0 on floor 1: returned a non-finite",
        ),
        (exits, r"^controller exits at step 0 \(floors 0\.\.\., 2 driving\) raised SystemExit: 3$"),
        (
            lambda o: np.ones((o.floor.size, 2)) * (1 + 1j),
            r"^controller <lambda> at step 0 on floor 0: returned actions of type complex128, expected real",
        ),
        (
            lambda o: [["fast", "left"]] * o.floor.size,
            r"^controller <lambda> at step 0 on floor 0: returned actions of type <U4, expected real",
        ),
    ],
)
def test_a_failing_policy_is_one_line_naming_the_controller_step_and_floor(policy, message):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # said in the one line, not in a warning beside it
        with pytest.raises(MazeError, match=message) as raised:
            drive(population(ARENA, [[], []]), robot=robot_for(ARENA, beams=8), controller=policy)
    assert "\n" not in str(raised.value)
    if policy is raises:
        assert isinstance(raised.value.__cause__, ValueError)


@pytest.mark.parametrize("field", ["limits", "angles"])
def test_a_policy_cannot_write_into_what_the_simulator_reads(field):
    def vandal(observations):
        getattr(observations, field)[:] = np.nan
        return np.zeros((observations.floor.size, 2))

    floors, robot = population(ARENA, [[], []]), robot_for(ARENA, beams=8)
    with pytest.raises(MazeError, match=r"^controller vandal at step 0 .* raised ValueError: .*read-only"):
        drive(floors, robot=robot, controller=vandal)


def test_the_gap_seeking_example_drives_floors(monkeypatch):
    monkeypatch.syspath_prepend(str(EXAMPLES / "policies"))
    floors = population(ARENA, [[], [("cobot", 500, 300, 80, 80, 0)], ZIGZAG])
    episodes = drive(floors, robot=robot_for(ARENA), controller="gap_seeking:policy")
    assert episodes.controller == "gap_seeking:policy"
    assert episodes.outcome[0] == ARRIVED and episodes.outcome[1] == ARRIVED
    assert episodes.clearance[1] > 0


def test_a_policy_path_is_found_in_the_current_folder(tmp_path, monkeypatch):
    """As ``python -m`` finds it, though the ``mazegen`` command's path holds its script's folder."""
    (tmp_path / "forward_here.py").write_text(
        "import numpy as np\n\n"
        "def policy(observations):\n"
        "    return np.tile([observations.limits[0], 0.0], (observations.floor.size, 1))\n"
    )
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "path", [entry for entry in sys.path if entry not in ("", str(tmp_path))])
    monkeypatch.delitem(sys.modules, "forward_here", raising=False)
    episodes = drive(
        population(ARENA, [[]]), robot=robot_for(ARENA, beams=0), controller="forward_here:policy"
    )
    assert episodes.outcome[0] == ARRIVED


def test_a_package_registers_a_policy_under_the_entry_point_group(tmp_path, monkeypatch):
    (tmp_path / "wanderers.py").write_text(
        "import numpy as np\n\n"
        "def forward(observations):\n"
        "    return np.tile([observations.limits[0], 0.0], (observations.floor.size, 1))\n"
    )
    info = tmp_path / "wanderers-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: wanderers\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text("[mazegen.controllers]\nforward = wanderers:forward\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "wanderers", raising=False)
    episodes = drive(population(ARENA, [[]]), robot=robot_for(ARENA, beams=0), controller="forward")
    assert episodes.controller == "forward" and episodes.outcome[0] == ARRIVED
