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
