"""Occupancy maps: the files they come in (map_server's YAML and image, grids of cells, BARN's worlds),
what their cells mean, their cells as shapes, a map as the base of an arena, and tasks drawn where a
robot stands on a floor.

A plain package every layer may use: the language reads an arena's map when it loads the spec, the
runtime's rooms read the cells it keeps.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.maps._base import (
        UNKNOWN,
        base_cells,
        base_digest,
        base_map_of,
        base_on_grid,
        free_box,
        point_on_walls,
        read_base_map,
        wall_boxes,
    )
    from mazegen.maps._cells import Cells, near_cells, wall_rectangles
    from mazegen.maps._occupancy import OccupancyMap, checked_resolution, read_occupancy_map, scenario_name
    from mazegen.maps._tasks import draw_tasks, standing_cells

__all__ = [
    "UNKNOWN",
    "Cells",
    "OccupancyMap",
    "base_cells",
    "base_digest",
    "base_map_of",
    "base_on_grid",
    "checked_resolution",
    "draw_tasks",
    "free_box",
    "near_cells",
    "point_on_walls",
    "read_base_map",
    "read_occupancy_map",
    "scenario_name",
    "standing_cells",
    "wall_boxes",
    "wall_rectangles",
]

__getattr__ = lazy_names(
    __name__,
    {
        "_base": [
            "UNKNOWN",
            "base_cells",
            "base_digest",
            "base_map_of",
            "base_on_grid",
            "free_box",
            "point_on_walls",
            "read_base_map",
            "wall_boxes",
        ],
        "_cells": ["Cells", "near_cells", "wall_rectangles"],
        "_occupancy": ["OccupancyMap", "checked_resolution", "read_occupancy_map", "scenario_name"],
        "_tasks": ["draw_tasks", "standing_cells"],
    },
)
