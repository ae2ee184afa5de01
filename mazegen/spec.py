"""The resolved scenario specification as plain, picklable data.

A :class:`Spec` is what the DSL produces from a ``.maze`` file and what the
generator and the runtime consume. It holds no textX objects, so it crosses
process boundaries and serialises to JSON (``spec.json`` in a build directory).

Geometry convention: an element type is a union of convex *parts*. Each part
vertex ``k`` has a unit coordinate ``u_k`` (scaled by the element's size) and an
absolute offset ``o_k`` (arena units, not scaled, e.g. half the thickness of a
bar). In the element frame a vertex is ``(u_x * sx + o_x, u_y * sy + o_y)``;
the element is then rotated by its rotation and moved to its position.
Vertices run counter-clockwise.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from mazegen.errors import MazeError
from mazegen.fileio import json_value

Point = tuple[float, float]

SPEC_FORMAT_VERSION = 1


@dataclass(frozen=True)
class Part:
    """One convex polygon of an element type (see the module docstring)."""

    unit: tuple[Point, ...]
    offset: tuple[Point, ...]


@dataclass(frozen=True)
class ElementType:
    """A kind of obstacle a scenario may contain.

    Attributes:
        name: Identifier used in grammars and phenotypes (``cobot``).
        shape: Shape kind: rect, square, triangle, polygon, points or bars.
        parts: Convex parts in the unit frame (see module docstring).
        size: Range ``(lo, hi)`` of the uniform size, or of the width for rect.
        size2: Range of the height for rect (``None`` for uniform shapes).
        rotations: Allowed rotations in degrees (discrete choice).
        rotation_range: Continuous rotation range in degrees, or ``None``.
        colour: CSS colour used in drawings.
        semantic_class: Free-form class (robot, wall, network…).
        height: Height in arena units for 3D export.
        position_step: Positions lie on multiples of this (``at step``), or anywhere for ``None``.
        size_step: Sizes (widths of a rect) are ``size[0]`` plus multiples of this, or any for ``None``;
            ``depth_step`` likewise of a rect's depth.
        against_wall: The element stands against a wall, its back (its own -y side) to it; its
            rotation says which wall (:data:`WALL_ROTATIONS`).
    """

    name: str
    shape: str
    parts: tuple[Part, ...]
    size: tuple[float, float]
    size2: tuple[float, float] | None = None
    rotations: tuple[float, ...] = (0.0,)
    rotation_range: tuple[float, float] | None = None
    colour: str = "#555555"
    semantic_class: str = "obstacle"
    height: float = 100.0
    position_step: float | None = None
    size_step: float | None = None
    depth_step: float | None = None
    against_wall: bool = False

    @property
    def uniform(self) -> bool:
        """True when one size scales both axes (every shape but rect)."""
        return self.size2 is None


STRUCTURE_DEFAULTS = {"position_step": None, "size_step": None, "depth_step": None, "against_wall": False}
"""The fields of :class:`ElementType` that place it on steps and against walls, and their defaults:
``spec.json`` leaves them out when they are the default, so a spec without them reads as before."""

WALL_ROTATIONS = (0.0, 90.0, 180.0, 270.0)
"""The rotation that turns an element's back (its own -y side) to each wall: bottom, right, top, left."""


def wall_of(rotation: float) -> int:
    """Which wall (an index of :data:`WALL_ROTATIONS`) an element against a wall at ``rotation`` stands at."""
    return round(rotation / 90.0) % 4


Box = tuple[float, float, float, float]
"""A rectangle ``(x0, y0, x1, y1)``, lower-left and upper-right corners."""


def step_span(low: float, high: float, step: float) -> tuple[int, int]:
    """The multiples of ``step`` within ``[low, high]`` (a billionth of a step of rounding either way):
    the first one's index, and how many there are."""
    first = math.ceil(low / step - 1e-9)
    return first, max(math.floor(high / step + 1e-9) - first + 1, 0)


def placing_area(arena: Arena, element: ElementType, walls: Box) -> Box:
    """Where elements of type ``element`` are placed (:meth:`Arena.area_of`); along a wall, for one that
    stands against the walls of the box ``walls``, within that box."""
    area = arena.area_of(element.name)
    if not element.against_wall:
        return area
    return (max(area[0], walls[0]), max(area[1], walls[1]), min(area[2], walls[2]), min(area[3], walls[3]))


