"""Readable one-line messages for textX syntax errors."""

from __future__ import annotations

import re

from arpeggio import RegExMatch
from textx.exceptions import TextXSyntaxError

from mazegen.errors import MazeError
from mazegen.text import quoted

# Named terminal rules of maze.tx and how a user would call them.
_RULE_NAMES = {
    "Number": "a number",
    "Integer": "a whole number",
    "Name": "a name",
    "STRING": "a quoted string",
    "NonTerminal": "a rule name such as <scenario>",
    "ControllerName": "a controller name (dwa, or a policy's path package.module:name)",
    "EOF": "end of file",
}

# Hints for common slips, keyed by what was expected (checked in order).
_HINTS = (
    ({"'..'"}, "write a range as LOW..HIGH"),
    ({"'x'"}, "write a size as WIDTH x HEIGHT"),
    ({"'::='"}, "a grammar rule reads <name> ::= alternative | alternative"),
)

_TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*|[-+]?\d+(\.\d+)?([eE][-+]?\d+)?|\S")
_EXPONENT = re.compile(r"'[-+]?\d+(\.\d+)?[eE][-+]?\d+'")
_DECIMAL = re.compile(r"'[-+]?\d+\.\d+'")


def _number_hint(expected: list[str], found: str) -> str | None:
    """A hint for a number written in a form the language does not take."""
    if _RULE_NAMES["Number"] in expected and _EXPONENT.fullmatch(found):
        return "write numbers without an exponent, e.g. 1500 or 0.25"
    if _RULE_NAMES["Integer"] in expected and (_EXPONENT.fullmatch(found) or _DECIMAL.fullmatch(found)):
        return "write a whole number such as 4000"
    return None


def _describe(rule) -> str | None:
    """How to name an expected rule, or None for one a user never types (comments)."""
    name = getattr(rule, "rule_name", "") or ""
    if name in _RULE_NAMES:
        return _RULE_NAMES[name]
    to_match = getattr(rule, "to_match", None)
    if isinstance(rule, RegExMatch) and not re.fullmatch(r"\w+", to_match or ""):
        return None  # the comment rules: keywords (autokwd) are word regexes
    return f"'{to_match}'" if to_match else _RULE_NAMES.get(type(rule).__name__, name or None)


def _found(text: str, line: int, col: int) -> str:
    lines = text.splitlines()
    if line - 1 >= len(lines):
        return "end of file"
    rest = lines[line - 1][col - 1 :]
    match = _TOKEN.match(rest.lstrip())
    if match is None:
        tail = "".join(lines[line:]).strip()
        return "end of file" if not tail else "end of line"
    return quoted(match.group(0))


def syntax_error(error: TextXSyntaxError, text: str, filename: str) -> MazeError:
    """Turn a textX syntax error into a located one-line :class:`MazeError`."""
    expected: list[str] = []
    for rule in getattr(error, "expected_rules", []) or []:
        described = _describe(rule)
        if described is not None and described not in expected:
            expected.append(described)
    line, col = error.line or 1, error.col or 1
    found = _found(text, line, col)
    if not expected:
        message = f"unexpected {found}"
    else:
        alternatives = ", ".join(expected[:-1]) + (" or " if len(expected) > 1 else "") + expected[-1]
        message = f"expected {alternatives}, found {found}"
        hint = _number_hint(expected, found) or next(
            (hint for wanted, hint in _HINTS if wanted <= set(expected)), None
        )
        if hint is not None:
            message += f" ({hint})"
    return MazeError(message, filename=filename, line=line, col=col)
