"""Text from users' files: made safe to print on one terminal line, grammar escapes decoded, and the
known name suggested for a misspelt one."""

from __future__ import annotations

import codecs
import difflib
import warnings
from collections.abc import Iterable

_NAMED = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}

ELLIPSIS = "..."


def _escape(char: str) -> str:
    code = ord(char)
    if char in _NAMED:
        return _NAMED[char]
    if code < 0x100:
        return f"\\x{code:02x}"
    return f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}"


def printable(text: str, *, limit: int | None = None) -> str:
    """``text`` with every non-printable character escaped (``\\n``, ``\\x1b``, ``\\u202e``...),
    cut to ``limit`` characters plus an ellipsis when longer.

    Control characters in a spec, a phenotype or a file name would otherwise split a one-line
    message or drive the user's terminal (retitle it, clear it); the cut keeps a message that
    quotes a huge token short.
    """
    pieces: list[str] = []
    size = 0
    for char in text:
        piece = char if char.isprintable() else _escape(char)
        if limit is not None and size + len(piece) > limit:
            return "".join(pieces) + ELLIPSIS
        pieces.append(piece)
        size += len(piece)
    return "".join(pieces)


def quoted(text: str, *, limit: int = 40) -> str:
    """``'text'`` for a message: printable and cut to ``limit`` characters."""
    return f"'{printable(text, limit=limit)}'"


def suggestion(name: str, known: Iterable[str]) -> str:
    """`` (did you mean 'x'?)`` when a known name is close to ``name``."""
    close = difflib.get_close_matches(name, list(known), n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""


def decode_escapes(part: str) -> str:
    """Decode backslash escapes (``\\n``, ``\\u00e9``...) like PonyGE2's ``unicode-escape`` step,
    as grammar terminals are read; the language checks grammar text with it too.

    Raises:
        ValueError: for a malformed escape, saying why (``truncated \\xXX escape``).
    """
    if "\\" not in part:
        return part
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            return codecs.decode(part.encode("latin-1", "backslashreplace"), "unicode-escape")
    except UnicodeDecodeError as exc:
        raise ValueError(exc.reason) from None


def number(value: float) -> str:
    """A number as the language writes it: ``1400`` rather than ``1400.0``, ``0.05`` as is."""
    return str(int(value)) if float(value).is_integer() and abs(value) < 1e15 else repr(float(value))
