"""Checkpoints: a run resumed from any generation ends as if never stopped; damaged files fall back."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from mazegen.errors import MazeError
from mazegen.runtime.runs._checkpoint import (
    CheckpointPolicy,
    CheckpointStore,
    DamagedCheckpoint,
    read_checkpoint,
)
from mazegen.runtime.engine._evolution import RunState, evolve
from mazegen.runtime.runs._worker import run_rng


def without_seconds(stats):
    return [replace(row, seconds=0.0) for row in stats]


def test_run_resumed_from_a_checkpoint_ends_identical(factory, tmp_path):
    settings = replace(factory.spec.evolution, population=120, generations=6, selection="tournament")
    store = CheckpointStore(directory=tmp_path / "run-01", experiment="x", keep=10)
    whole = evolve(factory, settings, run_rng(3, 1), on_generation=store.save)
    for generation in (0, 2, 5, 6):
        state = read_checkpoint(store.directory / f"gen-{generation:06d}.ckpt", experiment="x")
        assert state.generation == generation and len(state.stats) == generation + 1
        # The generator is seeded afresh: the checkpoint's state replaces its state.
        resumed = evolve(factory, settings, run_rng(3, 1), resume=state)
        assert np.array_equal(resumed.codons, whole.codons) and np.array_equal(resumed.genes, whole.genes)
        assert np.array_equal(resumed.fitness, whole.fitness)
        # Evaluations and cache hits too: the rebuilt cache is the one the run had.
        assert without_seconds(resumed.stats) == without_seconds(whole.stats)


def test_store_keeps_the_last_two_and_falls_back_past_damage(factory, tmp_path):
    settings = replace(factory.spec.evolution, population=40, generations=4)
    store = CheckpointStore(directory=tmp_path / "run-02", experiment="e1")
    evolve(factory, settings, run_rng(1, 2), on_generation=store.save)
    newest, previous = store.paths()
    assert [p.name for p in store.paths()] == ["gen-000004.ckpt", "gen-000003.ckpt"]
    assert store.latest() == ((newest, 4), [])

    data = bytearray(newest.read_bytes())
    data[len(data) // 3] ^= 0xFF  # one flipped byte inside an array: the member's CRC-32 catches it
    newest.write_bytes(bytes(data))
    found, warnings = store.latest()
    assert found == (previous, 3)
    assert len(warnings) == 1 and "gen-000004.ckpt: damaged checkpoint" in warnings[0]

    previous.write_bytes(previous.read_bytes()[:-100])  # truncated by a crash
    with pytest.raises(MazeError, match="no usable checkpoint"):
        store.latest()


def test_checkpoint_of_another_experiment_is_refused(factory, tmp_path):
    settings = replace(factory.spec.evolution, population=30, generations=1)
    store = CheckpointStore(directory=tmp_path / "run-01", experiment="one")
    evolve(factory, settings, run_rng(1, 1), on_generation=store.save)
    with pytest.raises(DamagedCheckpoint, match="another experiment"):
        read_checkpoint(store.paths()[0], experiment="two")
    assert CheckpointStore(directory=tmp_path / "none", experiment="one").latest() == (None, [])


def test_policy_every_k_generations_or_by_time():
    assert [g for g in range(7) if CheckpointPolicy(every=3).due(g, 0.0)] == [0, 3, 6]
    assert not CheckpointPolicy(every=0).enabled and not CheckpointPolicy(every=0).due(0, 1e9)
    automatic = CheckpointPolicy()
    assert automatic.enabled and not automatic.due(5, 1.0) and automatic.due(5, 31.0)


def test_states_handed_to_callbacks_are_complete(factory):
    settings = replace(factory.spec.evolution, population=50, generations=2)
    seen: list[RunState] = []
    result = evolve(factory, settings, run_rng(2, 1), on_generation=seen.append)
    assert [state.generation for state in seen] == [0, 1, 2]
    assert seen[-1].stats == result.stats and seen[-1].rng_state["bit_generator"] == "PCG64"
