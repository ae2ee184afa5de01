"""Seeded mutants of every bundled ``.maze`` file, token by token and character by character.

Mutant ``i`` of seed ``s`` depends on ``(s, i)`` only, so any one of them can be made again alone.
"""

from __future__ import annotations

import random
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SOURCES = tuple(
    sorted(
        [
            *ROOT.glob("examples/*.maze"),
            *ROOT.glob("examples/table1/*.maze"),
            *ROOT.glob("mazegen/library/*.maze"),
            *ROOT.glob("tests/dsl/sources/*.maze"),  # what the examples do not show: driving a robot
        ]
    )
)

# Every keyword of the language, read from its grammar, to put in the wrong places.
KEYWORDS = tuple(sorted(set(re.findall(r"'([a-z_]+)'", (ROOT / "mazegen/dsl/maze.tx").read_text()))))

HOSTILE_NUMBERS = (
    "0",
    "-1",
    "-0",
    "0.5",
    "-2.5",
    "1.0000001",
    "0." + "0" * 30 + "1",
    "255",
    "1000",
    "100000000",
    "2147483648",
    "9223372036854775808",
    "99999999999999999999",
    "1" + "0" * 400,
    "9" * 5000,
    "1e3",
    "1.5e-3",
)

HOSTILE_TEXT = (
    "\x00",
    "\n",
    "\r\n",
    "\t",
    "\x1b]0;TITLE\x07",
    "\x1b[2J",
    "\\x",
    "\\N{NOPE}",
    "\\u12",
    "\\",
    "\\n",
    '"',
    "'",
    "|",
    "<x> ::=",
    "#",
    "é",
    "\u202e",
    "a" * 100_000,
)

_PIECE = re.compile(
    r"\s+"
    r"|\"(?:\\.|[^\"\\])*\"|'(?:\\.|[^'\\])*'"
    r"|//[^\n]*|/\*.*?\*/"
    r"|<[^>\s]*>|::=|\.\."
    r"|[-+]?\d+(?:\.\d+)?"
    r"|\w+"
    r"|.",
    re.DOTALL,
)
_NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?")


@dataclass(frozen=True)
class Mutant:
    """One mutant: its number, the bundled file it comes from, the mutations and the text."""

    index: int
    source: Path
    mutations: tuple[str, ...]
    text: str


def pieces_of(text: str) -> list[str]:
    """``text`` cut into tokens and the white space between them (joined, they give it back)."""
    return _PIECE.findall(text)


def _tokens(pieces: list[str]) -> list[int]:
    return [i for i, piece in enumerate(pieces) if not piece.isspace()] or [0]


def _delete(rng: random.Random, pieces: list[str]) -> None:
    del pieces[rng.choice(_tokens(pieces))]


def _duplicate(rng: random.Random, pieces: list[str]) -> None:
    i = rng.choice(_tokens(pieces))
    pieces[i:i] = [pieces[i], " "]


def _swap(rng: random.Random, pieces: list[str]) -> None:
    tokens = _tokens(pieces)
    k = rng.randrange(len(tokens))
    j = tokens[min(len(tokens) - 1, k + rng.randint(1, 3))]
    i = tokens[k]
    pieces[i], pieces[j] = pieces[j], pieces[i]


def _keyword_instead(rng: random.Random, pieces: list[str]) -> None:
    pieces[rng.choice(_tokens(pieces))] = rng.choice(KEYWORDS)


def _keyword_inserted(rng: random.Random, pieces: list[str]) -> None:
    pieces.insert(rng.choice(_tokens(pieces)), f" {rng.choice(KEYWORDS)} ")


def _hostile_number(rng: random.Random, pieces: list[str]) -> None:
    numbers = [i for i, piece in enumerate(pieces) if _NUMBER.fullmatch(piece)] or _tokens(pieces)
    pieces[rng.choice(numbers)] = rng.choice(HOSTILE_NUMBERS)


def _plausible_number(rng: random.Random, pieces: list[str]) -> None:
    """A number scaled as a user might mistype it, so that many mutants still pass the checks."""
    numbers = [i for i, piece in enumerate(pieces) if _NUMBER.fullmatch(piece)] or _tokens(pieces)
    i = rng.choice(numbers)
    if _NUMBER.fullmatch(pieces[i]):
        value = float(pieces[i]) * rng.choice((0, 0.5, 2, 3, 10, 100, -1))
        pieces[i] = str(int(value)) if value.is_integer() and rng.random() < 0.7 else f"{value:.3f}"


def _hostile_text(rng: random.Random, pieces: list[str]) -> None:
    strings = [i for i, piece in enumerate(pieces) if piece[:1] in "\"'" and len(piece) > 1]
    hostile = rng.choice(HOSTILE_TEXT)
    if strings:
        i = rng.choice(strings)
        cut = rng.randint(1, len(pieces[i]) - 1)
        pieces[i] = pieces[i][:cut] + hostile + pieces[i][cut:]
    else:
        pieces.insert(rng.choice(_tokens(pieces)), f' "{hostile}" ')


def _bracket(rng: random.Random, pieces: list[str]) -> None:
    pieces.insert(rng.choice(_tokens(pieces)), rng.choice(["{", "}", "(", ")", "{ }", "..", "::=", ","]))


def _long_name(rng: random.Random, pieces: list[str]) -> None:
    pieces[rng.choice(_tokens(pieces))] = "n" * rng.choice([300, 100_000])


def _splice(rng: random.Random, pieces: list[str]) -> None:
    """A line of another bundled file, where it does not belong (or, by luck, where it does)."""
    lines = [line for line in rng.choice(SOURCES).read_text().splitlines() if line.strip()]
    pieces.insert(rng.choice(_tokens(pieces)), "\n" + rng.choice(lines) + "\n")


_TOKEN_MUTATIONS: tuple[Callable[[random.Random, list[str]], None], ...] = (
    _delete,
    _duplicate,
    _swap,
    _keyword_instead,
    _keyword_inserted,
    _hostile_number,
    _hostile_number,
    _plausible_number,
    _plausible_number,
    _plausible_number,
    _hostile_text,
    _bracket,
    _long_name,
    _splice,
)

_ODD_CHARS = [chr(c) for c in (*range(32), 127, 0x85, 0xA0, 0x2028, 0x202E, 0xFEFF)] + list("{}()<>\"'|#.,-x")


def _char_mutation(rng: random.Random, text: str) -> tuple[str, str]:
    at = rng.randrange(len(text) + 1)
    kind = rng.choice(["insert", "delete", "repeat"])
    if kind == "insert":
        return "insert char", text[:at] + rng.choice(_ODD_CHARS) + text[at:]
    if kind == "delete":
        return "delete char", text[:at] + text[at + 1 :]
    span = text[at : at + rng.randint(1, 60)]
    return "repeat span", text[:at] + span * rng.randint(2, 5) + text[at:]


def mutant(seed: int, index: int) -> Mutant:
    """Mutant ``index`` of ``seed``: 1 to 3 token or character mutations of one bundled file."""
    rng = random.Random(f"{seed}:{index}")
    source = SOURCES[index % len(SOURCES)]
    text = source.read_text(encoding="utf-8")
    done = []
    for _ in range(rng.choice((1, 1, 2, 3))):
        if rng.random() < 0.75:
            pieces = pieces_of(text)
            mutation = rng.choice(_TOKEN_MUTATIONS)
            mutation(rng, pieces)
            text = "".join(pieces)
            done.append(mutation.__name__.strip("_").replace("_", " "))
        else:
            name, text = _char_mutation(rng, text)
            done.append(name)
    return Mutant(index, source, tuple(done), text)
