"""Command-line options out of their bounds, or that would change nothing: one line each, before any work."""

from __future__ import annotations

import pytest
from click.testing import CliRunner

from mazegen.cli.main import main
from tests.conftest import EXAMPLES

FACTORY = str(EXAMPLES / "factory.maze")
SEED_MAX = "9223372036854775807"
HUGE = "99999999999999999999"
EXPORT = ["export", FACTORY, "-f"]
SCALES = "from 1e-06 to 1000 metres per arena unit"
FORMATS = "bundled: ros, gazebo, irsim, movingai, json, svg, png"
WAREHOUSE = str(EXAMPLES / "maps" / "warehouse.yaml")
DIGITS_400 = "1" + "0" * 400
"""More digits than a float holds: still one short line."""

BAD_COMMAND_LINES = [
    (
        ["run", FACTORY, "--seed", "9223372036854775808"],
        f"--seed must be from 0 to {SEED_MAX}, got 9223372036854775808",
    ),
    (["run", FACTORY, "--seed", "-1"], f"--seed must be from 0 to {SEED_MAX}, got -1"),
    (["run", FACTORY, "--population", "100000000"], "--population must be from 1 to 1000000, got 100000000"),
    (["run", FACTORY, "--population", "0"], "--population must be from 1 to 1000000, got 0"),
    (
        ["run", FACTORY, "--generations", "99999999999"],
        "--generations must be from 0 to 1000000, got 99999999999",
    ),
    (["run", FACTORY, "--runs", HUGE], f"--runs must be from 1 to 10000, got {HUGE}"),
    (["run", FACTORY, "--workers", HUGE], f"--workers must be from 1 to 1024, got {HUGE}"),
    (["run", FACTORY, "--workers", "0"], "--workers must be from 1 to 1024, got 0"),
    (
        ["run", FACTORY, "--checkpoint-every", HUGE],
        f"--checkpoint-every must be from 0 to 1000000, got {HUGE}",
    ),
    (["resume", str(EXAMPLES), "--workers", "0"], "--workers must be from 1 to 1024, got 0"),
    (
        ["run", FACTORY, "--workers", "2", "--executor", "serial"],
        "--workers goes with --executor local, not serial",
    ),
    (
        ["run", FACTORY, "--seed", DIGITS_400],
        f"--seed must be from 0 to {SEED_MAX}, got 1000000000000000000000000000000000000000...",
    ),
    (["suite", FACTORY, "--size", HUGE], f"--size must be from 1 to 10000, got {HUGE}"),
    (["suite", FACTORY, "--iterations", HUGE], f"--iterations must be from 0 to 1000000, got {HUGE}"),
    (["suite", FACTORY, "--batch", "1"], "--batch must be from 2 to 1000000, got 1"),
    (["suite", FACTORY, "--seed", HUGE], f"--seed must be from 0 to {SEED_MAX}, got {HUGE}"),
    (["map", FACTORY, "3", HUGE], f"codon must be from 0 to 2147483647, got {HUGE}"),
    (["import", WAREHOUSE, "-o", "out"], f"{WAREHOUSE}: give --start X,Y and --goal X,Y, or --tasks N"),
    (["import", WAREHOUSE, "--tasks", "0", "-o", "out"], "--tasks must be from 1 to 1000, got 0"),
    (
        ["import", WAREHOUSE, "--tasks", "1", "--robot-radius", HUGE, "-o", "out"],
        f"--robot-radius must be from 0 to 100 metres, got {HUGE}",
    ),
    (["map", FACTORY, "3", "--wraps", "101"], "--wraps must be from 0 to 100, got 101"),
    (["sweep", FACTORY, "--runs", HUGE], f"--runs must be from 1 to 10000, got {HUGE}"),
    (
        ["sweep", FACTORY, "--set", f"seed=1..{HUGE}"],
        f"--set seed: 1..{HUGE} holds {HUGE} values; a sweep has at most 10000 cells",
    ),
    (
        ["sweep", FACTORY, "--set", "seed=1..9999999"],
        "--set seed: 1..9999999 holds 9999999 values; a sweep has at most 10000 cells",
    ),
    (
        ["sweep", FACTORY, "--set", "seed=1..101", "--set", "population=1..100"],
        "--set: 10100 cells; a sweep has at most 10000 cells",
    ),
    (
        ["sweep", FACTORY, str(EXAMPLES / "workshop.maze"), "--set", "seed=1..5001"],
        "--set: 2 specs x 5001 cells; a sweep has at most 10000 cells",
    ),
    (["sweep", FACTORY, "--set", f"seed={HUGE}"], f"--set seed: {HUGE} must be from 0 to {SEED_MAX}"),
    (
        ["sweep", FACTORY, "--set", f"seed={DIGITS_400}"],
        f"--set seed: 1000000000000000000000000000000000000000... must be from 0 to {SEED_MAX}",
    ),
    (
        ["sweep", FACTORY, "--set", "fitness.overlap=inf"],
        "--set fitness.overlap: inf must be a finite number",
    ),
    (
        ["sweep", FACTORY, "--set", "fitness.overlap=nan"],
        "--set fitness.overlap: nan must be a finite number",
    ),
    (["sweep", FACTORY, "--set", "mutation=nan"], "--set mutation: nan must be a finite number"),
    (
        ["sweep", FACTORY, "--set", "seed=1,2", "--set", "seed=3"],
        "--set seed is given twice (give all its values in one --set)",
    ),
    (
        ["sweep", FACTORY, "--set", "fitness.solvable=0,1"],
        "--set fitness.solvable=0 changes nothing in spec 'factory' (it runs the same experiment as without",
    ),
    (["scenarios", "--limit", HUGE], f"--limit must be from 1 to {SEED_MAX}, got {HUGE}"),
    (["scenarios", "--min-elements", HUGE], f"--min-elements must be from 0 to 1000000, got {HUGE}"),
    (
        ["scenarios", "--where", "difficulty>=nan"],
        "condition 'difficulty>=nan': 'nan' is not a finite number",
    ),
    ([*EXPORT, "svg", "--cell", "5"], "--cell does not apply to svg exports (only to ros, movingai)"),
    ([*EXPORT, "gazebo", "--cell", "5"], "--cell does not apply to gazebo exports (only to ros, movingai)"),
    (
        [*EXPORT, "movingai", "--scale", "1"],
        "--scale does not apply to movingai exports (only to ros, gazebo, irsim)",
    ),
    ([*EXPORT, "png", "--scale", "1"], "--scale does not apply to png exports (only to ros, gazebo, irsim)"),
    ([*EXPORT, "gazebo", "--scale", "1e9"], f"--scale must be {SCALES}, got 1e+09"),
    ([*EXPORT, "gazebo", "--scale", "inf"], f"--scale must be {SCALES}, got inf"),
    ([*EXPORT, "ros", "--cell", "nan"], "--cell must be a positive number of arena units, got nan"),
    ([*EXPORT, "rso"], f"unknown export format 'rso' (did you mean 'ros'?) ({FORMATS})"),
]
"""Known-bad command lines and the one line each must give (the source need not be read to refuse them)."""


