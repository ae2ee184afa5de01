"""The `mazegen` command end to end, as a user runs it."""

from __future__ import annotations

import json
import random
import stat
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from mazegen.cli.main import main
from tests.conftest import EXAMPLES
from tests.runtime.floors import floor_file


def invoke(*args: str):
    return CliRunner().invoke(main, list(args), catch_exceptions=False)


def test_check_prints_ok_per_file():
    result = invoke("check", str(EXAMPLES / "factory.maze"), str(EXAMPLES / "mazegen1.maze"))
    assert result.exit_code == 0
    assert result.output.splitlines() == [
        f"{EXAMPLES / 'factory.maze'}: OK",
        f"{EXAMPLES / 'mazegen1.maze'}: OK",
    ]


def test_check_reports_located_error_without_traceback(write_spec):
    path = write_spec("element box { shape square size 40..20 }\n")
    result = invoke("check", str(path))
    assert result.exit_code == 1
    assert result.stderr.strip().endswith("spec.maze:1:33: empty size range 40..20 (low is above high)")
    assert "Traceback" not in result.output


def test_every_command_is_listed_and_resolves_to_itself():
    from mazegen.cli.main import COMMANDS

    result = invoke("--help")
    listed = [line.split()[0] for line in result.output.split("Commands:")[1].splitlines() if line.strip()]
    assert listed == sorted(COMMANDS)
    context = main.make_context("mazegen", ["check", "x"])
    assert all(main.get_command(context, name).name == name for name in COMMANDS)
    assert main.get_command(context, "nosuch") is None


