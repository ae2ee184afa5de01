"""The HTML report of a run directory: self-contained, complete, and seen by a real browser."""

from __future__ import annotations

import base64
import csv
import html.parser
import io
import shutil
import subprocess
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from PIL import Image

from mazegen.errors import MazeError
from mazegen.runtime.report import read_run, report_html, statistic_table

SVG = "{http://www.w3.org/2000/svg}"


class Page(html.parser.HTMLParser):
    """The images, headings and table cells of a page."""

    def __init__(self, text: str) -> None:
        super().__init__()
        self.images: list[dict[str, str | None]] = []
        self.text: list[str] = []
        self.links: list[str] = []
        self.feed(text)

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag == "img":
            self.images.append(dict(attrs))
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


def test_the_page_is_self_contained_and_shows_every_best_scenario(factory_run):
    run = read_run(factory_run)
    page = Page(report_html(run))
    assert page.links == []  # nothing to fetch: no scripts, stylesheets or remote images
    gallery = [image for image in page.images if (image.get("alt") or "").startswith("run ")]
    assert len(gallery) == len(run.scenarios) == 8
    for image in gallery:
        assert list(svg_of(image).iter(f"{SVG}polygon"))  # a scenario drawing, elements and all
    assert "run 2, #4" in {(image.get("alt") or "").split(" · ")[0] for image in gallery}
    charts = [image for image in page.images if image not in gallery]
    assert [image.get("alt") for image in charts] == ["fitness per generation", "distributions"]
    for chart in charts:
        assert svg_of(chart).iter(f"{SVG}path")
    # The settings: evolution values and the arena from the spec.
    for expected in (
        "population",
        "80",
        "generations",
        "3",
        "1400.0 x 1050.0 cm",
        "fitness: overlap",
        "weight 0.5",
    ):
        assert expected in page.text


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
    # The start (green) of every drawing in view.
    start = (abs(r - 44) < 30) & (abs(g - 160) < 30) & (abs(b - 44) < 30)
    assert start.sum() > 100


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
