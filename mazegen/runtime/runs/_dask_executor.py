"""Runs on an existing Dask distributed cluster (the optional extra: ``pip install 'mazegen[dask]'``).

Each run is one task. Workers report generations as Dask events on a topic of this
launch, which the client receives in its own thread; a stop request is a Dask
``Event`` that runs look at, at most once a second, between generations. Checkpoints
are written by the workers into the run directory, so with checkpoints on, the
workers must see that directory (one machine, or a shared file system).
"""

from __future__ import annotations

import queue
import uuid
from dataclasses import replace
from time import monotonic
from typing import Any

from mazegen.errors import MazeError, option
from mazegen.runtime.engine import GenerationStats
from mazegen.runtime.runs._executors import PooledExecutor, ProgressBatch
from mazegen.runtime.runs._worker import RunKey, RunOutcome, RunTask, run_task

CONNECT_TIMEOUT = 10.0
"""Seconds to reach the scheduler before giving up."""

STOP_CHECK_SECONDS = 1.0
"""A run asks the scheduler whether to stop at most this often (each ask is a round trip)."""


class _DaskChannel:
    def __init__(self, topic: str, stop: str) -> None:
        from distributed import Event, get_worker

        worker = get_worker()
        self._progress = ProgressBatch(lambda message: worker.log_event(topic, message))
        self._stop = Event(stop)
        self._checked, self._stopping = monotonic(), False

    def progress(self, key: RunKey, stats: GenerationStats, *, flush: bool) -> None:
        self._progress.add(key, stats, flush=flush)

    def stop_requested(self) -> bool:
        now = monotonic()
        if not self._stopping and now - self._checked >= STOP_CHECK_SECONDS:
            self._stopping, self._checked = bool(self._stop.is_set()), now
        return self._stopping


def _run_on_worker(task: RunTask, topic: str, stop: str) -> RunOutcome:
    return run_task(task, _DaskChannel(topic, stop))


def _check_address(address: str) -> None:
    """Refuse a malformed address before a client exists (one half-made waits long to close)."""
    from distributed.comm import parse_address, parse_host_port

    try:
        scheme, location = parse_address(address)
        if scheme in ("tcp", "tls"):
            parse_host_port(location)
    except ValueError as error:
        raise MazeError(
            f"not a Dask scheduler address '{address}' ({error}); write tcp://HOST:PORT"
        ) from None


class DaskExecutor(PooledExecutor):
    """Sends runs to the Dask scheduler at ``scheduler`` (``tcp://HOST:PORT``).

    Args:
        scheduler: The scheduler's address.
        threads_per_run: numba threads of each run (1: a worker's threads each run a task).
        connect_timeout: Seconds to reach the scheduler.

    Raises:
        MazeError: when ``distributed`` is not installed or the scheduler cannot be reached.
    """

    def __init__(
        self, *, scheduler: str, threads_per_run: int = 1, connect_timeout: float = CONNECT_TIMEOUT
    ) -> None:
        try:
            from distributed import Client, Event
        except ImportError:
            raise MazeError(
                f"{option('executor dask')} needs the distributed package: pip install 'mazegen[dask]'"
            ) from None
        _check_address(scheduler)
        super().__init__(queue.Queue())
        try:
            self._client = Client(scheduler, timeout=connect_timeout, set_as_default=False)
        except (OSError, ValueError, TypeError) as error:  # TimeoutError is an OSError
            reason = str(error).splitlines()[0] if str(error) else type(error).__name__
            raise MazeError(f"cannot reach the Dask scheduler at {scheduler}: {reason}") from None
        launch = uuid.uuid4().hex
        self._topic, self._stop_name = f"mazegen-progress-{launch}", f"mazegen-stop-{launch}"
        self._stop = Event(self._stop_name, client=self._client)
        self._client.subscribe_topic(self._topic, self._receive)
        self._threads = threads_per_run
        self.name = f"dask:{scheduler}"

    def _receive(self, event: tuple[float, Any]) -> None:
        self._messages.put(event[1])

    def submit(self, task: RunTask) -> None:
        """Send a run to the cluster."""
        experiment, run = task.key
        future = self._client.submit(
            _run_on_worker,
            replace(task, threads=self._threads),
            self._topic,
            self._stop_name,
            key=f"mazegen-run-{self._topic[-32:]}-{experiment}-{run}",
            pure=False,
        )
        self._futures[future] = task

    def request_stop(self) -> None:
        """Set the launch's stop event; runs see it within a second."""
        self._stop.set()

    def close(self) -> None:
        """Forget unfinished runs and disconnect."""
        self._client.unsubscribe_topic(self._topic)
        self._client.cancel(list(self._futures))
        self._client.close()
