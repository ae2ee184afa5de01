"""What generated experiments import: mapping, geometry, metrics, evolution, results.

The runtime never imports textX: a Spec is plain data.
"""

import hashlib
import os
from pathlib import Path

import numba

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


if not os.environ.get("NUMBA_CACHE_DIR"):  # a folder the user chose wins
    numba.config.CACHE_DIR = str(_kernel_cache_dir())  # type: ignore[attr-defined]  # set at import by numba
