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
from mazegen.runtime.navigation import navigation_of
from mazegen.runtime.simulation import ARRIVED, NO_PATH, OUTCOMES, Episodes
from mazegen.spec import Robot, Spec, unsized_problem


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
        """A JSON-ready line: the file, the controller and :meth:`measures`."""
        return {"file": self.file, "controller": self.controller, **self.measures()}

    def line(self, unit: str) -> str:
        """The drive in words: ``arrived, 31.1 s, 1555 cm driven, closest 14.8 cm, score 0.5``."""
        if not self.driven:
            return f"{self.outcome} (not driven)"
        return (
            f"{self.outcome}, {self.time:.1f} s, {self.distance:.1f} {unit} driven, "
            f"closest {self.clearance or 0.0:.1f} {unit}, score {self.score:.3g}"
            + (f", {self.contacts} steps touching" if self.contacts and self.outcome != "collision" else "")
        )


def not_driven(file: str, controller: str) -> Drive:
    """The :class:`Drive` of a floor without a path."""
    return Drive(file, controller, OUTCOMES[NO_PATH], 0.0, 0.0, None, None, 0.0, False, None, ())


def episode_drive(file: str, episodes: Episodes, index: int, scores: np.ndarray) -> Drive:
    """Episode ``index`` of ``episodes`` as a :class:`Drive`, rounded as documents are."""
    if episodes.outcome[index] == NO_PATH:  # the simulator's path search found none either
        return not_driven(file, episodes.controller)
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
    )


@dataclass(frozen=True)
class Floors:
    """Scenario documents of one spec, ready to drive.

    Attributes:
        spec: The spec the documents were made under (its arena, elements and robot).
        files: Each document's file, in order.
        population: One individual per document, in the same order.
        solvable: ``bool[N]`` whether the robot has a path from start to goal.
    """

    spec: Spec
    files: tuple[str, ...]
    population: Population
    solvable: np.ndarray

    @classmethod
    def of(cls, spec: Spec, documents: Sequence[tuple[str, dict[str, Any]]]) -> Floors:
        """The floors of ``(file, document)`` pairs, each document already checked against ``spec``."""
        table = ElementTable.from_types(spec.scenario_elements)
        population = population_from_documents(spec, table, list(documents))
        return cls.of_population(spec, [file for file, _ in documents], population)

    @classmethod
    def of_population(cls, spec: Spec, files: Sequence[str], population: Population) -> Floors:
        """The floors of a population made from the documents ``files`` (one individual each)."""
        return cls(spec, tuple(files), population, navigation_of(population).solvable.copy())

    @property
    def robot(self) -> Robot:
        """The spec's robot, or the arena's default robot when the spec has no robot block."""
        return self.spec.robot_or_default

    @property
    def without_path(self) -> list[str]:
        """The files of the floors that are not driven: no path from start to goal."""
        return [file for file, solvable in zip(self.files, self.solvable) if not solvable]

    def drive(self, controllers: Sequence[str]) -> list[list[Drive]]:
        """Drive every floor with a path with each controller (with the spec's settings of it), one
        batch call per controller; ``[floor][controller]`` in the order of files and controllers."""
        return drive_batches([self], controllers)[0]


def drive_batches(batches: Sequence[Floors], controllers: Sequence[str]) -> list[list[list[Drive]]]:
    """Drive every floor with a path of every batch (each with its spec's robot and settings of the
    controller) with each controller: the floors of all batches in one batch of the simulator per
    controller. ``[batch][floor][controller]``, in the order of batches, files and controllers."""
    from mazegen.runtime.simulation import DriveRequest, drive_many

    indices = [np.flatnonzero(batch.solvable) for batch in batches]
    drives = [[[not_driven(file, name) for name in controllers] for file in batch.files] for batch in batches]
    driven = [k for k, rows in enumerate(indices) if rows.size]
    for column, name in enumerate(controllers):
        requests = [
            DriveRequest(
                batches[k].population, batches[k].robot, batches[k].robot.controller(name), indices[k]
            )
            for k in driven
        ]
        for k, episodes in zip(driven, drive_many(requests, record=True)):
            scores = episodes.score()
            for row, index in enumerate(indices[k].tolist()):
                drives[k][index][column] = episode_drive(batches[k].files[index], episodes, row, scores)
    return drives


def drive_floors(
    floors: Sequence[Floor],
    controllers: Sequence[str],
    *,
    no_path: Callable[[str, Floors], None] | None = None,
) -> tuple[list[Floor], list[list[Drive]]]:
    """Drive each floor with each controller: the floors of every spec (a floor's own start and goal
    make a spec of their own) in one batch per controller. Returns the floors grouped by spec, in
    the order each spec first appears, and their drives, ``[floor][controller]`` in that order;
    ``no_path`` is told of each floor not driven for want of a path, before any is driven."""
    groups: dict[Spec, list[Floor]] = {}
    for floor in floors:
        groups.setdefault(floor.needs_spec("driving"), []).append(floor)
    batches = [
        Floors.of(spec, [(floor.where, floor.document) for floor in group]) for spec, group in groups.items()
    ]
    if no_path is not None:
        for batch in batches:
            for file in batch.without_path:
                no_path(file, batch)
    drives = [row for batch_drives in drive_batches(batches, controllers) for row in batch_drives]
    return [floor for group in groups.values() for floor in group], drives


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
    for column, name in enumerate(controllers):
        driven = [row[column] for row in drives if row[column].driven]
        scores = [drive.score for drive in driven]
        mean = _round(sum(scores) / len(scores)) if scores else None
        found.append(Summary(name, len(driven), sum(drive.arrived for drive in driven), mean))
    return found


def with_drives(document: dict[str, Any], drives: Sequence[Drive]) -> dict[str, Any]:
    """``document`` with its ``drive`` section holding ``drives`` (earlier drives by other controllers
    are kept; a controller driven again replaces its entry)."""
    section = dict(document.get("drive") or {})
    section.update({drive.controller: drive.section() for drive in drives})
    return {**document, "drive": section}
