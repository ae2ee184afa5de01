"""Read ``.maze`` files, follow their imports and build a :class:`Spec`."""

from __future__ import annotations

import contextlib
import dataclasses
import os
from collections.abc import Iterator
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from textx import get_model
from textx.exceptions import TextXSemanticError, TextXSyntaxError

from mazegen import plugins
from mazegen.dsl.arena import convert_arena
from mazegen.dsl.blocks import convert_evolution, convert_fitness, convert_scenario
from mazegen.dsl.elements import check_fits, convert_element, in_arena_units
from mazegen.dsl.located import display_path, fail, where
from mazegen.dsl.metamodel import metamodel
from mazegen.dsl.robot import convert_robot
from mazegen.dsl.structure import (
    Lengths,
    check_placed,
    check_row_fits,
    check_row_members,
    check_structure,
    convert_row,
    place_element,
)
from mazegen.dsl.syntax_errors import syntax_error
from mazegen.dsl.zones import check_zone_types
from mazegen.errors import MazeError
from mazegen.fileio import read_text
from mazegen.spec import METRES_PER_UNIT, Arena, Box, ElementType, FitnessTerm, Spec
from mazegen.text import quoted

LIBRARY_DIR = Path(__file__).resolve().parent.parent / "library"

# Set while this module parses, so the textX model processor does not check twice.
loading: ContextVar[bool] = ContextVar("loading", default=False)


@contextlib.contextmanager
def _loading() -> Iterator[None]:
    token = loading.set(True)
    try:
        yield
    finally:
        loading.reset(token)


@dataclass(frozen=True)
class ParsedFile:
    """A parsed ``.maze`` file: its textX model and where it came from."""

    path: Path
    label: str
    model: Any


def bundled_libraries() -> list[str]:
    """Names of the element libraries shipped with MazeGen."""
    return sorted(p.stem for p in LIBRARY_DIR.glob("*.maze"))


def parse_file(path: Path) -> ParsedFile:
    """Parse one file; syntax errors become a located :class:`MazeError`."""
    path = path.resolve()
    label = display_path(path)
    text = read_text(path, "spec")
    with _loading():
        try:
            model = metamodel().model_from_str(text, file_name=label)
        except TextXSyntaxError as error:
            raise syntax_error(error, text, label) from None
        except TextXSemanticError as error:
            raise MazeError(error.message, filename=label, line=error.line, col=error.col) from None
    _check_declares(model, label)
    return ParsedFile(path, label, model)


def _check_declares(model: Any, label: str | None) -> None:
    if not hasattr(model, "declarations"):  # textX gives back the text itself when it holds no rule
        raise MazeError(
            "the file declares nothing (a spec needs 'scenario NAME on ARENA { ... }', "
            "a library at least one element)",
            filename=label,
        )


def _resolve_import(imp: Any, importer: Path) -> Path:
    if imp.library is not None:
        return _library(imp)
    if not imp.path.isprintable():
        fail(imp, f"import path {quoted(imp.path)} holds a control character")
    try:
        candidate = (importer.parent / imp.path).resolve()
        found = candidate.is_file()
    except OSError as error:  # a name too long for the file system, a loop of links...
        fail(imp, f"imported file {quoted(imp.path)} cannot be read: {error.strerror or error}")
    if not found:
        fail(imp, f"imported file {quoted(imp.path)} not found")
    return candidate


def _library(imp: Any) -> Path:
    """The file of ``import NAME``: the bundled library, else the one an installed package registers
    (a bundled name is never replaced: a :class:`MazeNote` says so)."""
    name = imp.library
    if name in bundled_libraries():
        plugins.note_unused("libraries", name, "library", at=f"{where(imp)}: ")
        return LIBRARY_DIR / f"{name}.maze"
    try:
        plugin = plugins.find("libraries", name)
        if plugin is not None:
            return _plugin_library(plugin)
    except MazeError as error:  # a plug-in's mistake, said at the import that uses it
        fail(imp, error.message)
    hint = "import a file with a quoted path"
    fail(imp, plugins.unknown("libraries", "library", name, bundled_libraries(), hint=hint))


