"""Turning a user's mistake into one line on standard error and exit status 1, and a note
(:class:`~mazegen.errors.MazeNote`) into one line on standard error."""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable
from typing import Any, TypeVar

import click

from mazegen.errors import MazeError, MazeNote
from mazegen.text import printable

F = TypeVar("F", bound=Callable[..., Any])


def reports_errors(command: F) -> F:
    """Wrap a command so a :class:`MazeError` prints ``file:line:col: message`` and exits 1, and a
    :class:`MazeNote` prints ``note: message``."""

    @functools.wraps(command)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            with warnings.catch_warnings():
                warnings.showwarning = _show_notes(warnings.showwarning)
                return command(*args, **kwargs)
        except MazeError as error:
            click.echo(error.render(command_line=True), err=True)
            raise SystemExit(1) from None

    return wrapper  # type: ignore[return-value]


def _show_notes(show: Callable[..., None]) -> Callable[..., None]:
    """``warnings.showwarning`` that prints a note as one line, and leaves other warnings to ``show``."""

    def shown(message: Warning | str, category: type[Warning], *args: Any, **kwargs: Any) -> None:
        if issubclass(category, MazeNote):
            click.echo(f"note: {printable(str(message))}", err=True)  # one line, as an error
        else:
            show(message, category, *args, **kwargs)

    return shown


def skip_file(error: MazeError, *, alone: bool) -> None:
    """A file's mistake in a command over many files: one line on standard error, so that the others
    go on; the command's own error (raised) when the file is ``alone``."""
    if alone:
        raise error
    click.echo(str(error), err=True)
