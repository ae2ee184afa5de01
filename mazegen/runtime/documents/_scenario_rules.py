"""What a scenario file may hold: read safely, then checked against one table of types and bounds.

Every command that reads a scenario file (``score``, ``drive``, ``render``, ``export``,
``report``) goes through :func:`mazegen.runtime.documents._scenario.read_document`, which
uses :func:`read_json` (the file read up to :data:`MAX_FILE_BYTES`, parsed with
hooks that refuse over-long numbers, NaN and infinities) and
:func:`check_document` (every field against :data:`DOCUMENT`, the rules of every
field the format defines). A field that is absent is not checked here (a floor written by
hand gives only its elements); a field that is present must follow its rule.
Fields the format does not define are ignored, but nothing may nest deeper than
:data:`MAX_DEPTH`. ``docs/scenario.schema.json`` states the same rules; a test
compares the two.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NoReturn

from mazegen.errors import MazeError
from mazegen.fileio import read_bytes
from mazegen.maps import UNKNOWN
from mazegen.spec import MAX_TASKS, ZONE_RULES

MAX_FILE_BYTES = 64 * 2**20
"""Largest scenario file read (64 MiB): a floor of :data:`MAX_ELEMENTS` elements is far smaller."""
MAX_NUMBER_CHARACTERS = 40
"""Longest number literal read: MazeGen writes at most 19 digits (a 64-bit seed)."""
MAX_DEPTH = 16
"""Deepest nesting of lists and objects; the format's own is 5 (``drive.NAME.trajectory[i][j]``)."""
MAX_ELEMENTS = 1000
"""Most elements a floor has: the language's bound on ``max elements``."""
MAX_PARTS = 1024
"""Most convex parts of one element."""
MAX_VERTICES = 1024
"""Most vertices of one part."""
MAX_PATH = 1_000_000
"""Most corners of a path."""
MAX_POSES = 1_000_000
"""Most poses of a driven trajectory: a 100,000 s episode at the default 0.1 s step."""
MAX_SECONDS = 1e9
"""Longest time of a drive, in seconds."""
DRIVE_OUTCOMES = ("arrived", "collision", "timeout", "no path")
"""How a drive ended: the simulator's outcomes (a floor without a path is not driven: ``no path``)."""
MIN_DOCUMENT_LENGTH = 1e-4
"""Smallest size, in arena units: documents round to 4 decimals, so a smaller one is written as 0."""
MAX_DOCUMENT_LENGTH = 1e9
"""Largest size and coordinate a document holds, in arena units (a spec's lengths stay below
:data:`mazegen.dsl.bounds.MAX_LENGTH`)."""
MAX_NAME = 200
"""Longest name (scenario, arena, element type and class, term)."""
UNITS = ("mm", "cm", "m", "px")
"""The arena units."""
NAME_PATTERN = r"^[^\u0000-\u001f\u007f-\u009f\ud800-\udfff]*$"
"""A name holds no control character and no lone surrogate (which no file can encode)."""
_BYTE = "(25[0-5]|2[0-4][0-9]|1[0-9][0-9]|[1-9]?[0-9])"
COLOUR_PATTERN = (
    rf"^(#[0-9a-fA-F]{{3}}|#[0-9a-fA-F]{{6}}|[a-zA-Z]{{3,20}}|rgb\( *{_BYTE} *, *{_BYTE} *, *{_BYTE} *\))$"
)
COLOUR_MEANING = "a colour: #rgb, #rrggbb, a colour name, or rgb(R, G, B) with R, G and B from 0 to 255"


@dataclass(frozen=True)
class Number:
    """A finite number within ``[low, high]`` (an open end excludes the bound itself)."""

    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    integer: bool = False
    null: bool = False


@dataclass(frozen=True)
class Text:
    """A string of at most ``longest`` characters matching ``pattern``, or one of ``choices``."""

    pattern: str | None = NAME_PATTERN
    longest: int | None = MAX_NAME
    choices: tuple[str, ...] | None = None
    null: bool = False
    meaning: str = "a name without control characters"
    """What ``pattern`` allows, in words."""


@dataclass(frozen=True)
class Flag:
    """``true`` or ``false``."""


@dataclass(frozen=True)
class Items:
    """A list of ``least`` to ``most`` items, each following ``item``."""

    item: Rule
    least: int = 0
    most: int | None = None
    null: bool = False


@dataclass(frozen=True)
class Fields:
    """An object whose listed fields, when present, follow their rules; others are ignored."""

    fields: dict[str, Rule] = field(default_factory=dict)


@dataclass(frozen=True)
class Mapping:
    """An object of any names (:data:`NAME_PATTERN`), every value following ``value``."""

    value: Rule


Rule = Number | Text | Flag | Items | Fields | Mapping