def walls_reached(area: Box, walls: Box, rotations: tuple[float, ...]) -> tuple[float, ...]:
    """Those of ``rotations`` (of an element against a wall) whose wall of the box ``walls`` the box
    ``area``, where the element may stand, reaches (touches or crosses)."""
    reached = (area[1] <= walls[1], area[2] >= walls[2], area[3] >= walls[3], area[0] <= walls[0])
    return tuple(rotation for rotation in rotations if reached[wall_of(rotation)])


@dataclass(frozen=True)
class BaseMap:
    """The map an arena is built on (``arena hall { map "hall.yaml" }``): its blocked cells are walls
    every floor of the arena has, and its extent is the arena.

    Attributes:
        source: The map file as the spec names it.
        resolution: Arena units per cell.
        rows: Cells along y.
        cols: Cells along x.
        origin: The map frame's ``(x, y)`` of the arena's lower-left corner, metres (map_server's
            ``origin``), so that exports put the floor back where the map lies.
        unknown: ``"blocked"`` or ``"free"``: what the spec made of the map's unknown cells.
        blocked: The blocked cells, row 0 the lowest, packed 8 to a byte (first cell in the lowest
            bit) and written in base64: plain text, so a spec holding a map still pickles, hashes
            and serialises as before (:func:`mazegen.maps.base_cells` unpacks it).
    """

    source: str
    resolution: float
    rows: int
    cols: int
    origin: Point
    unknown: str
    blocked: str


ZONE_RULES = ("clear", "accepts", "holds")
"""What a zone says of the elements: none may overlap it (``keep clear``), only the listed types may
(``accepts``), or the listed types must lie wholly inside it, or inside another zone that holds them
(``holds``; it accepts them too)."""


@dataclass(frozen=True)
class Zone:
    """A named area of an arena and its rule for the elements (one of :data:`ZONE_RULES`).

    ``outline`` is the area's polygon (counter-clockwise, arena units) and ``parts`` the convex
    polygons it is split into (one for a rectangle); ``types`` are the element types ``accepts`` and
    ``holds`` name.
    """

    name: str
    rule: str
    outline: tuple[Point, ...]
    parts: tuple[tuple[Point, ...], ...]
    types: tuple[str, ...] = ()


MAX_TASKS = 1000
"""The most tasks an arena may have, listed and drawn together."""

MAX_CLASSES = 8
"""Homotopy classes of a floor's paths kept per task, at most (the shortest: docs/classes.md)."""
DETOUR = 1.5
"""A homotopy class whose shortest path is longer than this many times the floor's shortest is left out."""


@dataclass(frozen=True)
class Station:
    """A named pose of an arena where tasks start or end; ``heading`` in degrees, or None."""

    name: str
    point: Point
    heading: float | None = None


@dataclass(frozen=True)
class Task:
    """One start and goal a floor is measured and driven on; headings in degrees, or None."""

    name: str
    start: Point
    goal: Point
    start_heading: float | None = None
    goal_heading: float | None = None

    def start_poses(self, count: int) -> Any:
        """``float64[count, 3]``: ``(x, y, theta)`` of ``count`` robots at the start, theta in radians,
        for a task whose start has a heading; None for one without (the robot faces its path)."""
        if self.start_heading is None:
            return None
        import numpy as np  # the spec is plain data: numpy only where poses are made

        return np.tile([self.start[0], self.start[1], math.radians(self.start_heading)], (count, 1))


