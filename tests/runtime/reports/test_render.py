"""Tests of the SVG and PNG drawings of a scenario document."""

from __future__ import annotations

import io
import itertools
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import cast

import numpy as np
import pytest
from PIL import Image

from mazegen.errors import MazeError
from mazegen.runtime.reports._picture import layout
from mazegen.runtime.reports._render import render_file, scenario_png, scenario_svg
from mazegen.runtime.reports._scene import parse

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
    return list(ET.fromstring(svg).iter(f"{SVG}polygon"))


def centre_y(polygon: ET.Element) -> float:
    ys = [float(p.split(",")[1]) for p in polygon.get("points", "").split()]
    return sum(ys) / len(ys)


def texts(svg: str) -> list[str]:
    return [t.text or "" for t in ET.fromstring(svg).iter(f"{SVG}text")]


def test_svg_parses_and_has_one_shape_per_element(doc: dict) -> None:
    svg = scenario_svg(doc)
    root = ET.fromstring(svg)
    assert root.tag == f"{SVG}svg"
    assert svg.endswith("</svg>\n")
    shapes = [shape for shape in root.iter() if shape.tag in (f"{SVG}polygon", f"{SVG}path")]
    kinds = [shape.tag.removeprefix(SVG) for shape in shapes]
    assert kinds == ["polygon", "polygon", "path"]  # the router's two squares apart: one path
    assert [shape.get("fill") for shape in shapes] == ["#e4572e", "#e4572e", "#1f77b4"]


def test_svg_size_keeps_aspect_with_longest_side_pixels(doc: dict) -> None:
    wide = ET.fromstring(scenario_svg(doc, pixels=640))
    assert int(wide.get("width", "0")) == 640 and int(wide.get("height", "0")) < 640
    tall = ET.fromstring(scenario_svg(document(width=500.0, height=2000.0), pixels=640))
    assert int(tall.get("height", "0")) == 640 and int(tall.get("width", "0")) < 640


def test_svg_flips_y(doc: dict) -> None:
    top, bottom = polygons(scenario_svg(doc))[:2]
    assert centre_y(top) < centre_y(bottom)
    circles = list(ET.fromstring(scenario_svg(doc)).iter(f"{SVG}circle"))
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
    (line,) = root.iter(f"{SVG}polyline")
    points = [tuple(map(float, p.split(","))) for p in line.get("points", "").split()]
    circles = list(root.iter(f"{SVG}circle"))
    start, goal = circles[0], circles[1]
    assert points[0] == pytest.approx((float(start.get("cx", "0")), float(start.get("cy", "0"))), abs=0.01)
    assert points[-1] == pytest.approx((float(goal.get("cx", "0")), float(goal.get("cy", "0"))), abs=0.01)
    assert points[1][1] == pytest.approx(points[0][1])  # the first leg runs along y = 60
    drawn = list(root.iter())
    assert drawn.index(line) > max(drawn.index(p) for p in root.iter(f"{SVG}polygon"))
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
    assert not list(ET.fromstring(scenario_svg(doc)).iter(f"{SVG}polyline"))
    assert not any(t.startswith("path") for t in texts(scenario_svg(doc)))


def frame_of(svg: str) -> tuple[float, float, float, float]:
    """The arena's frame (x0, y0, x1, y1): the white rect drawn under the elements."""
    arena = ET.fromstring(svg).findall(f"{SVG}rect")[1]
    assert arena.get("fill") == "#ffffff"
    x, y = float(arena.get("x", "0")), float(arena.get("y", "0"))
    return x, y, x + float(arena.get("width", "0")), y + float(arena.get("height", "0"))


def pixels_of(data: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(data)).convert("RGB"), dtype=int)