def test_check_loads_the_language_not_the_engine():
    """``mazegen check`` must stay quick: numba and the runtime are not imported for it."""
    code = (
        "import sys\n"
        "from mazegen.cli.main import main\n"
        f"main(['check', {str(EXAMPLES / 'factory.maze')!r}], standalone_mode=False)\n"
        "print(sorted(m for m in ('numba', 'mazegen.runtime') if m in sys.modules))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.splitlines()[-1] == "[]"


def test_map_a_spec_as_its_built_grammar_with_its_settings(tmp_path, write_spec):
    out = tmp_path / "build"
    invoke("build", str(EXAMPLES / "factory.maze"), "-o", str(out))
    genomes = tmp_path / "genomes.txt"
    rng = random.Random(5)
    lines = (" ".join(str(rng.randrange(256)) for _ in range(12)) for _ in range(40))
    genomes.write_text("\n".join(lines) + "\n")
    from_spec = invoke("map", str(EXAMPLES / "factory.maze"), "--genomes", str(genomes))
    from_build = invoke("map", str(out / "grammar.bnf"), "--genomes", str(genomes))
    assert from_spec.exit_code == 0 and from_spec.output == from_build.output
    assert len(set(from_spec.output.splitlines())) > 5
    # The spec's own wraps and consume apply unless the options say otherwise.
    wrapped = (EXAMPLES / "mazegen1.maze").read_text().replace("evolution {", "evolution {\n    wraps 2")
    spec = write_spec(wrapped, name="wrapped.maze")
    with_spec = invoke("map", str(spec), "4", "4", "4")
    paper = str(EXAMPLES / "mazegen1.maze")
    assert with_spec.output == invoke("map", paper, "4", "4", "4", "--wraps", "2").output
    assert with_spec.output != invoke("map", str(spec), "4", "4", "4", "--wraps", "0").output


def test_map_genomes_file_as_json(tmp_path):
    out = tmp_path / "build"
    invoke("build", str(EXAMPLES / "mazegen1.maze"), "-o", str(out))
    genomes = tmp_path / "genomes.txt"
    genomes.write_text("34 10 200 80 5 70 45 43\n4,4,4\n\n0, 1\n")
    result = invoke("map", str(out / "grammar.bnf"), "--genomes", str(genomes), "--json")
    rows = [json.loads(line) for line in result.output.splitlines()]
    assert rows[0] == {"phenotype": "eshape(angle)", "valid": True, "used_codons": 3}
    # PonyGE2 reads codon 0 once more when the genome ends just before a non-terminal.
    assert rows[1] == {"phenotype": None, "valid": False, "used_codons": 4}
    assert rows[2] == {"phenotype": "angle", "valid": True, "used_codons": 1}


def test_map_rejects_a_bad_genome_line(tmp_path):
    grammar = tmp_path / "g.bnf"
    grammar.write_text("<s> ::= a | b\n")
    genomes = tmp_path / "genomes.txt"
    genomes.write_text("1 2\n1 x 3\n")
    result = invoke("map", str(grammar), "--genomes", str(genomes))
    assert result.exit_code == 1
    assert "genomes.txt:2:1: a genome is integers" in result.stderr


@pytest.fixture(scope="module")
def small_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("small") / "run"
    assert run_small(out).exit_code == 0
    return out


def run_small(out: Path, *extra: str):
    return invoke(
        "run",
        str(EXAMPLES / "factory.maze"),
        "--population",
        "60",
        "--generations",
        "3",
        "--runs",
        "2",
        "--executor",
        "serial",
        "-q",
        "-o",
        str(out),
        *extra,
    )


def test_run_writes_a_complete_run_directory(tmp_path):
    out = tmp_path / "run"
    result = run_small(out, "--executor", "local")  # the default: runs on worker processes
    assert result.exit_code == 0, result.output
    assert "run 1: best fitness" in result.output
    assert (out / "experiment" / "grammar.bnf").is_file() and (out / "experiment" / "fitness.py").is_file()
    record = json.loads((out / "experiment.json").read_text())
    assert record["evolution"]["population"] == 60 and record["evolution"]["runs"] == 2
    stats = (out / "stats.csv").read_text().splitlines()
    assert stats[0] == "run,generation,evaluations,best,mean,median,invalid,unique,cache_hits"
    assert len(stats) == 1 + 2 * 4
    timing = (out / "timing.csv").read_text().splitlines()
    assert timing[0] == "run,generation,seconds" and len(timing) == 1 + 2 * 4
    assert not (out / "checkpoints").exists() and (tmp_path / "catalog.sqlite").is_file()
    for run in ("run-01", "run-02"):
        document = json.loads((out / run / "best-01.json").read_text())
        assert document["format"] == "mazegen-scenario"
        assert (out / run / "best-01.svg").read_text().startswith("<svg") or "<svg" in (
            out / run / "best-01.svg"
        ).read_text()
        assert (out / run / "population.npz").is_file()


def test_run_files_get_the_modes_the_umask_gives(tmp_path):
    # Written through private temporary files and folders, yet readable as any file the user
    # makes, e.g. by a simulator's container running as another user.
    out = tmp_path / "run"
    assert run_small(out).exit_code == 0
    picture = tmp_path / "floor.png"
    assert invoke("render", str(out / "run-01" / "best-01.json"), "-o", str(picture)).exit_code == 0
    # What a plain open and mkdir give, under the same umask.
    (tmp_path / "plain").mkdir()
    (tmp_path / "plain" / "file").write_text("")
    folder_mode, file_mode = (
        stat.S_IMODE(p.stat().st_mode) for p in (tmp_path / "plain", tmp_path / "plain" / "file")
    )
    paths = [out, *out.rglob("*"), picture]
    modes = {path.relative_to(tmp_path): stat.S_IMODE(path.stat().st_mode) for path in paths}
    expected = {path.relative_to(tmp_path): folder_mode if path.is_dir() else file_mode for path in paths}
    assert modes == expected


def test_run_refuses_to_overwrite_and_keeps_old_results(tmp_path):
    out = tmp_path / "run"
    run_small(out)
    before = (out / "stats.csv").read_bytes()
    result = run_small(out, "--seed", "9")
    assert result.exit_code == 1
    assert "output directory already exists" in result.stderr
    assert (out / "stats.csv").read_bytes() == before


def test_run_ends_saying_where_the_pictures_are(tmp_path):
    out = tmp_path / "run"
    result = run_small(out)
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines()[-3:] == [
        f"wrote {out}",
        f"pictures: {out}/run-NN/best-KK.svg (as PNG: mazegen export {out} --format png)",
        f"one page of settings, pictures and plots: mazegen report {out}",
    ]


OVERSIZED = """
element block { shape rect size 20..40 x 400..500 }
arena small { size 300 x 300 cm  start (30, 30)  goal (270, 270)  robot radius 10 }
scenario blocks on small { elements block  grammar nested  max elements 8 }
fitness { count  outside reject }
evolution { population 40  generations 1  genome GENOME  runs 2 }
"""
"""Every element is taller than the arena (it could lie across its diagonal, were it turned): no scenario
stays inside it."""


def test_a_run_without_a_valid_scenario_says_why_and_fails(tmp_path, write_spec):
    spec = write_spec(OVERSIZED.replace("GENOME", "32"))
    result = invoke("run", str(spec), "-q", "--executor", "serial", "-o", str(tmp_path / "run"))
    assert result.exit_code == 1
    lines = result.stdout.splitlines()
    assert lines[:2] == [
        "run 1: no valid scenario; of its final generation's 40 individuals,",
        "  100 % rejected by outside reject: elements not wholly inside the arena "
        "(larger than it, placed beyond it, or on its map's walls?)",
    ]
    assert lines[2].startswith("run 2: no valid scenario")
    assert result.stderr.splitlines() == ["no run produced a valid scenario (see why above)"]
    assert (tmp_path / "run" / "stats.csv").is_file()  # the run itself is whole


def test_a_sweep_without_a_valid_scenario_says_why_and_fails(tmp_path, write_spec):
    spec = write_spec(OVERSIZED.replace("GENOME", "32").replace("runs 2", "runs 1"))
    args = ["sweep", str(spec), "--set", "seed=1,2", "-q", "--executor", "serial", "-o", str(tmp_path / "s")]
    result = invoke(*args)
    assert result.exit_code == 1
    lines = result.stdout.splitlines()
    assert lines[:3] == [
        "blocks-seed1: 1 runs, no valid scenario",
        "  run 1: no valid scenario; of its final generation's 40 individuals,",
        "    100 % rejected by outside reject: elements not wholly inside the arena "
        "(larger than it, placed beyond it, or on its map's walls?)",
    ]
    assert lines[3] == "blocks-seed2: 1 runs, no valid scenario"
    assert result.stderr.splitlines() == ["no run produced a valid scenario (see why above)"]


def test_a_run_of_genomes_too_short_says_so(tmp_path, write_spec):
    # One codon: half the genomes pick a composed element and run out of codons, the others
    # make one block, larger than the arena.
    spec = write_spec(OVERSIZED.replace("GENOME", "1").replace("runs 2", "runs 1"))
    result = invoke("run", str(spec), "-q", "--executor", "serial", "-o", str(tmp_path / "run"))
    assert result.exit_code == 1
    header, *causes = result.stdout.splitlines()[:3]
    assert header == "run 1: no valid scenario; of its final generation's 40 individuals,"
    shares = [int(line.split("%")[0]) for line in causes]
    assert abs(sum(shares) - 100) <= 1 and all(share > 0 for share in shares)  # rounded
    assert causes[0].endswith(
        "invalid: the genome ran out of codons before the derivation ended "
        "(try a longer genome or more wraps)"
    )
    assert "rejected by outside reject" in causes[1]


def test_run_rejects_population_zero(tmp_path):
    result = invoke(
        "run", str(EXAMPLES / "factory.maze"), "--population", "0", "-q", "-o", str(tmp_path / "r")
    )
    assert result.exit_code == 1
    assert result.stderr.strip() == "--population must be from 1 to 1000000, got 0"
    assert not (tmp_path / "r").exists()


def test_score_a_hand_drawn_floor(tmp_path):
    def routers(*xs: int) -> list[dict]:
        return [{"type": "router", "x": x, "y": 100, "size": 30} for x in xs]

    path = floor_file(tmp_path / "floor.json", *routers(100, 300, 500, 700))
    result = invoke("score", str(EXAMPLES / "factory.maze"), str(path))
    assert result.output.splitlines()[:3] == ["fitness\t4", "elements\t4", "term count\t4"]
    # Figure 19: four elements, three overlapping pairs -> 4 - 0.5 * 3 = 2.5.
    overlapping = routers(100, 110, 120, 700)
    floor_file(path, *overlapping)
    result = invoke("score", str(EXAMPLES / "factory.maze"), str(path))
    assert "term overlap\t-1.5" in result.output.splitlines()
    assert result.output.splitlines()[0] == "fitness\t2.5"
    assert "solvable\tyes" in result.output.splitlines()
    assert any(line.startswith("tortuosity\t1.0") for line in result.output.splitlines())
    labels = [line.split("\t")[0] for line in result.output.splitlines()]
    for label in ("closest obstacle", "visibility", "dispersion", "characteristic dimension", "difficulty"):
        assert label in labels
    # A wall from floor to ceiling: no path, and factory requires one.
    floor_file(path, *overlapping, {"type": "vwall", "x": 1000, "y": 525, "width": 20, "depth": 1100})
    lines = invoke("score", str(EXAMPLES / "factory.maze"), str(path)).output.splitlines()
    assert lines[0] == "fitness\tinvalid (rejected by the spec)" and "solvable\tno" in lines


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("{not json", "floor.json:1:2: not valid JSON"),
        ('{"format": "other"}', "not a scenario file"),
        (
            '{"format": "mazegen-scenario", "version": 1, "elements": [{"type": "crate", "x": 1, "y": 1}]}',
            "elements[0].type: 'crate' is not an element of scenario 'factory'",
        ),
        (
            '{"format": "mazegen-scenario", "version": 1, "elements": [{"type": "router", "x": "a", "y": 1, '
            '"size": 3}]}',
            'elements[0].x: must be a number from -1e+09 to 1e+09, got "a"',
        ),
        (
            '{"format": "mazegen-scenario", "version": 1, "elements": [{"type": "router", "x": 90, "y": 80, '
            '"size": 30}, {"type": "hwall", "x": 500, "y": 500, "width": 200, "depth": -10}]}',
            "elements[1].depth: must be a number from 0.0001 to 1e+09, got -10",
        ),
    ],
)
def test_score_reports_bad_scenarios(tmp_path, content, message):
    path = tmp_path / "floor.json"
    path.write_text(content)
    result = invoke("score", str(EXAMPLES / "factory.maze"), str(path))
    assert result.exit_code == 1
    assert message in result.stderr


