"""The HTML report of a run directory: self-contained, complete, and seen by a real browser."""

from __future__ import annotations

import base64
import csv
import html.parser
import io
import json
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

import mazegen
from mazegen.cli.main import main
from mazegen.errors import MazeError
from mazegen.runtime.campaigns._suite import SuiteSettings, fill_archive, suite_documents, write_suite
from mazegen.runtime.reports._report import distribution_chart, read_run, report_html, statistic_table
from mazegen.runtime.reports._report_html import THUMBNAIL_PIXELS, phenotype_html
from mazegen.runtime.reports._spec_words import evolution_words, scenario_words, term_words
from mazegen.spec import Evolution
from tests.conftest import EXAMPLES

SVG = "{http://www.w3.org/2000/svg}"


class Page(html.parser.HTMLParser):
    """The images, headings and table cells of a page."""

    def __init__(self, text: str) -> None:
        super().__init__()
        self.images: list[dict[str, str | None]] = []
        self.text: list[str] = []
        self.links: list[str] = []
        self.opened: list[str] = []
        self.anchor: str | None = None
        self.feed(text)

    def handle_endtag(self, tag: str) -> None:
        if tag == "a":
            self.anchor = None

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag == "img":
            self.images.append({**dict(attrs), "href": self.anchor})
        if tag == "a":
            self.anchor = dict(attrs).get("href")
        if tag in ("details", "figure", "table"):
            self.opened.append(tag)
        for key, value in attrs:
            if key in ("href", "src") and value and not value.startswith("data:"):
                self.links.append(value)
        if tag in ("script", "link", "iframe"):
            self.links.append(tag)

    def handle_data(self, data: str) -> None:
        if data.strip():
            self.text.append(data.strip())


def svg_of(image: dict[str, str | None]) -> ET.Element:
    source = image["src"] or ""
    assert source.startswith("data:image/svg+xml;base64,")
    return ET.fromstring(base64.b64decode(source.split(",", 1)[1]))


def test_the_page_is_self_contained_and_shows_the_best_of_each_run(factory_run):
    run = read_run(factory_run)
    text = report_html(run)
    page = Page(text)
    assert not {"script", "link", "iframe"} & set(page.links)  # no scripts, stylesheets or frames
    assert all(not link.startswith(("http:", "https:", "//")) for link in page.links)  # nothing remote
    gallery = [image for image in page.images if (image.get("alt") or "").startswith("run ")]
    assert len(run.scenarios) == 8 and len(gallery) == len(run.runs) == 2  # rank 1 of each run
    assert [(image.get("alt") or "").split(" · ")[0] for image in gallery] == ["run 1, #1", "run 2, #1"]
    for image in gallery:
        assert list(svg_of(image).iter(f"{SVG}polygon"))  # a scenario drawing, elements and all
    charts = [image for image in page.images if image not in gallery]
    assert [image.get("alt") for image in charts] == ["fitness per generation", "distributions"]
    for chart in charts:
        assert svg_of(chart).iter(f"{SVG}path")
    # Every best scenario is a table row linked to its picture and JSON file.
    for _, saved in run.scenarios:
        for suffix in (".svg", ".json"):
            assert saved.file.with_suffix(suffix).relative_to(factory_run).as_posix() in page.links
    # The settings: the arena, evolution and fitness from the spec.
    assert "size 1400 x 1050 cm" in text and "population 80" in text and "overlap penalty 0.5" in text


def test_the_best_scenarios_are_grouped_by_their_canonical_class(factory_run):
    """Each best scenario is in one group of the distinct-tests table, whose class is its own."""
    import mazegen

    text = report_html(read_run(factory_run))
    table = text[text.index("Distinct tests") :]
    table = table[: table.index("</table>")]
    found = mazegen.classes(factory_run)
    assert f"{len(found.groups)} distinct tests among {len(found.floors)} scenarios" in table
    for group in found.groups:
        assert f"<code>{html.escape(group.key)}</code>" in table
    assert table.count("<tr>") == 1 + len(found.groups)


