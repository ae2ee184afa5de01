"""How kernels compile, and saying so when a command waits for numba to compile them.

numba compiles a kernel the first time a process calls it, unless this version's compiled code is
in the kernel cache (:mod:`mazegen.runtime`). A command that may be the first to call some kernel
(a drive with a controller never driven before, say) runs its work inside :func:`noting_compiles`,
which says so once, the moment numba starts to compile, and says nothing when every kernel came
from the cache. The figures the notes give are those ``benchmarks/startup.py`` measures.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from numba import njit
from numba.core import event

inner_kernel = njit(cache=True, no_cpython_wrapper=True)  # type: ignore[call-overload]  # not in numba's stubs
"""The decorator of a kernel that only other kernels call: compiled without the wrapper that lets
Python call it, which a first run would spend seconds on (docs/architecture.md, Compiling)."""

leaf_kernel = njit(cache=True, no_cpython_wrapper=True, _nrt=False)  # type: ignore[call-overload]
"""An inner kernel that allocates no array and returns none, compiled without numba's reference
counting (``_nrt=False``; numba refuses to compile an allocation in it). Otherwise every array a kernel
is given is counted up and down, atomically, at every call: half of a ``movebase`` drive's time, when
its rollouts' kernels were counted. Never return an array (a view of an argument, say) from one: its
caller would count it down once too often. numba compiles what such a kernel calls without reference
counting too, unless the callee says otherwise, so it calls only its like (a test checks)."""

wrapped_leaf_kernel = njit(cache=True, _nrt=False)  # type: ignore[call-overload]
"""A :data:`leaf_kernel` that Python calls too (tests, mostly)."""

counted_kernel = njit(cache=True, _nrt=True)  # type: ignore[call-overload]
"""A kernel that allocates and that a :data:`leaf_kernel` calls (a controller the episode loop's
dispatch calls, say): its reference counting said explicitly, so that it keeps it whoever calls it."""

RUN_SECONDS = 40
"""Seconds a first run waits for its kernels, at most, on a quiet 2-core machine (``benchmarks/startup.py``
measured 18–22 s for ``mazegen run``, which compiles on both cores, 34–36 s for a run of the Python API,
``resume`` or ``sweep``, which compile on one)."""

DRIVE_SECONDS = 20
"""Seconds a first drive with one bundled controller waits, at most, likewise (7–13 s measured quiet for
``mazegen drive``, which compiles on both cores; ``movebase``, the largest, about 16 s in one process, as
``score``, ``classes`` and the Python API compile)."""


def compile_note(work: str, seconds: int) -> str:
    """The line that says a first ``work`` (run, drive, score) compiles for up to ``seconds``."""
    return (
        f"compiling MazeGen's kernels for this {work}, once for this version "
        f"(up to {seconds} s on a quiet 2-core machine); later ones start at once"
    )


class _FirstCompile(event.Listener):
    """Calls ``say(note)`` when numba first starts compiling, once."""

    def __init__(self, say: Callable[[str], None], note: str) -> None:
        self._say, self._note = say, note
        self._lock = threading.Lock()  # kernels called from several threads compile one at a time
        self.compiled = False

    def on_start(self, ev: event.Event) -> None:
        with self._lock:
            if self.compiled:
                return
            self.compiled = True
        self._say(self._note)

    def on_end(self, ev: event.Event) -> None:
        """Nothing to say."""


@contextmanager
def noting_compiles(say: Callable[[str], None], work: str, seconds: int) -> Iterator[None]:
    """Run the block; if numba compiles anything in it, ``say`` :func:`compile_note` once, as it starts."""
    with event.install_listener("numba:compile", _FirstCompile(say, compile_note(work, seconds))):
        yield
