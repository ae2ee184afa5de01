"""What a spec's grammar text derives, and the names of files, reach the terminal escaped: no spec and
no file name can drive the terminal."""

from __future__ import annotations

from click.testing import CliRunner

import mazegen.runtime
import mazegen.runtime.runs._warmup
from mazegen.cli.main import main
from mazegen.runtime.runs._progress import FIRST_COMPILE_NOTE
from tests.conftest import EXAMPLES

# The grammar's text escapes decode to ESC ] 0 ; TITLE BEL: a terminal would take the title.
TITLE_SPEC = """
element box { shape square size 20..40 }
arena floor { size 1000 x 800 cm start (50, 50) goal (950, 750) robot radius 20 }
scenario s on floor { grammar custom { <s> ::= box "\\x1b]0;TITLE\\x07" } max elements 4 }
evolution { population 10 generations 0 }
"""


def invoke(*args: str):
    return CliRunner().invoke(main, list(args), catch_exceptions=False)


def test_map_prints_control_characters_escaped(write_spec):
    result = invoke("map", str(write_spec(TITLE_SPEC)), "0")
    assert result.exit_code == 0, result.output
    assert result.output == "box\\x1b]0;TITLE\\x07\t1 codons\n"


def test_run_prints_the_best_phenotype_escaped(write_spec, tmp_path):
    result = invoke(
        "run", str(write_spec(TITLE_SPEC)), "--executor", "serial", "-q", "-o", str(tmp_path / "run")
    )
    assert result.exit_code == 0, result.output
    assert "\x1b" not in result.output and "\x07" not in result.output
    assert "box\\x1b]0;TITLE\\x07" in result.output


def test_check_prints_a_file_name_with_control_characters_escaped(write_spec):
    good = write_spec(TITLE_SPEC, name="we\x1b]0;TITLE\x07ird.maze")
    bad = write_spec("elemnt", name="ba\x1b[2Jd.maze")
    result = CliRunner().invoke(main, ["check", str(good), str(bad)])
    assert result.exit_code == 1
    assert "\x1b" not in result.output and "\x07" not in result.output
    assert "we\\x1b]0;TITLE\\x07ird.maze: OK" in result.output
    assert "ba\\x1b[2Jd.maze:1:1: expected" in result.output


def test_the_compile_note_is_one_line_in_a_pipe(write_spec, tmp_path, monkeypatch):
    # Rich wrapped it at 80 columns, mid-sentence, for whatever read standard error.
    monkeypatch.setattr(mazegen.runtime.runs._warmup, "compile_kernels", lambda problem: None)
    monkeypatch.setattr(mazegen.runtime, "kernels_cached", lambda kernels=(): False)
    monkeypatch.delenv("COLUMNS", raising=False)
    assert len(FIRST_COMPILE_NOTE) > 80
    result = invoke("run", str(write_spec(TITLE_SPEC)), "--executor", "serial", "-o", str(tmp_path / "run"))
    assert result.exit_code == 0, result.output
    assert result.stderr.startswith(FIRST_COMPILE_NOTE + "\n")


WEIRD = "we\x1b]0;TITLE\x07i\nrd"
"""A file name that would retitle the terminal, and split a line in two, if printed raw."""
SHOWN = "we\\x1b]0;TITLE\\x07i\\nrd"


def assert_escaped(output: str) -> None:
    assert "\x1b" not in output and "\x07" not in output, output
    assert SHOWN in output, output


def test_every_command_prints_the_paths_it_names_escaped(tmp_path):
    spec, out = str(EXAMPLES / "factory.maze"), tmp_path / WEIRD
    settings = ["--runs", "1", "--population", "40", "--generations", "1", "--executor", "serial", "-q"]
    ran = invoke("run", spec, *settings, "-o", str(out))
    assert ran.exit_code == 0, ran.output
    assert_escaped(ran.stdout)
    catalog = str(tmp_path / "catalog.sqlite")
    assert_escaped(invoke("runs", "--catalog", catalog).stdout)
    assert_escaped(invoke("scenarios", "--catalog", catalog).stdout)
    paths = invoke("scenarios", "--catalog", catalog, "--paths").stdout.splitlines()
    best = sorted(out.glob("run-*/best-*.json"))
    assert len(paths) == len(best) > 1  # still one path a line
    assert_escaped("\n".join(paths))
    assert_escaped(invoke("score", spec, str(out)).stdout)
    drawn = invoke("render", str(best[0]), "-o", str(tmp_path / f"{WEIRD}.svg"))
    assert drawn.exit_code == 0 and (tmp_path / f"{WEIRD}.svg").is_file()
    assert_escaped(drawn.stdout)
    reported = invoke("report", str(out))
    assert reported.exit_code == 0
    assert_escaped(reported.stdout)
    exported = invoke("export", str(best[0]), "-f", "json", "-o", str(tmp_path / WEIRD / "json"))
    assert exported.exit_code == 0
    assert_escaped(exported.stdout)
