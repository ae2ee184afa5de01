"""The bundled controllers: one row each, the one table the language, the simulator and the docs
read.

A row says everything about a controller but its kernel's code: the code the episode loop branches
on, the kernel, what the kernel reads, and its parameters in the order the kernel reads them. A
parameter's default is in SI units (metres, seconds, radians); the simulator scales lengths to the
arena's unit (:func:`mazegen.spec.metres_per_unit`). A spec sets a parameter in the arena's unit,
like every other length it writes. ``tests/runtime/simulation/test_registry.py`` checks the kernels
against the rows.
"""

from __future__ import annotations

from dataclasses import dataclass

LENGTH, SPEED, TIME, ANGLE, TURN, NUMBER = "m", "m/s", "s", "rad", "rad/s", ""
"""Units of parameters; lengths and speeds are scaled to the arena's unit."""

LIDAR, PATH, FIELDS, COSTMAP = "lidar", "path", "fields", "costmap"
"""What a kernel may read besides the pose, the goal and the robot's limits: the lidar's scan,
MazeGen's path, the navigation and clearance fields, and a move_base costmap with its planners'
fields (all at the controller's own ``resolution``)."""

LIMITS = (
    "max_speed", "min_speed", "max_turn", "accel", "turn_accel", "step", "radius", "goal_tolerance",
    "length", "width",
)  # fmt: skip
"""The robot's limits in the order of the ``limits`` array every kernel reads (and a user's policy
sees): the spec's robot block, the arena's robot radius, and the box the simulator collides (its
``footprint``; length and width 0 for the disc of the radius)."""


@dataclass(frozen=True)
class Parameter:
    """One parameter of a controller: its name in the spec, default (SI), unit, meaning, bounds
    (SI) and where its default comes from."""

    name: str
    default: float
    unit: str
    doc: str
    low: float = 0.0
    high: float = 1e9
    source: str = ""

    @property
    def scaled(self) -> bool:
        """Whether the value is a length (or speed) that the arena's unit scales."""
        return self.unit in (LENGTH, SPEED)


@dataclass(frozen=True)
class BundledController:
    """A controller MazeGen ships.

    Attributes:
        name: Its name in a spec and on the command line.
        code: The argument slot of its parameters in the episode loop's dispatch
            (``command`` in ``mazegen/runtime/simulation/_loop.py``): 0, 1, 2 … in turn.
        kernel: Its kernel, ``module.function`` in ``mazegen/runtime/simulation`` (numba names the
            kernel's cache files so).
        reads: What the kernel reads of :data:`LIDAR`, :data:`PATH`, :data:`FIELDS` and :data:`COSTMAP`.
        limits: The robot's limits (:data:`LIMITS`) the kernel reads.
        summary: What it does, in a line.
        source: Where it comes from.
        parameters: Its parameters, in the order the kernel reads them.
        margin: The parameter saying how much wider a robot the path it reads is searched for
            (None: MazeGen's own path).
        window: The parameter beyond which it ignores lidar readings, so that the lidar is cast no
            farther (None: the lidar's whole range).
    """

    name: str
    code: int
    kernel: str
    reads: frozenset[str]
    limits: tuple[str, ...]
    summary: str
    source: str
    parameters: tuple[Parameter, ...]
    margin: str | None = None
    window: str | None = None

    @property
    def lidar(self) -> bool:
        """Whether it reads the lidar."""
        return LIDAR in self.reads

    def parameter(self, name: str) -> Parameter | None:
        """The parameter called ``name``, or None."""
        return next((p for p in self.parameters if p.name == name), None)

    def index(self, name: str) -> int:
        """The position of parameter ``name`` in the kernel's ``params``."""
        return [p.name for p in self.parameters].index(name)


_SAMPLES = (
    Parameter("v_samples", 6, NUMBER, "speeds sampled in the dynamic window", 1, 100, "BARN's vx_samples"),
    Parameter(
        "w_samples", 20, NUMBER, "turn rates sampled in the dynamic window", 1, 200, "BARN's vtheta_samples"
    ),
)
"""The dynamic window's samples, as both DWA controllers take them."""

