"""The language fuzzer at a small size: no mutant of a bundled file crashes or hangs the checks."""

from __future__ import annotations

from tests.dsl.fuzz import ACCEPTED, REJECTED, fuzz
from tests.dsl.mutants import SOURCES, mutant


def test_mutants_are_seeded_and_cover_every_bundled_file():
    first = [mutant(7, index) for index in range(2 * len(SOURCES))]
    assert first == [mutant(7, index) for index in range(2 * len(SOURCES))]
    assert {m.source for m in first} == set(SOURCES)
    assert [m.text for m in first] != [mutant(8, index).text for index in range(2 * len(SOURCES))]


def test_mutants_give_no_traceback_no_long_message_and_no_hang():
    summary = fuzz(mutants=300, seed=19, workers=2)
    assert summary.failures == [], "\n".join(summary.lines())
    # Both ways are exercised: mutants the checks refuse, and mutants built like real specs.
    assert summary.outcomes[ACCEPTED] > 10 and summary.outcomes[REJECTED] > 100
