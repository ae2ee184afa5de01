"""The kernels' threads: blocks that cover a range once, on as many threads as asked."""

from __future__ import annotations

import threading

import numpy as np
import pytest
from numba import njit

from mazegen.runtime.threads import CORES, in_blocks, map_in_threads, thread_count, threads, threads_for


@njit(nogil=True)
def _count_visits(first, last, visits):  # pragma: no cover - compiled
    for i in range(first, last):
        visits[i] += 1


@pytest.mark.parametrize("count", [0, 1, 2, 7, 1000])
@pytest.mark.parametrize("workers", [1, 2, 3])
def test_blocks_cover_the_range_once(count, workers):
    visits = np.zeros(count, np.int64)
    with threads(workers):
        in_blocks(_count_visits, count, visits, per_thread=3)
    assert np.array_equal(visits, np.ones(count, np.int64))


def test_one_thread_runs_in_the_calling_thread_in_one_block():
    calls = []
    with threads(1):
        in_blocks(lambda first, last: calls.append((first, last, threading.current_thread())), 10)
    assert calls == [(0, 10, threading.current_thread())]


@pytest.mark.skipif(CORES < 2, reason="one core: every block runs in the calling thread")
def test_several_threads_share_the_blocks():
    both = threading.Barrier(2, timeout=60)  # passes only once two threads hold a block each
    seen = []

    def block(first, last):
        thread = threading.current_thread()
        if thread not in seen:
            seen.append(thread)
            both.wait()

    with threads(2):
        in_blocks(block, 8, per_thread=4)
    assert len(seen) == 2 and threading.current_thread() in seen  # the caller works blocks too


def test_a_block_that_raises_raises_in_the_caller():
    def fails(first, last):
        if first > 0:
            raise ValueError(f"block {first}")

    with threads(2), pytest.raises(ValueError, match="block"):
        in_blocks(fails, 10)


def test_thread_counts_are_bounded_and_restored():
    before = thread_count()
    with threads(10 * CORES) as count:
        assert count == CORES == thread_count()
    with threads(0) as count:
        assert count == 1
    with threads_for(10) as small, threads_for(10**6) as large:
        assert small == 1 and large == 1  # a large population inside a small one's block stays on one
    assert thread_count() == before


@pytest.mark.skipif(CORES < 2, reason="needs two threads")
def test_map_in_threads_keeps_the_order_and_each_call_runs_its_kernels_on_one_thread():
    def work(item: int) -> tuple[int, int, str]:
        visits = np.zeros(50, np.int64)
        in_blocks(_count_visits, 50, visits)  # nested: on this item's thread alone, never waiting on the pool
        return item * item, thread_count(), threading.current_thread().name

    with threads(2):
        found = map_in_threads(work, list(range(40)))
        alone = map_in_threads(work, [7])
    assert [square for square, _, _ in found] == [k * k for k in range(40)]
    assert {count for _, count, _ in found} == {1}
    assert alone == [(49, 2, threading.current_thread().name)]  # one item: here, on every thread


def test_map_in_threads_raises_the_first_failing_items_error_whichever_thread_met_it():
    def work(item: int) -> int:
        if item in (3, 30):
            raise ValueError(f"item {item}")
        return item

    for _ in range(20):
        with threads(2), pytest.raises(ValueError, match=r"^item 3$"):
            map_in_threads(work, list(range(40)))