@dataclass(frozen=True)
class Arena:
    """The floor: a rectangle ``[0, width] x [0, height]`` with a start and goal.

    ``grid`` is the cell size of the occupancy grid that solvability and the
    difficulty metrics are computed on, or ``None`` for :attr:`cell`'s default.
    ``base`` is the map the floor is built on, or ``None`` for an empty rectangle; ``zones`` its named
    areas. ``tasks`` are the floor's tasks when it has several (listed between ``stations`` or
    drawn), the first one's start and goal being ``start`` and ``goal``; empty for a floor of one
    task, ``start`` to ``goal``.
    """

    name: str
    width: float
    height: float
    unit: str
    start: Point
    goal: Point
    robot_radius: float
    grid: float | None = None
    base: BaseMap | None = None
    zones: tuple[Zone, ...] = ()
    stations: tuple[Station, ...] = ()
    tasks: tuple[Task, ...] = ()

    @property
    def every_task(self) -> tuple[Task, ...]:
        """The floor's tasks: :attr:`tasks`, or the one from ``start`` to ``goal``."""
        return self.tasks or (Task("start -> goal", self.start, self.goal),)

    def for_task(self, task: Task) -> Arena:
        """The floor with ``task`` as its only one: what the path search and the simulator see."""
        return dataclasses.replace(self, start=task.start, goal=task.goal, stations=(), tasks=())

    @property
    def cell(self) -> float:
        """The grid's cell size: ``grid``, else half the robot radius, coarsened so
        that no side has more than 128 cells."""
        if self.grid is not None:
            return self.grid
        longest = max(self.width, self.height)
        return max(self.robot_radius / 2, longest / 128)

    def holding(self, name: str) -> tuple[Zone, ...]:
        """The zones that hold elements of type ``name`` (``holds``)."""
        return tuple(zone for zone in self.zones if zone.rule == "holds" and name in zone.types)

    def area_of(self, name: str) -> Box:
        """Where elements of type ``name`` are placed: the box around the zones that hold them, or the
        whole arena (positions drawn elsewhere could only be rejected)."""
        corners = [point for zone in self.holding(name) for point in zone.outline]
        if not corners:
            return (0.0, 0.0, self.width, self.height)
        xs, ys = [x for x, _ in corners], [y for _, y in corners]
        return (min(xs), min(ys), max(xs), max(ys))


def task_point_problem(label: str, point: Point, width: float, height: float, radius: float) -> str | None:
    """Why ``point`` cannot be the ``start`` or ``goal`` (``label``) of a ``width x height`` arena for a
    robot of ``radius``, or None when it can."""
    x, y = point
    if not (0 <= x <= width and 0 <= y <= height):
        return f"{label} ({x:g}, {y:g}) is outside the arena {width:g} x {height:g}"
    if min(x, y, width - x, height - y) < radius:
        return f"{label} ({x:g}, {y:g}) is closer to the arena wall than the robot radius {radius:g}"
    return None


@dataclass(frozen=True)
class GrammarPlacement:
    """Placement carried by the grammar itself (MazeGen 1.0 style).

    Each element is written ``name(<size>,<number>,<number>…)``; the size
    terminals are ``sizes`` and are multiplied by ``scale``; positions are
    ``positions`` in arena units.
    """

    sizes: tuple[int, ...]
    scale: float
    positions: tuple[int, ...]


@dataclass(frozen=True)
class Row:
    """A row: 2..N elements of one type in a line, derived by the grammar as one choice
    (``row rackRow of shelfRack { count 2..6  spacing 120..150 }``).

    Attributes:
        name: Identifier used in grammars and phenotypes (``rackRow``).
        member: The element type of its members.
        count: Fewest and most members.
        spacing: Range of the gap between neighbours along the row's line, arena units.
        spacing_step: Gaps are ``spacing[0]`` plus multiples of this, or any for ``None``.
        rotations: Allowed rotations of the row (its line and every member), degrees.
        rotation_range: Continuous rotation range, or ``None``.
    """

    name: str
    member: str
    count: tuple[int, int]
    spacing: tuple[float, float]
    spacing_step: float | None = None
    rotations: tuple[float, ...] = (0.0,)
    rotation_range: tuple[float, float] | None = None


def row_count_rule(name: str) -> str:
    """The grammar rule that chooses row ``name``'s member count: ``<rackRow-count>``."""
    return f"<{name}-count>"


@dataclass(frozen=True)
class Scenario:
    """What a scenario may contain and how its grammar is written.

    Attributes:
        name: Scenario name (also the build and run directory name).
        arena: Name of the arena it is placed on.
        elements: Element type names, in declaration order.
        grammar: ``nested``, ``flat``, ``list`` or ``custom``.
        custom_rules: For ``custom``: ``(lhs, alternatives)`` with each
            alternative already written in BNF (PonyGE2 dialect).
        max_elements: Placement slots; a derivation with more is invalid (a row's members count).
        placement: ``None`` for placement genes, else grammar placement.
        required: ``(name, count, exactly)``: every floor has ``count`` elements of the type (or rows),
            exactly or at least; its grammar derives them first, so every floor has them.
        rows: The rows the scenario lists, in its order.
        listed: The ``elements`` list as written, element types and rows, when it holds rows (the
            grammar's order); empty when it names element types alone: then ``elements``.
    """

    name: str
    arena: str
    elements: tuple[str, ...]
    grammar: str = "nested"
    custom_rules: tuple[tuple[str, tuple[str, ...]], ...] = ()
    max_elements: int = 32
    placement: GrammarPlacement | None = None
    required: tuple[tuple[str, int, bool], ...] = ()
    rows: tuple[Row, ...] = ()
    listed: tuple[str, ...] = ()

    @property
    def entries(self) -> tuple[str, ...]:
        """What the grammar derives, in the ``elements`` list's order: element types and rows."""
        return self.listed or self.elements


