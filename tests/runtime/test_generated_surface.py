"""Generated code imports the top level of mazegen.runtime only, so builds from earlier versions run."""

from __future__ import annotations

from click.testing import CliRunner

from mazegen.cli.main import main
from tests.conftest import EXAMPLES

SMALL = ("--population", "20", "--generations", "1", "--executor", "serial", "-q")

EARLIER_IMPORTS = {
    "fitness.py": [
        "from mazegen.runtime import metrics",
        "from mazegen.runtime.population import Population",
    ],
    "experiment.py": ["from mazegen.runtime.experiment import main"],
}
"""What builds made before the runtime had sub-packages import (MazeGen 0.1.0)."""


def invoke(*args: str):
    return CliRunner().invoke(main, list(args), catch_exceptions=False)


def test_a_build_made_before_the_sub_packages_still_runs(tmp_path):
    build = tmp_path / "build"
    assert invoke("build", str(EXAMPLES / "factory.maze"), "-o", str(build)).exit_code == 0
    for name, lines in EARLIER_IMPORTS.items():
        imports = [line for line in (build / name).read_text().splitlines() if "import" in line]
        assert [line for line in imports if "mazegen" in line] == lines
    result = invoke("run", str(build), *SMALL, "-o", str(tmp_path / "run"))
    assert result.exit_code == 0, result.output
    assert (tmp_path / "run" / "run-01" / "best-01.json").is_file()


def test_a_fitness_module_that_imports_a_moved_module_says_to_rebuild(tmp_path):
    build = tmp_path / "build"
    assert invoke("build", str(EXAMPLES / "factory.maze"), "-o", str(build)).exit_code == 0
    fitness = build / "fitness.py"
    fitness.write_text("from mazegen.runtime.difficulty import survey\n" + fitness.read_text())
    result = invoke("run", str(build), *SMALL, "-o", str(tmp_path / "run"))
    assert result.exit_code == 1
    assert result.stderr.splitlines() == [
        f"{fitness}:1: fitness.py imports mazegen.runtime.difficulty, which this MazeGen does not have: "
        "it was made by an earlier version; rebuild it with 'mazegen build SPEC' (and redo any edits)"
    ]
