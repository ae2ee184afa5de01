"""Scenario documents, MazeGen's output: made from a population and read back, their
validation rules, the best distinct scenarios of a run, scoring documents under a spec, a
scenario file read with its spec (a floor), and the layout of the folders that hold them.

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.documents.best import best_documents
    from mazegen.runtime.documents.floor import Floor, load_floor
    from mazegen.runtime.documents.folders import RunDirectory, SuiteDirectory, scenario_files
    from mazegen.runtime.documents.scenario import (
        dumps,
        population_from_document,
        read_document,
        scenario_document,
    )
    from mazegen.runtime.documents.scenario_rules import check_document
    from mazegen.runtime.documents.scoring import Scored, Scorer

__all__ = [
    "Floor",
    "RunDirectory",
    "Scored",
    "Scorer",
    "SuiteDirectory",
    "best_documents",
    "check_document",
    "dumps",
    "load_floor",
    "population_from_document",
    "read_document",
    "scenario_document",
    "scenario_files",
]

__getattr__ = lazy_names(
    __name__,
    {
        "best": ["best_documents"],
        "floor": ["Floor", "load_floor"],
        "folders": ["RunDirectory", "SuiteDirectory", "scenario_files"],
        "scenario": ["dumps", "population_from_document", "read_document", "scenario_document"],
        "scenario_rules": ["check_document"],
        "scoring": ["Scored", "Scorer"],
    },
)
