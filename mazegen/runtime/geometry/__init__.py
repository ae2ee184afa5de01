"""Shapes on the floor: the element table (each type's outline), world placement, overlap
tests, and the rasterised configuration space that navigation searches (bit rows, free rectangles).

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.geometry.cspace import Grid, grid_of, point_grid_of, unpack
    from mazegen.runtime.geometry.elements import ElementTable, element_bounds, world_parts, world_vertices
    from mazegen.runtime.geometry.overlap import elements_outside, overlapping_pairs

__all__ = [
    "ElementTable",
    "Grid",
    "element_bounds",
    "elements_outside",
    "grid_of",
    "overlapping_pairs",
    "point_grid_of",
    "unpack",
    "world_parts",
    "world_vertices",
]

__getattr__ = lazy_names(
    __name__,
    {
        "cspace": ["Grid", "grid_of", "point_grid_of", "unpack"],
        "elements": ["ElementTable", "element_bounds", "world_parts", "world_vertices"],
        "overlap": ["elements_outside", "overlapping_pairs"],
    },
)
