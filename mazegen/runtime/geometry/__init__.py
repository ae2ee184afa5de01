"""Shapes on the floor: the element table (each type's outline), world placement, overlap
tests, and the rasterised configuration space that navigation searches (bit rows, free rectangles).

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.geometry._bits import ONE, is_set
    from mazegen.runtime.geometry._cspace import (
        Grid,
        cspace,
        elements_on_walls,
        floor_cells,
        grid_args,
        grid_of,
        is_free,
        point_grid_of,
        raster_arrays,
        straight_free,
        unpack,
    )
    from mazegen.runtime.geometry._elements import (
        ElementTable,
        element_bounds,
        world_element,
        world_parts,
        world_vertices,
    )
    from mazegen.runtime.geometry._overlap import elements_outside, overlapping_pairs
    from mazegen.runtime.geometry._rectangles import (
        ABOVE,
        BELOW,
        DOWN_COUNT,
        DOWN_FIRST,
        FIRST_COL,
        FIRST_ROW,
        LAST_COL,
        LAST_ROW,
        UP_COUNT,
        UP_FIRST,
        decompose,
        rectangle_arrays,
        row_runs_of,
        run_arrays,
        run_label_at,
        runs_per_row,
        same_as_below,
    )
    from mazegen.runtime.geometry._zones import ZoneArrays, elements_off_zones

__all__ = [
    "ABOVE",
    "BELOW",
    "DOWN_COUNT",
    "DOWN_FIRST",
    "FIRST_COL",
    "FIRST_ROW",
    "LAST_COL",
    "LAST_ROW",
    "ONE",
    "UP_COUNT",
    "UP_FIRST",
    "ElementTable",
    "Grid",
    "ZoneArrays",
    "cspace",
    "decompose",
    "element_bounds",
    "elements_off_zones",
    "elements_on_walls",
    "elements_outside",
    "floor_cells",
    "grid_args",
    "grid_of",
    "is_free",
    "is_set",
    "overlapping_pairs",
    "point_grid_of",
    "raster_arrays",
    "rectangle_arrays",
    "row_runs_of",
    "run_arrays",
    "run_label_at",
    "runs_per_row",
    "same_as_below",
    "straight_free",
    "unpack",
    "world_element",
    "world_parts",
    "world_vertices",
]

__getattr__ = lazy_names(
    __name__,
    {
        "_zones": ["ZoneArrays", "elements_off_zones"],
        "_bits": ["is_set", "ONE"],
        "_cspace": [
            "cspace",
            "elements_on_walls",
            "floor_cells",
            "Grid",
            "grid_args",
            "grid_of",
            "is_free",
            "point_grid_of",
            "raster_arrays",
            "straight_free",
            "unpack",
        ],
        "_elements": ["element_bounds", "ElementTable", "world_element", "world_parts", "world_vertices"],
        "_overlap": ["elements_outside", "overlapping_pairs"],
        "_rectangles": [
            "ABOVE",
            "BELOW",
            "decompose",
            "DOWN_COUNT",
            "DOWN_FIRST",
            "FIRST_COL",
            "FIRST_ROW",
            "LAST_COL",
            "LAST_ROW",
            "rectangle_arrays",
            "row_runs_of",
            "run_arrays",
            "run_label_at",
            "runs_per_row",
            "same_as_below",
            "UP_COUNT",
            "UP_FIRST",
        ],
    },
)
