"""`mazegen resume` on a damaged run directory: one line naming the directory's own file, or the right result.

A checkpoint edited with valid CRCs (shapes, dtypes, codons, fitness, generator state) is
damaged like a truncated one: the one before it is used.
"""

from __future__ import annotations

import json
import shutil
import zipfile
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from mazegen.runtime.runs._checkpoint import RunState, checkpoint_bytes, read_checkpoint
from mazegen.runtime.runs._results import RunDirectoryWriter
from tests.runtime.rundirs import Killed, file_digests, invoke, small_run


@pytest.fixture(scope="module")
def killed_at_the_end(tmp_path_factory) -> Path:
    """A run directory killed as it ended: each run keeps its last two checkpoints (generations 2, 3)."""
    out = tmp_path_factory.mktemp("killed") / "run"
    with pytest.MonkeyPatch.context() as patched:
        patched.setattr(RunDirectoryWriter, "drop_checkpoints", lambda self: (_ for _ in ()).throw(Killed()))
        with pytest.raises(Killed):
            small_run(out, checkpoint_every=1)
    return out


@pytest.fixture
def run(killed_at_the_end, tmp_path) -> Path:
    return Path(shutil.copytree(killed_at_the_end, tmp_path / "run"))


def _checkpoints_a_file(run: Path) -> None:
    shutil.rmtree(run / "checkpoints")
    (run / "checkpoints").write_text("")


DAMAGE = {
    "checkpoints is a file": (_checkpoints_a_file, "run/checkpoints: not a folder"),
    "fitness.py missing": (
        lambda run: (run / "experiment" / "fitness.py").unlink(),
        "run/experiment/fitness.py: missing from this run directory",
    ),
    "spec.json null": (
        lambda run: (run / "experiment" / "spec.json").write_text("null"),
        "run/experiment/spec.json: damaged spec.json (AttributeError",
    ),
    "experiment.json not JSON": (
        lambda run: (run / "experiment.json").write_text("{"),
        "run/experiment.json: damaged experiment.json (Expecting",
    ),
    "experiment.json edited": (
        lambda run: (run / "experiment.json").write_text(json.dumps({"format": "mazegen-run"})),
        "run/experiment.json: damaged experiment.json: it does not record the experiment",
    ),
    "experiment.json nested too deeply": (
        lambda run: (run / "experiment.json").write_text("[" * 100_000),
        "run/experiment.json: damaged experiment.json (nested too deeply",
    ),
    "spec.json nested too deeply": (
        lambda run: (run / "experiment" / "spec.json").write_text("[" * 100_000),
        "run/experiment/spec.json: damaged spec.json (ValueError: nested too deeply",
    ),
    "fitness.py raises as it loads": (
        lambda run: (run / "experiment" / "fitness.py").write_text("raise RuntimeError('edited')\n"),
        "run/experiment/fitness.py: fitness module raised RuntimeError as it loads: edited",
    ),
    "fitness.py edited": (
        lambda run: (run / "experiment" / "fitness.py").open("a").write("# edited\n"),
        "run/checkpoints/run-01: checkpoints of another build",
    ),
}


@pytest.mark.parametrize("damage", DAMAGE)
def test_a_damaged_run_directory_is_one_line_naming_its_own_file(run, damage):
    spoil, message = DAMAGE[damage]
    spoil(run)
    result = invoke(
        "resume", str(run), "-q", "--executor", "serial", "--catalog", str(run.parent / "c.sqlite")
    )
    assert result.exit_code == 1, result.output
    assert len(result.stderr.splitlines()) == 1 and "Traceback" not in result.output
    assert message in result.stderr and "mazegen-resume" not in result.stderr


def _first_codon_is(state: RunState, value: int) -> RunState:
    codons = state.codons.copy()
    codons[0, 0] = value
    return replace(state, codons=codons)


def _first_fitness_nan(state: RunState) -> RunState:
    fitness = state.fitness.copy()
    fitness[0] = np.nan
    return replace(state, fitness=fitness)


EDITS: dict[str, Callable[[RunState], RunState]] = {
    "codon beyond codon_max": lambda state: _first_codon_is(state, 10**6),
    "negative codon": lambda state: _first_codon_is(state, -1),
    "NaN fitness": _first_fitness_nan,
    "codons as int64": lambda state: replace(state, codons=state.codons.astype(np.int64)),
    "genes as float": lambda state: replace(state, genes=state.genes.astype(np.float64)),
    "a row short": lambda state: replace(
        state, codons=state.codons[1:], genes=state.genes[1:], fitness=state.fitness[1:]
    ),
    "generator state": lambda state: replace(state, rng_state={"bit_generator": "PCG64", "state": {}}),
    "generation beyond the last": lambda state: replace(
        state, generation=4, stats=(*state.stats, replace(state.stats[-1], generation=4))
    ),
}


@pytest.mark.parametrize("edit", EDITS)
def test_a_checkpoint_edited_with_valid_crcs_is_damaged_and_the_one_before_used(run, small_reference, edit):
    newest = run / "checkpoints" / "run-01" / "gen-000003.ckpt"
    with zipfile.ZipFile(newest) as archive:
        experiment = json.loads(archive.read("state.json"))["experiment"]
    state = EDITS[edit](read_checkpoint(newest, experiment=experiment))
    newest.write_bytes(checkpoint_bytes(state, experiment=experiment))
    result = invoke(
        "resume", str(run), "-q", "--executor", "serial", "--catalog", str(run.parent / "c.sqlite")
    )
    assert result.exit_code == 0, result.output
    assert (
        "run-01/gen-000003.ckpt: damaged checkpoint" in result.stderr
        and "using the one before" in result.stderr
    )
    assert file_digests(run) == small_reference