PATH_METRICS = (
    "path_length",
    "clearance",
    "visibility",
    "dispersion",
    "dimension",
    "tortuosity",
    "path_ratio",
    "narrowest",
)
"""Metrics of the robot's path a ``metric`` term can target (see docs/language.md §6)."""

DIFFICULTY_LEVELS = {"easy": (0.0, 25.0), "medium": (25.0, 50.0), "hard": (50.0, 100.0)}
"""Difficulty score ranges of the named levels."""


@dataclass(frozen=True)
class PluginMetric:
    """Where a ``metric`` term's function comes from and what it is given (docs/extending.md).

    Attributes:
        source: The Python file that defines it (absolute), or None for an installed package's
            ``mazegen.metrics`` entry point.
        package: The distribution that registers it (None for a file): named when a machine lacks it.
        arguments: Keyword arguments the spec gives it, in the spec's order.
        types: The scenario's element type names, which the floors' type ids index.
        where: ``file:line:col`` of the term, for errors raised while it runs.
    """

    source: str | None
    package: str | None
    arguments: tuple[tuple[str, float], ...]
    types: tuple[str, ...]
    where: str


@dataclass(frozen=True)
class FitnessTerm:
    """One term of the fitness; its kind is a row of :data:`mazegen.fitness_terms.TERMS`.

    ``weight`` multiplies the term (penalties are subtracted; a metric plug-in's weight is signed,
    negative for ``penalty W``). ``limit`` is the size limit, or a plug-in's reject threshold.
    ``reject`` makes an individual invalid instead of penalised. ``target`` is the ``(low, high)``
    range a difficulty, metric, coverage, drive or plug-in term rewards closeness to; ``metric`` names
    the metric of a ``metric`` term, ``entropy`` / ``types`` for a diversity term, a drive term's
    measure (one of :data:`DRIVE_MEASURES`) or a plug-in's name. A ``drive`` term reads how the robot
    fares under ``controllers`` (one name, two for ``disagree``); ``plugin`` says where a
    plug-in's function comes from. ``tasks`` (one of :data:`TASK_AGGREGATES`) says how a difficulty or
    path-metric term scores a floor of several tasks.
    """

    kind: str
    weight: float = 1.0
    limit: float | None = None
    reject: bool = False
    target: tuple[float, float] | None = None
    metric: str | None = None
    controllers: tuple[str, ...] = ()
    plugin: PluginMetric | None = None
    tasks: str = "mean"

    @property
    def key(self) -> str:
        """The term's name in fitness breakdowns: its kind, its metric's or plug-in's name, or for a
        drive term its controllers' and measure's (``dwa_fails``, ``dwa_purepursuit_disagree``)."""
        if self.kind == "drive":
            return "_".join(re.sub(r"\W", "_", name) for name in (*self.controllers, self.metric or ""))
        if self.kind == "travel":
            return f"travel_{self.metric}"
        return self.metric if self.kind in ("metric", "plugin") and self.metric else self.kind


TASK_AGGREGATES = ("mean", "worst", "all")
"""How a difficulty or path-metric term scores a floor of several tasks: the tasks' mean value against
the target, the task farthest from it, or every task against it, their scores averaged."""

DRIVE_MEASURES = ("fails", "time", "clearance", "disagree")
"""What a ``drive`` fitness term reads of the episodes (see docs/language.md)."""

METRES_PER_UNIT = {"m": 1.0, "cm": 0.01, "mm": 0.001}
"""Length units with a known size; a ``px`` arena is sized by its robot (:func:`metres_per_unit`)."""

