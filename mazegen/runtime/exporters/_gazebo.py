"""Gazebo worlds (SDF 1.6, for Gazebo classic and the new Gazebo).

A world holds a ground plane, a sun, the arena's four edge walls, for a floor built on a map
that map's walls (one static model of boxes, the map's blocked cells merged into few rectangles),
a flat start and goal marker (seen, not collided with), and one static model per element, named
``element_NN_TYPE`` and posed at the element's ``(x, y)`` and rotation. Each convex
part of an element is a box when it is a rectangle, else an extruded polygon
(``polyline``), as tall as the element. Lengths are metres, the world frame is the
arena's: its lower-left corner at the origin, z up.
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from collections.abc import Callable, Sequence
from functools import partial
from typing import Any

import numpy as np

from mazegen.maps import wall_boxes
from mazegen.runtime.documents import Floor, safe_name
from mazegen.runtime.exporters._floor import ExportOptions, map_note, rectangle_of, task_comments
from mazegen.runtime.reports import rgb
from mazegen.spec import BaseMap

SDF_VERSION = "1.6"
WALL_THICKNESS = 0.1
"""Metres; the walls stand just outside the arena, their inner faces on its edge."""
MARKER_HEIGHT = 0.002
"""Metres: start and goal markers are flat discs on the ground."""
MARKER_RADIUS = 0.05
"""Metres: the start and goal markers' radius when the robot has none."""
_ORIGIN = "0 0 0 0 0 0"
_WALL = "0.5 0.5 0.5 1"
_START = "0.17 0.63 0.17 1"
_GOAL = "0.84 0.15 0.16 1"


def _text(value: float) -> str:
    """A number with at most six decimals (micrometres) and no trailing zeros."""
    text = f"{value:.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _numbers(*values: float) -> str:
    return " ".join(_text(v) for v in values)


def _child(parent: ET.Element, tag: str, text: str | None = None, **attributes: str) -> ET.Element:
    node = ET.SubElement(parent, tag, attributes)
    if text is not None:
        node.text = text
    return node


def _sdf_name(text: Any) -> str:
    """``text`` with every character but letters, digits and ``_`` replaced (SDF reserves ``::``)."""
    return re.sub(r"[^A-Za-z0-9_]", "_", str(text))[:40]


def _model_name(index: int, width: int, kind: Any) -> str:
    """``element_07_cobot``: unique by its index."""
    return f"element_{index:0{width}d}_{_sdf_name(kind)}"


def _material(parent: ET.Element, colour: str) -> None:
    material = _child(parent, "material")
    for tag in ("ambient", "diffuse"):
        _child(material, tag, colour)
    _child(material, "specular", "0.1 0.1 0.1 1")


def _shape(link: ET.Element, name: str, pose: str, colour: str, fill: Callable[[ET.Element], object]) -> None:
    """A collision and a visual of one geometry; ``fill(geometry)`` writes the geometry."""
    for role in ("collision", "visual"):
        node = _child(link, role, name=f"{name}_{role}")
        _child(node, "pose", pose)
        fill(_child(node, "geometry"))
        if role == "visual":
            _material(node, colour)


def _box(
    link: ET.Element, name: str, centre: Sequence[float], size: Sequence[float], yaw: float, colour: str
) -> None:
    """A box standing on the ground, ``size`` = (length, width, height), turned by ``yaw``."""
    pose = _numbers(centre[0], centre[1], size[2] / 2, 0, 0, yaw)
    _shape(link, name, pose, colour, partial(_box_geometry, size=size))


def _box_geometry(geometry: ET.Element, size: Sequence[float]) -> None:
    _child(_child(geometry, "box"), "size", _numbers(*size))


def _polyline(geometry: ET.Element, points: np.ndarray, height: float) -> None:
    """A convex polygon extruded from the ground up to ``height``."""
    shape = _child(geometry, "polyline")
    for x, y in points:
        _child(shape, "point", _numbers(x, y))
    _child(shape, "height", _text(height))


def _plane(geometry: ET.Element, size: Sequence[float]) -> None:
    shape = _child(geometry, "plane")
    _child(shape, "normal", "0 0 1")
    _child(shape, "size", _numbers(*size))


def _element_model(world: ET.Element, name: str, element: dict[str, Any], metres: float) -> None:
    """A static model of one element: its pose, then each part in the element's own frame."""
    x, y = float(element["x"]) * metres, float(element["y"]) * metres
    yaw = math.radians(float(element.get("rotation", 0.0)))
    height = float(element.get("height", 100.0)) * metres
    r, g, b = rgb(element.get("colour"))
    colour = _numbers(r / 255, g / 255, b / 255, 1)
    model = _child(world, "model", name=name)
    _child(model, "static", "true")
    _child(model, "pose", _numbers(x, y, 0, 0, 0, yaw))
    link = _child(model, "link", name="link")
    turn = np.array([[math.cos(yaw), math.sin(yaw)], [-math.sin(yaw), math.cos(yaw)]])
    for k, part in enumerate(element["parts"]):
        local = (np.asarray(part, dtype=np.float64) * metres - (x, y)) @ turn.T
        rectangle = rectangle_of(local)
        if rectangle is not None:
            centre, length, width, angle = rectangle
            _box(link, f"part_{k}", centre, (length, width, height), angle, colour)
        else:
            _shape(link, f"part_{k}", _ORIGIN, colour, partial(_polyline, points=local, height=height))


