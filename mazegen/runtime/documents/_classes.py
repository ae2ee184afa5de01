"""The homotopy classes of scenario files, and which of them are the same test.

A floor's classes are found task by task on the configuration space of its spec's robot
(:mod:`mazegen.runtime.navigation._classes`). Two floors are equivalent when their canonical
classes match, task by task; for a controller, when its outcome and the class of the trajectory it
drove match too.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from mazegen.runtime.documents._driving import Drive, Floors, drive_floors
from mazegen.runtime.documents._floor import Floor
from mazegen.runtime.navigation import Topology, floor_topology
from mazegen.spec import DETOUR, MAX_CLASSES

if TYPE_CHECKING:
    from mazegen.spec import Task

NO_CLASS = "other"
"""A trajectory's class when it is none of the floor's classes kept (a detour, a loop)."""


@dataclass(frozen=True)
class FloorClasses:
    """The classes of one scenario file, task by task.

    Attributes:
        file: The scenario file, as given.
        tasks: ``(task name, its topology)``, the name None on a floor of one task.
    """

    file: str
    tasks: tuple[tuple[str | None, Topology], ...]

    @property
    def count(self) -> int:
        """Classes of every task together."""
        return sum(len(top.classes) for _, top in self.tasks)

    @property
    def signature(self) -> str:
        """The canonical class of the floor: its tasks', in order, ``;`` between them."""
        return ";".join(top.signature for _, top in self.tasks)

    def trajectory_class(self, drive: Drive) -> str | None:
        """The class of the trajectory ``drive`` drove (its task's), :data:`NO_CLASS` for one that is
        none of the classes kept; None for a robot that did not arrive."""
        if not drive.arrived:
            return None
        top = next(top for name, top in self.tasks if name == drive.task)
        found = top.class_of(np.array([(x, y) for x, y, _ in drive.trajectory]).reshape(-1, 2))
        return NO_CLASS if found is None else found

    def record(self, unit: str) -> dict:
        """The classes as JSON: per task its canonical class and each class's signature, length and
        narrowest gap (arena ``unit``)."""
        return {
            "file": self.file,
            "classes": self.count,
            "signature": self.signature,
            "unit": unit,
            "tasks": [
                {
                    "task": name,
                    "signature": top.signature,
                    "classes": [
                        {
                            "signature": c.signature,
                            "length": round(c.length, 6),
                            "narrowest": None if c.narrowest == float("inf") else round(c.narrowest, 6),
                        }
                        for c in top.classes
                    ],
                }
                for name, top in self.tasks
            ],
        }


def floor_classes(floor: Floor, *, max_classes: int = MAX_CLASSES, detour: float = DETOUR) -> FloorClasses:
    """The classes of ``floor``'s every task, for its spec's robot.

    Raises:
        MazeError: For a floor whose spec is unknown.
    """
    spec = floor.needs_spec("finding classes")
    free, grid = floor.configuration_space(None)
    tasks = spec.arena.tasks
    found = []
    for task in spec.arena.every_task:
        on = grid.for_task(task.start, task.goal)
        top = floor_topology(floor.population, on, 0, free=free, max_classes=max_classes, detour=detour)
        found.append((task.name if tasks else None, top))
    return FloorClasses(floor.where, tuple(found))


@dataclass(frozen=True)
class ClassGroup:
    """Floors that are one test.

    Attributes:
        key: What they share: the canonical class, then per controller its outcome and trajectory's class.
        files: The floors, in the order given; the first represents them.
    """

    key: str
    files: tuple[str, ...]


def equivalence_key(classes: FloorClasses, drives: Sequence[Drive] = ()) -> str:
    """What two equivalent floors share: their canonical class and, for each drive (controller and
    task, in order), its outcome and the class of its trajectory."""
    parts = [classes.signature]
    for drive in drives:
        found = classes.trajectory_class(drive)
        task = "" if drive.task is None else f"[{drive.task}]"
        parts.append(f"{drive.controller}{task} {drive.outcome}" + ("" if found is None else f" {found}"))
    return " | ".join(parts)


def equivalence_groups(keys: Sequence[tuple[str, str]]) -> list[ClassGroup]:
    """``(file, key)`` pairs grouped by key: the largest group first, then by key."""
    groups: dict[str, list[str]] = {}
    for file, key in keys:
        groups.setdefault(key, []).append(file)
    ordered = sorted(groups.items(), key=lambda item: (-len(item[1]), item[0]))
    return [ClassGroup(key, tuple(files)) for key, files in ordered]


@dataclass(frozen=True)
class Classification:
    """The classes of a set of floors and the tests they make.

    Attributes:
        floors: Each floor's classes, in the order given.
        drives: Each floor's drives (task by task, controller by controller), none without controllers.
        groups: The floors grouped by :func:`equivalence_key`, the largest group first.
    """

    floors: tuple[FloorClasses, ...]
    drives: tuple[tuple[Drive, ...], ...]
    groups: tuple[ClassGroup, ...]


def classify(
    floors: Sequence[Floor],
    controllers: Sequence[str] = (),
    *,
    max_classes: int = MAX_CLASSES,
    detour: float = DETOUR,
    no_path: Callable[[str, Floors, Task | None], None] | None = None,
) -> Classification:
    """The classes of ``floors`` and, driven by each of ``controllers`` (in one batch per spec), the
    outcome and trajectory class of every drive; floors grouped into the tests they make."""
    found = [floor_classes(floor, max_classes=max_classes, detour=detour) for floor in floors]
    by_file: dict[str, tuple[Drive, ...]] = {floor.where: () for floor in floors}
    if controllers:
        driven, rows = drive_floors(floors, controllers, no_path=no_path)
        by_file.update((floor.where, tuple(row)) for floor, row in zip(driven, rows))
    drives = tuple(by_file[floor.where] for floor in floors)
    keys = [(c.file, equivalence_key(c, row)) for c, row in zip(found, drives)]
    return Classification(tuple(found), drives, tuple(equivalence_groups(keys)))
