"""The ``robot`` block and the fitness terms that drive it → the Spec's :class:`Robot` and drive terms.

The spec writes angles in degrees and lengths in the arena's unit, as everywhere in the language;
the Robot holds radians (:mod:`mazegen.spec`), and a controller's parameters are checked against
the bounds of :mod:`mazegen.controllers`, which are in SI units.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

from mazegen import plugins
from mazegen.controllers import ANGLE, BUNDLED, LENGTH, SPEED, TIME, TURN, Parameter
from mazegen.dsl.bounds import MAX_LENGTH, MAX_TARGET
from mazegen.dsl.located import fail, single_properties, suggestion, where
from mazegen.policies import SEARCHED, malformed_path, policy_module_found
from mazegen.spec import (
    Arena,
    ControllerSpec,
    FitnessTerm,
    Robot,
    metres_per_unit,
    robot_for,
    unsized_problem,
)


@dataclass(frozen=True)
class _Setting:
    """One number of the robot block: how it is written, the Robot field it sets, its bounds as
    written (``open_low``: the low bound itself is refused), and whether it is written in degrees
    (the Robot holds radians)."""

    label: str
    field: str
    low: float
    high: float
    unit: str
    open_low: bool = True
    degrees: bool = False


_SETTINGS = {
    setting.label: setting
    for setting in (
        _Setting("speed", "max_speed", 0, MAX_LENGTH, "arena units per second"),
        _Setting("min speed", "min_speed", -MAX_LENGTH, MAX_LENGTH, "arena units per second", open_low=False),
        _Setting("turn rate", "max_turn", 0, 3600, "degrees per second", degrees=True),
        _Setting("acceleration", "accel", 0, MAX_TARGET, "arena units per second squared"),
        _Setting("turn acceleration", "turn_accel", 0, 1_000_000, "degrees per second squared", degrees=True),
        _Setting("step", "step", 0.001, 1, "seconds", open_low=False),
        _Setting("goal tolerance", "goal_tolerance", 0, MAX_LENGTH, "arena units"),
        _Setting("timeout factor", "timeout", 1, 1000, "times the optimal time", open_low=False),
        _Setting("stuck", "stuck", 0, 3600, "seconds"),
        _Setting(
            "beams", "beams", 1, 3600, "beams", open_low=False
        ),  # a whole number, as the grammar reads it
        _Setting("fov", "fov", 0, 360, "degrees", degrees=True),
        _Setting("range", "lidar_range", 0, MAX_LENGTH, "arena units"),
    )
}

_LABELS = {
    "SpeedLimit": "speed",
    "MinSpeedLimit": "min speed",
    "TurnRateLimit": "turn rate",
    "TurnAccelerationLimit": "turn acceleration",
    "AccelerationLimit": "acceleration",
    "StepSetting": "step",
    "GoalToleranceSetting": "goal tolerance",
    "TimeoutSetting": "timeout factor",
    "StuckSetting": "stuck",
    "ContactSetting": "contact",
    "FootprintSetting": "footprint",
    "BeamsSetting": "beams",
    "FovSetting": "fov",
    "LidarRangeSetting": "range",
    "LidarProperty": "lidar",
    "DriveProperty": "drive",
}
"""How each property of the robot block is written, by its class in maze.tx."""

_PAIR_MEASURES = ("disagree",)
_TARGETED_MEASURES = ("time", "clearance")


def _bounds(low: float, high: float, *, open_low: bool) -> str:
    return f"{'(' if open_low else '['}{low:.15g}, {high:.15g}]"


def _setting_value(node: Any, setting: _Setting) -> float:
    value = node.value
    too_low = value <= setting.low if setting.open_low else value < setting.low
    if too_low or value > setting.high:
        bounds = _bounds(setting.low, setting.high, open_low=setting.open_low)
        fail(node, f"{setting.label} must be within {bounds} {setting.unit}, got {value:.15g}")
    return math.radians(value) if setting.degrees else value


def registered_controllers() -> list[str]:
    """Names installed packages register under the ``mazegen.controllers`` entry point."""
    return plugins.names("controllers")


def check_controller_name(node: Any, name: str) -> None:
    """Fail at ``node`` unless ``name`` is bundled, registered, or a policy's path (``pkg.mod:name``,
    whose module :func:`convert_robot` looks for)."""
    if name in BUNDLED or ":" in name:
        return
    registered = registered_controllers()
    if name in registered:
        return
    if "." in name:
        fail(node, malformed_path(name))
    known = [*BUNDLED, *registered]
    fail(
        node,
        f"unknown controller '{name}'{suggestion(name, known)} (bundled: {', '.join(BUNDLED)}; "
        "or a policy's path package.module:name)",
    )


def _term_controllers(term: Any) -> tuple[str, ...]:
    """The controllers a drive term names, as written."""
    return tuple(term.controllers) if term.controller is None else (term.controller,)


def drive_controllers(term: Any) -> tuple[str, ...]:
    """The controllers a drive term reads, checked against its measure and its target range."""
    pair = term.controller is None  # written 'controllers A, B'
    names = _term_controllers(term)
    for name in names:
        check_controller_name(term, name)
    if term.measure in _PAIR_MEASURES:
        if not pair or len(names) != 2:
            fail(
                term,
                f"'{term.measure}' compares two controllers: "
                f"write 'controllers dwa, purepursuit {term.measure}'",
            )
        if names[0] == names[1]:
            fail(term, f"'{term.measure}' compares two different controllers, got '{names[0]}' twice")
    elif pair:
        fail(term, f"'{term.measure}' reads one controller: write 'controller {names[0]} {term.measure}'")
    if term.range is not None and term.measure not in _TARGETED_MEASURES:
        fail(term.range, f"a '{term.measure}' term takes no target range (only time and clearance do)")
    return names


def _unit(parameter: Parameter, arena: Arena) -> str:
    return {
        LENGTH: arena.unit,
        SPEED: f"{arena.unit}/s",
        TIME: "s",
        ANGLE: "degrees",
        TURN: "degrees/s",
    }.get(parameter.unit, "")


def _parameter_value(node: Any, controller: str, parameter: Parameter, arena: Arena) -> float:
    """A parameter's value as the simulator reads it (lengths in arena units, angles in radians),
    checked against the table's bounds (SI) converted to how the spec writes it."""
    written = node.value
    scale = metres_per_unit(arena) if parameter.scaled else 1.0
    degrees = parameter.unit in (ANGLE, TURN)
    to_spec = (lambda si: math.degrees(si)) if degrees else (lambda si: si / scale)
    low, high = to_spec(parameter.low), to_spec(parameter.high)
    what = f"{controller} {parameter.name}"
    if isinstance(parameter.default, int) and not float(written).is_integer():
        fail(node, f"{what} is a count: expected a whole number, got {written:.15g}")
    if not low <= written <= high:
        unit = _unit(parameter, arena)
        shown = f"at least {low:.6g}" if parameter.high >= 1e9 else f"within {low:.6g}..{high:.6g}"
        fail(node, f"{what} must be {shown}{' ' + unit if unit else ''}, got {written:.15g}")
    return math.radians(written) if degrees else float(written)