def test_elements_are_clipped_to_the_arena_in_svg(doc: dict) -> None:
    doc["elements"].append(element("huge", "#0000ff", square(700, 525, 5000)))  # covers the whole picture
    svg = scenario_svg(doc)
    root = ET.fromstring(svg)
    groups = [g for g in root.iter(f"{SVG}g") if g.findall(f"{SVG}polygon")]
    assert len(groups) == 1 and len(groups[0].findall(f"{SVG}polygon")) == 3  # the router is a path
    assert len(groups[0].findall(f"{SVG}path")) == 1  # every element, in one group
    reference = groups[0].get("clip-path", "")
    assert reference.startswith("url(#") and reference.endswith(")")
    (clip,) = [c for c in root.iter(f"{SVG}clipPath") if c.get("id") == reference[5:-1]]
    (rect,) = clip.findall(f"{SVG}rect")
    x, y = float(rect.get("x", "0")), float(rect.get("y", "0"))
    box = (x, y, x + float(rect.get("width", "0")), y + float(rect.get("height", "0")))
    assert box == pytest.approx(frame_of(svg), abs=0.01)
    # The start, goal and path are inside the arena's clipped group too; title and legend are not.
    doc["path"] = [[60.0, 60.0], [1340.0, 990.0]]
    root = ET.fromstring(scenario_svg(doc))
    clipped = [g for g in root.iter(f"{SVG}g") if g.get("clip-path")]
    inside = {child.tag for g in clipped for child in g}
    assert {f"{SVG}polygon", f"{SVG}polyline", f"{SVG}circle"} <= inside
    assert not any(child.tag == f"{SVG}text" for g in clipped for child in g if g.get("class") == "elements")


def test_elements_are_clipped_to_the_arena_in_png(doc: dict) -> None:
    doc["elements"].append(element("huge", "#0000ff", square(700, 525, 5000)))
    image = pixels_of(scenario_png(doc, pixels=600))
    svg = scenario_svg(doc, pixels=600)
    x0, y0, x1, y1 = (round(v) for v in frame_of(svg))
    r, g, b = image.transpose(2, 0, 1)
    blue = (b > 150) & (r < 140) & (g < 140)  # #0000ff blended on white or paper
    inside = np.zeros_like(blue)
    inside[y0 - 2 : y1 + 3, x0 - 2 : x1 + 3] = True  # the frame's line and its antialiasing
    children = list(ET.fromstring(svg))
    (swatch,) = [a for a, b in itertools.pairwise(children) if b.text == "huge (1)"]
    sx, sy = round(float(swatch.get("x", "0"))), round(float(swatch.get("y", "0")))
    inside[sy - 2 : sy + 20, sx - 2 : sx + 20] = True  # the legend's swatch of the huge element
    assert blue[inside].sum() > 0.5 * (x1 - x0) * (y1 - y0)
    assert blue[~inside].sum() == 0  # the title, legend text, axes and scale bar stay visible


