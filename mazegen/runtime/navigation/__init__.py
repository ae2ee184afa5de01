"""Can a robot cross the floor, and how hard is it: reachability, path search and the
difficulty metrics, computed from a population (which knows nothing of them).

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.navigation._calibration import spearman
    from mazegen.runtime.navigation._class_counts import class_counts
    from mazegen.runtime.navigation._classes import PathClass, Topology, floor_topology, topology
    from mazegen.runtime.navigation._connectivity import Reach, reach
    from mazegen.runtime.navigation._difficulty import Survey, survey
    from mazegen.runtime.navigation._measures import (
        class_counts_of,
        corner_paths_of,
        navigation_of,
        reach_of,
        reachable_of,
        survey_of,
        task_views,
    )
    from mazegen.runtime.navigation._paths import (
        Navigation,
        copy_points,
        free_cells,
        kernel_args,
        navigate,
        path_of,
        paths_of,
        route,
        route_scratch,
    )

__all__ = [
    "Navigation",
    "PathClass",
    "Reach",
    "Survey",
    "Topology",
    "class_counts",
    "class_counts_of",
    "copy_points",
    "corner_paths_of",
    "floor_topology",
    "free_cells",
    "kernel_args",
    "navigate",
    "navigation_of",
    "path_of",
    "paths_of",
    "reach",
    "reach_of",
    "reachable_of",
    "route",
    "route_scratch",
    "spearman",
    "survey",
    "survey_of",
    "task_views",
    "topology",
]

__getattr__ = lazy_names(
    __name__,
    {
        "_calibration": ["spearman"],
        "_class_counts": ["class_counts"],
        "_classes": ["floor_topology", "PathClass", "Topology", "topology"],
        "_connectivity": ["Reach", "reach"],
        "_difficulty": ["Survey", "survey"],
        "_measures": [
            "class_counts_of",
            "corner_paths_of",
            "navigation_of",
            "reach_of",
            "reachable_of",
            "survey_of",
            "task_views",
        ],
        "_paths": [
            "copy_points",
            "free_cells",
            "kernel_args",
            "navigate",
            "Navigation",
            "path_of",
            "paths_of",
            "route",
            "route_scratch",
        ],
    },
)
