"""Tests of the SVG and PNG drawings of a scenario document."""

from __future__ import annotations

import io
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from mazegen.errors import MazeError
from mazegen.runtime.render import render_file, scenario_png, scenario_svg

SVG = "{http://www.w3.org/2000/svg}"


def square(cx: float, cy: float, half: float) -> list[list[float]]:
    """A counter-clockwise square part around (cx, cy)."""
    return [[cx - half, cy - half], [cx + half, cy - half], [cx + half, cy + half], [cx - half, cy + half]]


def element(kind: str, colour: str, *parts: list[list[float]]) -> dict:
    return {
        "type": kind,
        "class": "thing",
        "colour": colour,
        "height": 50.0,
        "x": parts[0][0][0],
        "y": parts[0][0][1],
        "rotation": 0.0,
        "size": 10.0,
        "parts": list(parts),
    }


def document(*elements: dict, width: float = 1400.0, height: float = 1050.0, name: str = "factory") -> dict:
    return {
        "format": "mazegen-scenario",
        "version": 1,
        "scenario": name,
        "arena": {
            "name": "floor",
            "width": width,
            "height": height,
            "unit": "cm",
            "start": [60.0, 60.0],
            "goal": [width - 60.0, height - 60.0],
            "robot_radius": 25.0,
        },
        "elements": list(elements),
        "phenotype": "x",
        "fitness": 4.0,
        "terms": {},
        "valid": True,
        "origin": {},
    }


@pytest.fixture
def doc() -> dict:
    return document(
        element("cobot", "#e4572e", square(300, 900, 60)),  # near the top
        element("cobot", "#e4572e", square(300, 150, 60)),  # near the bottom
        element("router", "#1f77b4", square(1000, 500, 40), square(1100, 500, 20)),
    )


def polygons(svg: str) -> list[ET.Element]:
    return ET.fromstring(svg).findall(f"{SVG}polygon")


def centre_y(polygon: ET.Element) -> float:
    ys = [float(p.split(",")[1]) for p in polygon.get("points", "").split()]
    return sum(ys) / len(ys)


def texts(svg: str) -> list[str]:
    return [t.text or "" for t in ET.fromstring(svg).iter(f"{SVG}text")]


def test_svg_parses_and_has_one_polygon_per_part(doc: dict) -> None:
    svg = scenario_svg(doc)
    root = ET.fromstring(svg)
    assert root.tag == f"{SVG}svg"
    assert svg.endswith("</svg>\n")
    assert len(polygons(svg)) == 4
    assert [p.get("fill") for p in polygons(svg)] == ["#e4572e", "#e4572e", "#1f77b4", "#1f77b4"]


def test_svg_size_keeps_aspect_with_longest_side_pixels(doc: dict) -> None:
    wide = ET.fromstring(scenario_svg(doc, pixels=640))
    assert int(wide.get("width", "0")) == 640 and int(wide.get("height", "0")) < 640
    tall = ET.fromstring(scenario_svg(document(width=500.0, height=2000.0), pixels=640))
    assert int(tall.get("height", "0")) == 640 and int(tall.get("width", "0")) < 640


def test_svg_flips_y(doc: dict) -> None:
    top, bottom = polygons(scenario_svg(doc))[:2]
    assert centre_y(top) < centre_y(bottom)
    circles = ET.fromstring(scenario_svg(doc)).findall(f"{SVG}circle")
    start, goal = circles[0], circles[1]
    assert float(goal.get("cy", "0")) < float(start.get("cy", "0"))
    assert float(goal.get("cx", "0")) > float(start.get("cx", "0"))


def test_svg_escapes_hostile_text(doc: dict) -> None:
    doc["elements"].append(element("<script>", "#123456", square(700, 500, 30)))
    doc["scenario"] = 'a"&<b>\x00'
    svg = scenario_svg(doc)
    assert "<script>" not in svg and "<b>" not in svg
    assert "&lt;script&gt; (1)" in svg
    assert any(t.startswith("<script>") for t in texts(svg))  # parsed back to the raw name
    assert any(t.startswith('a"&<b>') for t in texts(svg))


def test_legend_counts_each_type(doc: dict) -> None:
    legend = texts(scenario_svg(doc))
    assert "cobot (2)" in legend and "router (1)" in legend
    assert "start" in legend and "goal" in legend


