"""Mapping a function over tasks in order, here or on a Dask cluster.

:func:`map_ordered` runs ``function(task)`` for every task and yields the results in the
order of the tasks. Without a cluster it is a plain loop in this process. With
``scheduler=ADDRESS`` (an existing Dask cluster) or ``workers=N`` (a local cluster of N
single-threaded worker processes, started and stopped here) the tasks are submitted to the
cluster a few at a time (at most :data:`IN_FLIGHT` per worker thread, so memory stays bounded
however many tasks there are) and results are yielded as soon as they are next in order.

Dask (``pip install whipple[distributed]``) is imported only when a cluster is asked for:
this module is the only place that imports it, inside :func:`_connect`.
"""

from __future__ import annotations

import collections
import itertools
import threading
from collections.abc import Callable, Iterable, Iterator
from typing import Any, Generic, TypeVar

from whipple.errors import InputError

Task = TypeVar("Task")
Result = TypeVar("Result")

#: Tasks submitted ahead per worker thread: enough to keep workers busy while results are
#: written, few enough to bound the memory of queued tasks and results.
IN_FLIGHT = 2
#: Seconds to wait for a scheduler to answer before giving up (:func:`map_ordered`'s default).
CONNECT_TIMEOUT = 10.0


class ClusterError(InputError):
    """A Dask cluster cannot be reached or started (bad address, Dask not installed, N < 1)."""


def check_cluster_options(scheduler: str | None, workers: int | None) -> None:
    """Raise ClusterError for contradictory or impossible cluster options (before any work)."""
    if scheduler is not None and workers is not None:
        raise ClusterError("give either a scheduler address or a number of local workers, not both")
    if workers is not None and workers < 1:
        raise ClusterError(f"the number of workers must be at least 1, got {workers}")
    if scheduler is not None and not scheduler.strip():
        raise ClusterError("empty scheduler address")


def _connect(scheduler: str | None, workers: int | None, processes: bool, timeout: float) -> tuple[Any, Any]:
    """Return (client, local cluster or None); Dask is imported here, only when asked for."""
    import logging  # with Dask only: the serial sweep starts ~10 ms sooner

    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise ClusterError("Dask is not installed: pip install 'whipple[distributed]'") from None
    if workers is not None:
        # CRITICAL, not ERROR: a worker whose heartbeat races the scheduler's shutdown logs an
        # ERROR with a traceback although every result is in (seen after a finished
        # `diagnose --workers 2`); a task's own failure reaches the caller as its exception.
        # No dashboard; the scheduler's own HTTP server (health checks) still starts, on port 8787
        # unless told otherwise: a second local cluster at once (two commands, a benchmark beside
        # the tests) then warned that the port was in use. A free local port instead.
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=processes,
                               dashboard_address=None, scheduler_kwargs={"dashboard_address": "127.0.0.1:0"},
                               silence_logs=logging.CRITICAL)
        return Client(cluster), cluster
    try:
        return Client(scheduler, timeout=timeout), None
    except (OSError, TimeoutError) as error:
        reason = str(error).splitlines()[0] if str(error) else type(error).__name__
        raise ClusterError(f"cannot reach the Dask scheduler at {scheduler} within {timeout:g} s "
                           f"({reason})") from None
    except ValueError as error:  # a malformed address
        raise ClusterError(f"bad Dask scheduler address {scheduler!r}: {error}") from None


def map_ordered(function: Callable[[Task], Result], tasks: Iterable[Task], *,
                scheduler: str | None = None, workers: int | None = None,
                processes: bool = True, connect_timeout: float = CONNECT_TIMEOUT) -> OrderedMap[Result]:
    """Map ``function`` over `tasks`: an iterator of the results, in the order of `tasks`.

    The cluster is reached (or started) here, before any result is asked for, so that a bad
    address fails before any output is begun.

    Parameters
    ----------
    function : callable
        A module-level function (it is pickled to the workers of a cluster).
    tasks : iterable
        Its arguments, one per call; consumed lazily.
    scheduler : str, optional
        Address of an existing Dask scheduler (``tcp://host:8786``).
    workers : int, optional
        Start a local Dask cluster with this many workers (one thread each) for the mapping.
    processes : bool
        Local workers as processes (default) or threads of this process.
    connect_timeout : float
        Seconds [s] to wait for the scheduler at ``scheduler`` to answer.

    Returns
    -------
    OrderedMap
        Iterate over it for the results; close it (or use it in a ``with`` block) to cancel
        what is pending and release the cluster.

    Raises
    ------
    ClusterError
        Contradictory options, N < 1, Dask not installed, or an unreachable scheduler.

    Notes
    -----
    A task's exception is raised when its result is next in order. Tasks run one at a time in
    each worker process, whatever its number of threads: CasADi functions, which the analyses
    use, are not safe to call from several threads at once (give workers one thread each, as
    ``workers=N`` does, to use every core).
    """
    check_cluster_options(scheduler, workers)
    if scheduler is None and workers is None:
        return OrderedMap(map(function, tasks))
    client, cluster = _connect(scheduler, workers, processes, connect_timeout)
    return OrderedMap(_submitted(client, _OneAtATime(function), iter(tasks)), client, cluster)


def _submitted(client: Any, function: Callable[[Task], Result], tasks: Iterator[Task]) -> Iterator[Result]:
    """Results of the tasks submitted to `client`, a bounded number ahead, in order."""
    threads = sum(client.nthreads().values()) or 1
    pending: collections.deque[Any] = collections.deque(
        client.submit(function, task, pure=False) for task in itertools.islice(tasks, IN_FLIGHT * threads))
    try:
        while pending:
            result = pending.popleft().result()
            pending.extend(client.submit(function, task, pure=False) for task in itertools.islice(tasks, 1))
            yield result
    finally:
        for future in pending:
            future.cancel()


#: Held while a task runs in a worker process (see :func:`map_ordered`).
_TASK_LOCK = threading.Lock()


class _OneAtATime(Generic[Task, Result]):
    """`function`, called under this process's task lock (picklable if `function` is)."""

    def __init__(self, function: Callable[[Task], Result]) -> None:
        self.function = function

    def __call__(self, task: Task) -> Result:
        with _TASK_LOCK:
            return self.function(task)


class OrderedMap(Generic[Result]):
    """Results of :func:`map_ordered` in order; closing it releases the cluster, if any."""

    def __init__(self, results: Iterator[Result], client: Any = None, cluster: Any = None) -> None:
        self._results, self._client, self._cluster = results, client, cluster

    def __iter__(self) -> OrderedMap[Result]:
        return self

    def __next__(self) -> Result:
        return next(self._results)

    def __enter__(self) -> OrderedMap[Result]:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Cancel the pending tasks and close the client and a local cluster."""
        close = getattr(self._results, "close", None)
        if close is not None:
            close()
        if self._client is not None:
            self._client.close()
            self._client = None
        if self._cluster is not None:
            self._cluster.close()
            self._cluster = None