LENGTH = Number(low=MIN_DOCUMENT_LENGTH, high=MAX_DOCUMENT_LENGTH)
COORDINATE = Number(low=-MAX_DOCUMENT_LENGTH, high=MAX_DOCUMENT_LENGTH)
POINT = Items(COORDINATE, least=2, most=2)
MEASURE = Number(null=True)
COUNT = Number(low=0, integer=True)

HEADING = Number(low=0, high=360, high_open=True, null=True)
METRICS = Fields(
    {
        "solvable": Flag(),
        "coverage": Number(low=0, high=1),
        "path_length": MEASURE,
        "difficulty": Number(low=0, high=100, null=True),
        **dict.fromkeys(
            ("clearance", "visibility", "dispersion", "dimension", "tortuosity", "path_ratio"),
            MEASURE,
        ),
        "narrowest": MEASURE,
        "difficulty_version": Number(low=1, high=2, integer=True),
    }
)
PATH = Items(POINT, least=2, most=MAX_PATH, null=True)
DRIVE = Mapping(
    Fields(
        {
            "outcome": Text(choices=DRIVE_OUTCOMES),
            "time": Number(low=0, high=MAX_SECONDS),
            "distance": Number(low=0, high=MAX_DOCUMENT_LENGTH),
            "clearance": Number(low=0, high=MAX_DOCUMENT_LENGTH, null=True),
            "optimal_time": Number(low=0, high=MAX_SECONDS, null=True),
            "score": Number(low=0, high=0.5),
            "stuck": Flag(),
            "collision": Items(COORDINATE, least=2, most=2, null=True),
            "contacts": Number(low=1, integer=True),
            "trajectory": Items(Items(COORDINATE, least=3, most=3), most=MAX_POSES),
        }
    )
)

DOCUMENT = Fields(
    {
        "format": Text(choices=("mazegen-scenario",)),
        "version": Number(low=1, high=1, integer=True),
        "scenario": Text(),
        "arena": Fields(
            {
                "name": Text(),
                "width": LENGTH,
                "height": LENGTH,
                "unit": Text(choices=UNITS),
                "start": POINT,
                "goal": POINT,
                "robot_radius": Number(low=0, high=MAX_DOCUMENT_LENGTH),
                "map": Fields(
                    {
                        "source": Text(longest=4096),
                        "resolution": Number(low=0, low_open=True),
                        "rows": Number(low=1, integer=True),
                        "cols": Number(low=1, integer=True),
                        "origin": Items(Number(), least=2, most=2),
                        "unknown": Text(choices=UNKNOWN),
                        "cells": Text(pattern="^[0-9a-f]{16}$", longest=16, meaning="16 hex digits"),
                    }
                ),
                "zones": Items(
                    Fields(
                        {
                            "name": Text(),
                            "rule": Text(choices=ZONE_RULES),
                            "outline": Items(POINT, least=3),
                            "types": Items(Text()),
                        }
                    )
                ),
                "stations": Items(Fields({"name": Text(), "point": POINT, "heading": HEADING})),
                "tasks": Items(
                    Fields(
                        {
                            "name": Text(),
                            "start": POINT,
                            "goal": POINT,
                            "start_heading": HEADING,
                            "goal_heading": HEADING,
                        }
                    ),
                    least=1,
                    most=MAX_TASKS,
                ),
            }
        ),
        "elements": Items(
            Fields(
                {
                    "type": Text(),
                    "class": Text(),
                    "colour": Text(pattern=COLOUR_PATTERN, longest=40, meaning=COLOUR_MEANING),
                    "height": LENGTH,
                    "x": COORDINATE,
                    "y": COORDINATE,
                    "rotation": Number(low=0, high=360, high_open=True),
                    "size": LENGTH,
                    "width": LENGTH,
                    "depth": LENGTH,
                    "row": Fields({"name": Text(), "index": COUNT, "member": COUNT}),
                    "parts": Items(Items(POINT, least=3, most=MAX_VERTICES), least=1, most=MAX_PARTS),
                }
            ),
            most=MAX_ELEMENTS,
        ),
        "phenotype": Text(longest=None, null=True),
        "fitness": Number(null=True),
        "terms": Mapping(Number()),
        "metrics": METRICS,
        "path": PATH,
        "valid": Flag(),
        "drive": DRIVE,
        "tasks": Items(
            Fields({"name": Text(), "metrics": METRICS, "path": PATH, "drive": DRIVE}),
            least=1,
            most=MAX_TASKS,
        ),
        "origin": Fields(
            {
                "seed": Number(low=0, high=2**63 - 1, integer=True),
                "run": Number(low=1, integer=True),
                "generation": COUNT,
                "rank": Number(low=1, integer=True),
                "codons": Items(COUNT),
                "placement": Items(Items(Number(low=0, high=65535, integer=True), least=5, most=5)),
                "suite": Fields({"cell": COUNT, "difficulty": Text(), "elements": Text()}),
            }
        ),
    }
)
"""The rules of every field of a scenario document (format ``mazegen-scenario``, version 1)."""


