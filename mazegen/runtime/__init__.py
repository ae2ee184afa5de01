"""What generated experiments import: mapping, geometry, metrics, evolution, results.

The runtime never imports textX: a Spec is plain data.
"""

from __future__ import annotations

import hashlib
import os
import shutil
from pathlib import Path
from typing import TYPE_CHECKING

import numba

from mazegen.controllers import BUNDLED

if TYPE_CHECKING:
    from mazegen.spec import Spec

# With OpenMP's default active waiting every parallel numba call costs ~45 ms on a busy machine.
os.environ.setdefault("OMP_WAIT_POLICY", "passive")


def _kernel_cache_dir(sources: Path = Path(__file__).parent) -> Path:
    """Where numba keeps the compiled kernels: one folder per version of the runtime's sources.

    numba checks a cached kernel against its own file only, yet a kernel carries the
    machine code of every kernel it calls, from other files too: after an edit or a
    partial update, a stale copy would run (and can crash). Keying the folder on
    every runtime source makes any change start a fresh cache.
    """
    digest = hashlib.sha256()
    for source in sorted(sources.rglob("*.py")):
        digest.update(source.name.encode() + b"\0" + source.read_bytes())
    root = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return root / "mazegen" / "numba" / digest.hexdigest()[:16]


KEPT_KERNEL_CACHES = 3
"""Kernel cache folders kept: the one in use and the most recently used others (upgrades
and edits each start a fresh one of about 10 MB)."""


def prune_kernel_caches(current: Path, keep: int = KEPT_KERNEL_CACHES) -> None:
    """Mark ``current`` as used now and delete all but the ``keep`` most recently used kernel
    cache folders beside it. Best effort: a folder another process holds or removes is skipped."""
    try:
        current.mkdir(parents=True, exist_ok=True)
        os.utime(current)
        others = [folder for folder in current.parent.iterdir() if folder.is_dir() and folder != current]
        others.sort(key=lambda folder: folder.stat().st_mtime, reverse=True)
    except OSError:
        return
    for stale in others[max(keep - 1, 0) :]:
        shutil.rmtree(stale, ignore_errors=True)


if not os.environ.get("NUMBA_CACHE_DIR"):  # a folder the user chose wins
    _cache = _kernel_cache_dir()
    prune_kernel_caches(_cache)
    numba.config.CACHE_DIR = str(_cache)  # type: ignore[attr-defined]  # set at import by numba


EVERY_RUN_KERNELS = ("_mapping._map_all", "_difficulty._survey_all")
"""Kernels every run calls, first and last (its scenario files' metrics): a cache without
both was never filled, or its filling was cut short."""


CONTROLLER_KERNELS = {name: row.kernel for name, row in BUNDLED.items()}
"""The kernel of each bundled controller, its row's: the episode loop compiles once per controller,
with it. Each is compiled on its own, not inlined into the loop, so that its cache file says the controller
was compiled (tests/runtime/test_compiling.py)."""

POLICY_KERNEL = "_step._apply"
"""The kernel that steps the robots of a user's policy."""


ARENA_KERNELS = ("_cspace._walls_kernel", "_zones._zones_kernel")
"""The kernels that find elements on an arena map's walls and in its zones where they may not stand."""


REACHABLE_KERNEL = "_connectivity._reachable_all"
"""The kernel of the ``reachable`` term: the share of the free floor joined to the start."""


def run_kernels(spec: Spec) -> tuple[str, ...]:
    """The kernels every run of ``spec`` calls: a run's, those of its arena's map and zones, the
    ``reachable`` term's, and the
    simulator's for each controller its drive terms name (a spec without drive terms loads none of the
    simulator)."""
    walls, zones = ARENA_KERNELS
    arena = (walls,) * (spec.arena.base is not None) + (zones,) * bool(spec.arena.zones)
    drives = {CONTROLLER_KERNELS.get(name, POLICY_KERNEL) for name in spec.drive_controllers}
    reachable = (REACHABLE_KERNEL,) * any(term.kind == "reachable" for term in spec.fitness)
    return EVERY_RUN_KERNELS + arena + reachable + tuple(sorted(drives))


_FOUND: set[tuple[str, str]] = set()
"""(cache folder, kernel) pairs found on disk by this process: once there, they stay (the folder
is this version's own), so a process that runs many small experiments walks the folder once."""


def kernels_cached(kernels: tuple[str, ...] = EVERY_RUN_KERNELS) -> bool:
    """Whether this version's ``kernels`` (a run's by default) are on disk; a command without them
    compiles them first, for up to a minute, with nothing else to show for it."""
    folder = numba.config.CACHE_DIR  # type: ignore[attr-defined]  # set at import by numba
    if not folder:  # numba's default place, beside the sources: not ours to judge
        return True
    for kernel in kernels:
        if (folder, kernel) not in _FOUND:
            if not any(Path(folder).rglob(f"{kernel}-*.nbi")):
                return False
            _FOUND.add((folder, kernel))
    return True