def cie_lab(colour: tuple[float, float, float]) -> tuple[float, float, float]:
    """CIE L*a*b* (D65) of an sRGB colour given as 0..255 channels."""

    def linear(c: float) -> float:
        c /= 255
        return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4

    r, g, b = (linear(c) for c in colour)
    xyz = (
        (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047,
        0.2126 * r + 0.7152 * g + 0.0722 * b,
        (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883,
    )
    fx, fy, fz = (t ** (1 / 3) if t > 216 / 24389 else (24389 / 27 * t + 16) / 116 for t in xyz)
    return 116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)


def seen(node: ET.Element, colour_key: str = "fill") -> tuple[float, float, float]:
    """The colour a swatch shows: its colour over white at its opacity."""
    hex_colour = node.get(colour_key, "")
    opacity = float(node.get(f"{colour_key}-opacity", "1"))
    channels = (int(hex_colour[i : i + 2], 16) for i in (1, 3, 5))
    return cast(tuple[float, float, float], tuple(255 - opacity * (255 - c) for c in channels))


def test_every_bundled_type_has_its_own_colour_in_the_legend(tmp_path: Path) -> None:
    import mazegen
    from mazegen.dsl.loader import LIBRARY_DIR, bundled_libraries

    names = []
    for library in bundled_libraries():
        text = (LIBRARY_DIR / f"{library}.maze").read_text(encoding="utf-8")
        names += re.findall(r"^element (\w+)", text, flags=re.MULTILINE)
    assert len(names) >= 10
    spec_file = tmp_path / "all.maze"
    spec_file.write_text(
        "".join(f"import {library}\n" for library in bundled_libraries())
        + "arena a { size 1400 x 1050 cm  start (60, 60)  goal (1340, 990) }\n"
        + f"scenario s on a {{ elements {', '.join(names)} }}\n",
        encoding="utf-8",
    )
    spec = mazegen.load(spec_file)
    doc = document(
        *(
            element(name, spec.element(name).colour, square(100 + 120 * i, 500, 40))
            for i, name in enumerate(names)
        )
    )
    doc["path"] = [[60.0, 60.0], [1340.0, 990.0]]
    svg = scenario_svg(doc)
    legend_x = frame_of(svg)[2]
    swatches = {}
    for swatch, text in itertools.pairwise(ET.fromstring(svg)):
        label = text.text or ""
        in_legend = text.tag == f"{SVG}text" and float(text.get("x", "0")) > legend_x
        if in_legend and swatch.tag in (f"{SVG}rect", f"{SVG}circle", f"{SVG}line"):
            key = "stroke" if swatch.tag == f"{SVG}line" else "fill"
            swatches[label.split(" (")[0]] = seen(swatch, key)
    assert set(swatches) == {*names, "start", "goal", "path"}
    # The drawing uses the legend's colours.
    fills = {p.get("fill") for p in polygons(scenario_svg(doc))}
    assert fills == {mazegen_colour(spec.element(name).colour) for name in names}
    close = [
        (a, b, round(math.dist(cie_lab(swatches[a]), cie_lab(swatches[b])), 1))
        for a, b in itertools.combinations(sorted(swatches), 2)
        if math.dist(cie_lab(swatches[a]), cie_lab(swatches[b])) < 20  # CIE76 ΔE: 2.3 is just noticeable
    ]
    assert close == []


def mazegen_colour(colour: str) -> str:
    from mazegen.runtime.reports._render import rgb

    return "#{:02x}{:02x}{:02x}".format(*rgb(colour))


def unsolvable(doc: dict) -> dict:
    doc["metrics"] = {"solvable": False, "difficulty": None}
    doc["path"] = None
    return doc


def test_no_path_mark_iff_the_floor_is_unsolvable(doc: dict) -> None:
    def marks(d: dict) -> int:
        root = ET.fromstring(scenario_svg(d))
        groups = [g for g in root.iter(f"{SVG}g") if g.get("class") == "no-path"]
        if groups:
            assert groups[0].get("clip-path")  # inside the arena, like the elements
            assert "no path" in [t.text for t in groups[0].iter(f"{SVG}text")]
            assert "no path" in texts(scenario_svg(d))  # and in the legend
        return len(groups)

    assert marks(doc) == 0  # no metrics: nothing known
    doc["metrics"] = {"solvable": True}
    doc["path"] = [[60.0, 60.0], [1340.0, 990.0]]
    assert marks(doc) == 0 and "no path" not in texts(scenario_svg(doc))
    assert marks(unsolvable(doc)) == 1
    assert not list(ET.fromstring(scenario_svg(doc)).iter(f"{SVG}polyline"))


def test_png_shows_the_no_path_mark(doc: dict) -> None:
    def black_in_arena(d: dict) -> int:
        x0, y0, x1, y1 = (round(v) for v in frame_of(scenario_svg(d, pixels=600)))
        image = pixels_of(scenario_png(d, pixels=600))[y0 + 3 : y1 - 2, x0 + 3 : x1 - 2]
        return int((image.max(axis=2) < 60).sum())

    doc["metrics"] = {"solvable": True}
    solvable = black_in_arena(doc)
    assert black_in_arena(unsolvable(doc)) > solvable + 300


def test_axes_have_ticks_in_the_arena_unit(doc: dict) -> None:
    svg = scenario_svg(doc)
    x0, _, x1, y1 = frame_of(svg)
    labels = [t for t in ET.fromstring(svg).iter(f"{SVG}text") if re.fullmatch(r"\d+", t.text or "")]
    below = [t for t in labels if float(t.get("y", "0")) > y1 and t.get("text-anchor") == "middle"]
    left = [t for t in labels if float(t.get("x", "0")) < x0 and t.get("text-anchor") == "end"]
    xs = [int(t.text or "") for t in below]
    ys = [int(t.text or "") for t in left]
    assert xs == list(range(0, 1401, 200)) and ys == list(range(0, 1001, 200))
    k = (x1 - x0) / 1400  # pixels per cm
    for t in below:  # each label sits under its coordinate
        assert float(t.get("x", "0")) == pytest.approx(x0 + k * int(t.text or ""), abs=0.01)
    for t in left:
        assert float(t.get("y", "0")) == pytest.approx(y1 - k * int(t.text or "") + 0.35 * 13, abs=0.01)
    assert "x, y in cm" in texts(svg)
    small = scenario_svg(document(width=3.0, height=2.0))
    fractions = [t for t in texts(small) if re.fullmatch(r"\d\.\d", t)]
    assert "0.0" in fractions and "2.5" in fractions and "3.0" in fractions


def test_any_css_colour_draws(doc: dict) -> None:
    doc["elements"].append(element("odd", "rgb(99999999999999999999,0,0)", square(700, 500, 30)))
    doc["elements"].append(element("odder", "hsv(400,400%,400%)", square(900, 500, 30)))
    doc["elements"].append(element("none", "x" * 100_000, square(1100, 500, 30)))
    assert scenario_png(doc)
    fills = [p.get("fill") for p in polygons(scenario_svg(doc))][-3:]
    assert fills == ["#ff0000", "#ff0000", "#555555"]


@pytest.mark.parametrize("width", [0.003, 3.0, 1400.0, 123456.0, 1e300])
def test_tick_labels_stay_short_and_apart(width: float) -> None:
    svg = scenario_svg(document(width=width, height=width * 0.75))
    x0, _, x1, y1 = frame_of(svg)
    below = [t for t in ET.fromstring(svg).iter(f"{SVG}text") if t.get("text-anchor") == "middle"]
    below = [t for t in below if float(t.get("y", "0")) > y1]
    assert len(below) >= 3
    assert all(len(t.text or "") <= 8 for t in below)
    xs = [float(t.get("x", "0")) for t in below]
    widest = max(len(t.text or "") for t in below) * 0.6 * 13  # pixels, about, at font size 13
    assert min(b - a for a, b in itertools.pairwise(xs)) > widest
    assert x0 - 1 <= xs[0] and xs[-1] <= x1 + 1


def driven(doc: dict) -> dict:
    """``doc`` driven by two controllers: ``straight`` collided at (700, 400), ``dwa`` arrived."""
    crash = [[60, 60, 0], [400, 300, 30], [700, 400, 30]]
    arrival = [[60, 60, 0], [700, 100, 0], [1340, 990, 50]]
    doc["drive"] = {
        "straight": {"outcome": "collision", "trajectory": crash, "collision": [700.0, 400.0]},
        "dwa": {"outcome": "arrived", "trajectory": arrival, "collision": None},
    }
    return doc


def test_each_controller_is_a_line_in_its_colour_named_in_the_legend_with_an_x_where_it_collided(
    doc: dict,
) -> None:
    svg = scenario_svg(driven(doc))
    root = ET.fromstring(svg)
    (group,) = [
        g for g in root.iter(f"{SVG}g") if g.get("class") == "drive" and g.find(f"{SVG}polyline") is not None
    ]
    lines = group.findall(f"{SVG}polyline")
    assert len(lines) == 2 and lines[0].get("stroke") != lines[1].get("stroke")
    x0, y0, x1, y1 = frame_of(svg)

    def at(x: float, y: float) -> tuple[float, float]:  # arena units to the picture's pixels, y down
        return x0 + (x1 - x0) * x / 1400, y1 - (y1 - y0) * y / 1050

    ends = [tuple(map(float, line.get("points", "").split()[-1].split(","))) for line in lines]
    assert ends[0] == pytest.approx(at(700, 400), abs=0.01) and ends[1] == pytest.approx(
        at(1340, 990), abs=0.01
    )
    cross = [g for g in root.iter(f"{SVG}g") if g.get("class") == "drive"][-1].findall(f"{SVG}line")
    assert len(cross) == 2 and {line.get("stroke") for line in cross} == {lines[0].get("stroke")}
    for line in cross:  # both strokes of the × are centred on the collision point, and cross there
        a = (float(line.get("x1", "0")), float(line.get("y1", "0")))
        b = (float(line.get("x2", "0")), float(line.get("y2", "0")))
        assert ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2) == pytest.approx(at(700, 400), abs=0.01)
    ends_of = [[float(line.get(key, "0")) for key in ("x1", "y1", "x2", "y2")] for line in cross]
    slopes = [(y2 - y1) / (x2 - x1) for x1, y1, x2, y2 in ends_of]
    assert sorted(slopes) == pytest.approx([-1.0, 1.0], abs=0.01)  # coordinates to 2 decimals
    assert {"straight: collision", "dwa: arrived"} <= set(texts(svg))


