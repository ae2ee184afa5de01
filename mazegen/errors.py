"""The one exception a user's mistake raises, printed as ``file:line:col: message``."""

from __future__ import annotations

from mazegen.text import printable

MESSAGE_LIMIT = 500
"""The most characters a message shows: one that quotes a huge token is cut with an ellipsis."""


class MazeError(Exception):
    """A user-facing error with an optional source location.

    The message and the file name are made printable (control characters escaped, the message
    cut to :data:`MESSAGE_LIMIT`), so an error is always one short line whatever the input held.

    Args:
        message: What is wrong, in one line.
        filename: File the error is in, if any.
        line: 1-based line, if known.
        col: 1-based column, if known.
    """

    def __init__(
        self, message: str, *, filename: str | None = None, line: int | None = None, col: int | None = None
    ) -> None:
        message = printable(message, limit=MESSAGE_LIMIT)
        super().__init__(message)
        self.message = message
        self.filename = filename
        self.line = line
        self.col = col

    def __str__(self) -> str:
        filename = None if self.filename is None else printable(self.filename)
        where = [str(part) for part in (filename, self.line, self.col) if part is not None]
        return ":".join([*where, " " + self.message]) if where else self.message
