"""The one exception a user's mistake raises, printed as ``file:line:col: message``."""

from __future__ import annotations

import re

from mazegen.text import printable

MESSAGE_LIMIT = 500
"""The most characters a message shows: one that quotes a huge token is cut with an ellipsis."""

SPELLINGS: dict[str, tuple[str, str]] = {
    "force": ("--force", "force=True"),
    "run force": ("mazegen run --force", "mazegen.run(..., force=True)"),
    "out_dir": ("-o", "out_dir"),
    "resume": ("mazegen resume", "mazegen.resume"),
    "workers": ("--workers", "workers"),
    "scheduler": ("--scheduler", "scheduler"),
    "executor dask": ("--executor dask", 'executor="dask"'),
    "checkpoint_every 0": ("--checkpoint-every 0", "checkpoint_every=0"),
}
"""What a message may tell the caller to change: on the command line, and in the Python API."""

_OPTION = re.compile("<option:([a-z_ ]+)>")  # an option's name in a message until the message is printed


def option(name: str) -> str:
    """The option ``name`` (a key of :data:`SPELLINGS`) in a message, spelled as its caller spells it.

    One message serves both callers: ``--force`` when the command line prints it,
    ``force=True`` in a Python traceback.
    """
    if name not in SPELLINGS:
        raise KeyError(f"no spelling for the option {name!r}")
    return f"<option:{name}>"


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
        return self.render(command_line=False)

    def render(self, *, command_line: bool) -> str:
        """The error in one line, naming options as the command line or the Python API spells them."""
        spelling = 0 if command_line else 1
        message = _OPTION.sub(lambda found: SPELLINGS.get(found[1], (found[0],) * 2)[spelling], self.message)
        filename = None if self.filename is None else printable(self.filename)
        where = [str(part) for part in (filename, self.line, self.col) if part is not None]
        return ":".join([*where, " " + message]) if where else message


class MazeNote(UserWarning):
    """Something the user should know that is no mistake (a bundled library used rather than a
    plug-in's of the same name): a warning in Python, one line on standard error from the command line."""


def brief(text: object, limit: int = 40) -> str:
    """``text`` as a message quotes it: printable and cut to ``limit`` characters, so a 5,000-digit
    number or a 100 KB token does not flood the one line of an error."""
    return printable(str(text), limit=limit)