def test_a_document_without_a_drive_draws_no_trajectory(doc: dict) -> None:
    assert not [g for g in ET.fromstring(scenario_svg(doc)).iter(f"{SVG}g") if g.get("class") == "drive"]


def test_png_shows_each_trajectory(doc: dict) -> None:
    def blue(data: bytes) -> int:  # the first controller's colour, #1f77b4
        r, g, b = pixels_of(data).transpose(2, 0, 1)
        return int(((abs(r - 31) < 30) & (abs(g - 119) < 30) & (abs(b - 180) < 30)).sum())

    without = blue(scenario_png(doc))
    assert blue(scenario_png(driven(doc))) > without + 200


def pixel_at(svg: str, x: float, y: float) -> tuple[float, float]:
    """The picture's pixel (y down) of the point (x, y) of the fixtures' 1400 x 1050 arena."""
    x0, y0, x1, y1 = frame_of(svg)
    return x0 + (x1 - x0) * x / 1400, y1 - (y1 - y0) * y / 1050


def test_a_timed_out_trajectory_ends_in_a_square_and_the_legend_shows_how_each_drive_ended(
    doc: dict,
) -> None:
    doc = driven(doc)
    wander = [[60, 60, 0], [700, 100, 0], [900, 600, 1]]
    doc["drive"]["dwa"] = {"outcome": "timeout", "trajectory": wander, "collision": None}
    svg = scenario_svg(doc)
    root = ET.fromstring(svg)
    drive = [g for g in root.iter(f"{SVG}g") if g.get("class") == "drive"]
    straight, dwa = (line.get("stroke") for g in drive for line in g.findall(f"{SVG}polyline"))
    (square_mark,) = [rect for g in drive for rect in g.findall(f"{SVG}rect")]
    x, y = float(square_mark.get("x", "0")), float(square_mark.get("y", "0"))
    width, height = float(square_mark.get("width", "0")), float(square_mark.get("height", "0"))
    assert (x + width / 2, y + height / 2) == pytest.approx(pixel_at(svg, 900, 600), abs=0.02)
    assert width == pytest.approx(height) and width > 4
    assert square_mark.get("stroke") == dwa and square_mark.get("fill") == "none"
    # The legend: each controller's line ends in the mark its drive ended with (none for an arrival).
    children = list(root)
    row = {child.text: children[i - 3 : i] for i, child in enumerate(children) if child.tag == f"{SVG}text"}
    *_, line, mark = row["dwa: timeout"]
    assert line.tag == f"{SVG}line" and line.get("stroke") == dwa
    assert mark.tag == f"{SVG}rect" and mark.get("stroke") == dwa and mark.get("fill") == "none"
    assert float(mark.get("x", "0")) + float(mark.get("width", "0")) / 2 == pytest.approx(
        float(line.get("x2", "0")), abs=0.02
    )
    line, *cross = row["straight: collision"]
    assert [shape.tag for shape in (line, *cross)] == [f"{SVG}line"] * 3
    assert {shape.get("stroke") for shape in (line, *cross)} == {straight}
    doc["drive"]["dwa"]["outcome"] = "arrived"
    drive = [g for g in ET.fromstring(scenario_svg(doc)).iter(f"{SVG}g") if g.get("class") == "drive"]
    assert not [rect for g in drive for rect in g.iter(f"{SVG}rect")]  # an arrival has no mark


