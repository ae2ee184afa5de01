"""The layout of run directories, and the walk of a folder for its scenario files."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from mazegen.errors import MazeError
from mazegen.runtime.documents._folders import RunDirectory, scenario_files
from mazegen.runtime.runs._experiment import BUILD_FILES


def test_the_layout_names_every_file_a_run_writes(factory_run):
    layout = RunDirectory(factory_run)
    ranked = [RunDirectory.best_rank(path) for path in layout.best_files()]
    assert ranked == [(run, rank) for run in (1, 2) for rank in (1, 2, 3, 4)]
    named = {layout.record, layout.stats, layout.timing, *(layout.build / name for name in BUILD_FILES)}
    for run, rank in ranked:
        named |= {layout.run_path(run) / RunDirectory.best_name(rank, suffix) for suffix in (".json", ".svg")}
        named.add(layout.population(run))
    assert named == {path for path in factory_run.rglob("*") if path.is_file()}
    assert layout.spec in named and layout.finished and layout.started_anything


def test_checkpoint_names_read_back_their_generation():
    assert RunDirectory.checkpoint_generation(RunDirectory.checkpoint_name(12)) == 12
    assert RunDirectory.checkpoint_generation("gen-12.ckpt.tmp") is None
    assert RunDirectory.best_rank(Path("run-x/best-01.json")) is None


def test_a_run_directory_stands_for_its_best_scenarios_any_other_folder_only_when_asked(
    factory_run, tmp_path
):
    best = [(path, Path(path.parent.name)) for path in RunDirectory(factory_run).best_files()]
    assert scenario_files(factory_run) == scenario_files(factory_run, any_folder=True) == best
    folder = tmp_path / "floors"
    shutil.copytree(factory_run / "run-01", folder / "kept")
    shutil.copytree(factory_run / "run-02", folder / ".hidden")
    shutil.copy(factory_run / "experiment.json", folder / "kept")  # JSON of another format
    with pytest.raises(MazeError, match="not a run or suite directory"):
        scenario_files(folder)
    kept = sorted((folder / "kept").glob("best-*.json"))
    assert scenario_files(folder, any_folder=True) == [(path, Path("kept")) for path in kept]
    (tmp_path / "empty").mkdir()
    with pytest.raises(MazeError, match="no scenario files in this folder"):
        scenario_files(tmp_path / "empty", any_folder=True)