ROBOT_RADIUS_METRES = 0.25
"""The radius of the robot the default limits are for (a Clearpath Jackal, as in the BARN challenge)."""


def unsized_problem(arena: Arena) -> str | None:
    """Why a robot cannot be sized on ``arena`` (a ``px`` arena without a robot radius), or None."""
    if arena.unit in METRES_PER_UNIT or arena.robot_radius > 0:
        return None
    return (
        f"arena '{arena.name}' is in px with no robot radius: give it one ('robot radius 25'), "
        "which sizes the driven robot"
    )


def metres_per_unit(arena: Arena) -> float:
    """Metres in one arena unit: the unit's size, or for ``px`` the robot taken as Jackal-sized.

    Raises:
        MazeError: for a ``px`` arena without a robot radius (:func:`unsized_problem`).
    """
    if arena.unit in METRES_PER_UNIT:
        return METRES_PER_UNIT[arena.unit]
    problem = unsized_problem(arena)
    if problem is not None:
        raise MazeError(problem)
    return ROBOT_RADIUS_METRES / arena.robot_radius


@dataclass(frozen=True)
class ControllerSpec:
    """A controller the spec drives the robot with: a bundled name (``dwa``), a dotted path to a
    user's policy, or a name a package registers under the ``mazegen.controllers`` entry point.
    ``params`` overrides its documented parameters, in arena units and seconds."""

    name: str
    params: tuple[tuple[str, float], ...] = ()


@dataclass(frozen=True)
class Robot:
    """The driven robot: a disc of the arena's robot radius, or a box, with unicycle kinematics.

    Lengths are in arena units, times in seconds, angles in radians. :func:`robot_for` gives the
    defaults for an arena (the BARN challenge's Jackal limits scaled to the arena's unit).

    Attributes:
        max_speed: Largest forward speed; ``min_speed`` the smallest (0: the robot may stop).
        max_turn: Largest turn rate, either way.
        accel: Largest change of speed per second; ``turn_accel`` of turn rate.
        step: Simulation time step.
        goal_tolerance: An episode arrives when the centre is this close to the goal.
        timeout: An episode times out after ``timeout`` times the optimal time (path length over
            ``max_speed``); ``stuck`` seconds without getting closer to the goal also end it.
        beams, fov, lidar_range: The 2D lidar: beams spread evenly over ``fov`` radians centred
            on the heading, each reading up to ``lidar_range``.
        driven: Who is driven in an evolution: the best fraction of each generation among those
            the static terms keep (1 = every individual).
        controllers: The controllers the spec names, with their parameter overrides.
        contact: What a touch does (:data:`CONTACT_MODES`): ``end`` the episode, a collision (MazeGen's
            verdict, and a test's), or ``continue`` it as Gazebo does, the robot stopped short of the
            obstacle and each touch counted.
        footprint: ``(length, width)`` of the box the simulator collides, its length along the
            heading, centred on the robot's centre (a Jackal is 0.508 x 0.430 m); None: the disc of
            the arena's robot radius. The floor's path and fields keep to the radius either way.
    """

    max_speed: float
    min_speed: float
    max_turn: float
    accel: float
    turn_accel: float
    step: float = 0.1
    goal_tolerance: float = 0.0
    timeout: float = 8.0
    stuck: float = 10.0
    beams: int = 360
    fov: float = 6.283185307179586
    lidar_range: float = 0.0
    driven: float = 0.1
    controllers: tuple[ControllerSpec, ...] = ()
    contact: str = "end"
    footprint: tuple[float, float] | None = None

    def controller(self, name: str) -> ControllerSpec:
        """The spec's settings of controller ``name`` (none set: its defaults)."""
        for controller in self.controllers:
            if controller.name == name:
                return controller
        return ControllerSpec(name)


CONTACT_MODES = ("end", "continue")
"""What a touch does to an episode (:attr:`Robot.contact`)."""


def robot_for(arena: Arena, **changes: Any) -> Robot:
    """The default robot of ``arena``: BARN's Jackal limits (0.5 m/s, 1.57 rad/s, accelerations
    10 m/s² and 20 rad/s²), goal tolerance 0.3 m and a 3.5 m lidar, in the arena's unit."""
    units = 1.0 / metres_per_unit(arena)
    robot = Robot(
        max_speed=0.5 * units,
        min_speed=0.0,
        max_turn=1.57,
        accel=10.0 * units,
        turn_accel=20.0,
        goal_tolerance=0.3 * units,
        lidar_range=3.5 * units,
    )
    return dataclasses.replace(robot, **changes)