def bar(x0: float, y0: float, x1: float, y1: float) -> list[list[float]]:
    """A counter-clockwise rectangle part from (x0, y0) to (x1, y1)."""
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


def test_an_element_of_several_parts_is_one_outline_without_seams(doc: dict) -> None:
    corner = element("lshape", "#8c564b", bar(100, 500, 500, 560), bar(100, 500, 160, 900))  # overlapping
    frame = element(
        "frame", "#9467bd", bar(700, 300, 1100, 340), bar(1060, 300, 1100, 700), bar(700, 660, 1100, 700),
        bar(700, 300, 740, 700),
    )  # fmt: skip
    doc["elements"] = [corner, frame, doc["elements"][2]]  # and the router: two squares apart
    svg = scenario_svg(doc)
    (group,) = [g for g in ET.fromstring(svg).iter(f"{SVG}g") if g.get("class") == "elements"]
    outlines = [shape for shape in group if shape.tag in (f"{SVG}polygon", f"{SVG}path")]
    assert [shape.get("fill") for shape in outlines] == ["#8c564b", "#9467bd", "#1f77b4"]  # one shape each
    assert outlines[0].tag == f"{SVG}polygon" and len(outlines[0].get("points", "").split()) == 6  # an L
    for shape in outlines[1:]:  # the frame's outside and hole, the router's two squares
        assert shape.tag == f"{SVG}path" and shape.get("fill-rule") == "evenodd"
        assert shape.get("d", "").count("M") == 2 and shape.get("d", "").count("Z") == 2
    image = pixels_of(scenario_png(doc))

    def seen_at(x: float, y: float) -> list[int]:  # the PNG's colour at a point of the arena
        column, row = (round(v) for v in pixel_at(svg, x, y))
        return [int(channel) for channel in image[row, column]]

    assert seen_at(130, 530) == pytest.approx(seen_at(300, 530), abs=3)  # the parts' overlap: no darker
    assert seen_at(130, 530) == pytest.approx(seen_at(130, 700), abs=3)
    assert seen_at(900, 500) == [255, 255, 255]  # the frame's hole shows the floor
    assert seen_at(720, 500) == pytest.approx(seen_at(900, 320), abs=3)