BUNDLED: dict[str, BundledController] = {
    "straight": BundledController(
        "straight",
        code=0,
        kernel="_controllers.straight_command",
        reads=frozenset(),
        limits=("max_speed",),
        summary="turn toward the goal and drive at top speed: a lower bound no planner should lose to",
        source="a proportional heading controller",
        parameters=(
            Parameter(
                "heading_gain", 2.0, NUMBER, "turn rate per radian of heading error", 0.0, 100, "MazeGen's"
            ),
            Parameter(
                "turn_in_place", 0.785, ANGLE, "heading error to turn on the spot at", 0.0, 3.15, "MazeGen's"
            ),
        ),
    ),
    "dwa": BundledController(
        "dwa",
        code=2,
        kernel="_dwa.dwa_command",
        reads=frozenset({PATH, FIELDS}),
        limits=("max_speed", "min_speed", "max_turn", "accel", "turn_accel", "step", "radius"),
        summary="the dynamic window approach over a navigation function from the goal",
        source="the BARN challenge's move_base DWA baseline on a Clearpath Jackal",
        parameters=(
            *_SAMPLES,
            Parameter(
                "horizon",
                2.0,
                TIME,
                "how far ahead each sample is rolled out (sim_time)",
                0.1,
                60.0,
                "BARN's sim_time",
            ),
            Parameter(
                "obstacle_weight",
                0.1,
                NUMBER,
                "weight of the obstacle cost (occdist_scale)",
                source="BARN's occdist_scale",
            ),
            Parameter(
                "path_weight",
                0.75,
                NUMBER,
                "weight of the distance to the path (pdist_scale)",
                source="BARN's pdist_scale",
            ),
            Parameter(
                "goal_weight",
                1.0,
                NUMBER,
                "weight of the distance to the goal (gdist_scale)",
                source="BARN's gdist_scale",
            ),
            Parameter(
                "inflation",
                0.30,
                LENGTH,
                "obstacle cost is 0 this far from the robot's edge",
                source="BARN's inflation_radius",
            ),
            Parameter(
                "decay",
                0.1,
                LENGTH,
                "obstacle cost falls by e over this gap (1 / cost_scaling_factor)",
                1e-9,
                source="costmap_2d's default cost_scaling_factor 10",
            ),
            Parameter(
                "resolution",
                0.05,
                LENGTH,
                "costmap cell the path and goal distances are counted in",
                1e-9,
                source="BARN's local costmap",
            ),
            Parameter(
                "forward",
                0.325,
                LENGTH,
                "turns on the spot face the goal this far ahead",
                0.0,
                source="dwa_local_planner's forward_point_distance",
            ),
            Parameter(
                "path_margin",
                0.3,
                LENGTH,
                "the path keeps this far beyond the radius where it can",
                0.0,
                source="BARN's inflation radius",
            ),
        ),
        margin="path_margin",
    ),
    "purepursuit": BundledController(
        "purepursuit",
        code=1,
        kernel="_controllers.purepursuit_command",
        reads=frozenset({PATH}),
        limits=("max_speed", "max_turn"),
        summary="regulated pure pursuit along the path MazeGen finds",
        source="nav2's regulated pure pursuit controller",
        parameters=(
            Parameter(
                "lookahead",
                0.6,
                LENGTH,
                "fixed lookahead distance, when lookahead_time is 0",
                0.0,
                source="nav2's lookahead_dist",
            ),
            Parameter(
                "min_lookahead", 0.3, LENGTH, "shortest lookahead", 0.0, source="nav2's min_lookahead_dist"
            ),
            Parameter(
                "max_lookahead", 0.9, LENGTH, "longest lookahead", 0.0, source="nav2's max_lookahead_dist"
            ),
            Parameter(
                "lookahead_time",
                1.5,
                TIME,
                "lookahead = speed × this, clamped (0: fixed)",
                0.0,
                60.0,
                "nav2's lookahead_time",
            ),
            Parameter(
                "min_radius",
                0.9,
                LENGTH,
                "turns tighter than this radius slow the robot",
                0.0,
                source="nav2's regulated_linear_scaling_min_radius",
            ),
            Parameter(
                "rotate_to_heading",
                0.785,
                ANGLE,
                "heading error to turn on the spot at",
                0.0,
                3.15,
                "nav2's rotate_to_heading_min_angle",
            ),
            Parameter(
                "regulated_min_speed",
                0.25,
                SPEED,
                "slowest speed the turn regulation slows to",
                0.0,
                source="nav2's regulated_linear_scaling_min_speed",
            ),
            Parameter(
                "path_margin",
                0.3,
                LENGTH,
                "the path keeps this far past the radius if it can",
                0.0,
                source="BARN's inflation radius",
            ),
        ),
        margin="path_margin",
    ),
    "vfh": BundledController(
        "vfh",
        code=3,
        kernel="_vfh.vfh_command",
        reads=frozenset({LIDAR}),
        limits=("max_speed", "max_turn", "radius"),
        summary="the vector field histogram: steers through the widest lidar gap toward the goal, no map",
        source="Borenstein and Koren, IEEE T-RA 1991",
        parameters=(
            Parameter(
                "sectors",
                72,
                NUMBER,
                "angular sectors of the polar histogram",
                8,
                720,
                "the paper's 5° sectors",
            ),
            Parameter(
                "threshold",
                0.5,
                NUMBER,
                "density above which a sector is blocked",
                0.0,
                1e6,
                "blocked when an enlarged reading is within half the window",
            ),
            Parameter(
                "safety",
                0.2,
                LENGTH,
                "distance kept from obstacles beyond the robot's radius",
                0.0,
                source="VFH+'s d_s",
            ),
            Parameter(
                "window",
                1.5,
                LENGTH,
                "readings farther than this do not block",
                0.0,
                source="the paper's active window",
            ),
            Parameter(
                "wide",
                1.571,
                ANGLE,
                "openings wider than this are entered half of it in",
                0.0,
                6.3,
                "the paper's s_max = 18 sectors of 5°",
            ),
            Parameter(
                "heading_gain",
                2.0,
                NUMBER,
                "turn rate per radian between heading and steer",
                0.0,
                100,
                "as straight's",
            ),
        ),
        window="window",
    ),
    "movebase": BundledController(
        "movebase",
        code=4,
        kernel="_movebase.movebase_command",
        reads=frozenset({COSTMAP}),
        limits=("max_speed", "max_turn", "accel", "turn_accel"),
        summary="move_base as BARN ran it: navfn replanning on an inflated costmap, base_local_planner's DWA",
        source="move_base with navfn and base_local_planner (dwa: true) on a Jackal, as BARN configured it",
        parameters=(
            *_SAMPLES,
            Parameter(
                "horizon", 2.0, TIME, "how far ahead each sample is rolled out", 0.1, 60.0, "BARN's sim_time"
            ),
            Parameter(
                "granularity",
                0.02,
                LENGTH,
                "longest step between a rollout's checked poses",
                1e-6,
                source="BARN's sim_granularity",
            ),
            Parameter(
                "angular_granularity",
                0.02,
                ANGLE,
                "largest turn between checked poses",
                1e-6,
                6.3,
                "BARN's angular_sim_granularity",
            ),
            Parameter(
                "period",
                0.05,
                TIME,
                "the window's reach: the accelerations over this",
                1e-6,
                10.0,
                "BARN's 1 / controller_frequency",
            ),
            Parameter("min_vel", 0.1, SPEED, "slowest forward speed sampled", 0.0, source="BARN's min_vel_x"),
            Parameter(
                "min_in_place_turn",
                0.314,
                TURN,
                "slowest turn on the spot",
                0.0,
                100.0,
                "BARN's min_in_place_vel_theta",
            ),
            Parameter(
                "path_weight",
                0.75,
                NUMBER,
                "weight of the distance to the plan",
                source="BARN's pdist_scale",
            ),
            Parameter(
                "goal_weight",
                1.0,
                NUMBER,
                "weight of the distance to the goal",
                source="BARN's gdist_scale",
            ),
            Parameter(
                "obstacle_weight",
                0.1,
                LENGTH,
                "goal distance each unit of cost of the costliest cell under the footprint weighs as",
                source="BARN's occdist_scale",
            ),
            Parameter(
                "heading_lookahead",
                0.325,
                LENGTH,
                "turns on the spot face the goal this far ahead",
                0.0,
                source="BARN's heading_lookahead",
            ),
            Parameter(
                "oscillation_reset",
                0.05,
                LENGTH,
                "drive this far to lift the oscillation guard",
                0.0,
                source="BARN's oscillation_reset_dist",
            ),
            Parameter(
                "escape_vel",
                -0.5,
                SPEED,
                "speed it backs up at when nothing else is valid (a robot that cannot reverse stands)",
                -100.0,
                0.0,
                "BARN's escape_vel",
            ),
            Parameter(
                "escape_reset_dist",
                0.1,
                LENGTH,
                "backing up ends after this far",
                0.0,
                source="BARN's escape_reset_dist",
            ),
            Parameter(
                "escape_reset_theta",
                0.1,
                ANGLE,
                "or after turning this much",
                0.0,
                6.3,
                "BARN's escape_reset_theta",
            ),
            Parameter(
                "length", 0.42, LENGTH, "footprint length, front to back", 0.0, source="BARN's footprint"
            ),
            Parameter("width", 0.33, LENGTH, "footprint width", 0.0, source="BARN's footprint"),
            Parameter(
                "padding",
                0.1,
                LENGTH,
                "added to the footprint on every side",
                0.0,
                source="BARN's footprint_padding",
            ),
            Parameter(
                "inflation",
                0.30,
                LENGTH,
                "cells this near an obstacle cost more than 0",
                0.0,
                source="BARN's inflation_radius",
            ),
            Parameter(
                "decay",
                0.1,
                LENGTH,
                "inflation cost falls by e over this",
                1e-9,
                source="costmap_2d's default cost_scaling_factor 10",
            ),
            Parameter("resolution", 0.05, LENGTH, "costmap cell", 1e-6, source="BARN's costmap resolution"),
        ),
    ),
}
"""The bundled controllers by name."""

BY_CODE = tuple(sorted(BUNDLED.values(), key=lambda row: row.code))
"""The rows in the order of their codes: the episode loop's slots."""
