"""Driving robots through scenario documents, for ``mazegen drive`` and ``mazegen score``.

The documents of one spec become one population; the floors where the robot has no path from
start to goal are known before anything is driven (they are not driven: ``no path``); each
controller then drives every other floor, of every spec, in one batch call of the simulator.
What a drive gives is kept as a :class:`Drive` per floor and controller, which is also the
``drive`` section a document carries (``docs/scenario-format.md``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from mazegen.errors import MazeError
from mazegen.runtime.documents._floor import Floor
from mazegen.runtime.documents._scenario import DIGITS, population_from_documents
from mazegen.runtime.engine import Population
from mazegen.runtime.geometry import ElementTable
from mazegen.runtime.navigation import navigation_of, task_views
from mazegen.runtime.simulation import ARRIVED, NO_PATH, OUTCOMES, Episodes
from mazegen.spec import Robot, Spec, Task, unsized_problem


def _round(value: float) -> float:
    return round(float(value), DIGITS) + 0.0  # + 0.0: no -0.0


def _heading(theta: float) -> float:
    """Radians as the documents write angles: degrees counter-clockwise, ``0 <= heading < 360``."""
    return round(math.degrees(theta) % 360.0, DIGITS) % 360.0  # 359.99996 must not round to 360


@dataclass(frozen=True)
class Drive:
    """One controller's episode on one floor.

    Attributes:
        file: The scenario file, as given.
        controller: The controller's name.
        outcome: ``arrived``, ``collision``, ``timeout`` or ``no path`` (not driven).
        time: Seconds driven; ``distance`` the track's length and ``clearance`` the closest
            approach of the robot's edge (None when not driven), in arena units.
        optimal_time: The path's length over the top speed (BARN's OT), None without a path.
        score: BARN's score of the episode (0 for a failure, at most 0.5).
        stuck: A timeout that ended early for lack of progress.
        collision: The robot's centre at first contact, or None.
        trajectory: ``[x, y, heading]`` at every step, heading in degrees.
        contacts: Steps that touched an obstacle, for a robot whose contacts continue (0 otherwise).
        task: The task's name, on a floor of several tasks (None on a floor of one).
    """

    file: str
    controller: str
    outcome: str
    time: float
    distance: float
    clearance: float | None
    optimal_time: float | None
    score: float
    stuck: bool
    collision: tuple[float, float] | None
    trajectory: tuple[tuple[float, float, float], ...]
    contacts: int = 0
    task: str | None = None

    @property
    def arrived(self) -> bool:
        return self.outcome == OUTCOMES[ARRIVED]

    @property
    def driven(self) -> bool:
        return self.outcome != OUTCOMES[NO_PATH]

    def section(self) -> dict[str, Any]:
        """The controller's entry of a document's ``drive`` section (``contacts`` only when a robot whose
        contacts continue touched something)."""
        touched = {"contacts": self.contacts} if self.contacts and self.outcome != "collision" else {}
        return {
            "outcome": self.outcome,
            "time": self.time,
            "distance": self.distance,
            "clearance": self.clearance,
            "optimal_time": self.optimal_time,
            "score": self.score,
            "stuck": self.stuck,
            "collision": None if self.collision is None else list(self.collision),
            **touched,
            "trajectory": [list(pose) for pose in self.trajectory],
        }

    def measures(self) -> dict[str, Any]:
        """The section without its trajectory: what a line of output shows."""
        section = self.section()
        del section["trajectory"]
        return section

    def record(self) -> dict[str, Any]:
        """A JSON-ready line: the file, its task (on a floor of several), the controller and
        :meth:`measures`."""
        task = {} if self.task is None else {"task": self.task}
        return {"file": self.file, **task, "controller": self.controller, **self.measures()}

    def line(self, unit: str) -> str:
        """The drive in words: ``arrived, 31.1 s, 1555 cm driven, closest 14.8 cm, score 0.5``."""
        if not self.driven:
            return f"{self.outcome} (not driven)"
        return (
            f"{self.outcome}, {self.time:.1f} s, {self.distance:.1f} {unit} driven, "
            f"closest {self.clearance or 0.0:.1f} {unit}, score {self.score:.3g}"
            + (f", {self.contacts} steps touching" if self.contacts and self.outcome != "collision" else "")
        )


def not_driven(file: str, controller: str, task: str | None = None) -> Drive:
    """The :class:`Drive` of a floor (or one of its tasks) without a path."""
    return Drive(file, controller, OUTCOMES[NO_PATH], 0.0, 0.0, None, None, 0.0, False, None, (), task=task)


def episode_drive(
    file: str, episodes: Episodes, index: int, scores: np.ndarray, task: str | None = None
) -> Drive:
    """Episode ``index`` of ``episodes`` as a :class:`Drive`, rounded as documents are."""
    if episodes.outcome[index] == NO_PATH:  # the simulator's path search found none either
        return not_driven(file, episodes.controller, task)
    collision = episodes.collision[index]
    poses: tuple[tuple[float, float, float], ...] = ()
    if episodes.trajectory is not None:
        track = episodes.trajectory[index]
        track = track[~np.isnan(track[:, 0])]
        poses = tuple((_round(x), _round(y), _heading(theta)) for x, y, theta in track.tolist())
    optimal = float(episodes.optimal_time[index])
    return Drive(
        file=file,
        controller=episodes.controller,
        outcome=OUTCOMES[int(episodes.outcome[index])],
        time=_round(episodes.time[index]),
        distance=_round(episodes.distance[index]),
        clearance=_round(max(0.0, float(episodes.clearance[index]))),
        optimal_time=_round(optimal) if math.isfinite(optimal) else None,
        score=_round(scores[index]),
        stuck=bool(episodes.stuck[index]),
        collision=None if np.isnan(collision).any() else (_round(collision[0]), _round(collision[1])),
        trajectory=poses,
        contacts=0 if episodes.contacts is None else int(episodes.contacts[index]),
        task=task,
    )


@dataclass(frozen=True)
class Floors:
    """Scenario documents of one spec, ready to drive.

    Attributes:
        spec: The spec the documents were made under (its arena, elements and robot).
        files: Each document's file, in order.
        population: One individual per document, in the same order.
    """

    spec: Spec
    files: tuple[str, ...]
    population: Population

    @classmethod
    def of(cls, spec: Spec, documents: Sequence[tuple[str, dict[str, Any]]]) -> Floors:
        """The floors of ``(file, document)`` pairs, each document already checked against ``spec``."""
        table = ElementTable.from_types(spec.scenario_elements)
        population = population_from_documents(spec, table, list(documents))
        return cls(spec, tuple(file for file, _ in documents), population)

    @property
    def robot(self) -> Robot:
        """The spec's robot, or the arena's default robot when the spec has no robot block."""
        return self.spec.robot_or_default

    @property
    def tasks(self) -> list[tuple[Task | None, Population]]:
        """Each task of the floors (None for a floor of one task) and the population that drives it."""
        views = task_views(self.population)
        return [(None, views[0])] if not self.spec.arena.tasks else list(zip(self.spec.arena.tasks, views))

    @property
    def without_path(self) -> list[tuple[str, Task | None]]:
        """The floors (and tasks, on floors of several) that are not driven: no path from start to goal."""
        return [
            (file, task)
            for task, view in self.tasks
            for file, solvable in zip(self.files, navigation_of(view).solvable)
            if not solvable
        ]

    def drive(self, controllers: Sequence[str]) -> list[list[Drive]]:
        """Drive every floor with a path with each controller (with the spec's settings of it), one
        batch call per controller; per floor, its drives task by task, controller by controller."""
        return drive_batches([self], controllers)[0]


def drive_batches(batches: Sequence[Floors], controllers: Sequence[str]) -> list[list[list[Drive]]]:
    """Drive every floor with a path of every batch (each with its spec's robot and settings of the
    controller) with each controller: the floors and tasks of all batches in one batch of the simulator
    per controller. ``[batch][floor]``: each floor's drives, task by task (its one task, or each of
    its arena's), controller by controller."""
    from mazegen.runtime.simulation import DriveRequest, drive_many

    units = [(k, task, view) for k, batch in enumerate(batches) for task, view in batch.tasks]
    indices = [np.flatnonzero(navigation_of(view).solvable) for _, _, view in units]
    drives = {
        (u, column): [
            not_driven(file, name, None if task is None else task.name) for file in batches[k].files
        ]
        for u, (k, task, _) in enumerate(units)
        for column, name in enumerate(controllers)
    }
    driven = [u for u, rows in enumerate(indices) if rows.size]
    for column, name in enumerate(controllers):
        requests = []
        for u in driven:
            k, task, view = units[u]
            robot = batches[k].robot
            starts = None if task is None else task.start_poses(indices[u].size)
            requests.append(DriveRequest(view, robot, robot.controller(name), indices[u], starts))
        for u, episodes in zip(driven, drive_many(requests, record=True)):
            k, task, _ = units[u]
            scores = episodes.score()
            for row, index in enumerate(indices[u].tolist()):
                drives[u, column][index] = episode_drive(
                    batches[k].files[index], episodes, row, scores, None if task is None else task.name
                )
    return [
        [
            [
                drives[u, column][index]
                for u, unit in enumerate(units)
                if unit[0] == k
                for column in range(len(controllers))
            ]
            for index in range(len(batch.files))
        ]
        for k, batch in enumerate(batches)
    ]


def drive_floors(
    floors: Sequence[Floor],
    controllers: Sequence[str],
    *,
    no_path: Callable[[str, Floors, Task | None], None] | None = None,
) -> tuple[list[Floor], list[list[Drive]]]:
    """Drive each floor with each controller: the floors of every spec (a floor's own start and goal
    make a spec of their own) in one batch per controller. Returns the floors grouped by spec, in
    the order each spec first appears, and their drives, task by task and controller by controller
    (:func:`drive_batches`); ``no_path`` is told of each floor (and task) not driven for want of a
    path, before any is driven."""
    ordered, batches = floor_batches(floors)
    if no_path is not None:
        for batch in batches:
            for file, task in batch.without_path:
                no_path(file, batch, task)
    drives = [row for batch_drives in drive_batches(batches, controllers) for row in batch_drives]
    return ordered, drives


def floor_batches(floors: Sequence[Floor]) -> tuple[list[Floor], list[Floors]]:
    """The floors grouped by spec (a floor's own start and goal make a spec of their own), in the
    order each spec first appears: the floors in that order, and one :class:`Floors` per spec."""
    groups: dict[Spec, list[Floor]] = {}
    for floor in floors:
        groups.setdefault(floor.needs_spec("driving"), []).append(floor)
    batches = [
        Floors.of(spec, [(floor.where, floor.document) for floor in group]) for spec, group in groups.items()
    ]
    return [floor for group in groups.values() for floor in group], batches


def driving_robot(spec: Spec, filename: str) -> Robot:
    """The robot that drives under ``spec`` (:attr:`Spec.robot_or_default`).

    Raises:
        MazeError: naming ``filename``, for a ``px`` arena with no robot radius to size the robot.
    """
    problem = unsized_problem(spec.arena)
    if problem is not None:
        raise MazeError(problem, filename=filename)
    return spec.robot_or_default


def spec_controllers(spec: Spec) -> list[str]:
    """The controllers a spec names, in its order: its robot block's, then its drive terms'."""
    names = [controller.name for controller in spec.robot.controllers] if spec.robot else []
    names += [name for term in spec.fitness if term.kind == "drive" for name in term.controllers]
    return list(dict.fromkeys(names))


@dataclass(frozen=True)
class Summary:
    """How one controller fared over the floors: driven, arrived, and BARN's mean score."""

    controller: str
    driven: int
    arrived: int
    mean_score: float | None

    @property
    def success(self) -> float | None:
        """The share of the floors driven where the robot arrived."""
        return self.arrived / self.driven if self.driven else None

    def record(self) -> dict[str, Any]:
        return {
            "controller": self.controller,
            "driven": self.driven,
            "arrived": self.arrived,
            "success": self.success,
            "mean_score": self.mean_score,
        }


def summaries(drives: Sequence[Sequence[Drive]], controllers: Sequence[str]) -> list[Summary]:
    """Each controller's :class:`Summary` over the floors driven (``drives`` as :meth:`Floors.drive`
    gives them); floors without a path count in neither the success rate nor the score."""
    found = []
    for name in controllers:
        driven = [drive for row in drives for drive in row if drive.controller == name and drive.driven]
        scores = [drive.score for drive in driven]
        mean = _round(sum(scores) / len(scores)) if scores else None
        found.append(Summary(name, len(driven), sum(drive.arrived for drive in driven), mean))
    return found


def with_drives(document: dict[str, Any], drives: Sequence[Drive]) -> dict[str, Any]:
    """``document`` with its ``drive`` section holding ``drives`` (earlier drives by other controllers
    are kept; a controller driven again replaces its entry); a task's drive goes into its entry of
    the document's ``tasks``."""
    mine = [drive for drive in drives if drive.task is None]
    if mine or all(drive.task is None for drive in drives):
        document = {**document, "drive": _section(document.get("drive"), mine)}
    if "tasks" not in document:
        return document
    tasks = [
        {**entry, "drive": _section(entry.get("drive"), [d for d in drives if d.task == entry["name"]])}
        if any(d.task == entry["name"] for d in drives)
        else entry
        for entry in document["tasks"]
    ]
    return {**document, "tasks": tasks}


def _section(section: dict[str, Any] | None, drives: Sequence[Drive]) -> dict[str, Any]:
    return {**(section or {}), **{drive.controller: drive.section() for drive in drives}}
