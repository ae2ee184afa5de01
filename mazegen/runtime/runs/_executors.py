"""Where runs execute: in this process, in local worker processes, or on a Dask cluster.

Every executor takes :class:`~mazegen.runtime.runs._worker.RunTask` objects and hands back
their outcomes as they finish, and the progress of each generation on the way.
Because a run is a pure function of its task, the results do not depend on the
executor; only the time does.

Local workers are processes, one numba thread each when they share the cores (a run
is mostly serial between its kernels, so processes use the cores better than threads).
They start from a fork server that has imported NumPy and numba once (else they are
spawned): never by forking this process, whose OpenMP threads a fork would not copy.
They end with the launcher, also when it is killed outright (see :func:`die_with_launcher`).
"""

from __future__ import annotations

import multiprocessing
import multiprocessing.connection
import os
import queue
import signal
import sys
import threading
from abc import ABC, abstractmethod
from collections import deque
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from dataclasses import astuple, replace
from time import monotonic
from types import TracebackType
from typing import Any

try:
    import fcntl
except ImportError:  # Windows: the watching thread alone
    fcntl = None  # type: ignore[assignment]

from mazegen.errors import MazeError, option
from mazegen.runtime.engine import GenerationStats
from mazegen.runtime.runs._worker import RunKey, RunOutcome, RunTask, run_task

ProgressSink = Callable[[RunKey, GenerationStats], None]

EXECUTORS = ("local", "serial", "dask")


def available_cores() -> int:
    """Cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


PROGRESS_SECONDS = 0.1
"""A worker sends its runs' progress at most this often: each message wakes the launcher."""


class ProgressBatch:
    """Generations' statistics sent as one message (a list of flat lists, which pickle and
    msgpack alike) at most every :data:`PROGRESS_SECONDS`, and at a run's end."""

    def __init__(self, send: Callable[[list[list[Any]]], None]) -> None:
        self._send = send
        self._pending: list[list[Any]] = []
        self._sent = monotonic()

    def add(self, key: RunKey, stats: GenerationStats, *, flush: bool) -> None:
        """Queue a generation; send the batch when asked, or when the last one is old enough."""
        self._pending.append([*key, *astuple(stats)])
        now = monotonic()
        if flush or now - self._sent >= PROGRESS_SECONDS:
            self._send(self._pending)
            self._pending, self._sent = [], now


def read_progress(message: list[list[Any]]) -> list[tuple[RunKey, GenerationStats]]:
    """The generations of a message from :class:`ProgressBatch`."""
    return [((entry[0], entry[1]), GenerationStats(*entry[2:])) for entry in message]


class Executor(ABC):
    """Runs tasks and reports their outcomes; a context manager that releases its workers."""

    name: str
    """How the catalog records it: ``serial``, ``local:N`` or ``dask:ADDRESS``."""

    @abstractmethod
    def submit(self, task: RunTask) -> None:
        """Queue a run."""

    @abstractmethod
    def poll(self, timeout: float, on_progress: ProgressSink) -> list[RunOutcome]:
        """Deliver progress and return the outcomes finished since the last call.

        Raises:
            Exception: whatever a run raised.
        """

    @property
    @abstractmethod
    def pending(self) -> int:
        """Runs submitted whose outcome has not been returned."""

    @abstractmethod
    def request_stop(self) -> None:
        """Ask every run to stop after its current generation (and save a checkpoint)."""

    @abstractmethod
    def close(self) -> None:
        """Release the workers."""

    def __enter__(self) -> Executor:
        return self

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> None:
        self.close()


class _InlineChannel:
    def __init__(self, on_progress: ProgressSink, stop: threading.Event) -> None:
        self._on_progress, self._stop = on_progress, stop

    def progress(self, key: RunKey, stats: GenerationStats, *, flush: bool) -> None:
        self._on_progress(key, stats)

    def stop_requested(self) -> bool:
        return self._stop.is_set()


class SerialExecutor(Executor):
    """Runs one run after another in this process, on every numba thread."""

    name = "serial"

    def __init__(self) -> None:
        self._tasks: deque[RunTask] = deque()
        self._stop = threading.Event()

    def submit(self, task: RunTask) -> None:
        """Queue a run."""
        self._tasks.append(task)

    def poll(self, timeout: float, on_progress: ProgressSink) -> list[RunOutcome]:
        """Run the next queued run to its end (``timeout`` does not apply)."""
        return (
            [run_task(self._tasks.popleft(), _InlineChannel(on_progress, self._stop))] if self._tasks else []
        )

    @property
    def pending(self) -> int:
        """Runs not yet run."""
        return len(self._tasks)

    def request_stop(self) -> None:
        """Stop the current run at its next generation; later ones do not start."""
        self._stop.set()

    def close(self) -> None:
        """Nothing to release."""


class PooledExecutor(Executor):
    """An executor whose runs finish elsewhere as futures, with progress arriving on a queue."""

    def __init__(self, messages: Any) -> None:
        self._messages = messages
        self._futures: dict[Any, RunTask] = {}

    @property
    def pending(self) -> int:
        """Runs submitted and not yet returned."""
        return len(self._futures)

    def poll(self, timeout: float, on_progress: ProgressSink) -> list[RunOutcome]:
        """Wait up to ``timeout`` s for progress, then collect the finished runs."""
        try:
            message = self._messages.get(timeout=timeout)
            while True:
                for key, stats in read_progress(message):
                    on_progress(key, stats)
                message = self._messages.get_nowait()
        except queue.Empty:
            pass
        done = [future for future in self._futures if future.done()]
        # Finished runs are returned before a failed one is raised, so none of them is lost.
        succeeded = [future for future in done if future.exception() is None] or done[:1]
        for future in succeeded:
            del self._futures[future]
        return [future.result() for future in succeeded]


