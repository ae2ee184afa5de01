"""A reader for BNF grammars in the PonyGE2 dialect.

The dialect, as PonyGE2 reads it:

* A rule is ``<name> ::= alternative | alternative ...``. Its body runs until the
  next ``<x> ::=`` (outside quotes and comments), so a rule may span lines. The
  first rule is the start rule.
* ``#`` starts a comment that runs to the end of the line (not inside quotes).
  Like ``|``, a comment ends the alternative it interrupts.
* In an alternative, ``<x>`` is a non-terminal; everything else is terminal text.
  Unquoted text is kept literally (inner spaces included) and quoted text loses
  its ``'...'`` or ``"..."`` quotes, which protect ``|``, ``#`` and ``<``.
  Backslash escapes (``\\n``, ``\\t``, ``\\u00e9``...) are decoded piece by piece
  with Python's ``unicode-escape`` codec; unknown escapes stay as written.
  Adjacent terminal pieces merge into one terminal symbol.
* Each alternative is stripped of surrounding whitespace; blank alternatives are
  skipped. Inside an alternative, a line break is kept in the terminal text and
  spaces after it are dropped (as are spaces before it that follow a quote or a
  non-terminal), as PonyGE2 does.

Deliberate differences, all on input PonyGE2 would silently misread: text other
than comments before the first rule, an unclosed quote, an undefined
non-terminal, a duplicate rule, a rule without alternatives and a malformed
escape raise :class:`~mazegen.errors.MazeError`; ``<x> ::=`` inside quotes or in
a comment before the first rule does not start a rule; non-ASCII characters are
kept as they are (PonyGE2 turns them into mojibake when decoding escapes).
PonyGE2's ``GE_RANGE``/``GE_GENERATE`` directives are not supported.
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass
from pathlib import Path

from mazegen.errors import MazeError
from mazegen.fileio import read_text
from mazegen.text import decode_escapes

_SCAN = re.compile(
    r"(?P<head><[^>|\s]+>)\s*::="
    r"|(?P<comment>#[^\r\n]*)"
    r"|(?P<quoted>'[^'\n]*'|\"[^\"\n]*\")"
    r"|(?P<quote>['\"])"
    r"|(?P<bar>\|)"
    r"|(?P<other>[^<'\"|#]+|<)"
)
_PIECE = re.compile(
    r" *(?P<newline>[\r\n]+) *"
    r"|(?P<text>[^'\"<\r\n]+)"
    r"|'(?P<single>[^'\n]*)'"
    r"|\"(?P<double>[^\"\n]*)\""
    r"|(?P<nonterminal><[^>|\s]+>)"
    r"|(?P<angles><+)"
)


@dataclass(frozen=True)
class Symbol:
    """One symbol of an alternative.

    Attributes:
        text: The terminal text, or the non-terminal's name with its angle
            brackets (``<scenario>``).
        nonterminal: True for a non-terminal.
    """

    text: str
    nonterminal: bool


Alternative = tuple[Symbol, ...]


@dataclass(frozen=True)
class Grammar:
    """A context-free grammar read from BNF.

    Attributes:
        start: Name of the start rule (the first one), with angle brackets.
        rules: Alternatives of every rule, keyed by name, in file order.
    """

    start: str
    rules: dict[str, tuple[Alternative, ...]]


class _Source:
    """Turns offsets in a text into located errors."""

    def __init__(self, text: str, filename: str | None) -> None:
        self.filename = filename
        self._line_starts = [0] + [m.end() for m in re.finditer(r"\r\n|\r|\n", text)]

    def line(self, offset: int) -> int:
        """The 1-based line of ``offset``."""
        return bisect.bisect_right(self._line_starts, offset)

    def error(self, message: str, offset: int) -> MazeError:
        """An error located at ``offset``."""
        line = self.line(offset)
        col = offset - self._line_starts[line - 1] + 1
        return MazeError(message, filename=self.filename, line=line, col=col)


@dataclass
class _Rule:
    name: str
    offset: int
    alternatives: list[Alternative]


def parse_bnf(text: str, *, filename: str | None = None) -> Grammar:
    """Read a grammar from BNF text (PonyGE2 dialect, see the module docstring).

    Args:
        text: The grammar.
        filename: Shown in error messages.

    Returns:
        The grammar, its rules in file order.

    Raises:
        MazeError: On malformed or inconsistent grammar text, located at the
            offending line and column.
    """
    source = _Source(text, filename)
    rules: dict[str, _Rule] = {}
    uses: list[tuple[str, int]] = []
    rule: _Rule | None = None
    alt_start = 0
    for token in _SCAN.finditer(text):
        kind = token.lastgroup
        if kind == "quote":
            raise source.error(f"unbalanced quote: {token.group()} is not closed on this line", token.start())
        if rule is None and kind in ("quoted", "bar", "other") and not token.group().isspace():
            raise source.error("expected a rule '<name> ::=' before this text", token.start())
        if kind not in ("head", "comment", "bar"):
            continue
        if rule is not None:
            _add_alternative(rule, text, alt_start, token.start(), source, uses)
        alt_start = token.end()
        if kind == "head":
            name = token.group("head")
            if name in rules:
                first = source.line(rules[name].offset)
                raise source.error(f"rule {name} is defined twice (first at line {first})", token.start())
            rule = rules[name] = _Rule(name, token.start(), [])
    if rule is None:
        raise MazeError("no rules found (expected '<name> ::= ...')", filename=filename, line=1, col=1)
    _add_alternative(rule, text, alt_start, len(text), source, uses)
    for r in rules.values():
        if not r.alternatives:
            raise source.error(f"rule {r.name} has no alternatives", r.offset)
    for name, offset in uses:
        if name not in rules:
            raise source.error(f"non-terminal {name} is used but never defined", offset)
    return Grammar(next(iter(rules)), {r.name: tuple(r.alternatives) for r in rules.values()})


def read_bnf(path: str | Path) -> Grammar:
    """Read a grammar from a BNF file (see :func:`parse_bnf`).

    Args:
        path: The file; its name is used in error messages.

    Returns:
        The grammar.
    """
    path = Path(path)
    return parse_bnf(read_text(path, "grammar"), filename=str(path))


def _add_alternative(
    rule: _Rule, text: str, start: int, end: int, source: _Source, uses: list[tuple[str, int]]
) -> None:
    """Parse ``text[start:end]`` as one alternative of ``rule``, unless blank."""
    raw = text[start:end]
    body = raw.strip()
    if not body:
        return
    origin = start + len(raw) - len(raw.lstrip())
    symbols: list[Symbol] = []
    terminal: str | None = None
    for piece in _PIECE.finditer(body):
        if piece.lastgroup == "nonterminal":
            if terminal is not None:
                symbols.append(Symbol(terminal, False))
                terminal = None
            symbols.append(Symbol(piece.group("nonterminal"), True))
            uses.append((piece.group("nonterminal"), origin + piece.start()))
        else:
            part = piece.group(piece.lastgroup or 0)
            terminal = (terminal or "") + _unescape(part, source, origin + piece.start())
    if terminal is not None:
        symbols.append(Symbol(terminal, False))
    rule.alternatives.append(tuple(symbols))


def _unescape(part: str, source: _Source, offset: int) -> str:
    try:
        return decode_escapes(part)
    except ValueError as exc:
        raise source.error(f"bad escape in terminal {part!r}: {exc}", offset) from None