def _controller(prop: Any, arena: Arena) -> ControllerSpec:
    check_controller_name(prop, prop.name)
    bundled = BUNDLED.get(prop.name)
    seen: dict[str, Any] = {}
    params = []
    for node in prop.parameters:
        if bundled is None:
            fail(
                node, f"controller '{prop.name}' is not bundled: its parameters are its own, set in its code"
            )
        parameter = bundled.parameter(node.name)
        if parameter is None:
            names = [p.name for p in bundled.parameters]
            fail(
                node,
                f"controller '{prop.name}' has no parameter '{node.name}'{suggestion(node.name, names)} "
                f"(its parameters: {', '.join(names)})",
            )
        if node.name in seen:
            fail(
                node,
                f"duplicate '{node.name}' in controller '{prop.name}' "
                f"(first given at {where(seen[node.name])})",
            )
        seen[node.name] = node
        params.append((node.name, _parameter_value(node, prop.name, parameter, arena)))
    return ControllerSpec(prop.name, tuple(params))


def _controllers(
    blocks: list[Any], terms: tuple[FitnessTerm, ...], arena: Arena
) -> tuple[ControllerSpec, ...]:
    """Every controller the spec names, first the robot block's then the fitness terms', each once."""
    found: dict[str, Any] = {}
    controllers = []
    for prop in blocks:
        if prop.name in found:
            fail(prop, f"controller '{prop.name}' is set twice (first at {where(found[prop.name])})")
        found[prop.name] = prop
        controllers.append(_controller(prop, arena))
    named = {controller.name for controller in controllers}
    for term in terms:
        for name in term.controllers:
            if name not in named:
                named.add(name)
                controllers.append(ControllerSpec(name))
    return tuple(controllers)