WALL = {"type": "vwall", "x": 700, "y": 525, "width": 20, "depth": 1100}
"""A wall from floor to ceiling across examples/factory.maze's arena: its start and goal are cut apart."""


def test_score_takes_the_task_of_the_document(tmp_path):
    own = {"format": "mazegen-scenario", "version": 1, "arena": {"start": [60, 60], "goal": [300, 990]}}
    path = tmp_path / "floor.json"
    path.write_text(json.dumps({**own, "elements": [WALL]}))
    result = invoke("score", str(EXAMPLES / "factory.maze"), str(path))
    assert result.exit_code == 0, result.output
    assert "solvable\tyes" in result.stdout.splitlines()  # both on the wall's left side
    assert result.stderr.splitlines() == [
        f"{path}: scored with its own start (60, 60) and goal (300, 990), "
        "not the spec's start (60, 60) and goal (1340, 990)"
    ]
    floor_file(path, WALL)  # no arena: the spec's task, without a word
    result = invoke("score", str(EXAMPLES / "factory.maze"), str(path))
    assert "solvable\tno" in result.stdout.splitlines() and result.stderr == ""
    path.write_text(json.dumps({**own, "arena": {"start": [-5, 60]}, "elements": [WALL]}))
    result = invoke("score", str(EXAMPLES / "factory.maze"), str(path))
    assert result.exit_code == 1
    assert result.stderr.splitlines() == [f"{path}: start (-5, 60) is outside the arena 1400 x 1050"]