def _plugin_library(plugin: plugins.Plugin) -> Path:
    """The ``.maze`` file a library plug-in names (its object is the file's path).

    Raises:
        MazeError: naming the plug-in and its package, when it names no existing file.
    """
    path = plugin.load()
    if not isinstance(path, (str, os.PathLike)):
        raise MazeError(f"{plugin.described} gives {type(path).__name__}, not the path of a .maze file")
    try:
        found = Path(path).is_file()
    except OSError as error:  # a name too long for the file system, a loop of links...
        raise MazeError(
            f"{plugin.described} gives the path {quoted(str(path))}, which cannot be read: "
            f"{error.strerror or error}"
        ) from None
    if not found:
        raise MazeError(f"{plugin.described} gives the path {quoted(str(path))}, which is no file")
    return Path(path).resolve()


def _collect(main: ParsedFile) -> list[ParsedFile]:
    """The main file followed by every file it imports, each once (cycles allowed)."""
    files = [main]
    seen = {main.path}
    queue = [main]
    while queue:
        current = queue.pop(0)
        for imp in current.model.imports:
            path = _resolve_import(imp, current.path)
            if path not in seen:
                seen.add(path)
                parsed = parse_file(path)
                files.append(parsed)
                queue.append(parsed)
    return files


@dataclass(frozen=True)
class Declarations:
    """The declarations of a file and the files it imports: elements, rows and arenas by name, and the
    main file's blocks (scenario, fitness, evolution; a robot from any file) by their textX class."""

    elements: dict[str, Any]
    rows: dict[str, Any]
    arenas: dict[str, Any]
    singles: dict[str, Any]


_NAMED = {"ElementDecl": "elements", "RowDecl": "rows", "ArenaDecl": "arenas"}


def _declarations(files: list[ParsedFile]) -> Declarations:
    """Element, row and arena declarations of all files (element and row names unique together, arena
    names among arenas) and the main file's blocks."""
    main = files[0]
    found = Declarations({}, {}, {}, {})
    for parsed in files:
        for decl in parsed.model.declarations:
            kind = type(decl).__name__
            if kind in _NAMED:
                table = getattr(found, _NAMED[kind])
                first = (table if kind == "ArenaDecl" else found.elements | found.rows).get(decl.name)
                if first is not None:
                    fail(decl, f"'{decl.name}' is already declared at {where(first)}")
                table[decl.name] = decl
            elif parsed is not main and kind != "RobotDecl":
                fail(
                    decl,
                    f"an imported file may declare only elements, rows, arenas and a robot; {main.label} "
                    "holds the scenario, fitness and evolution",
                )
            elif kind == "RobotDecl" and kind in found.singles:
                fail(decl, f"only one robot block per spec (first at {where(found.singles[kind])})")
            elif kind in found.singles:
                fail(
                    decl,
                    f"only one {kind.removesuffix('Decl').lower()} block per file "
                    f"(first at {where(found.singles[kind])})",
                )
            else:
                found.singles[kind] = decl
    check_row_members(found.rows, found.elements)
    return found


def spec_from_files(files: list[ParsedFile]) -> Spec:
    """Check and convert the main file (``files[0]``) and its imports."""
    main = files[0]
    found = _declarations(files)
    element_decls, singles = found.elements, found.singles
    if "ScenarioDecl" not in singles:
        raise MazeError(
            "no scenario declared (a spec needs 'scenario NAME on ARENA { ... }')", filename=main.label
        )
    evolution = convert_evolution(singles.get("EvolutionDecl"))
    arenas = {name: convert_arena(decl) for name, decl in found.arenas.items()}
    scenario = convert_scenario(singles["ScenarioDecl"], arenas, element_decls, found.rows, evolution.genome)
    # Every declared element is checked, used or not, so a library's mistakes surface.
    converted = {name: convert_element(decl) for name, decl in element_decls.items()}
    arena = arenas[scenario.arena]
    factors = _unit_factors(files, arena)

    def lengths(decl: Any) -> Lengths:  # of the file that declares it
        return Lengths(factors[id(get_model(decl))], arena)

    def placed(name: str) -> ElementType:
        decl = element_decls[name]
        return place_element(decl, in_arena_units(converted[name], lengths(decl).factor), lengths(decl))

    elements = tuple(placed(name) for name in scenario.elements)
    types = {element.name: element for element in elements}
    rows = tuple(
        convert_row(found.rows[name], types[found.rows[name].member], lengths(found.rows[name]))
        for name in scenario.entries
        if name in found.rows
    )
    scenario = dataclasses.replace(scenario, rows=rows)
    check_structure(singles["ScenarioDecl"], scenario, element_decls)
    if scenario.placement is None:  # else the grammar's numbers size the elements, not their ranges
        walls = _walls(arena)
        for element in elements:
            check_fits(element_decls[element.name], element, arena)
            check_placed(element_decls[element.name], element, arena, walls)
        for row in rows:
            check_row_fits(found.rows[row.name], row, types[row.member], arena)
    fitness = convert_fitness(singles.get("FitnessDecl"), scenario.elements)
    zone_props = [p for p in found.arenas[scenario.arena].properties if type(p).__name__ == "ZoneProperty"]
    check_zone_types(zone_props, set(element_decls), {name: decl.member for name, decl in found.rows.items()})
    if (arena.base is not None or arena.zones) and not any(term.kind == "outside" for term in fitness):
        fitness = (*fitness, FitnessTerm("outside", reject=True))  # elements where the map and zones allow
    robot = convert_robot(singles.get("RobotDecl"), arena, fitness, singles.get("FitnessDecl"))
    return Spec(
        name=scenario.name,
        source=main.label,
        elements=elements,
        arena=arena,
        scenario=scenario,
        fitness=fitness,
        evolution=evolution,
        robot=robot,
    )


