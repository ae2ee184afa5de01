"""Scenario documents, MazeGen's output: made from a population and read back, their
validation rules, the best distinct scenarios of a run, scoring documents under a spec, a
scenario file read with its spec (a floor), documents imported from occupancy maps, and the layout
of the folders that hold them.

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.documents._best import best_documents, row_document
    from mazegen.runtime.documents._classes import (
        ClassGroup,
        Classification,
        FloorClasses,
        classify,
        equivalence_groups,
        equivalence_key,
        floor_classes,
    )
    from mazegen.runtime.documents._driving import (
        Drive,
        Floors,
        Summary,
        drive_floors,
        driving_robot,
        floor_batches,
        spec_controllers,
        summaries,
        with_drives,
    )
    from mazegen.runtime.documents._fitting import (
        Agreement,
        Fit,
        FitProblem,
        Measured,
        SearchSpace,
        fit_controller,
        read_measured,
        robot_block,
    )
    from mazegen.runtime.documents._floor import Floor, floor_of, load_floor, safe_name
    from mazegen.runtime.documents._folders import RunDirectory, SuiteDirectory, scenario_files
    from mazegen.runtime.documents._import import ImportedMap
    from mazegen.runtime.documents._scenario import (
        check_complete,
        checked_document,
        completed_document,
        dumps,
        has_parts,
        population_from_document,
        read_document,
        scenario_document,
    )
    from mazegen.runtime.documents._scenario_rules import check_document
    from mazegen.runtime.documents._scoring import Scored, Scorer

__all__ = [
    "Agreement",
    "ClassGroup",
    "Classification",
    "Drive",
    "Fit",
    "FitProblem",
    "Floor",
    "FloorClasses",
    "Floors",
    "ImportedMap",
    "Measured",
    "RunDirectory",
    "Scored",
    "Scorer",
    "SearchSpace",
    "SuiteDirectory",
    "Summary",
    "best_documents",
    "check_complete",
    "check_document",
    "checked_document",
    "classify",
    "completed_document",
    "drive_floors",
    "driving_robot",
    "dumps",
    "equivalence_groups",
    "equivalence_key",
    "fit_controller",
    "floor_batches",
    "floor_classes",
    "floor_of",
    "has_parts",
    "load_floor",
    "population_from_document",
    "read_document",
    "read_measured",
    "robot_block",
    "row_document",
    "safe_name",
    "scenario_document",
    "scenario_files",
    "spec_controllers",
    "summaries",
    "with_drives",
]

__getattr__ = lazy_names(
    __name__,
    {
        "_best": ["best_documents", "row_document"],
        "_classes": [
            "ClassGroup",
            "Classification",
            "classify",
            "equivalence_groups",
            "equivalence_key",
            "floor_classes",
            "FloorClasses",
        ],
        "_driving": [
            "Drive",
            "drive_floors",
            "driving_robot",
            "floor_batches",
            "Floors",
            "spec_controllers",
            "summaries",
            "Summary",
            "with_drives",
        ],
        "_floor": ["Floor", "floor_of", "load_floor", "safe_name"],
        "_folders": ["RunDirectory", "scenario_files", "SuiteDirectory"],
        "_fitting": [
            "Agreement",
            "Fit",
            "FitProblem",
            "Measured",
            "SearchSpace",
            "fit_controller",
            "read_measured",
            "robot_block",
        ],
        "_import": ["ImportedMap"],
        "_scenario": [
            "check_complete",
            "checked_document",
            "completed_document",
            "dumps",
            "has_parts",
            "population_from_document",
            "read_document",
            "scenario_document",
        ],
        "_scenario_rules": ["check_document"],
        "_scoring": ["Scored", "Scorer"],
    },
)
