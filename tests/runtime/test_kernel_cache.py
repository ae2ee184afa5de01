"""The numba cache folder: keyed on the runtime's sources, unless the user chose one."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

SHOW_CACHE_DIR = "import numba, mazegen.runtime; print(numba.config.CACHE_DIR)"


def cache_dir_with(env: dict[str, str]) -> str:
    base = {key: value for key, value in os.environ.items() if key != "NUMBA_CACHE_DIR"}
    done = subprocess.run(
        [sys.executable, "-c", SHOW_CACHE_DIR],
        env={**base, **env},
        capture_output=True,
        text=True,
        check=True,
    )
    return done.stdout.strip()


def test_kernels_are_cached_per_version_of_the_runtime_sources(tmp_path, monkeypatch):
    from mazegen.runtime import _kernel_cache_dir

    folder = Path(cache_dir_with({"XDG_CACHE_HOME": str(tmp_path)}))
    assert folder.parent == tmp_path / "mazegen" / "numba"
    assert len(folder.name) == 16 and int(folder.name, 16) >= 0
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert _kernel_cache_dir() == folder


def test_a_folder_the_user_chose_wins(tmp_path):
    assert cache_dir_with({"NUMBA_CACHE_DIR": str(tmp_path / "mine")}) == str(tmp_path / "mine")


def test_an_edit_to_any_kernel_file_starts_a_fresh_cache(tmp_path):
    import shutil

    import mazegen.runtime
    from mazegen.runtime import _kernel_cache_dir

    copy = tmp_path / "runtime"
    shutil.copytree(Path(mazegen.runtime.__file__).parent, copy, ignore=shutil.ignore_patterns("__pycache__"))
    before = _kernel_cache_dir(copy)
    assert before == _kernel_cache_dir(copy)
    rectangles = copy / "geometry" / "_rectangles.py"
    rectangles.write_text(rectangles.read_text() + "\n# edited\n")
    assert _kernel_cache_dir(copy) != before


def test_only_the_most_recently_used_caches_are_kept(tmp_path):
    from mazegen.runtime import KEPT_KERNEL_CACHES, prune_kernel_caches

    folders = [tmp_path / f"{age:016x}" for age in range(6)]  # folder 0 used last, folder 5 first
    for age, folder in enumerate(folders):
        (folder / "index").mkdir(parents=True)
        os.utime(folder, (1e9 - age * 1e5, 1e9 - age * 1e5))
    current = tmp_path / "ffffffffffffffff"
    prune_kernel_caches(current)
    kept = sorted(folder.name for folder in tmp_path.iterdir())
    assert kept == sorted([current.name, *(f.name for f in folders[: KEPT_KERNEL_CACHES - 1])])
    prune_kernel_caches(folders[0])  # an older version used again: the newest two others stay
    assert sorted(folder.name for folder in tmp_path.iterdir()) == kept
    prune_kernel_caches(folders[5])  # a version whose folder went comes back to a fresh one
    assert folders[5].is_dir() and current.is_dir() and folders[0].is_dir() and not folders[1].exists()
