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

from mazegen.cli.export import FORMAT_NAMES
from mazegen.cli.main import main
from mazegen.errors import MazeError
from mazegen.runtime.scenario import read_document
from tests.conftest import EXAMPLES
from tests.runtime.scenario_mutants import mutant, whole_document, write

SPEC = str(EXAMPLES / "factory.maze")


def mutants(folder: Path, *, read: int, refused: int) -> list[Path]:
    """Seeded mutant files: ``read`` that the reader accepts (they reach the commands) and ``refused``."""
    chance, whole = random.Random(18), whole_document()
    kept: dict[bool, list[Path]] = {True: [], False: []}
    for index in itertools.count():
        path = write(folder / f"m{index}.json", mutant(whole, chance)[0])
        try:
            read_document(path)
            accepted = True
        except MazeError:
            accepted = False
        if len(kept[accepted]) < (read if accepted else refused):
            kept[accepted].append(path)
        if len(kept[True]) == read and len(kept[False]) == refused:
            return kept[True] + kept[False]
    raise AssertionError("unreachable")


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
    formats = itertools.cycle(FORMAT_NAMES)
    for index, path in enumerate(mutants(tmp_path, read=36, refused=12)):
        out = tmp_path / f"out{index}"
        commands = [
            ["score", SPEC, str(path)],
            ["render", str(path), "-o", str(out / "floor.svg"), *(["--spec", SPEC] if index % 2 else [])],
            ["export", str(path), "-f", next(formats), "-o", str(out), "--spec", SPEC],
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