SEED_MAX = 2**63 - 1
"""The largest seed: the catalog stores seeds as SQLite's 64-bit integers."""

CODON_MAX = 2**31 - 1
"""The largest codon value: codons are 32-bit integers."""

MAX_CODONS = 100_000_000
"""The most codons a population may hold (population x genome): about 0.4 GB each for the
parents and the children, within a 24 GB machine with the placement genes and metrics."""


EVOLUTION_BOUNDS: dict[str, tuple[Callable[[float], bool], str]] = {
    # Upper bounds keep counts within 64-bit integers and runs within reach of one machine;
    # Evolution also bounds population x genome (MAX_CODONS), what the arrays hold.
    "population": (lambda v: 1 <= v <= 1_000_000, "from 1 to 1000000"),
    "generations": (lambda v: 0 <= v <= 1_000_000, "from 0 to 1000000"),
    "genome": (lambda v: 1 <= v <= 10_000, "from 1 to 10000"),
    "runs": (lambda v: 1 <= v <= 10_000, "from 1 to 10000"),
    "seed": (lambda v: 0 <= v <= SEED_MAX, f"from 0 to {SEED_MAX}"),
    "elitism": (lambda v: 0 <= v <= 1_000_000, "from 0 to 1000000"),
    "best": (lambda v: 1 <= v <= 1_000, "from 1 to 1000"),
    "wraps": (lambda v: 0 <= v <= 100, "from 0 to 100"),
    "tournament": (lambda v: 1 <= v <= 1_000_000, "from 1 to 1000000"),
    "truncation": (lambda v: 0 < v <= 1, "within (0, 1]"),
    "crossover": (lambda v: 0 <= v <= 1, "within [0, 1]"),
    "mutation": (lambda v: 0 <= v <= 1, "within [0, 1]"),
    "codon_max": (lambda v: 1 <= v <= CODON_MAX, f"from 1 to {CODON_MAX}"),
}
"""Each evolution setting's bounds and how to say them: the one table the language, the
command-line overrides, sweeps and ``spec.json`` are checked against."""


def out_of_bounds(key: str, value: float) -> str | None:
    """``"must be at least 1"``-style text when ``value`` is outside ``key``'s bounds, else None."""
    check, bounds = EVOLUTION_BOUNDS[key]
    return None if check(value) else f"must be {bounds}"


CROSSOVER_OPERATORS = ("onepoint within used", "variable within used", "onepoint within genome")
"""Crossover operators as the evolution block writes them: PonyGE2's fixed and variable one-point
crossover with cuts within each parent's used codons, and one cut anywhere in the genome (with the
placement rows cut at a point of their own, MazeGen's first operator)."""

MUTATION_OPERATORS = ("within used", "within genome")
"""Where int-flip mutation applies: the used codons (and the placement rows of the elements the
individual has), as PonyGE2 does, or every codon and placement gene."""

FIRST_OPERATORS = {"crossover_operator": "onepoint within genome", "mutation_operator": "within genome"}
"""The operators of MazeGen before they were a setting: what a ``spec.json`` without them ran."""


@dataclass(frozen=True)
class Evolution:
    """Evolution settings (defaults follow the paper's Table 1, operators measured best in
    ``benchmarks/quality.py``).

    Raises:
        ValueError: for a setting outside its bounds (:data:`EVOLUTION_BOUNDS`) or an
            unknown selection, operator or consume mode.
    """

    population: int = 1000
    generations: int = 15
    genome: int = 32
    selection: str = "truncation"
    truncation: float = 0.1
    tournament: int = 3
    crossover: float = 0.9
    mutation: float = 0.05
    crossover_operator: str = "variable within used"
    mutation_operator: str = "within genome"
    elitism: int = 1
    runs: int = 1
    seed: int = 1
    codon_max: int = 255
    wraps: int = 0
    consume: str = "eager"
    best: int = 10

    def __post_init__(self) -> None:
        for key in EVOLUTION_BOUNDS:
            value = getattr(self, key)
            problem = out_of_bounds(key, value)
            if problem is not None:
                raise ValueError(f"{key} {problem}, got {value}")
        if self.population * self.genome > MAX_CODONS:
            raise ValueError(
                f"population x genome must be at most {MAX_CODONS} codons, got "
                f"{self.population} x {self.genome}"
            )
        if self.selection not in ("truncation", "tournament"):
            raise ValueError(f"selection must be truncation or tournament, got {self.selection!r}")
        if self.consume not in ("eager", "lazy"):
            raise ValueError(f"consume must be eager or lazy, got {self.consume!r}")
        if self.crossover_operator not in CROSSOVER_OPERATORS:
            raise ValueError(f"crossover operator must be one of {CROSSOVER_OPERATORS}")
        if self.mutation_operator not in MUTATION_OPERATORS:
            raise ValueError(f"mutation operator must be one of {MUTATION_OPERATORS}")