def test_score_many_files_and_folders_in_one_call(tmp_path):
    out = tmp_path / "run"
    run_small(out)
    floor = floor_file(tmp_path / "floor.json", {"type": "router", "x": 300, "y": 100, "size": 30})
    best = sorted(out.rglob("best-*.json"))
    result = invoke("score", str(EXAMPLES / "factory.maze"), str(floor), str(out), "--json")
    assert result.exit_code == 0, result.output
    records = [json.loads(line) for line in result.stdout.splitlines()]
    assert [record["file"] for record in records] == [str(floor), *map(str, best)]  # not experiment.json
    for path, record in zip(best, records[1:]):
        document = json.loads(path.read_text())
        assert record["fitness"] == document["fitness"] and record["terms"] == document["terms"]
        assert record["solvable"] == document["metrics"]["solvable"]
        assert record["metrics"]["tortuosity"] == pytest.approx(document["metrics"]["tortuosity"], abs=1e-3)
    assert records[0]["terms"] == {"count": 1.0, "overlap": 0.0, "outside": 0.0}
    table = invoke("score", str(EXAMPLES / "factory.maze"), str(floor), str(out)).stdout.splitlines()
    assert table[0].split()[:4] == ["file", "fitness", "elements", "solvable"] and "term count" in table[0]
    assert len(table) == 1 + len(records) and table[1].split()[:3] == [str(floor), "1", "1"]