def _static_model(world: ET.Element, name: str, pose: Sequence[float]) -> ET.Element:
    model = _child(world, "model", name=name)
    _child(model, "static", "true")
    _child(model, "pose", _numbers(*pose))
    return _child(model, "link", name="link")


def _surroundings(world: ET.Element, width: float, depth: float, wall_height: float) -> None:
    """Sun, ground plane and the arena's four edge walls."""
    sun = _child(world, "light", name="sun", type="directional")
    _child(sun, "cast_shadows", "true")
    _child(sun, "pose", "0 0 10 0 0 0")
    _child(sun, "diffuse", "0.8 0.8 0.8 1")
    _child(sun, "specular", "0.2 0.2 0.2 1")
    _child(sun, "direction", "-0.5 0.1 -0.9")
    ground = _static_model(world, "ground_plane", (width / 2, depth / 2, 0, 0, 0, 0))
    _shape(ground, "ground", _ORIGIN, "0.8 0.8 0.8 1", partial(_plane, size=(width + 2, depth + 2)))
    walls = _static_model(world, "arena_walls", (0, 0, 0, 0, 0, 0))
    t = WALL_THICKNESS
    for side, centre, size2 in (
        ("south", (width / 2, -t / 2), (width + 2 * t, t)),
        ("north", (width / 2, depth + t / 2), (width + 2 * t, t)),
        ("west", (-t / 2, depth / 2), (t, depth)),
        ("east", (width + t / 2, depth / 2), (t, depth)),
    ):
        _box(walls, side, centre, (*size2, wall_height), 0.0, _WALL)


def _map_walls(world: ET.Element, base: BaseMap, metres: float, wall_height: float) -> None:
    """The walls of the map the floor is built on: a box per rectangle of its merged blocked cells."""
    walls = _static_model(world, "map_walls", (0, 0, 0, 0, 0, 0))
    for k, (x0, y0, x1, y1) in enumerate(wall_boxes(base)):
        centre = ((x0 + x1) / 2 * metres, (y0 + y1) / 2 * metres)
        _box(walls, f"wall_{k}", centre, ((x1 - x0) * metres, (y1 - y0) * metres, wall_height), 0.0, _WALL)


def _marker(world: ET.Element, name: str, point: Sequence[float], radius: float, colour: str) -> None:
    """A flat disc on the ground: seen, never collided with."""
    link = _static_model(world, name, (point[0], point[1], 0, 0, 0, 0))
    visual = _child(link, "visual", name="visual")
    _child(visual, "pose", _numbers(0, 0, MARKER_HEIGHT / 2, 0, 0, 0))
    cylinder = _child(_child(visual, "geometry"), "cylinder")
    _child(cylinder, "radius", _text(radius))
    _child(cylinder, "length", _text(MARKER_HEIGHT))
    _material(visual, colour)


def gazebo_files(floor: Floor, options: ExportOptions) -> dict[str, bytes]:
    """``NAME.sdf``: the scenario as a Gazebo world.

    Raises:
        MazeError: When the arena's unit has no size in metres, or the floor is built on a map and its
            spec is unknown.
    """
    metres = floor.metres_per_unit(options)
    base = floor.base("a Gazebo world")
    arena, elements = floor.arena, floor.document["elements"]
    root = ET.Element("sdf", version=SDF_VERSION)
    about = [f"MazeGen scenario from {safe_name(floor.source.name)}", f"1 arena unit = {metres:g} m"]
    note = map_note(floor, metres)
    root.append(ET.Comment(f" {_comment('; '.join([*about, note] if note else about))} "))
    for line in task_comments(floor, metres, (0.0, 0.0)):  # the markers are the first task's
        root.append(ET.Comment(f" {_comment(line)} "))
    world = _child(root, "world", name=_sdf_name(floor.document.get("scenario", "mazegen")))
    tallest = max((float(e.get("height", 100.0)) for e in elements), default=100.0) * metres
    _surroundings(world, float(arena["width"]) * metres, float(arena["height"]) * metres, tallest)
    if base is not None:
        _map_walls(world, base, metres, tallest)
    radius = float(arena.get("robot_radius", 0.0)) * metres or MARKER_RADIUS
    _marker(world, "start", [float(v) * metres for v in arena["start"]], radius, _START)
    _marker(world, "goal", [float(v) * metres for v in arena["goal"]], radius, _GOAL)
    width = max(2, len(str(len(elements))))
    for index, element in enumerate(elements, start=1):
        _element_model(world, _model_name(index, width, element.get("type")), element, metres)
    ET.indent(root, space="  ")
    text = '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
    return {f"{floor.name}.sdf": text.encode("utf-8")}


def _comment(text: str) -> str:
    """Text safe inside an XML comment (once characters XML forbids are gone, :func:`safe_name`): no
    ``--``."""
    return re.sub("-{2,}", "-", text)