@dataclass(frozen=True)
class Spec:
    """A whole resolved specification."""

    name: str
    source: str
    elements: tuple[ElementType, ...]
    arena: Arena
    scenario: Scenario
    fitness: tuple[FitnessTerm, ...]
    evolution: Evolution = field(default_factory=Evolution)
    robot: Robot | None = None

    def element(self, name: str) -> ElementType:
        """Return the element type called ``name``."""
        for element in self.elements:
            if element.name == name:
                return element
        raise KeyError(name)

    @property
    def scenario_elements(self) -> tuple[ElementType, ...]:
        """The element types the scenario uses, in its order (id = index)."""
        return tuple(self.element(name) for name in self.scenario.elements)

    @property
    def row_tokens(self) -> tuple[tuple[str, int, int, int], ...]:
        """Each row as the mapping reads it: its name, its members' type id, its fewest and most members."""
        ids = self.scenario.elements
        return tuple((row.name, ids.index(row.member), *row.count) for row in self.scenario.rows)

    @property
    def robot_or_default(self) -> Robot:
        """The robot the spec drives: its robot block's, or the arena's default (:func:`robot_for`)."""
        return self.robot if self.robot is not None else robot_for(self.arena)

    @property
    def drive_controllers(self) -> tuple[str, ...]:
        """The controllers the drive terms name, each once, in order (none: the spec drives no robot)."""
        named = (name for term in self.fitness if term.kind == "drive" for name in term.controllers)
        return tuple(dict.fromkeys(named))

    def with_evolution(self, **changes: Any) -> Spec:
        """Return a copy with some evolution settings replaced."""
        changes = {k: v for k, v in changes.items() if v is not None}
        return dataclasses.replace(self, evolution=dataclasses.replace(self.evolution, **changes))

    def to_json(self) -> str:
        """Serialise to deterministic JSON text."""
        body = {"format": "mazegen-spec", "version": SPEC_FORMAT_VERSION, **dataclasses.asdict(self)}
        for term in body["fitness"]:  # a spec without plug-ins reads as it did before they came
            if term["plugin"] is None:
                del term["plugin"]
        if body["robot"] is not None and body["robot"]["contact"] == "end":  # likewise before contacts
            del body["robot"]["contact"]
        if body["robot"] is not None and body["robot"]["footprint"] is None:  # likewise before boxes
            del body["robot"]["footprint"]
        if body["arena"]["base"] is None:  # likewise before base maps and zones
            del body["arena"]["base"]
        for key in ("zones", "stations", "tasks"):  # likewise before zones and tasks
            if not body["arena"][key]:
                del body["arena"][key]
        for term in body["fitness"]:
            if term["tasks"] == "mean":
                del term["tasks"]
        for element in body["elements"]:  # likewise before steps and walls
            for key, default in STRUCTURE_DEFAULTS.items():
                if element[key] == default:
                    del element[key]
        for key in ("rows", "listed", "required"):  # likewise before rows and required elements
            if not body["scenario"][key]:
                del body["scenario"][key]
        return json.dumps(body, indent=2, sort_keys=True, allow_nan=False) + "\n"

    @classmethod
    def from_json(cls, text: str) -> Spec:
        """Rebuild a Spec from :meth:`to_json` output."""
        data = json_value(text)
        data.pop("format", None)
        data.pop("version", None)
        return _spec_from_dict(data)


def _points(items: Any) -> tuple[Point, ...]:
    return tuple((float(x), float(y)) for x, y in items)


def _pair(item: Any) -> tuple[float, float]:
    return (float(item[0]), float(item[1]))