def test_score_reports_a_bad_file_and_scores_the_others(tmp_path):
    good = floor_file(tmp_path / "a.json", {"type": "router", "x": 300, "y": 100, "size": 30})
    bad = tmp_path / "b.json"
    bad.write_text("{not json")
    other = floor_file(tmp_path / "c.json", {"type": "router", "x": 500, "y": 100, "size": 30})
    result = invoke("score", str(EXAMPLES / "factory.maze"), str(good), str(bad), str(other), "--json")
    assert result.exit_code == 1
    assert result.stderr.splitlines() == [
        f"{bad}:1:2: not valid JSON: Expecting property name enclosed in double quotes"
    ]
    assert [json.loads(line)["file"] for line in result.stdout.splitlines()] == [str(good), str(other)]
    empty = tmp_path / "empty"
    empty.mkdir()
    result = invoke("score", str(EXAMPLES / "factory.maze"), str(empty))
    assert result.exit_code == 1
    assert result.stderr.splitlines() == [f"{empty}: no scenario files in this folder"]


def test_suite_writes_spread_solvable_scenarios_and_a_heatmap(tmp_path):
    out = tmp_path / "suite"
    args = ["suite", str(EXAMPLES / "workshop.maze"), "--size", "5", "--iterations", "3", "--batch", "300"]
    result = invoke(*args, "-o", str(out), "--quiet")
    assert result.exit_code == 0, result.output
    assert result.output.splitlines()[-1] == f"wrote 5 scenarios to {out}"
    documents = [json.loads(path.read_text()) for path in sorted(out.glob("scenario-*.json"))]
    assert len(documents) == 5 and all(document["metrics"]["solvable"] for document in documents)
    assert (out / "archive.png").is_file() and (out / "scenario-05.svg").is_file()
    again = invoke(*args, "-o", str(out), "--quiet")
    assert again.exit_code == 1 and "already exists" in again.output
    by_class = invoke(*args, "--measure", "classes", "--distinct-classes", "-o", str(tmp_path / "c"), "-q")
    assert by_class.exit_code == 0, by_class.output
    written = [json.loads(path.read_text()) for path in sorted((tmp_path / "c").glob("scenario-*.json"))]
    assert written and all("classes" in document["origin"]["suite"] for document in written)
    assert json.loads((tmp_path / "c" / "archive.json").read_text())["bins"]["measure"] == "classes"