class _PoolChannel:
    def __init__(self, messages: Any, stop: Any) -> None:
        self._progress, self._stop = ProgressBatch(messages.put), stop

    def progress(self, key: RunKey, stats: GenerationStats, *, flush: bool) -> None:
        self._progress.add(key, stats, flush=flush)

    def stop_requested(self) -> bool:
        if _launcher_gone():  # asked before every checkpoint: none is written after the launcher's death
            os._exit(1)
        return self._stop.is_set()


def _launcher_gone() -> bool:
    launcher = multiprocessing.parent_process()
    return launcher is not None and not launcher.is_alive()


def die_with_launcher() -> None:
    """End this process (a worker or helper that :func:`process_context` started) as soon as
    the process that started it ends, also when that one is killed outright.

    Not a parent-death signal: the parent of a forkserver's child is the fork server, which
    lives as long as its children do. What ends with the launcher is the pipe that
    ``multiprocessing`` gives each child as the launcher's sentinel. Where the system can, its
    end raises SIGIO, whose default action ends this process at once, even in a numba kernel
    that holds the GIL; else (and also) a thread waiting on it exits the process. Either way
    nothing is left to write checkpoints into a run directory that a ``resume`` may own next.
    """
    launcher = multiprocessing.parent_process()
    if launcher is None:
        return
    sentinel = launcher.sentinel
    if fcntl is not None and hasattr(fcntl, "F_SETOWN") and hasattr(os, "O_ASYNC"):
        fcntl.fcntl(sentinel, fcntl.F_SETOWN, os.getpid())
        fcntl.fcntl(sentinel, fcntl.F_SETFL, fcntl.fcntl(sentinel, fcntl.F_GETFL) | os.O_ASYNC)
    threading.Thread(target=_exit_after, args=(sentinel,), name="mazegen-launcher-watch", daemon=True).start()


def _exit_after(sentinel: int) -> None:
    multiprocessing.connection.wait([sentinel])
    os._exit(1)


_channel: _PoolChannel | None = None


def _start_worker(messages: Any, stop: Any) -> None:
    global _channel
    # Ctrl-C reaches the whole process group; the launcher decides, and tells the runs through ``stop``.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    die_with_launcher()
    os.environ.setdefault("OMP_WAIT_POLICY", "passive")
    _channel = _PoolChannel(messages, stop)


def _run_in_pool(task: RunTask) -> RunOutcome:
    assert _channel is not None, "worker started without _start_worker"
    return run_task(task, _channel)


TRACKER_QUIET = "ignore:resource_tracker:UserWarning"
"""The ``-W`` option that keeps multiprocessing's resource tracker from warning about the semaphores
it removes."""


def _start_resource_tracker() -> None:
    """Start multiprocessing's resource tracker (unless it runs) without its warning about leaked semaphores.

    The queues and events of local workers are named semaphores; the tracker removes those of a
    launcher killed outright, which is its job, and would then print ``There appear to be 15 leaked
    semaphore objects to clean up at shutdown``: the one line a ``kill -9`` printed, about nothing
    the user can or needs to act on. The tracker takes its warning filters from the ``-W`` options
    of the process that starts it, so it is started here with that one added.
    """
    from multiprocessing import resource_tracker

    options = list(sys.warnoptions)
    sys.warnoptions.append(TRACKER_QUIET)
    try:
        resource_tracker.ensure_running()
    finally:
        sys.warnoptions[:] = options


def process_context() -> multiprocessing.context.ForkServerContext | multiprocessing.context.SpawnContext:
    """How this package starts processes: forkserver where there is one, else spawn."""
    if os.name == "posix":  # elsewhere semaphores are not named, and there is no tracker
        _start_resource_tracker()
    if "forkserver" in multiprocessing.get_all_start_methods():
        context = multiprocessing.get_context("forkserver")
        # The server imports the slow libraries once. Not this package: before Python 3.12 the server
        # imports from its own working folder, which may hold another copy than the launcher's.
        context.set_forkserver_preload(["numpy", "numba"])
        return context
    return multiprocessing.get_context("spawn")


class LocalExecutor(PooledExecutor):
    """Runs on a pool of local worker processes.

    Args:
        workers: Worker processes.
        threads_per_worker: numba threads of each (default: the cores shared out, at least 1).
    """

    def __init__(self, *, workers: int, threads_per_worker: int | None = None) -> None:
        if workers < 1:
            raise MazeError(f"{option('workers')} must be at least 1, got {workers}")
        context = process_context()
        super().__init__(context.Queue())
        self._stop = context.Event()
        self._pool = ProcessPoolExecutor(
            max_workers=workers,
            mp_context=context,
            initializer=_start_worker,
            initargs=(self._messages, self._stop),
        )
        self._threads = threads_per_worker or max(1, available_cores() // workers)
        self.name = f"local:{workers}"

    def submit(self, task: RunTask) -> None:
        """Queue a run on the pool."""
        self._futures[self._pool.submit(_run_in_pool, replace(task, threads=self._threads))] = task

    def request_stop(self) -> None:
        """Tell every worker to stop after its current generation."""
        self._stop.set()

    def close(self) -> None:
        """Stop the workers (after their current runs) and the progress queue."""
        self._pool.shutdown(wait=True, cancel_futures=True)
        self._messages.close()
        self._messages.join_thread()