def _optional_pair(item: Any) -> tuple[float, float] | None:
    return None if item is None else _pair(item)


def _spec_from_dict(data: dict[str, Any]) -> Spec:
    elements = tuple(
        ElementType(
            name=e["name"],
            shape=e["shape"],
            parts=tuple(Part(_points(p["unit"]), _points(p["offset"])) for p in e["parts"]),
            size=_pair(e["size"]),
            size2=_optional_pair(e["size2"]),
            rotations=tuple(float(r) for r in e["rotations"]),
            rotation_range=_optional_pair(e["rotation_range"]),
            colour=e["colour"],
            semantic_class=e["semantic_class"],
            height=float(e["height"]),
            **{key: e.get(key, default) for key, default in STRUCTURE_DEFAULTS.items()},
        )
        for e in data["elements"]
    )
    a = data["arena"]
    arena = Arena(
        a["name"],
        float(a["width"]),
        float(a["height"]),
        a["unit"],
        _pair(a["start"]),
        _pair(a["goal"]),
        float(a["robot_radius"]),
        None if a.get("grid") is None else float(a["grid"]),
        _base_from_dict(a.get("base")),
        tuple(
            Zone(
                z["name"],
                z["rule"],
                _points(z["outline"]),
                tuple(_points(p) for p in z["parts"]),
                tuple(z["types"]),
            )
            for z in a.get("zones", ())
        ),
        tuple(Station(t["name"], _pair(t["point"]), t["heading"]) for t in a.get("stations", ())),
        tuple(
            Task(t["name"], _pair(t["start"]), _pair(t["goal"]), t["start_heading"], t["goal_heading"])
            for t in a.get("tasks", ())
        ),
    )
    s = data["scenario"]
    placement = s["placement"]
    scenario = Scenario(
        name=s["name"],
        arena=s["arena"],
        elements=tuple(s["elements"]),
        grammar=s["grammar"],
        custom_rules=tuple((lhs, tuple(alts)) for lhs, alts in s["custom_rules"]),
        max_elements=int(s["max_elements"]),
        placement=None
        if placement is None
        else GrammarPlacement(
            tuple(placement["sizes"]), float(placement["scale"]), tuple(placement["positions"])
        ),
        required=tuple((str(name), int(count), bool(exact)) for name, count, exact in s.get("required", ())),
        rows=tuple(_row_from_dict(row) for row in s.get("rows", ())),
        listed=tuple(s.get("listed", ())),
    )
    fitness = tuple(
        FitnessTerm(
            **{
                **t,
                "target": _optional_pair(t.get("target")),
                "controllers": tuple(t.get("controllers", ())),
                "plugin": _plugin_from_dict(t.get("plugin")),
            }
        )
        for t in data["fitness"]
    )
    return Spec(
        data["name"],
        data["source"],
        elements,
        arena,
        scenario,
        fitness,
        Evolution(**{**FIRST_OPERATORS, **data["evolution"]}),
        _robot_from_dict(data.get("robot")),
    )


def _row_from_dict(data: dict[str, Any]) -> Row:
    count = data["count"]
    return Row(
        name=data["name"],
        member=data["member"],
        count=(int(count[0]), int(count[1])),
        spacing=_pair(data["spacing"]),
        spacing_step=data["spacing_step"],
        rotations=tuple(float(r) for r in data["rotations"]),
        rotation_range=_optional_pair(data["rotation_range"]),
    )


def _base_from_dict(data: dict[str, Any] | None) -> BaseMap | None:
    if data is None:
        return None
    return BaseMap(**{**data, "origin": _pair(data["origin"])})


def _plugin_from_dict(data: dict[str, Any] | None) -> PluginMetric | None:
    if data is None:
        return None
    arguments = tuple((str(name), float(value)) for name, value in data["arguments"])
    return PluginMetric(data["source"], data["package"], arguments, tuple(data["types"]), data["where"])


def _robot_from_dict(data: dict[str, Any] | None) -> Robot | None:
    if data is None:
        return None
    controllers = tuple(
        ControllerSpec(c["name"], tuple((str(k), float(v)) for k, v in c["params"]))
        for c in data["controllers"]
    )
    footprint = data.get("footprint")
    if footprint is not None:
        footprint = (float(footprint[0]), float(footprint[1]))
    return Robot(**{**data, "controllers": controllers, "footprint": footprint})
