"""The ``mazegen`` command: one sub-command per module of this package."""

from __future__ import annotations

import click

from mazegen import __version__
from mazegen.cli.build import build
from mazegen.cli.check import check
from mazegen.cli.export import export
from mazegen.cli.map import map_command
from mazegen.cli.render import render
from mazegen.cli.report import report
from mazegen.cli.resume import resume
from mazegen.cli.run import run
from mazegen.cli.runs import runs
from mazegen.cli.scenarios import scenarios
from mazegen.cli.score import score
from mazegen.cli.suite import suite
from mazegen.cli.sweep import sweep


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="mazegen")
def main() -> None:
    """Generate robot-navigation test scenarios from .maze specs by grammatical evolution."""


for command in (
    check,
    build,
    run,
    resume,
    sweep,
    runs,
    scenarios,
    suite,
    map_command,
    score,
    render,
    export,
    report,
):
    main.add_command(command)
