"""The bundled controllers and their parameters: the one table the language, the simulator and
the docs read.

A parameter's default is in SI units (metres, seconds, radians); the simulator scales lengths to
the arena's unit (:func:`mazegen.spec.metres_per_unit`). A spec sets a parameter in the arena's
unit, like every other length it writes.
"""

from __future__ import annotations

from dataclasses import dataclass

LENGTH, SPEED, TIME, ANGLE, TURN, NUMBER = "m", "m/s", "s", "rad", "rad/s", ""
"""Units of parameters; lengths and speeds are scaled to the arena's unit."""


@dataclass(frozen=True)
class Parameter:
    """One parameter of a controller: its name in the spec, default (SI), unit and meaning."""

    name: str
    default: float
    unit: str
    doc: str
    low: float = 0.0
    high: float = 1e9

    @property
    def scaled(self) -> bool:
        """Whether the value is a length (or speed) that the arena's unit scales."""
        return self.unit in (LENGTH, SPEED)


@dataclass(frozen=True)
class BundledController:
    """A controller MazeGen ships: its name, whether it reads the lidar, what it is, where its
    parameters come from, and the parameters in the order the kernels read them."""

    name: str
    lidar: bool
    summary: str
    source: str
    parameters: tuple[Parameter, ...]

    def parameter(self, name: str) -> Parameter | None:
        """The parameter called ``name``, or None."""
        return next((p for p in self.parameters if p.name == name), None)


BUNDLED: dict[str, BundledController] = {
    "straight": BundledController(
        "straight",
        lidar=False,
        summary="turn toward the goal and drive at top speed: a lower bound no planner should lose to",
        source="a proportional heading controller",
        parameters=(
            Parameter("heading_gain", 2.0, NUMBER, "turn rate per radian of heading error", 0.0, 100),
            Parameter("turn_in_place", 0.785, ANGLE, "heading error to turn on the spot at", 0.0, 3.15),
        ),
    ),
    "dwa": BundledController(
        "dwa",
        lidar=False,
        summary="the dynamic window approach over a navigation function from the goal",
        source="the BARN challenge's move_base DWA baseline on a Clearpath Jackal",
        parameters=(
            Parameter("v_samples", 6, NUMBER, "speeds sampled in the dynamic window", 1, 100),
            Parameter("w_samples", 20, NUMBER, "turn rates sampled in the dynamic window", 1, 200),
            Parameter("horizon", 2.0, TIME, "how far ahead each sample is rolled out (sim_time)", 0.1, 60.0),
            Parameter("obstacle_weight", 0.1, NUMBER, "weight of the obstacle cost (occdist_scale)"),
            Parameter("path_weight", 0.75, NUMBER, "weight of the distance to the path (pdist_scale)"),
            Parameter("goal_weight", 1.0, NUMBER, "weight of the distance to the goal (gdist_scale)"),
            Parameter("inflation", 0.30, LENGTH, "obstacle cost is 0 this far from the robot's edge"),
            Parameter(
                "decay", 0.1, LENGTH, "obstacle cost falls by e over this gap (1 / cost_scaling_factor)", 1e-9
            ),
            Parameter(
                "resolution", 0.05, LENGTH, "costmap cell the path and goal distances are counted in", 1e-9
            ),
            Parameter("forward", 0.325, LENGTH, "turns on the spot face the goal this far ahead", 0.0),
            Parameter(
                "path_margin", 0.3, LENGTH, "the path keeps this far beyond the radius where it can", 0.0
            ),
        ),
    ),
    "purepursuit": BundledController(
        "purepursuit",
        lidar=False,
        summary="regulated pure pursuit along the path MazeGen finds",
        source="nav2's regulated pure pursuit controller",
        parameters=(
            Parameter("lookahead", 0.6, LENGTH, "fixed lookahead distance, when lookahead_time is 0", 0.0),
            Parameter("min_lookahead", 0.3, LENGTH, "shortest lookahead", 0.0),
            Parameter("max_lookahead", 0.9, LENGTH, "longest lookahead", 0.0),
            Parameter("lookahead_time", 1.5, TIME, "lookahead = speed × this, clamped (0: fixed)", 0.0, 60.0),
            Parameter("min_radius", 0.9, LENGTH, "turns tighter than this radius slow the robot", 0.0),
            Parameter("rotate_to_heading", 0.785, ANGLE, "heading error to turn on the spot at", 0.0, 3.15),
            Parameter("regulated_min_speed", 0.25, SPEED, "slowest speed the turn regulation slows to", 0.0),
            Parameter("path_margin", 0.3, LENGTH, "the path keeps this far past the radius if it can", 0.0),
        ),
    ),
    "vfh": BundledController(
        "vfh",
        lidar=True,
        summary="the vector field histogram: steers through the widest lidar gap toward the goal, no map",
        source="Borenstein and Koren, IEEE T-RA 1991",
        parameters=(
            Parameter("sectors", 72, NUMBER, "angular sectors of the polar histogram", 8, 720),
            Parameter("threshold", 0.5, NUMBER, "density above which a sector is blocked", 0.0, 1e6),
            Parameter("safety", 0.2, LENGTH, "distance kept from obstacles beyond the robot's radius", 0.0),
            Parameter("window", 1.5, LENGTH, "readings farther than this do not block", 0.0),
            Parameter("wide", 1.571, ANGLE, "openings wider than this are entered half of it in", 0.0, 6.3),
            Parameter(
                "heading_gain", 2.0, NUMBER, "turn rate per radian between heading and steer", 0.0, 100
            ),
        ),
    ),
}
"""The bundled controllers by name."""
