"""How many threads the kernels use, and how a kernel's work is split over them.

Kernels are compiled for one thread, with the GIL released (``nogil``), and take the range of
items they work on; :func:`in_blocks` runs one over blocks of a range on a pool of Python
threads. numba's own parallel kernels (``parallel=True`` and ``prange``) compile each kernel
twice over (the parallel loop is outlined into a function of its own, after the parfor passes
analyse it): that cost most of a first run's compiling, for no speed a block split lacks.

Blocks write disjoint rows, so a result is the same whatever the thread count. Waking a
second thread costs tens of microseconds a call, so small populations run on one thread
(:func:`threads_for`), in the calling thread, and leave the other cores to other runs.
"""

from __future__ import annotations

import itertools
import os
import threading
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any

import numba

CORES: int = numba.config.NUMBA_NUM_THREADS  # type: ignore[attr-defined]  # set at import by numba
"""Threads available: the cores this process may use, or ``NUMBA_NUM_THREADS``."""

PARALLEL_FROM = 4096
"""Individuals per generation from which the kernels use every thread."""

_threads: ContextVar[int] = ContextVar("mazegen_threads", default=CORES)
_pools: dict[int, ThreadPoolExecutor] = {}
_pools_lock = threading.Lock()


def thread_count() -> int:
    """Threads the kernels called here use."""
    return _threads.get()


@contextmanager
def threads(count: int) -> Iterator[int]:
    """Run the block's kernels on ``count`` threads (at most :data:`CORES`); restored after.

    Yields:
        The number of threads in use.
    """
    token = _threads.set(max(1, min(count, CORES)))
    try:
        yield _threads.get()
    finally:
        _threads.reset(token)


@contextmanager
def threads_for(population: int) -> Iterator[int]:
    """Run the block on one thread below :data:`PARALLEL_FROM` individuals, else on all in use."""
    with threads(thread_count() if population >= PARALLEL_FROM else 1) as count:
        yield count


def in_blocks(kernel: Callable[..., Any], count: int, *args: Any, per_thread: int = 2) -> None:
    """Call ``kernel(first, last, *args)`` over blocks ``[first, last)`` that cover ``range(count)``.

    With one thread in use the kernel runs once, here, over the whole range. Otherwise the range
    is cut into ``per_thread`` blocks a thread (more blocks even out items of unequal cost), which
    this thread and the pool's take one after another until none is left.
    """
    workers = thread_count()
    if workers == 1 or count < 2:
        kernel(0, count, *args)
        return
    blocks = min(count, per_thread * workers)
    cuts = [k * count // blocks for k in range(blocks + 1)]
    todo = iter(itertools.pairwise(cuts))
    taking = threading.Lock()

    def work() -> None:
        while True:
            with taking:
                block = next(todo, None)
            if block is None:
                return
            kernel(*block, *args)

    helpers = [_pool(workers - 1).submit(work) for _ in range(workers - 1)]
    try:
        work()
    finally:
        for helper in helpers:
            helper.result()


def map_in_threads(function: Callable[[Any], Any], items: Sequence[Any]) -> list[Any]:
    """``[function(item) for item in items]``, the items spread over the threads in use, each call's
    kernels on its own thread: for many small pieces of work (a heterogeneous batch's floors, each a
    group of its own), whose kernels would each run on one thread anyway. A single item runs here on
    every thread. The results are in order and the same whatever the thread count; the first failing
    item's exception is raised, whatever thread met it first.
    """
    if len(items) < 2 or thread_count() == 1:
        return [function(item) for item in items]
    found: list[Any] = [None] * len(items)
    failed: list[BaseException | None] = [None] * len(items)

    def work(first: int, last: int) -> None:
        with threads(1):  # nested in_blocks would wait for the pool's thread that runs this
            for k in range(first, last):
                try:
                    found[k] = function(items[k])
                except Exception as error:  # raised below, in item order
                    failed[k] = error

    in_blocks(work, len(items), per_thread=8)
    first_failure = next((error for error in failed if error is not None), None)
    if first_failure is not None:
        raise first_failure
    return found


def _pool(workers: int) -> ThreadPoolExecutor:
    with _pools_lock:
        if workers not in _pools:
            _pools[workers] = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="mazegen-kernel")
        return _pools[workers]


def _forget_pools() -> None:
    """A forked child has none of its parent's threads: it starts pools of its own."""
    global _pools_lock
    _pools.clear()
    _pools_lock = threading.Lock()


os.register_at_fork(after_in_child=_forget_pools)
