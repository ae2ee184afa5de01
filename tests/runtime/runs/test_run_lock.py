"""A run directory belongs to one launch, and to its workers until the last of them is gone."""

from __future__ import annotations

import pytest

from mazegen.errors import MazeError
from mazegen.runtime.runs import _locks as locks
from mazegen.runtime.runs._locks import writing_checkpoints
from mazegen.runtime.runs._results import RunDirectoryWriter

pytestmark = pytest.mark.skipif(locks.fcntl is None, reason="run directories are locked with flock")

IN_USE = "this run directory is in use by another mazegen process"


def test_a_worker_writing_checkpoints_keeps_the_directory_in_use(tmp_path):
    path = tmp_path / "run"
    directory = RunDirectoryWriter.create(path, force=False, files={"experiment.json": "{}"})
    checkpoints = directory.checkpoints(1).parent
    # A worker of the launch that holds the directory takes its share without waiting.
    with writing_checkpoints(checkpoints), pytest.raises(MazeError, match=IN_USE):
        RunDirectoryWriter.create(path, force=True, files={})
    directory.close()  # the launcher is gone (killed outright), one of its workers not yet
    with writing_checkpoints(checkpoints), pytest.raises(MazeError, match=IN_USE):
        RunDirectoryWriter.create(path, force=True, files={})
    assert (path / "experiment.json").is_file()  # nothing replaced
    RunDirectoryWriter.create(path, force=True, files={}).close()  # free once the worker is gone too
    assert not (path / "experiment.json").exists()
