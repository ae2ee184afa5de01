"""A fuzzer over scenario files through every command that reads them: a one-line error or success, never a
traceback, and exported or drawn files that parse."""

from __future__ import annotations

import itertools
import json
import random
import xml.etree.ElementTree as ET
from pathlib import Path

import yaml
from click.testing import CliRunner

from mazegen.cli.main import main
from mazegen.export_formats import BUNDLED
from tests.conftest import EXAMPLES
from tests.runtime.scenario_mutants import mutant, whole_document, write

SPEC = str(EXAMPLES / "factory.maze")


def mutants(folder: Path, count: int) -> list[Path]:
    """Seeded mutant files, each changed where the commands read: the arena or the elements."""
    chance, whole = random.Random(18), whole_document()
    return [
        write(
            folder / f"m{index}.json", mutant(whole, chance, within=chance.choice(["arena", "elements"]))[0]
        )
        for index in range(count)
    ]


def outputs_parse(folder: Path) -> None:
    for path in folder.iterdir():
        if path.suffix in (".sdf", ".svg"):
            ET.parse(path)
        elif path.suffix == ".yaml":
            yaml.safe_load(path.read_text(encoding="utf-8"))
        elif path.suffix == ".json":
            json.loads(path.read_text(encoding="utf-8"))


def test_mutated_scenarios_give_one_line_errors_or_files_that_parse(tmp_path):
    runner = CliRunner()
    formats = itertools.cycle(BUNDLED)
    for index, path in enumerate(mutants(tmp_path, 80)):
        out = tmp_path / f"out{index}"
        commands = [
            ["score", SPEC, str(path)],
            ["render", str(path), "-o", str(out / "floor.svg"), *(["--spec", SPEC] if index % 2 else [])],
            ["export", str(path), "-f", next(formats), "-o", str(out), "--spec", SPEC],
            ["drive", str(path), "-c", "straight", "--spec", SPEC, "-o", str(out / "driven")],
        ]
        for args in commands:
            result = runner.invoke(main, args, catch_exceptions=False)  # a traceback fails the test
            assert result.exit_code in (0, 1), (args, result.output)
            if result.exit_code == 1:
                assert len(result.stderr.splitlines()) == 1 and result.stderr.startswith(str(path)), (
                    result.stderr
                )
        if out.is_dir():
            outputs_parse(out)