def test_title_and_scale_bar(doc: dict) -> None:
    labels = texts(scenario_svg(doc))
    assert "factory | 3 elements | fitness 4" in labels
    assert "200 cm" in labels  # 1400 / 4 = 350 -> 200


def test_svg_is_deterministic(doc: dict) -> None:
    assert scenario_svg(doc) == scenario_svg(dict(doc))


def test_png_size_colour_and_free_space(doc: dict) -> None:
    data = scenario_png(doc, pixels=600)
    assert data == scenario_png(doc, pixels=600)
    image = Image.open(io.BytesIO(data)).convert("RGB")
    assert max(image.size) == 600
    svg = ET.fromstring(scenario_svg(doc, pixels=600))
    assert image.size == (int(svg.get("width", "0")), int(svg.get("height", "0")))
    points = [
        tuple(map(float, p.split(",")))
        for p in polygons(scenario_svg(doc, pixels=600))[0].get("points", "").split()
    ]
    cx = round(sum(x for x, _ in points) / 4)
    cy = round(sum(y for _, y in points) / 4)
    r, g, b = image.getpixel((cx, cy))
    assert r > 200 and 100 < g < 200 and 90 < b < 180  # #e4572e blended on white
    arena = svg.findall(f"{SVG}rect")[1]
    free = (round(float(arena.get("x", "0"))) + 200, round(float(arena.get("y", "0"))) + 30)
    assert image.getpixel(free) == (255, 255, 255)


def test_render_file_writes_both_formats(doc: dict, tmp_path: Path) -> None:
    render_file(doc, tmp_path / "a.svg")
    render_file(doc, tmp_path / "a.PNG")
    assert (tmp_path / "a.svg").read_text(encoding="utf-8") == scenario_svg(doc)
    assert (tmp_path / "a.PNG").read_bytes() == scenario_png(doc)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.PNG", "a.svg"]


def test_render_file_rejects_other_suffix(doc: dict, tmp_path: Path) -> None:
    with pytest.raises(MazeError, match=r"\.svg or \.png"):
        render_file(doc, tmp_path / "a.jpg")
    assert not list(tmp_path.iterdir())


def test_bad_document_is_a_maze_error() -> None:
    with pytest.raises(MazeError):
        scenario_svg({"format": "something-else", "version": 1})
    bad = document(element("cobot", "#e4572e", [[0, 0], [1, 1]]))
    with pytest.raises(MazeError, match="three vertices"):
        scenario_png(bad)


def test_path_is_drawn_over_the_elements_and_named_in_the_legend(doc: dict) -> None:
    doc["path"] = [[60.0, 60.0], [700.0, 60.0], [1340.0, 990.0]]
    root = ET.fromstring(scenario_svg(doc))
    (line,) = root.findall(f"{SVG}polyline")
    points = [tuple(map(float, p.split(","))) for p in line.get("points", "").split()]
    circles = root.findall(f"{SVG}circle")
    start, goal = circles[0], circles[1]
    assert points[0] == pytest.approx((float(start.get("cx", "0")), float(start.get("cy", "0"))), abs=0.01)
    assert points[-1] == pytest.approx((float(goal.get("cx", "0")), float(goal.get("cy", "0"))), abs=0.01)
    assert points[1][1] == pytest.approx(points[0][1])  # the first leg runs along y = 60
    children = list(root)
    assert children.index(line) > max(children.index(p) for p in root.findall(f"{SVG}polygon"))
    assert line.get("fill") == "none" and line.get("stroke") == "#e6007e"
    assert "path (1769 cm)" in texts(scenario_svg(doc))  # 640 + hypot(640, 930) = 1768.9


def test_png_shows_the_path(doc: dict) -> None:
    def magenta(data: bytes) -> int:
        r, g, b = np.asarray(Image.open(io.BytesIO(data)).convert("RGB"), dtype=int).transpose(2, 0, 1)
        return int(((r > 200) & (g < 60) & (b > 90) & (b < 160)).sum())

    without = magenta(scenario_png(doc))
    doc["path"] = [[60.0, 60.0], [1340.0, 990.0]]
    assert magenta(scenario_png(doc)) > without + 300


def test_no_path_no_polyline(doc: dict) -> None:
    doc["path"] = None
    assert not ET.fromstring(scenario_svg(doc)).findall(f"{SVG}polyline")
    assert not any(t.startswith("path") for t in texts(scenario_svg(doc)))
