"""Plug-ins from installed packages: the entry point groups MazeGen reads, and what is registered.

A package adds to MazeGen by naming objects under these groups in its ``pyproject.toml``
(``[project.entry-points."mazegen.metrics"]``); docs/extending.md shows each kind. Looking a group up
imports nothing: a plug-in's module is imported only when the plug-in is used (:meth:`Plugin.load`).
"""

from __future__ import annotations

import importlib.metadata
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from mazegen.errors import MazeError, MazeNote
from mazegen.text import quoted, suggestion

GROUPS = {
    "controllers": "mazegen.controllers",
    "metrics": "mazegen.metrics",
    "exporters": "mazegen.exporters",
    "libraries": "mazegen.libraries",
}
"""Each kind of plug-in and the entry point group its packages register it under."""


@dataclass(frozen=True)
class Plugin:
    """One registered plug-in: its kind (a key of :data:`GROUPS`), its name, the object it names
    (``package.module:attribute``) and the distribution that registers it."""

    kind: str
    name: str
    value: str
    distribution: str
    version: str

    @property
    def origin(self) -> str:
        """Where it comes from, as messages and ``mazegen plugins`` say it: ``mazegen-warehouse 1.0``."""
        return f"{self.distribution} {self.version}".strip()

    @property
    def described(self) -> str:
        """The plug-in as messages name it: ``library plug-in 'warehouse' of mazegen-warehouse 1.0``."""
        return f"{_one(self.kind)} plug-in {self.name!r} of {self.origin}"

    def load(self) -> Any:
        """The object the entry point names.

        Raises:
            MazeError: in one line naming the plug-in and its package, when importing it fails.
        """
        (point,) = [p for p in _entry_points(self.kind) if p.name == self.name and p.value == self.value]
        try:
            return point.load()
        except (Exception, SystemExit) as error:  # a broken package: its own error, said in one line
            raise MazeError(
                f"{self.described} fails to load ({self.value}: {type(error).__name__}: {error})"
            ) from error


def _one(kind: str) -> str:
    """One of ``kind``: ``library`` of ``libraries``, ``metric`` of ``metrics``."""
    return kind.removesuffix("ies") + "y" if kind.endswith("ies") else kind.removesuffix("s")


def _entry_points(kind: str) -> list[importlib.metadata.EntryPoint]:
    return list(importlib.metadata.entry_points(group=GROUPS[kind]))


def _plugin(kind: str, point: importlib.metadata.EntryPoint) -> Plugin:
    dist = point.dist
    name = dist.metadata["Name"] if dist is not None else ""
    version = dist.version if dist is not None else ""
    return Plugin(kind, point.name, point.value, name or "an unnamed package", version or "")


def installed(kind: str) -> list[Plugin]:
    """The plug-ins of ``kind`` installed packages register, by name (a name registered twice is
    listed twice: :func:`find` refuses it)."""
    return sorted((_plugin(kind, point) for point in _entry_points(kind)), key=lambda p: (p.name, p.origin))


def find(kind: str, name: str) -> Plugin | None:
    """The plug-in of ``kind`` registered as ``name``, or None.

    Raises:
        MazeError: when two installed packages register the same name.
    """
    found = [plugin for plugin in installed(kind) if plugin.name == name]
    if len(found) > 1:
        raise MazeError(
            f"{_one(kind)} plug-in {name!r} is registered by more than one package "
            f"({', '.join(p.origin for p in found)}): uninstall all but one"
        )
    return found[0] if found else None


def names(kind: str) -> list[str]:
    """The names registered for ``kind``, sorted, each once."""
    return sorted({plugin.name for plugin in installed(kind)})


def note_unused(kind: str, name: str, what: str, *, at: str = "") -> None:
    """Say (a :class:`~mazegen.errors.MazeNote`) that a plug-in registered as ``name`` is not used,
    ``name`` being a bundled ``what``'s: installing a package never changes what a name means."""
    for plugin in installed(kind):
        if plugin.name == name:
            warnings.warn(
                f"{at}{plugin.described} is not used: '{name}' is a bundled {what}", MazeNote, stacklevel=3
            )


def unknown(kind: str, what: str, name: str, bundled: Sequence[str], *, hint: str = "") -> str:
    """The message for a ``name`` neither bundled nor registered: ``unknown WHAT 'NAME' (did you mean
    ...?) (bundled: ...; registered: ...; HINT)``."""
    registered = names(kind)
    listed = [f"bundled: {', '.join(bundled)}"]
    listed += [f"registered: {', '.join(registered)}"] if registered else []
    listed += [hint] if hint else []
    return f"unknown {what} {quoted(name)}{suggestion(name, [*bundled, *registered])} ({'; '.join(listed)})"
