"""Turning a user's mistake into one line on standard error and exit status 1."""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, TypeVar

import click

from mazegen.errors import MazeError

F = TypeVar("F", bound=Callable[..., Any])


def reports_errors(command: F) -> F:
    """Wrap a command so a :class:`MazeError` prints ``file:line:col: message`` and exits 1."""

    @functools.wraps(command)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return command(*args, **kwargs)
        except MazeError as error:
            click.echo(error.render(command_line=True), err=True)
            raise SystemExit(1) from None

    return wrapper  # type: ignore[return-value]


def skip_file(error: MazeError, *, alone: bool) -> None:
    """A file's mistake in a command over many files: one line on standard error, so that the others
    go on; the command's own error (raised) when the file is ``alone``."""
    if alone:
        raise error
    click.echo(str(error), err=True)
