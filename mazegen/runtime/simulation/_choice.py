"""Which controller drives: a bundled one with its parameters, or a user's policy.

A controller is named by a bundled name (:data:`mazegen.controllers.BUNDLED`), by a dotted path
``package.module:name`` to a user's policy, or by a name an installed package registers under
the ``mazegen.controllers`` entry point group; or it is given as a policy object directly. A
bundled controller's parameters are its defaults (SI, lengths scaled to the arena's unit by
:func:`mazegen.spec.metres_per_unit`) overridden by the spec's, which are in arena units.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from mazegen import plugins
from mazegen.controllers import BUNDLED, LIDAR, PATH
from mazegen.errors import MazeError
from mazegen.policies import SEARCHED, import_policy_module, is_policy_path, malformed_path
from mazegen.spec import Arena, ControllerSpec, Robot, metres_per_unit


@dataclass(frozen=True)
class Choice:
    """A resolved controller.

    Attributes:
        name: What the episodes are labelled with.
        code: The bundled controller's code in the episode loop, -1 for a user's policy.
        params: ``float64[:]`` the bundled controller's parameters, in arena units.
        reads: What it reads of :data:`~mazegen.controllers.LIDAR`, ``PATH`` and ``FIELDS`` (a
            user's policy: the lidar).
        margin: How much wider than the robot the path it reads is searched for (0: MazeGen's own
            path), or None when it reads no path.
        reach: How far its lidar is cast: the robot's range, or less where it reads less.
        policy: The user's batch policy, or None.
    """

    name: str
    code: int
    params: np.ndarray
    reads: frozenset[str]
    margin: float | None
    reach: float
    policy: Callable[[Any], Any] | None = None

    @property
    def lidar(self) -> bool:
        """Whether it reads the lidar."""
        return LIDAR in self.reads


def choose(controller: str | ControllerSpec | Callable[[Any], Any], robot: Robot, arena: Arena) -> Choice:
    """Resolve ``controller`` (a name, a spec's settings, or a policy object) for ``robot`` on ``arena``."""
    if isinstance(controller, ControllerSpec):
        name, overrides = controller.name, controller.params
    elif isinstance(controller, str):
        name, overrides = controller, robot.controller(controller).params
    elif callable(controller):
        label = getattr(controller, "__name__", type(controller).__name__)
        return _policy_choice(label, controller, robot)
    else:
        raise MazeError(f"a controller is a name or a policy, got {type(controller).__name__}")
    if name not in BUNDLED:
        if overrides:
            raise MazeError(f"controller {name} is a user's policy: it takes no parameters from the spec")
        return _policy_choice(name, load_policy(name), robot)
    row = BUNDLED[name]
    params = bundled_params(name, overrides, arena)
    margin = None
    if PATH in row.reads:
        margin = 0.0 if row.margin is None else float(params[row.index(row.margin)])
    reach = robot.lidar_range
    if row.window is not None:  # readings beyond its window change nothing: cast no farther
        reach = min(reach, float(params[row.index(row.window)]))
    return Choice(name, row.code, params, row.reads, margin, reach)


def _policy_choice(name: str, policy: Callable[[Any], Any], robot: Robot) -> Choice:
    return Choice(name, -1, np.zeros(0), frozenset({LIDAR}), None, robot.lidar_range, policy)


def bundled_params(name: str, overrides: tuple[tuple[str, float], ...], arena: Arena) -> np.ndarray:
    """Bundled controller ``name``'s parameters in its table's order, lengths in arena units."""
    entry = BUNDLED[name]
    units = 1.0 / metres_per_unit(arena)
    values = {p.name: p.default * (units if p.scaled else 1.0) for p in entry.parameters}
    for key, value in overrides:
        parameter = entry.parameter(key)
        if parameter is None:
            known = ", ".join(p.name for p in entry.parameters)
            raise MazeError(f"controller {name} has no parameter {key!r} (it has {known})")
        si = value / units if parameter.scaled else value
        if not parameter.low <= si <= parameter.high:
            raise MazeError(
                f"controller {name}'s {key} must be within [{parameter.low:g}, {parameter.high:g}] "
                f"{parameter.unit or ''}, got {si:g}".replace("  ", " ")
            )
        values[key] = float(value)
    return np.array([values[p.name] for p in entry.parameters], np.float64)


def load_policy(name: str) -> Callable[[Any], Any]:
    """The policy called ``name``: a dotted path ``package.module:attribute`` (its module looked for in
    :data:`mazegen.policies.SEARCHED`), or a name an installed package registers under the
    ``mazegen.controllers`` entry point group."""
    if ":" in name:
        if not is_policy_path(name):
            raise MazeError(malformed_path(name))
        module, _, attribute = name.partition(":")
        try:
            found: Any = import_policy_module(module)
            for part in attribute.split("."):
                found = getattr(found, part)
        except ModuleNotFoundError as error:  # the policy's module, or one it imports
            missing = error.name is not None and f"{module}.".startswith(f"{error.name}.")
            searched = f": a policy's module is looked for in {SEARCHED}" if missing else ""
            raise MazeError(f"controller {name}: cannot load it ({error}){searched}") from error
        except (Exception, SystemExit) as error:  # the user's module: its failure said in one line
            raise MazeError(f"controller {name}: cannot load it ({type(error).__name__}: {error})") from error
    else:
        plugin = plugins.find("controllers", name)
        if plugin is None:
            known = ", ".join(sorted(BUNDLED))
            raise MazeError(
                f"unknown controller {name!r}: not bundled ({known}), not a dotted path "
                "package.module:name, and no installed package registers it under "
                + plugins.GROUPS["controllers"]
            )
        found = plugin.load()
    if not callable(found):
        raise MazeError(f"controller {name} is not callable: a policy is called with the observations")
    return found