@pytest.mark.parametrize(
    ("args", "message"), BAD_COMMAND_LINES, ids=[" ".join(args[2:]) for args, _ in BAD_COMMAND_LINES]
)
def test_bad_command_lines_are_one_line_errors(tmp_path, monkeypatch, args, message):
    monkeypatch.chdir(tmp_path)  # nothing may be written; if something is, it stays in tmp_path
    result = CliRunner().invoke(main, args)
    assert not isinstance(result.exception, Exception), result.exception  # a traceback
    assert result.exit_code == 1, result.output
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith(message), result.stderr
    assert list(tmp_path.iterdir()) == []


def _webots_files(floor, options):
    return {}


_webots_files.options = ("scale",)


def _dpi_files(floor, options):
    return {}


_dpi_files.options = ("dpi",)

PLUGIN_COMMAND_LINES = [
    (
        [*EXPORT, "webot"],
        f"unknown export format 'webot' (did you mean 'webots'?) ({FORMATS}; registered: dpi, webots)",
    ),
    ([*EXPORT, "webots", "--cell", "5"], "--cell does not apply to webots exports (only to ros, movingai)"),
    (
        [*EXPORT, "dpi"],
        "exporter plug-in 'dpi' of fake-plugins 1.0 declares the options ('dpi',), "
        "not a tuple of scale or cell",
    ),
]
"""Known-bad command lines where packages register the export formats ``webots`` and ``dpi``."""


@pytest.mark.parametrize(
    ("args", "message"), PLUGIN_COMMAND_LINES, ids=[" ".join(args[2:]) for args, _ in PLUGIN_COMMAND_LINES]
)
def test_bad_command_lines_with_plugins_are_one_line_errors(
    tmp_path, monkeypatch, register_plugins, args, message
):
    register_plugins("exporters", {"webots": _webots_files, "dpi": _dpi_files})
    test_bad_command_lines_are_one_line_errors(tmp_path, monkeypatch, args, message)


@pytest.mark.parametrize(
    ("command", "option"), [("run", "--population"), ("suite", "--batch")], ids=["run", "suite"]
)
def test_too_many_codons_for_the_population_is_one_line(tmp_path, write_spec, command, option):
    text = (EXAMPLES / "factory.maze").read_text().replace("genome 32", "genome 10000")
    spec = write_spec(text, "big.maze")
    result = CliRunner().invoke(main, [command, str(spec), option, "20000", "-q", "-o", str(tmp_path / "r")])
    assert not isinstance(result.exception, Exception), result.exception
    assert result.exit_code == 1, result.output
    assert result.stderr.splitlines() == [
        f"{option} 20000: population x genome must be at most 100000000 codons, got 20000 x 10000"
    ]
    assert not (tmp_path / "r").exists()


def test_codons_of_a_genomes_file_are_bounded_at_their_line(tmp_path):
    genomes = tmp_path / "genomes.txt"
    genomes.write_text(f"3 4 5\n3 {HUGE} 5\n")
    result = CliRunner().invoke(main, ["map", FACTORY, "--genomes", str(genomes)])
    assert not isinstance(result.exception, Exception), result.exception
    assert result.exit_code == 1
    assert result.stderr.splitlines() == [f"{genomes}:2:1: codons must be from 0 to 2147483647"]


def test_help_shows_the_bounds():
    shown = " ".join(CliRunner().invoke(main, ["run", "-h"]).output.split())
    assert f"Seed of the experiment (overrides the spec). [from 0 to {SEED_MAX}]" in shown
    assert "Local worker processes (default: the cores). [from 1 to 1024]" in shown