def read_json(path: Path) -> Any:
    """The JSON value of a scenario file, read safely.

    Raises:
        MazeError: Naming the file (and the line where known) for a file too large or
            unreadable, JSON that is not valid or holds a number too long or not finite,
            or nesting deeper than :data:`MAX_DEPTH`.
    """
    filename = str(path)
    text = _read(path, filename)
    try:
        value = json.loads(text, parse_int=_integer, parse_float=_float, parse_constant=_not_a_number)
    except json.JSONDecodeError as error:
        raise MazeError(
            f"not valid JSON: {error.msg}", filename=filename, line=error.lineno, col=error.colno
        ) from None
    except _BadLiteral as error:
        line, col = _where(text, error.literal)
        raise MazeError(f"not valid JSON: {error}", filename=filename, line=line, col=col) from None
    except RecursionError:
        raise MazeError(f"nested deeper than {MAX_DEPTH} levels", filename=filename) from None
    _check_depth(value, filename)
    return value


def check_document(document: dict[str, Any], filename: str) -> None:
    """Check every field of a document that :data:`DOCUMENT` has a rule for, and each element's size.

    Raises:
        MazeError: ``FILE: WHERE: must be ..., got VALUE``, ``WHERE`` the JSON path of the value.
    """
    check(document, DOCUMENT, "", filename)
    for index, item in enumerate(document.get("elements", ())):
        if ("width" in item) != ("depth" in item) or ("size" in item and "width" in item):
            given = ", ".join(repr(key) for key in ("size", "width", "depth") if key in item)
            raise MazeError(
                f"elements[{index}]: give 'size', or 'width' and 'depth' for a rect, not {given}",
                filename=filename,
            )


Where = str | tuple
"""A value's JSON path: text, or ``(parent, step)`` pairs built on the way down, a step a field's name
or an item's index, written out (:func:`_path`) only when a value breaks its rule: a document of
thousands of numbers is checked without making a string for each."""


def check(value: Any, rule: Rule, where: Where, filename: str) -> None:
    """Check ``value``, found at JSON path ``where``, against ``rule``.

    Raises:
        MazeError: ``FILE: WHERE: must be ..., got VALUE``.
    """
    if value is None and getattr(rule, "null", False):
        return
    kind = type(rule)
    if kind is Number:
        _check_number(value, rule, where, filename)  # type: ignore[arg-type]
    elif kind is Text:
        _check_text(value, rule, where, filename)  # type: ignore[arg-type]
    elif kind is Flag:
        if not isinstance(value, bool):
            _fail(where, "must be true or false", _shown(value), filename)
    elif kind is Items:
        _check_items(value, rule, where, filename)  # type: ignore[arg-type]
    elif kind is Fields:
        if not isinstance(value, dict):
            _fail(where, "must be an object", _shown(value), filename)
        for key, inner in rule.fields.items():  # type: ignore[union-attr]
            if key in value:
                check(value[key], inner, (where, key), filename)
    else:
        if not isinstance(value, dict):
            _fail(where, "must be an object", _shown(value), filename)
        for key, inner_value in value.items():
            _check_text(key, Text(), f"{_path(where)}: a name", filename)
            check(inner_value, rule.value, (where, key), filename)  # type: ignore[union-attr]


def _path(where: Where) -> str:
    """``where`` written out: ``elements[3].parts[0]``."""
    steps = []
    while isinstance(where, tuple):
        where, step = where
        steps.append(step)
    text = where
    for step in reversed(steps):
        text = f"{text}[{step}]" if isinstance(step, int) else f"{text}.{step}" if text else step
    return text


def describe(rule: Number) -> str:
    """What a number must be, in words (``a number from 0.0001 to 1e+09``)."""
    kind = "an integer" if rule.integer else "a number"
    if rule.low is not None and rule.low == rule.high:
        return f"{kind} equal to {_plain(rule.low)}"
    if rule.low is not None and rule.high is not None and not (rule.low_open or rule.high_open):
        return f"{kind} from {_plain(rule.low)} to {_plain(rule.high)}"
    ends = []
    if rule.low is not None:
        ends.append(f"{'above' if rule.low_open else 'at least'} {_plain(rule.low)}")
    if rule.high is not None:
        ends.append(f"{'below' if rule.high_open else 'at most'} {_plain(rule.high)}")
    return " ".join([kind, " and ".join(ends)]).strip()


def _plain(bound: float) -> str:
    """A bound as written: integers in full (``9223372036854775807``), others short (``1e+09``)."""
    return str(bound) if isinstance(bound, int) else f"{bound:g}"


