"""``mazegen import MAP.yaml|GRID.npy|GRID.txt|BARN.json -o DIR``: scenario documents from an occupancy map.

``DIR`` is laid out as a suite directory (``spec.json`` and ``scenario-NN.json``, one per task) with the
spec also in the language (``NAME.maze``), so that ``drive``, ``export`` and ``score`` read it as they
read any floor. Every file is made before any is written.
"""

from __future__ import annotations

import dataclasses
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

import click

from mazegen.cli.bounds import Bounded, BoundedOption, setting, within
from mazegen.cli.errors import reports_errors
from mazegen.errors import MazeError
from mazegen.spec import Point
from mazegen.text import printable

if TYPE_CHECKING:
    from mazegen.runtime.documents import ImportedMap

MAX_TASKS = 1000
"""Tasks one import may draw: one document each."""

DEFAULT_RADIUS = 0.3
"""Metres: BARN's Jackal radius (its C-space keeps 2 cells of 0.15 m)."""


def _point(option: str, text: str | None) -> Point | None:
    """``X,Y`` of ``option`` as two numbers, or a one-line error."""
    if text is None:
        return None
    try:
        x, y = (float(part) for part in text.split(","))
    except ValueError:
        raise MazeError(f"{option} must be X,Y (two numbers in metres), got {text!r}") from None
    return x, y


@click.command("import")
@click.argument("source", type=click.Path(path_type=Path))
@click.option(
    "-o",
    "--out",
    required=True,
    metavar="DIR",
    type=click.Path(file_okay=False, path_type=Path),
    help="Directory to write the documents and their spec into.",
)
@click.option("--start", metavar="X,Y", help="The robot's start, metres in the map's frame.")
@click.option("--goal", metavar="X,Y", help="The robot's goal, metres in the map's frame.")
@click.option(
    "--tasks",
    type=within(1, MAX_TASKS),
    cls=BoundedOption,
    help="Draw N starts and goals among free cells the robot can connect (one document each).",
)
@click.option(
    "--seed", type=setting("seed"), cls=BoundedOption, default=1, help="Seed of --tasks (default 1)."
)
@click.option(
    "--robot-radius",
    type=Bounded(float, lambda value: 0 <= value <= 100, "from 0 to 100 metres"),
    cls=BoundedOption,
    default=DEFAULT_RADIUS,
    help=f"The robot's radius in metres (default {DEFAULT_RADIUS}, BARN's Jackal).",
)
@click.option(
    "--resolution",
    type=float,
    help="Metres per cell of a .npy or .txt grid (default 1); a map_server YAML and BARN give their own.",
)
@click.option("--world", type=int, help="The world of a BARN file (barn-train.json) to import.")
@click.option("--force", is_flag=True, help="Replace files that exist already.")
@reports_errors
def import_command(
    source: Path,
    out: Path,
    start: str | None,
    goal: str | None,
    tasks: int | None,
    seed: int,
    robot_radius: float,
    resolution: float | None,
    world: int | None,
    force: bool,
) -> None:
    """Write scenario documents of an occupancy map: its obstacle cells merged into walls.

    SOURCE is a ROS map_server map (.yaml with its image), a grid of cells (.npy: nonzero an obstacle;
    .txt: rows of 0/1 or ./#, first row at the top) or BARN's barn-train.json with --world N. Each
    task, --start and --goal or --tasks N drawn at random, is one document; a BARN world without
    either gets the start and goal of BARN's 2020 timing runs.
    """
    given = [_point("--start", start), _point("--goal", goal)]
    if (given[0] is None) != (given[1] is None):
        raise MazeError("--start and --goal go together")
    if tasks is not None and given[0] is not None:
        raise MazeError("--tasks draws starts and goals: give it or --start and --goal, not both")
    from mazegen.maps import checked_resolution, read_occupancy_map
    from mazegen.runtime.documents import ImportedMap

    if resolution is not None:
        checked_resolution(resolution, "--resolution")
    imported = ImportedMap(read_occupancy_map(source, resolution=resolution, world=world), robot_radius)
    if given[0] is not None and given[1] is not None:
        chosen = [(given[0], given[1])]
    elif tasks is None and imported.map.task is not None:
        chosen = [imported.map.task]
    elif tasks is None:
        raise MazeError("give --start X,Y and --goal X,Y, or --tasks N", filename=str(source))
    if tasks is None:
        found = [(imported.checked_point("start", s), imported.checked_point("goal", g)) for s, g in chosen]
    else:
        found = imported.random_tasks(tasks, seed)
    _write(imported, found, source, out, force)


def _write(
    imported: ImportedMap, tasks: list[tuple[Point, Point]], source: Path, out: Path, force: bool
) -> None:
    """The spec, checked by the language, and one document per task, all made before any is written."""
    from mazegen.dsl.loader import load_spec
    from mazegen.runtime.documents import SuiteDirectory, dumps
    from mazegen.runtime.exporters import write_files

    maze = out / f"{imported.map.name}.maze"
    text = imported.maze_text(tasks[0], source.name)
    with tempfile.TemporaryDirectory() as folder:
        written = Path(folder) / maze.name
        written.write_text(text, encoding="utf-8")
        spec = dataclasses.replace(load_spec(written), source=str(maze))
    suite = SuiteDirectory(out)
    files = {maze: text.encode("utf-8"), suite.spec: spec.to_json().encode("utf-8")}
    for number, document in enumerate(imported.documents(spec, tasks), start=1):
        path = out / suite.scenario_name(number, ".json")
        files[path] = dumps(document, str(path)).encode("utf-8")
    write_files(files, force=force)
    click.echo(
        f"wrote {len(tasks)} scenario{'s' if len(tasks) > 1 else ''} of {len(imported.walls)} walls "
        f"and their spec to {printable(str(out))}"
    )
