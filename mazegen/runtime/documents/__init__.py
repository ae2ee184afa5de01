"""Scenario documents, MazeGen's output: made from a population and read back, their
validation rules, the best distinct scenarios of a run, and scoring documents under a spec.

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.documents.best import best_documents
    from mazegen.runtime.documents.scenario import (
        dumps,
        population_from_document,
        read_document,
        scenario_document,
    )
    from mazegen.runtime.documents.scenario_rules import check_document
    from mazegen.runtime.documents.scoring import Scored, Scorer

__all__ = [
    "Scored",
    "Scorer",
    "best_documents",
    "check_document",
    "dumps",
    "population_from_document",
    "read_document",
    "scenario_document",
]

__getattr__ = lazy_names(
    __name__,
    {
        "best": ["best_documents"],
        "scenario": ["dumps", "population_from_document", "read_document", "scenario_document"],
        "scenario_rules": ["check_document"],
        "scoring": ["Scored", "Scorer"],
    },
)