def test_the_page_is_deterministic(factory_run):
    assert report_html(read_run(factory_run)) == report_html(read_run(factory_run))


def test_statistics_per_run_and_generation(factory_run):
    run = read_run(factory_run)
    best = statistic_table(run, "best")
    assert best.shape == (2, 4)
    rows = [r for r in run.stats if r["run"] == "2" and r["generation"] == "3"]
    assert best[1, 3] == float(rows[0]["best"])
    assert (np.diff(best, axis=1) >= 0).all()  # elitism: the best never drops


def test_not_a_run_directory(tmp_path):
    with pytest.raises(MazeError, match="not a run directory"):
        read_run(tmp_path)


@pytest.mark.parametrize(
    ("name", "what"), [("experiment.json", "experiment.json"), ("experiment/spec.json", "spec.json")]
)
def test_a_run_file_nested_too_deeply_is_one_line(factory_run, tmp_path, name, what):
    run = shutil.copytree(factory_run, tmp_path / "run")
    (run / name).write_text("[" * 100_000)  # deeper than the JSON parser can go
    with pytest.raises(MazeError, match=f"damaged {what}: nested too deeply"):
        read_run(run)


@pytest.mark.skipif(
    shutil.which("chromium") is None,
    reason="chromium is not installed (Debian: chromium; .ci/run installs it)",
)
def test_headless_chromium_shows_the_gallery(factory_run, tmp_path):
    page = tmp_path / "report.html"
    page.write_text(report_html(read_run(factory_run)), encoding="utf-8")
    shot = tmp_path / "shot.png"
    done = subprocess.run(
        [
            "chromium",
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            f"--user-data-dir={tmp_path / 'profile'}",
            "--hide-scrollbars",
            "--window-size=1200,1800",
            f"--screenshot={shot}",
            page.as_uri(),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0 and shot.is_file(), done.stderr
    image = np.asarray(Image.open(io.BytesIO(shot.read_bytes())).convert("RGB"), dtype=int)
    r, g, b = image.transpose(2, 0, 1)
    # The robots' paths (magenta) appear only in the gallery's drawings, below the settings.
    path = (r > 200) & (g < 80) & (b > 90) & (b < 170)
    rows = np.nonzero(path.any(axis=1))[0]
    assert path.sum() > 500 and rows.min() > 300
    # The start (green) of every drawing in view, and its legend's dot (paths may cross the marker).
    start = (abs(r - 44) < 30) & (abs(g - 160) < 30) & (abs(b - 44) < 30)
    assert start.sum() > 60


def test_run_times_come_from_timing_csv_when_stats_have_none(factory_run, tmp_path):
    run = tmp_path / "run"
    shutil.copytree(factory_run, run)
    timings = list(csv.DictReader((run / "timing.csv").open()))
    expected = {n: sum(float(r["seconds"]) for r in timings if r["run"] == str(n)) for n in (1, 2)}
    assert read_run(run).seconds == pytest.approx(expected)
    (run / "timing.csv").unlink()
    assert read_run(run).seconds == {}
    # Run directories written before timing.csv kept the seconds in a last column of stats.csv.
    rows = list(csv.DictReader((run / "stats.csv").open()))
    with (run / "stats.csv").open("w", newline="") as out:
        writer = csv.DictWriter(out, fieldnames=[*rows[0], "seconds"])
        writer.writeheader()
        writer.writerows({**row, "seconds": timing["seconds"]} for row, timing in zip(rows, timings))
    assert read_run(run).seconds == pytest.approx(expected)


def test_run_times_keep_their_digits(factory_run, tmp_path):
    # A run of a sweep's tiny cells takes a few milliseconds, shown as "0.00" seconds.
    run = tmp_path / "run"
    shutil.copytree(factory_run, run)
    rows = list(csv.DictReader((run / "timing.csv").open()))
    with (run / "timing.csv").open("w", newline="") as out:
        writer = csv.DictWriter(out, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows({**row, "seconds": "0.0004" if row["run"] == "1" else "123.456"} for row in rows)
    (runs,) = [table for table in report_html(read_run(run)).split("<table>") if "<th>seconds</th>" in table]
    seconds = [row.split("<td>")[-1].split("</td>")[0] for row in runs.split("</table>")[0].split("<tr>")[2:]]
    assert seconds == ["0.0016", "494"]  # four generations each


def test_element_counts_all_alike_get_whole_ticks():
    documents = [{"elements": [{}] * 16, "metrics": {"difficulty": 10.0 * n}} for n in range(1, 4)]
    chart = ET.fromstring(distribution_chart(documents))
    numbers = [t.text or "" for t in chart.iter(f"{SVG}text") if re.fullmatch(r"[\d.]+", t.text or "")]
    assert "16" in numbers
    assert all(number.isdigit() for number in numbers), numbers  # not 15.6, 15.8 ... 16.4


def test_settings_are_written_as_the_language_writes_them(factory_run):
    text = report_html(read_run(factory_run))
    for words in ("codons 0..255", "selection truncation 0.1", "solvable required", "outside penalty 1"):
        assert words in text
    for field in ("codon_max", "tournament", "solvable reject", "truncation 0.1,"):
        assert field not in text  # spec.json's names, and settings that do not apply


def test_settings_words_read_back_as_written(write_spec):
    terms = [
        "count weight 2",
        "overlap reject",
        "size limit 300 penalty 0.5",
        "outside allow",
        "solvable penalty 3",
        "difficulty target hard",
        "tortuosity 1.4..2 weight 0.5",
        "diversity entropy",
        "coverage 0.1..0.3",
    ]
    settings = [
        "population 60", "generations 2", "genome 16", "selection tournament 4",
        "crossover onepoint within genome 0.8", "mutation within genome 0.1", "elitism 2", "runs 3", "seed 7",
        "codons 0..1000", "wraps 1", "consume lazy", "best 5",
    ]  # fmt: skip
    spec = mazegen.load(
        write_spec(
            "import manufacturing\n"
            "arena floor { size 1400 x 1050 cm  start (60, 60)  goal (1340, 990)  robot radius 25 }\n"
            "scenario s on floor { elements cobot, router }\n"
            "fitness {\n" + "\n".join(terms) + "\n}\n"
            "evolution {\n" + "\n".join(settings) + "\n}\n"
        )
    )
    assert [term_words(term) for term in spec.fitness] == terms
    assert evolution_words(spec.evolution) == settings
    assert "selection truncation 0.25" in evolution_words(Evolution(truncation=0.25))
    assert not any("tournament" in words for words in evolution_words(Evolution(truncation=0.25)))


def test_thumbnails_are_readable_and_link_to_the_picture_and_json(factory_run, tmp_path):
    out = tmp_path / "elsewhere" / "page.html"
    result = CliRunner().invoke(main, ["report", str(factory_run), "-o", str(out)], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    page = Page(out.read_text(encoding="utf-8"))
    gallery = [image for image in page.images if (image.get("alt") or "").startswith("run ")]
    assert gallery
    for image in gallery:
        drawing = svg_of(image)
        assert max(int(drawing.get("width", "0")), int(drawing.get("height", "0"))) == THUMBNAIL_PIXELS
        sizes = [float(t.get("font-size", "0")) for t in drawing.iter(f"{SVG}text")]
        assert min(sizes) >= 10  # pixels, as drawn at its size in the page
        target = out.parent / (image.get("href") or "")  # the drawing links to the full picture
        assert target.suffix == ".svg" and target.resolve().is_file()
    assert all((out.parent / link).resolve().is_file() for link in page.links)  # relative to the page


def test_a_metrics_table_and_a_folded_long_phenotype_per_scenario(factory_run, tmp_path):
    run = tmp_path / "run"
    shutil.copytree(factory_run, run)
    best = run / "run-01" / "best-01.json"
    document = json.loads(best.read_text())
    document["phenotype"] = "cobot(" * 60 + ")" * 60
    best.write_text(json.dumps(document))
    text = report_html(read_run(run))
    page = Page(text)
    assert page.opened.count("figure") == 2
    assert page.opened.count("details") == 1  # the long phenotype only
    assert "phenotype, 420 characters" in page.text
    for row in ("term count", "term overlap", "metric solvable", "metric path_length", "metric difficulty"):
        assert page.text.count(row) == 2  # in the table of each scenario shown
    assert phenotype_html("cobot(router)") == "<code>cobot(router)</code>"


def test_a_report_of_many_runs_draws_one_scenario_per_run(tmp_path):
    spec = mazegen.load(EXAMPLES / "factory.maze")
    out = tmp_path / "run"
    mazegen.run(spec, runs=15, population=30, generations=1, out_dir=out, executor="serial")
    run = read_run(out)
    assert len(run.scenarios) > 100  # up to 10 a run
    page = Page(report_html(run))
    drawings = [image for image in page.images if (image.get("alt") or "").startswith("run ")]
    assert len(drawings) == 15
    assert len({link for link in page.links if link.endswith(".json")}) == len(run.scenarios)  # a row each


def test_a_suite_folder(factory, tmp_path):
    archive = fill_archive(factory, seed=1, iterations=2, batch=100)
    documents = suite_documents(factory, archive, 3, seed=1)
    settings = SuiteSettings(seed=1, iterations=2, batch=100, size=3)
    write_suite(tmp_path / "suite", factory, archive, documents, settings, force=False)
    result = CliRunner().invoke(main, ["report", str(tmp_path / "suite")], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    text = (tmp_path / "suite" / "report.html").read_text(encoding="utf-8")
    page = Page(text)
    drawings = [image for image in page.images if (image.get("alt") or "").startswith("scenario ")]
    assert len(drawings) == len(documents) == 3
    assert [image.get("alt") for image in page.images if image not in drawings] == ["archive"]
    assert "scenario-03.json" in page.links and "codons 0..255" in text


def test_a_sweep_folder(tmp_path):
    out = tmp_path / "sweep"
    args = ["sweep", str(EXAMPLES / "factory.maze"), "--set", "population=30,40", "--set", "generations=1"]
    result = CliRunner().invoke(main, [*args, "--runs", "2", "--executor", "serial", "-o", str(out)])
    assert result.exit_code == 0, result.output
    result = CliRunner().invoke(main, ["report", str(out)], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    page = Page((out / "report.html").read_text(encoding="utf-8"))
    cells = sorted(path.name for path in out.iterdir() if (path / "experiment.json").is_file())
    assert len(cells) == 2
    for cell in cells:  # a section per cell, its settings apart, every best scenario linked
        assert cell in page.text
        assert f"{cell}/run-02/best-01.svg" in page.links
    assert "population 30" in page.text and "population 40" in page.text
    drawings = [image for image in page.images if (image.get("alt") or "").startswith("run ")]
    assert len(drawings) == 2  # the fittest scenario of each cell


def test_a_suite_report_shows_the_settings_the_suite_used(tmp_path):
    suite = tmp_path / "suite"
    args = ["suite", str(EXAMPLES / "factory.maze"), "--size", "2", "--seed", "5", "--iterations", "1"]
    result = CliRunner().invoke(main, [*args, "--batch", "60", "-q", "-o", str(suite)])
    assert result.exit_code == 0, result.output
    assert CliRunner().invoke(main, ["report", str(suite)]).exit_code == 0
    text = Page((suite / "report.html").read_text(encoding="utf-8")).text
    settings = text[text.index("Settings") : text.index("Archive")]
    for row in (["seed", "5"], ["iterations", "1"], ["batch", "60"], ["size", "2"]):
        assert row in [settings[i : i + 2] for i in range(len(settings))]  # the suite's table
    blocks = "\n".join(settings)
    for used in ("genome 32", "crossover variable within used 0.9", "codons 0..255", "wraps 0", "consume"):
        assert used in blocks
    for unused in ("population", "generations", "selection", "elitism", "runs", "best", "seed 1"):
        assert unused not in blocks  # the spec's, which the suite did not use


def test_a_sweep_of_two_specs_is_named_after_both(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    specs = [str(EXAMPLES / "factory.maze"), str(EXAMPLES / "table1" / "exp3.maze")]
    args = ["sweep", *specs, "--set", "population=30", "--set", "generations=1", "--runs", "1"]
    result = CliRunner().invoke(main, [*args, "--executor", "serial", "-q"])
    assert result.exit_code == 0, result.output
    out = tmp_path / "sweeps" / "factory+table1_exp3"
    assert result.output.splitlines()[-1] == f"wrote {out.relative_to(tmp_path)}"
    assert (out / "catalog.sqlite").is_file()
    assert CliRunner().invoke(main, ["report", str(out)]).exit_code == 0
    page = (out / "report.html").read_text(encoding="utf-8")
    assert "<h1>MazeGen sweep: factory+table1_exp3</h1>" in page
    assert "2 finished cells of the scenarios factory, table1_exp3" in page
    for scenario in ("scenario factory on floor {", "scenario table1_exp3 on canvas {"):
        assert scenario in page  # each spec's settings


def test_a_folder_of_something_else(tmp_path):
    result = CliRunner().invoke(main, ["report", str(tmp_path)])
    assert result.exit_code == 1
    assert "not a run, suite or sweep folder" in result.output


def test_scenario_words_of_grammar_placement_and_custom_rules(write_spec):
    placed = mazegen.load(EXAMPLES / "table1" / "exp1.maze")
    assert "placement grammar sizes 1..8 scale 50 positions 100..800 step 100" in scenario_words(
        placed.scenario
    )
    custom = mazegen.load(
        write_spec(
            "import manufacturing\n"
            "arena floor { size 1400 x 1050 cm  start (60, 60)  goal (1340, 990) }\n"
            'scenario s on floor { grammar custom { <scenario> ::= <cell> | <cell> ";" <scenario>\n'
            "<cell> ::= cobot | cobot router } }\n"
        )
    )
    words = scenario_words(custom.scenario)
    assert words[0] == "elements cobot, router" and words[1].startswith("grammar custom { ... }  // 2 rules")


def test_a_driven_scenario_shows_its_drive_table(factory_run, tmp_path):
    run = tmp_path / "run"
    shutil.copytree(factory_run, run)
    best = run / "run-01" / "best-01.json"
    document = json.loads(best.read_text())
    entry = {"outcome": "collision", "time": 4.25, "distance": 120.5, "clearance": 0.0, "optimal_time": 30.0}
    entry.update(score=0.0, stuck=False, collision=[100.0, 80.0], trajectory=[[60.0, 60.0, 0.0]])
    document["drive"] = {"straight": entry}
    best.write_text(json.dumps(document))
    page = Page(report_html(read_run(run)))
    assert page.opened.count("figure") == 2
    assert page.text.count("collision") == 1 and "4.25" in page.text and "120.5" in page.text
    assert report_html(read_run(factory_run)).count('class="drive"') == 0


def test_the_arena_words_of_a_map_and_zones_read_back_as_the_same_arena(tmp_path):
    """The report's words for examples/warehouse.maze's arena, written back as an arena block, are
    that arena: its map, tasks, robot, grid and every zone."""
    from mazegen.runtime.reports._spec_words import arena_words
    from tests.conftest import EXAMPLES

    spec = mazegen.load(EXAMPLES / "warehouse.maze")
    shutil.copytree(EXAMPLES / "maps", tmp_path / "maps")
    shutil.copytree(EXAMPLES / "plugins", tmp_path / "plugins")
    text = (EXAMPLES / "warehouse.maze").read_text()
    start = text.index("arena hall {")
    end = text.index("\n}\n", start) + len("\n}\n")
    block = "arena hall {\n    " + "\n    ".join(arena_words(spec.arena)) + "\n}\n"
    (tmp_path / "again.maze").write_text(text[:start] + block + text[end:])
    assert mazegen.load(tmp_path / "again.maze").arena == spec.arena
