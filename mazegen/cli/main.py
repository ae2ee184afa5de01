"""The ``mazegen`` command: one sub-command per module of this package.

A sub-command's module is imported only when that command runs (or help lists
them all): ``mazegen check`` then loads the language, not numba and the engine.
"""

from __future__ import annotations

import importlib
import keyword

import click

from mazegen.cli.errors import reports_errors
from mazegen.version import __version__

COMMANDS = {
    "check": "check",
    "build": "build",
    "run": "run",
    "resume": "resume",
    "sweep": "sweep",
    "runs": "runs",
    "scenarios": "scenarios",
    "suite": "suite",
    "map": "map_command",
    "import": "import_command",
    "score": "score",
    "drive": "drive",
    "classes": "classes",
    "fit": "fit",
    "render": "render",
    "export": "export",
    "report": "report",
    "plugins": "plugins",
}
"""Sub-command name -> the name of its click command in module ``mazegen.cli.<sub-command>``
(``<sub-command>_`` for a Python keyword: ``mazegen.cli.import_``)."""


class LazyGroup(click.Group):
    """A group whose sub-commands are imported when looked up."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(COMMANDS)

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        if cmd_name not in COMMANDS:
            return None
        module = importlib.import_module(f"mazegen.cli.{cmd_name}{'_' * keyword.iskeyword(cmd_name)}")
        command: click.Command = getattr(module, COMMANDS[cmd_name])
        return command

    def invoke(self, ctx: click.Context) -> object:
        """Run the sub-command; a mistake found while its options are read (a number out of its
        bounds, see :mod:`mazegen.cli.bounds`) is one line too, as in the command itself."""
        return reports_errors(super().invoke)(ctx)


@click.group(cls=LazyGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="mazegen")
def main() -> None:
    """Generate robot-navigation test scenarios from .maze specs by grammatical evolution."""
