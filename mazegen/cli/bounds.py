"""Numbers on the command line, each checked against its bounds as it is read.

An option out of its bounds is a user's mistake: one line naming the option and its
bounds (``--seed must be from 0 to ..., got ...``), exit status 1, before any work.
Evolution settings take their bounds from :data:`mazegen.spec.EVOLUTION_BOUNDS`, the
one table the language checks too; other options state theirs where they are declared.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import click

from mazegen.errors import MazeError, brief
from mazegen.spec import EVOLUTION_BOUNDS, Evolution

WORKERS = (1, 1024)
"""Local worker processes a run may start."""

CHECKPOINT_EVERY = (0, 1_000_000)
"""Generations between checkpoints (0: never); beyond the most generations a run has, the same as never."""


class Bounded(click.ParamType):
    """An integer or a finite number within bounds; out of them a :class:`MazeError` naming the option.

    Args:
        kind: ``int`` or ``float``.
        check: True for a value within the bounds.
        bounds: The bounds as the message says them (``from 1 to 1024``).
        what: The name in messages, when not the option's (``codon`` for an argument).
    """

    def __init__(
        self,
        kind: type[int] | type[float],
        check: Callable[[Any], bool],
        bounds: str,
        *,
        what: str | None = None,
    ) -> None:
        self.kind, self.check, self.bounds, self.what = kind, check, bounds, what
        self.name = "integer" if kind is int else "number"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        try:
            number = self.kind(value)
        except (TypeError, ValueError):
            self.fail(f"'{brief(value)}' is not a valid {self.name}", param, ctx)
        if (isinstance(number, float) and not math.isfinite(number)) or not self.check(number):
            raise MazeError(f"{self.what or _option_name(param)} must be {self.bounds}, got {brief(value)}")
        return number


class BoundedOption(click.Option):
    """An option whose help shows its :class:`Bounded` type's bounds, as click shows an ``IntRange``'s."""

    def get_help_extra(self, ctx: click.Context) -> Any:
        extra = super().get_help_extra(ctx)
        if isinstance(self.type, Bounded):
            extra["range"] = self.type.bounds
        return extra


def _option_name(param: click.Parameter | None) -> str:
    """``--checkpoint-every`` rather than ``-c``: the longest of the option's names."""
    return max(param.opts, key=len) if param is not None else "value"


def within(low: int, high: int, *, what: str | None = None) -> Bounded:
    """An integer from ``low`` to ``high``."""
    return Bounded(int, lambda value: low <= value <= high, f"from {low} to {high}", what=what)


def setting(key: str) -> Bounded:
    """An evolution setting (``population``) within its bounds of :data:`EVOLUTION_BOUNDS`."""
    check, bounds = EVOLUTION_BOUNDS[key]
    return Bounded(type(getattr(Evolution(), key)), check, bounds)
