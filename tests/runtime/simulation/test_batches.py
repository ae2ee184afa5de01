"""drive_many(): floors of different specs, arenas, tasks, robots and controller parameters drive in
one batch, and every episode is exactly what driving its floors alone gives."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mazegen.runtime.documents import Floors, load_floor
from mazegen.runtime.simulation import DriveRequest, Episodes, _loop, drive, drive_many
from mazegen.runtime.simulation import _drive as drive_module
from mazegen.spec import Arena, ControllerSpec, robot_for
from tests.conftest import EXAMPLES
from tests.runtime.documents.test_import import imported
from tests.runtime.floors import ARENA, population, random_floors

YARD = Arena("yard", 9.0, 7.0, "m", (0.8, 0.8), (8.2, 6.1), 0.25, 0.1)
"""A metre arena of another size, cell and robot."""
YARD_FLOORS = [
    [],
    [("vwall", 4.5, 3.0, 0.2, 4.0, 0)],
    [("hwall", 3.0, 4.0, 3.0, 0.2, 30), ("router", 6.0, 2.0, 0.8, 0.8, 10)],
]


def requests(controller: str, tmp_path) -> list[DriveRequest]:
    """Three specs: the cm hall with two tasks on the same floors, a metre yard with its own robot
    and controller settings, and an imported map (rect walls only) with three tasks."""
    floors = random_floors(np.random.default_rng(5), 6, ARENA)
    hall = population(ARENA, floors)
    other_task = dataclasses.replace(ARENA, start=(900.0, 80.0), goal=(120.0, 520.0))
    yard_robot = robot_for(YARD, max_speed=0.8, goal_tolerance=0.2, contact="continue")
    found = [
        DriveRequest(hall, robot_for(ARENA), controller),
        DriveRequest(population(other_task, floors), robot_for(other_task), controller, np.array([5, 0, 3])),
        DriveRequest(population(YARD, YARD_FLOORS), yard_robot, _tuned(controller)),
    ]
    for path in imported(
        EXAMPLES / "maps" / "rooms.txt", tmp_path / controller, "--tasks", "3", "--seed", "4"
    ):
        floor = load_floor(path)
        batch = Floors.of(floor.needs_spec("driving"), [(floor.where, floor.document)])
        found.append(DriveRequest(batch.population, batch.robot, batch.robot.controller(controller)))
    return found


def _tuned(controller: str) -> ControllerSpec | str:
    """Settings of the controller other than its defaults, where it has any to tune."""
    settings = {
        "dwa": (("v_samples", 7.0),),
        "purepursuit": (("lookahead", 0.6),),
        "vfh": (("safety", 0.15),),
        "movebase": (("w_samples", 12.0),),
    }
    return ControllerSpec(controller, settings[controller]) if controller in settings else controller


def assert_same(batched: Episodes, alone: Episodes) -> None:
    for field in dataclasses.fields(Episodes):
        a, b = getattr(batched, field.name), getattr(alone, field.name)
        if isinstance(a, np.ndarray):
            assert a.dtype == b.dtype and a.shape == b.shape, field.name
            assert np.array_equal(a, b, equal_nan=True), field.name
        else:
            assert a == b, field.name


@pytest.mark.parametrize("controller", ["straight", "purepursuit", "dwa", "vfh", "movebase"])
def test_one_batch_drives_every_request_exactly_as_alone(controller, tmp_path, monkeypatch):
    given = requests(controller, tmp_path)
    calls = []
    monkeypatch.setattr(
        drive_module,
        "run_bundled",
        lambda state, fields: calls.append(len(state.rows)) or _loop.run_bundled(state, fields),
    )
    batched = drive_many(given, record=True)
    assert calls == [
        sum(len(r.indices) if r.indices is not None else int(r.population.valid.sum()) for r in given)
    ]
    assert len(batched) == len(given)
    for request, episodes in zip(given, batched):
        alone = drive(
            request.population,
            robot=request.robot,
            controller=request.controller,
            indices=request.indices,
            record=True,
        )
        assert_same(episodes, alone)
    outcomes = np.concatenate([e.outcome for e in batched])
    assert len(set(outcomes.tolist())) > 1, "the floors should not all end alike"


def test_requests_of_different_lidars_or_a_policy_drive_apart_and_alike(tmp_path):
    seen = []

    def policy(observations):
        seen.append(observations.limits[0])
        return np.tile([observations.limits[0], 0.0], (observations.floor.size, 1))

    given = requests("straight", tmp_path)[:3]
    wide = dataclasses.replace(given[2], robot=dataclasses.replace(given[2].robot, beams=90))
    mixed = [dataclasses.replace(r, controller="vfh") for r in (given[0], wide)] + [
        dataclasses.replace(r, controller=policy) for r in (given[0], given[2])
    ]
    batched = drive_many(mixed)
    for request, episodes in zip(mixed, batched):
        assert_same(
            episodes,
            drive(
                request.population,
                robot=request.robot,
                controller=request.controller,
                indices=request.indices,
            ),
        )
    # the policy drives each request on its own: every call sees one robot's limits, both robots seen
    assert {float(limit) for limit in seen} == {given[0].robot.max_speed, given[2].robot.max_speed}