def test_render_svg_and_png(tmp_path):
    out = tmp_path / "run"
    run_small(out)
    for suffix in ("svg", "png"):
        picture = tmp_path / f"best.{suffix}"
        assert invoke("render", str(out / "run-01" / "best-01.json"), "-o", str(picture)).exit_code == 0
        assert picture.stat().st_size > 0


def test_generated_experiment_runs_alone(tmp_path):
    build = tmp_path / "build"
    invoke("build", str(EXAMPLES / "factory.maze"), "-o", str(build))
    out = tmp_path / "alone"
    done = subprocess.run(
        [
            sys.executable,
            str(build / "experiment.py"),
            "--seed",
            "3",
            "--population",
            "40",
            "--generations",
            "2",
            "--quiet",
            "-o",
            str(out),
        ],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    assert (out / "run-01" / "best-01.json").is_file()
    assert json.loads((out / "experiment.json").read_text())["evolution"]["seed"] == 3


def test_textx_knows_the_language_and_generator(tmp_path):
    check = subprocess.run(["textx", "check", str(EXAMPLES / "factory.maze")], capture_output=True, text=True)
    assert check.returncode == 0 and "factory.maze: OK" in check.stdout + check.stderr
    bad = tmp_path / "bad.maze"
    bad.write_text("element b { shape square size 9..1 }\n")
    refused = subprocess.run(["textx", "check", str(bad)], capture_output=True, text=True)
    assert (
        refused.returncode != 0 and "bad.maze:1:31: empty size range 9..1" in refused.stdout + refused.stderr
    )
    bad.write_text("// nothing yet\n")
    empty = subprocess.run(["textx", "check", str(bad)], capture_output=True, text=True)
    assert empty.returncode != 0 and "Traceback" not in empty.stderr
    assert "the file declares nothing" in empty.stdout + empty.stderr
    out = tmp_path / "gen"
    generate = subprocess.run(
        ["textx", "generate", str(EXAMPLES / "mazegen1.maze"), "--target", "mazegen", "-o", str(out)],
        capture_output=True,
        text=True,
    )
    assert generate.returncode == 0, generate.stderr
    assert "<composed> ::=" in (out / "grammar.bnf").read_text()


def test_render_a_hand_drawn_floor_with_its_spec(tmp_path):
    path = floor_file(
        tmp_path / "floor.json", {"type": "productionLine", "x": 700, "y": 500, "width": 400, "depth": 80}
    )
    without = invoke("render", str(path), "-o", str(tmp_path / "a.svg"))
    assert without.exit_code == 1
    assert without.stderr.strip().endswith("no element parts: give --spec SPEC.maze to compute them")
    done = invoke(
        "render", str(path), "-o", str(tmp_path / "a.svg"), "--spec", str(EXAMPLES / "factory.maze")
    )
    assert done.exit_code == 0, done.output
    assert (tmp_path / "a.svg").read_text().count("<polygon") == 1


@pytest.mark.parametrize(
    ("damage", "message"),
    [
        (lambda d: d["elements"][0].pop("type"), "elements[0]: 'type' is missing"),
        (lambda d: d["arena"].update(width=-1), "arena.width: must be a number from 0.0001 to 1e+09, got -1"),
        (lambda d: d["elements"][0].update(x="abc"), "elements[0].x: must be a number"),
        (lambda d: d["elements"][0].update(parts=[[[0, 0]]]), "elements[0].parts[0]: must be a list of 3"),
    ],
)
def test_render_refuses_a_damaged_scenario_in_one_line(tmp_path, small_run, damage, message):
    document = json.loads((small_run / "run-01" / "best-01.json").read_text())
    damage(document)
    path = tmp_path / "damaged.json"
    path.write_text(json.dumps(document))
    result = invoke("render", str(path), "-o", str(tmp_path / "floor.svg"))
    assert result.exit_code == 1
    assert len(result.stderr.splitlines()) == 1 and result.stderr.startswith(f"{path}: {message}")
    assert not (tmp_path / "floor.svg").exists()


def test_unreadable_inputs_give_one_line_errors(tmp_path):
    binary = tmp_path / "floor.json"
    binary.write_bytes(b"\xff\xfe\x00")
    for args in (
        ("score", str(EXAMPLES / "factory.maze"), str(binary)),
        ("render", str(binary), "-o", "x.svg"),
        ("map", str(binary), "1"),
    ):
        result = invoke(*args)
        assert result.exit_code == 1
        assert result.stderr.strip().endswith(
            "floor.json: cannot read " + ("grammar" if args[0] == "map" else "scenario") + ": not UTF-8 text"
        )


def test_outputs_under_a_file_give_one_line_errors(tmp_path):
    blocker = tmp_path / "plain.txt"
    blocker.write_text("not a folder")
    run_small(tmp_path / "run")
    scenario = str(tmp_path / "run" / "run-01" / "best-01.json")
    small = ("--iterations", "1", "--batch", "50", "-q")
    for args, folder in (
        (("run", str(EXAMPLES / "factory.maze"), "-q", "-o", str(blocker / "run")), blocker),
        (
            ("suite", str(EXAMPLES / "workshop.maze"), "--size", "2", *small, "-o", str(blocker / "s")),
            blocker,
        ),
        (("render", scenario, "-o", str(blocker / "deeper" / "floor.svg")), blocker / "deeper"),
    ):
        result = invoke(*args)
        assert result.exit_code == 1, result.output
        assert result.stderr.splitlines() == [
            f"{folder}: cannot create the folder: "
            + ("a file is in the way" if folder == blocker else "Not a directory")
        ]
    assert blocker.read_text() == "not a folder"


def test_an_edited_build_that_fails_gives_one_line_errors(tmp_path):
    build = tmp_path / "build"
    assert invoke("build", str(EXAMPLES / "factory.maze"), "-o", str(build)).exit_code == 0
    fitness = build / "fitness.py"
    text = fitness.read_text()
    head = "def terms(pop: Population) -> dict[str, np.ndarray]:"
    at = text.splitlines().index(head) + 2  # the line of the raise, just below the def
    fitness.write_text(text.replace(head, head + "\n    raise ValueError('a slip')"))
    small = ("--population", "20", "--generations", "1", "-q")
    for executor in ("serial", "local"):
        result = invoke("run", str(build), *small, "--executor", executor, "-o", str(tmp_path / executor))
        assert result.exit_code == 1
        assert result.stderr.splitlines() == [f"fitness.py:{at}: terms(pop) raised ValueError: a slip"]
    fitness.write_text(text)
    spec = json.loads((build / "spec.json").read_text())
    spec["evolution"]["population"] = -3
    (build / "spec.json").write_text(json.dumps(spec))
    result = invoke("run", str(build), "-q", "-o", str(tmp_path / "damaged"))
    assert result.exit_code == 1
    assert result.stderr.strip().endswith(
        "damaged spec.json (ValueError: population must be from 1 to 1000000, got -3)"
    )


def test_run_a_build_dir_names_the_run_by_the_seed_used(tmp_path, monkeypatch):
    build = tmp_path / "build"
    invoke("build", str(EXAMPLES / "factory.maze"), "-o", str(build))
    monkeypatch.chdir(tmp_path)
    result = invoke("run", str(build), "--seed", "7", "--population", "30", "--generations", "1", "-q")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "runs" / "factory-seed7" / "stats.csv").is_file()
    (build / "spec.json").write_text("{broken")
    damaged = invoke("run", str(build), "-q")
    assert damaged.exit_code == 1 and "spec.json: damaged spec.json" in damaged.stderr