def test_zones_are_drawn_under_the_elements_in_their_rules_colours_and_named(doc: dict) -> None:
    zones = [
        {
            "name": "aisle",
            "rule": "clear",
            "outline": [[0, 400], [1400, 400], [1400, 600], [0, 600]],
            "types": [],
        },
        {
            "name": "store",
            "rule": "holds",
            "outline": [[100, 700], [700, 700], [400, 1000]],
            "types": ["cobot"],
        },
    ]
    doc["arena"]["zones"] = zones
    svg = scenario_svg(doc)
    root = ET.fromstring(svg)
    group = next(g for g in root.iter(f"{SVG}g") if g.get("class") == "zones")
    drawn = list(group.iter(f"{SVG}polygon"))
    assert [len(p.get("points", "").split()) for p in drawn] == [4, 3]
    assert [p.get("fill") for p in drawn] == ["#e57373", "#81c784"]
    groups = [g.get("class") for g in root.iter(f"{SVG}g") if g.get("class")]
    assert groups.index("zones") < groups.index("elements")
    assert {"aisle", "store", "keep clear: aisle", "holds: store"} <= set(texts(svg))
    # the PNG: the aisle's middle (no element there) faint red, where the floor without zones is white
    (left, top), (right, bottom) = layout(parse(doc), 800).frame
    x, y = round(left + (right - left) / 2), round(top + (bottom - top) * (1 - 500 / 1050))
    r, g, b = Image.open(io.BytesIO(scenario_png(doc, pixels=800))).convert("RGB").getpixel((x, y))
    assert r > g + 20 and r > b + 20 and g > 150
    plain = Image.open(io.BytesIO(scenario_png(document(*doc["elements"]), pixels=800))).convert("RGB")
    assert plain.getpixel((x, y)) == (255, 255, 255)