def _walls(arena: Arena) -> Box:
    """The box whose sides an element against a wall stands at: the arena's, or the free cells' of its map."""
    if arena.base is None:
        return (0.0, 0.0, arena.width, arena.height)
    from mazegen.maps import free_box  # numpy: only for an arena on a map

    return free_box(arena.base)


def _unit_factors(files: list[ParsedFile], arena: Arena) -> dict[int, float]:
    """By file (the ``id`` of its model), what its elements' lengths are multiplied by to be in
    ``arena``'s unit: 1 where the file declares no ``units`` (its lengths are the arena's)."""
    factors = {}
    for parsed in files:
        declared = parsed.model.units
        if declared is None or declared.unit == arena.unit:
            factors[id(parsed.model)] = 1.0
        elif declared.unit not in METRES_PER_UNIT or arena.unit not in METRES_PER_UNIT:
            fail(
                declared,
                f"this file's lengths are in {declared.unit} and arena '{arena.name}' is in {arena.unit}: "
                "px has no size in metres to convert by (give both in mm, cm or m, or drop 'units')",
            )
        else:
            factors[id(parsed.model)] = METRES_PER_UNIT[declared.unit] / METRES_PER_UNIT[arena.unit]
    return factors


def check_library(files: list[ParsedFile]) -> None:
    """Check a file that declares no scenario (an element library): its lengths are checked, not converted
    (that needs the arena a scenario is on)."""
    found = _declarations(files)
    elements = {
        name: place_element(decl, convert_element(decl), Lengths()) for name, decl in found.elements.items()
    }
    for decl in found.rows.values():
        convert_row(decl, elements[decl.member], Lengths())
    for decl in found.arenas.values():
        convert_arena(decl)


def load_spec(path: str | os.PathLike[str]) -> Spec:
    """Load, check and convert a ``.maze`` spec into a :class:`Spec`.

    Raises:
        MazeError: located at the user's line for any mistake.
    """
    return spec_from_files(_collect(parse_file(_existing(path))))


def _check_files(files: list[ParsedFile]) -> None:
    """Check a spec, or a library when the main file declares no scenario."""
    if any(type(d).__name__ == "ScenarioDecl" for d in files[0].model.declarations):
        spec_from_files(files)
    else:
        check_library(files)


def check_file(path: str | os.PathLike[str]) -> None:
    """Check a spec or a library file (a file without a scenario is a library)."""
    _check_files(_collect(parse_file(_existing(path))))


def _files_of_model(model: Any) -> list[ParsedFile]:
    path = Path(model._tx_filename or "model.maze")
    return _collect(ParsedFile(path.resolve(), model._tx_filename or "<string>", model))


def check_model(model: Any) -> None:
    """Check an already parsed main model (used by the textX model processor)."""
    _check_declares(model, None)
    with _loading():
        _check_files(_files_of_model(model))


def spec_from_model(model: Any) -> Spec:
    """The :class:`Spec` of a model parsed by textX itself (``textx generate``)."""
    with _loading():
        return spec_from_files(_files_of_model(model))


def _existing(path: str | os.PathLike[str]) -> Path:
    p = Path(path)
    try:
        found = p.is_file()
    except OSError as error:  # a name too long for the file system
        raise MazeError(f"cannot read spec: {error.strerror or error}", filename=str(path)) from None
    if not found:
        raise MazeError("no such spec file", filename=str(path))
    return p