def convert_robot(
    decl: Any | None, arena: Arena, terms: tuple[FitnessTerm, ...], fitness: Any | None
) -> Robot | None:
    """The spec's robot: its block over :func:`robot_for`'s defaults, or those alone when a fitness
    term drives it; None when neither (``fitness``: the fitness block, whose drive terms name
    controllers too)."""
    drives = [term for term in terms if term.kind == "drive"]
    if decl is None and not drives:
        return None
    unsized = unsized_problem(arena)
    if unsized is not None:
        fail(decl if decl is not None else fitness, unsized)
    props = [] if decl is None else list(decl.properties)
    blocks = [prop for prop in props if type(prop).__name__ == "ControllerProperty"]
    single = single_properties([p for p in props if p not in blocks], "robot", labels=_LABELS)
    changes: dict[str, Any] = {}
    lidar = single.pop("LidarProperty", None)
    nested = single_properties(lidar.settings, "lidar", labels=_LABELS) if lidar is not None else {}
    for kind, node in [*single.items(), *nested.items()]:
        if kind == "DriveProperty":
            changes["driven"] = 1.0 if node.all else _fraction(node)
            continue
        if kind == "ContactSetting":
            changes["contact"] = node.mode
            continue
        if kind == "FootprintSetting":
            changes["footprint"] = _footprint(node)
            continue
        setting = _SETTINGS[_LABELS[kind]]
        changes[setting.field] = _setting_value(node, setting)
    robot = robot_for(arena, **changes)
    if robot.min_speed > robot.max_speed:
        node = single.get("MinSpeedLimit") or single["SpeedLimit"]
        fail(node, f"min speed {robot.min_speed:g} is above the speed {robot.max_speed:g}")
    if robot.min_speed < -robot.max_speed:
        node = single.get("MinSpeedLimit") or single["SpeedLimit"]
        fail(node, f"min speed {robot.min_speed:g} backs up faster than the speed {robot.max_speed:g}")
    controllers = _controllers(blocks, terms, arena)
    _check_policies_found(blocks, [] if fitness is None else fitness.terms)
    return dataclasses.replace(robot, controllers=controllers)


def _check_policies_found(blocks: list[Any], term_nodes: list[Any]) -> None:
    """Fail where a policy whose module is not found is first named: its robot block's controller,
    else its first drive term (the module is imported when the robot is first driven)."""
    named = [(prop, prop.name) for prop in blocks]
    drives = [node for node in term_nodes if type(node).__name__ == "DriveTerm"]
    named += [(node, name) for node in drives for name in _term_controllers(node)]
    looked_for = set()
    for node, name in named:
        module = name.partition(":")[0]
        if ":" not in name or module in looked_for:
            continue
        looked_for.add(module)
        if not policy_module_found(module):
            fail(node, f"controller '{name}': no module '{module}' in {SEARCHED}")


def _footprint(node: Any) -> tuple[float, float]:
    for side, value in (("length", node.length), ("width", node.width)):
        if not 0 < value <= MAX_LENGTH:
            bounds = f"(0, {MAX_LENGTH:.15g}] arena units"
            fail(node, f"footprint {side} must be within {bounds}, got {value:.15g}")
    return float(node.length), float(node.width)


def _fraction(node: Any) -> float:
    if not 0 < node.fraction <= 1:
        fail(node, f"drive best takes a fraction within (0, 1], got {node.fraction:.15g}")
    return float(node.fraction)
