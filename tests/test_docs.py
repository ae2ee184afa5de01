"""Every code block of README.md and docs/*.md does what the page says it does.

A block's info string names its kind (GitHub highlights by the first word and ignores the rest):

- ``python``: run in this process, twice (a reader pastes it again); ``python fragment``: an excerpt,
  compiled only.
- ``sh``: every ``mazegen ...`` command (also after ``&&``) runs as ``python -m mazegen`` and exits 0;
  any other command must match :data:`SKIPPED`.
- ``console``: each ``$ mazegen ...`` line runs; its standard output must be the lines shown under it
  (a line ``...`` stands for any lines), so figures quoted from an output follow the code.
- ``maze``: a whole spec or library, which must pass ``mazegen check``.
- ``json``, ``yaml``, ``toml``, ``csv``: must parse. ``sql``: runs on the page's ``runs/catalog.sqlite``.
- ``text``: anything not to run: synopses, fragments of the language, grammars, outputs, trees.

Any other kind, or none, fails: a new block says what it is. A block with ``file=NAME`` in its
info string is also written to ``NAME`` first, for the blocks after it.

Each page runs in a fresh working directory holding ``examples/`` and ``docs/``, as a reader
would at the repository's root, in the page's order; :data:`PRELUDES` makes what a page takes
as already done. Commands that would take minutes run with :data:`OVERRIDES`.
"""

from __future__ import annotations

import csv
import io
import json
import re
import shlex
import sqlite3
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest
import yaml

from mazegen.dsl.loader import check_file
from tests.conftest import ROOT

PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]

SKIPPED = {
    "pip install": "installs packages: the tests run the checkout as installed",
    "python -m pytest": "the test suite itself",
    "python benchmarks/": "benchmarks take minutes; benchmarks/README.md holds their measured figures",
    "ros2 ": "ROS 2 is not part of the test environment",
}
"""Commands of ``sh`` blocks not run here, by their beginning, with the reason."""

OVERRIDES = {
    "mazegen sweep examples/table1/exp3.maze examples/table1/exp5.maze --set population=1000,5000": (
        "mazegen sweep examples/table1/exp3.maze examples/table1/exp5.maze --set population=50,100 --runs 1",
        "180 runs of Table 1 take minutes: smaller populations, one run per cell",
    ),
    "mazegen run examples/layout.maze -o runs/layout": (
        "mazegen run examples/layout.maze -o runs/layout --population 100 --generations 2",
        "the layout example's 30 generations of 500 take seconds the page need not spend",
    ),
}
"""Beginnings of commands replaced here, with the replacement and the reason."""

SAMPLE_RUN = "mazegen run examples/factory.maze --population 50 --generations 2"
"""The run the pages quote files of (scenario-format.md and exports.md say so)."""

PRELUDES = {
    "catalog.md": [
        f"{SAMPLE_RUN} -q",
        "mazegen sweep examples/factory.maze --set seed=1..2 --set population=50 --set generations=2 -q",
    ],
    "exports.md": [f"{SAMPLE_RUN} -q"],
}
"""Commands run before a page's blocks: what the page assumes its reader has done."""

_FENCE = re.compile(r"^(?P<indent> *)```(?P<info>[^\n`]*)\n(?P<body>.*?)^(?P=indent)```[ \t]*$", re.M | re.S)


@dataclass(frozen=True)
class Block:
    """A fenced code block of a page."""

    page: Path
    line: int
    kind: str
    options: tuple[str, ...]
    text: str

    @property
    def where(self) -> str:
        return f"{self.page.relative_to(ROOT)}:{self.line}"


def page_blocks(page: Path) -> list[Block]:
    text = page.read_text(encoding="utf-8")
    blocks = []
    for fence in _FENCE.finditer(text):
        kind, *options = fence["info"].split() or [""]
        body = "".join(line[len(fence["indent"]) :] for line in fence["body"].splitlines(keepends=True))
        blocks.append(Block(page, text.count("\n", 0, fence.start()) + 1, kind, tuple(options), body))
    return blocks


BLOCKS = [block for page in PAGES for block in page_blocks(page)]