class _BadLiteral(ValueError):
    """A number literal JSON allows but a scenario does not."""

    def __init__(self, message: str, literal: str) -> None:
        super().__init__(message)
        self.literal = literal


def _read(path: Path, filename: str) -> str:
    data = read_bytes(path, "scenario", limit=MAX_FILE_BYTES + 1)
    if len(data) > MAX_FILE_BYTES:
        raise MazeError(f"larger than {MAX_FILE_BYTES // 2**20} MiB: not a scenario file", filename=filename)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise MazeError("cannot read scenario: not UTF-8 text", filename=filename) from None


def _long(literal: str) -> None:
    if len(literal) > MAX_NUMBER_CHARACTERS:
        raise _BadLiteral(f"a number of {len(literal)} characters (at most {MAX_NUMBER_CHARACTERS})", literal)


def _integer(literal: str) -> int:
    _long(literal)
    return int(literal)


def _float(literal: str) -> float:
    _long(literal)
    number = float(literal)
    if number in (float("inf"), float("-inf")):
        raise _BadLiteral(f"{literal} is too large for a number", literal)
    return number


def _not_a_number(literal: str) -> float:
    raise _BadLiteral(f"{literal} is not a number in JSON", literal)


def _where(text: str, literal: str) -> tuple[int | None, int | None]:
    """Line and column of the first number token ``literal`` in ``text``, if found."""
    found = re.search(rf"(?<![\w.+-]){re.escape(literal)}(?![\w.])", text)
    if found is None:
        return None, None
    line = text.count("\n", 0, found.start()) + 1
    return line, found.start() - text.rfind("\n", 0, found.start())


def _check_depth(value: Any, filename: str) -> None:
    """Refuse nesting deeper than :data:`MAX_DEPTH`, without recursion."""
    pending = [(value, 1)]
    while pending:
        item, depth = pending.pop()
        children = item.values() if isinstance(item, dict) else item if isinstance(item, list) else ()
        if children and depth > MAX_DEPTH:
            raise MazeError(f"nested deeper than {MAX_DEPTH} levels", filename=filename)
        pending.extend((child, depth + 1) for child in children if isinstance(child, (dict, list)))


def _check_number(value: Any, rule: Number, where: Where, filename: str) -> None:
    wanted = int if rule.integer else (int, float)
    good = isinstance(value, wanted) and not isinstance(value, bool)
    if good and rule.low is not None:
        good = value > rule.low if rule.low_open else value >= rule.low
    if good and rule.high is not None:
        good = value < rule.high if rule.high_open else value <= rule.high
    if not good:
        _fail(where, f"must be {describe(rule)}{' or null' if rule.null else ''}", _shown(value), filename)


def _check_text(value: Any, rule: Text, where: Where, filename: str) -> None:
    if rule.choices is not None:
        if value not in rule.choices:
            _fail(where, f"must be one of {', '.join(rule.choices)}", _shown(value), filename)
        return
    if not isinstance(value, str):
        _fail(where, f"must be a string{' or null' if rule.null else ''}", _shown(value), filename)
    if rule.longest is not None and len(value) > rule.longest:
        _fail(where, f"must be at most {rule.longest} characters long", _shown(value), filename)
    if rule.pattern is not None and not re.search(rule.pattern, value):
        _fail(where, f"must be {rule.meaning}", _shown(value), filename)


def _check_items(value: Any, rule: Items, where: Where, filename: str) -> None:
    if not isinstance(value, list):
        _fail(where, f"must be a list{' or null' if rule.null else ''}", _shown(value), filename)
    if len(value) < rule.least or (rule.most is not None and len(value) > rule.most):
        if rule.least == rule.most:
            count = f"exactly {rule.least}"
        elif rule.most is None:
            count = f"at least {rule.least}"
        else:
            count = f"{rule.least} to {rule.most}" if rule.least else f"at most {rule.most}"
        _fail(where, f"must be a list of {count} items", f"{len(value)} items", filename)
    inner = rule.item
    if type(inner) is Number:  # lists of numbers, most of a document: no dispatch per number
        for index, item in enumerate(value):
            if not (item is None and inner.null):
                _check_number(item, inner, (where, index), filename)
        return
    for index, item in enumerate(value):
        check(item, inner, (where, index), filename)


def _fail(where: Where, message: str, got: str, filename: str) -> NoReturn:
    """Raise the one-line error of a value that breaks its rule: ``WHERE: MESSAGE, got GOT``."""
    raise MazeError(f"{_path(where) or 'the document'}: {message}, got {got}", filename=filename)


def _shown(value: Any) -> str:
    """``value`` as JSON on one line, at most 40 characters."""
    text = json.dumps(value)  # escapes control characters: the message stays one line
    return text if len(text) <= 40 else text[:37] + "..."
