"""The one exception a user's mistake raises, printed as ``file:line:col: message``."""

from __future__ import annotations


class MazeError(Exception):
    """A user-facing error with an optional source location.

    Args:
        message: What is wrong, in one line.
        filename: File the error is in, if any.
        line: 1-based line, if known.
        col: 1-based column, if known.
    """

    def __init__(
        self, message: str, *, filename: str | None = None, line: int | None = None, col: int | None = None
    ) -> None:
        super().__init__(message)
        self.message = message
        self.filename = filename
        self.line = line
        self.col = col

    def __str__(self) -> str:
        where = [str(part) for part in (self.filename, self.line, self.col) if part is not None]
        return ":".join([*where, " " + self.message]) if where else self.message


def brief(text: object, limit: int = 40) -> str:
    """``text`` as a message quotes it: cut to ``limit`` characters, so a 5,000-digit number or a
    100 KB token does not flood the one line of an error."""
    shown = str(text)
    return shown if len(shown) <= limit else shown[: limit - 1] + "…"