def sh_commands(text: str) -> list[str]:
    """The commands of an ``sh`` block, comments dropped and ``&&`` chains split."""
    commands = []
    for line in text.splitlines():
        words = shlex.split(line, comments=True)
        while words:
            end = words.index("&&") if "&&" in words else len(words)
            commands.append(shlex.join(words[:end]))
            words = words[end + 1 :]
    return commands


def mazegen(command: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    """Run ``mazegen ...`` as ``python -m mazegen ...`` in ``cwd``, with an override if it has one."""
    for start, (replacement, _) in OVERRIDES.items():
        if command.startswith(start):
            command = replacement + command[len(start) :]
    words = shlex.split(command)
    assert words[0] == "mazegen", command
    return subprocess.run(
        [sys.executable, "-m", "mazegen", *words[1:]], cwd=cwd, capture_output=True, text=True, timeout=600
    )


def run_ok(command: str, cwd: Path) -> str:
    done = mazegen(command, cwd)
    assert done.returncode == 0, f"{command}\n{done.stderr}"
    return done.stdout


@pytest.fixture(scope="module")
def workdirs() -> dict[Path, Path]:
    """Each page's working directory, once made."""
    return {}


@pytest.fixture
def workdir(request, tmp_path_factory, workdirs: dict[Path, Path]) -> Path:
    """The working directory of the block's page, made (with its prelude) for the page's first block."""
    page: Path = request.node.callspec.params["block"].page
    if page not in workdirs:
        folder = tmp_path_factory.mktemp(page.stem)
        for shared in ("examples", "docs"):
            (folder / shared).symlink_to(ROOT / shared)
        for command in PRELUDES.get(page.name, []):
            run_ok(command, folder)
        workdirs[page] = folder
    return workdirs[page]


def run_console(text: str, cwd: Path) -> None:
    sessions = re.split(r"^\$ ", text, flags=re.M)
    assert sessions[0] == "", f"a console block starts with '$ ': {sessions[0]!r}"
    for session in sessions[1:]:
        command, _, shown = session.partition("\n")
        output = run_ok(command, cwd)
        assert shown_as(shown, output), f"$ {command}\nshown:\n{shown}\nprinted:\n{output}"


@pytest.mark.parametrize("block", BLOCKS, ids=[block.where for block in BLOCKS])
def test_block(block: Block, workdir: Path, monkeypatch) -> None:
    for option in block.options:
        if option.startswith("file="):
            (workdir / option.removeprefix("file=")).write_text(block.text, encoding="utf-8")
    if block.kind == "python":
        code = compile(block.text, block.where, "exec")
        if "fragment" not in block.options:
            monkeypatch.chdir(workdir)
            for _ in range(2):
                exec(code, {"__name__": "__docs__"})
    elif block.kind == "sh":
        for command in sh_commands(block.text):
            if command.startswith("mazegen "):
                run_ok(command, workdir)
            else:
                assert any(command.startswith(skipped) for skipped in SKIPPED), f"cannot run: {command}"
    elif block.kind == "console":
        run_console(block.text, workdir)
    elif block.kind == "maze":
        spec = workdir / "block.maze"
        spec.write_text(block.text, encoding="utf-8")
        check_file(spec)
    elif block.kind == "json":
        json.loads(block.text)
    elif block.kind == "yaml":
        yaml.safe_load(block.text)
    elif block.kind == "toml":
        pytest.importorskip("tomllib").loads(block.text)  # Python 3.11 on
    elif block.kind == "csv":
        rows = list(csv.reader(io.StringIO(block.text)))
        assert len({len(row) for row in rows}) == 1, "rows of different lengths"
    elif block.kind == "sql":
        with sqlite3.connect(f"file:{workdir / 'runs' / 'catalog.sqlite'}?mode=ro", uri=True) as catalog:
            assert catalog.execute(block.text).fetchall()
    else:
        assert block.kind == "text", f"{block.where}: say what the block is (```text, ```maze, ```sh ...)"


def test_every_skip_and_override_is_still_needed():
    commands = [c for block in BLOCKS if block.kind == "sh" for c in sh_commands(block.text)]
    for start in [*SKIPPED, *OVERRIDES]:
        assert any(command.startswith(start) for command in commands), f"no docs command needs {start!r}"
    assert {page.name for page in PAGES} >= set(PRELUDES)


SAMPLES = [
    ("scenario-format.md", "run,generation,evaluations,", "stats.csv"),
    ("exports.md", "# MazeGen scenario", "exports/ros/run-01/best-01.yaml"),
    ("exports.md", "type octile", "exports/movingai/run-01/best-01.map"),
    ("exports.md", "version 1\n", "exports/movingai/run-01/best-01.scen"),
]
"""Blocks quoting a file of the sample run: the page, how the block starts, the file."""


def shown_as(shown: str, text: str) -> bool:
    """Whether ``text`` reads as ``shown``, where a line ``...`` in ``shown`` stands for any lines."""
    pattern = "".join("(?:.*\n)*" if line == "..." else re.escape(line) + "\n" for line in shown.splitlines())
    return re.fullmatch(pattern, text) is not None


def quoted_block(page: str, start: str) -> Block:
    [block] = [b for b in BLOCKS if b.page.name == page and b.text.startswith(start)]
    return block


@pytest.fixture(scope="module")
def sample_run(tmp_path_factory) -> Path:
    """The sample run's directory, with its ROS and MovingAI exports."""
    folder = tmp_path_factory.mktemp("sample")
    (folder / "examples").symlink_to(ROOT / "examples")
    run_ok(f"{SAMPLE_RUN} -o sample -q", folder)
    for kind in ("ros", "movingai"):
        run_ok(f"mazegen export sample --format {kind}", folder)
    return folder / "sample"


def test_the_files_quoted_are_those_the_sample_run_writes(sample_run):
    for page, start, name in SAMPLES:
        block = quoted_block(page, start)
        assert shown_as(block.text, (sample_run / name).read_text()), f"{block.where} is not {name}"
    quoted = json.loads(quoted_block("scenario-format.md", '{\n  "evolution"').text)
    written = json.loads((sample_run / "experiment.json").read_text())
    assert set(quoted.pop("versions")) == set(written.pop("versions"))  # their numbers are this machine's
    assert written.pop("source").endswith("/" + quoted.pop("source"))  # written as an absolute path
    assert quoted == written


def test_the_difficulty_of_the_example_floors_is_the_one_quoted():
    from mazegen.runtime.navigation._difficulty import difficulty_score, survey
    from tests.runtime.floors import ARENA, ZIGZAG, population

    text = " ".join((ROOT / "docs" / "difficulty.md").read_text(encoding="utf-8").split())
    quoted = re.search(r"the open floor scores (\d+) and a zig-zag between two walls, [^,]*, (\d+)", text)
    assert quoted is not None, "difficulty.md no longer quotes the example floors' scores"
    found = survey(population(ARENA, [[], ZIGZAG]))
    version_1 = difficulty_score(found.table, ARENA.robot_radius, version=1)
    assert [int(quoted[1]), int(quoted[2])] == [round(float(score)) for score in version_1]
    quoted = re.search(r"the open floor above scores (\d+), the zig-zag (\d+)", text)
    assert quoted is not None, "difficulty.md no longer quotes the example floors' version 2 scores"
    assert [int(quoted[1]), int(quoted[2])] == [round(float(score)) for score in found.difficulty]


def abridges(shown: object, actual: object) -> bool:
    """Whether ``shown`` is ``actual`` with some keys and list items left out (kept items in order)."""
    if isinstance(shown, dict):
        return isinstance(actual, dict) and all(
            k in actual and abridges(v, actual[k]) for k, v in shown.items()
        )
    if isinstance(shown, list):
        rest = iter(actual) if isinstance(actual, list) else iter(())
        return all(any(abridges(item, candidate) for candidate in rest) for item in shown)
    return shown == actual


def test_the_abridged_scenario_is_the_sample_runs_best(sample_run):
    block = quoted_block("scenario-format.md", '{\n "format": "mazegen-scenario"')
    shown = json.loads(re.sub(r",\s*\.\.\.|\.\.\.,\s*|\n\s*\.\.\.\n", "\n", block.text))
    written = json.loads((sample_run / "run-01" / "best-01.json").read_text())
    assert abridges(shown, written), f"{block.where} is not run-01/best-01.json of: {SAMPLE_RUN}"
