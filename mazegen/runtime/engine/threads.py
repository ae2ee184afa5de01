"""How many threads the numba kernels of a run use.

Waking OpenMP's sleeping threads (``OMP_WAIT_POLICY=passive``, set in this package)
costs about 50 µs a parallel call, while one thread starts in about 5 µs. A generation
makes several such calls, so small populations run faster on one thread and leave the
other cores to other runs.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import numba

PARALLEL_FROM = 4096
"""Individuals per generation from which the kernels use every thread."""


@contextmanager
def threads_for(population: int) -> Iterator[int]:
    """Run the block with one numba thread below :data:`PARALLEL_FROM` individuals, else all.

    Yields:
        The number of threads in use.
    """
    previous = numba.get_num_threads()
    count = previous if population >= PARALLEL_FROM else 1
    numba.set_num_threads(count)
    try:
        yield count
    finally:
        numba.set_num_threads(previous)
