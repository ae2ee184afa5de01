"""Can a robot cross the floor, and how hard is it: reachability, path search and the
difficulty metrics, computed from a population (which knows nothing of them).

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.navigation.connectivity import Reach, reach
    from mazegen.runtime.navigation.difficulty import Survey, survey
    from mazegen.runtime.navigation.measures import navigation_of, reach_of, survey_of
    from mazegen.runtime.navigation.paths import Navigation, free_cells, navigate, path_of

__all__ = [
    "Navigation",
    "Reach",
    "Survey",
    "free_cells",
    "navigate",
    "navigation_of",
    "path_of",
    "reach",
    "reach_of",
    "survey",
    "survey_of",
]

__getattr__ = lazy_names(
    __name__,
    {
        "connectivity": ["Reach", "reach"],
        "difficulty": ["Survey", "survey"],
        "measures": ["navigation_of", "reach_of", "survey_of"],
        "paths": ["Navigation", "free_cells", "navigate", "path_of"],
    },
)
