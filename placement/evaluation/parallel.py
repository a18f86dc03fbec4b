"""Where the work runs: this machine's process pool, or a Dask distributed cluster.

Maps, fronts, searches and studies hand their chunks of work to a ``concurrent.futures``
executor. By default that is a pool of local worker processes (or this process alone). Given
the address of a Dask scheduler (``--scheduler tcp://host:8786``, or the environment variable
``PLACEMENT_SCHEDULER``), the same chunks go to the cluster's workers through
``distributed.Client.get_executor()``: each chunk carries its robot, path and settings, so the
workers need only this package installed, not the files.
"""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Executor, ProcessPoolExecutor, as_completed
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, TypeVar

from placement.distribution import CLUSTER, require
from placement.dynamics.inverse import openmp_started
from placement.evaluation.exceptions import ClusterError

Result = TypeVar("Result")

SCHEDULER_VARIABLE = "PLACEMENT_SCHEDULER"
CONNECT_TIMEOUT_S = 20.0


@dataclass(frozen=True)
class Cluster:
    """An executor on a Dask cluster.

    Attributes:
        executor: Runs callables on the cluster's workers.
        threads: Worker threads the cluster has in all: how many chunks to cut work into.
        address: The scheduler's address.
    """

    executor: Executor
    threads: int
    address: str


def scheduler_address(option: str | None) -> str | None:
    """The scheduler to use: the option's value, else the environment variable's, else None (local)."""
    address = option if option is not None else os.environ.get(SCHEDULER_VARIABLE)
    return address.strip() or None if address is not None else None


@contextmanager
def cluster(address: str | None) -> Iterator[Cluster | None]:
    """Connect to the Dask scheduler at ``address`` for the duration of the block (None: yield None).

    Raises:
        ClusterError: The scheduler cannot be reached.
        MissingExtraError: Dask's distributed package (the ``cluster`` extra) is not installed.
    """
    if address is None:
        yield None
        return
    require(CLUSTER)
    from distributed import Client  # optional dependency: the [cluster] extra

    try:
        client = Client(address, timeout=CONNECT_TIMEOUT_S, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as error:
        raise ClusterError(f"cannot reach the Dask scheduler at '{address}': {str(error)[:200]}") from None
    try:
        threads = max(1, sum(client.nthreads().values()))
        # pure=False: each chunk's key is a fresh id. A pure key hashes the chunk's pickled robot, path and settings
        # in this process (some 40 ms of CPU a chunk, half the client's CPU in a front), only so that identical
        # chunks in flight at once could share one computation; the results are the same either way.
        yield Cluster(client.get_executor(pure=False), threads, address)
    finally:
        client.close()


def run_in_order(function: Callable[..., Result], tasks: Sequence[tuple[Any, ...]], workers: int,
                 executor: Executor | None, done: Callable[[int], None] | None = None) -> list[Result]:
    """``function(*task)`` for every task, results in the tasks' order.

    Args:
        function: A picklable function.
        tasks: Its arguments, one tuple per call.
        workers: Processes of the local pool; 1 runs the tasks here, one after the other.
        executor: Runs the tasks instead of a local pool (a Dask cluster's, :func:`cluster`).
        done: Called with each task's index as it finishes (for a progress bar).
    """
    if executor is None and workers == 1:
        results = []
        for index, task in enumerate(tasks):
            results.append(function(*task))
            if done:
                done(index)
        return results
    pool = executor or process_pool(min(workers, len(tasks)))
    try:
        futures = {pool.submit(function, *task): index for index, task in enumerate(tasks)}
        finished: dict[int, Result] = {}
        for future in as_completed(futures):
            finished[futures[future]] = future.result()
            if done:
                done(futures[future])
    finally:
        if executor is None:
            pool.shutdown(cancel_futures=True)
    return [finished[index] for index in range(len(tasks))]


def process_pool(workers: int, initializer: Callable[..., None] | None = None,
                 initargs: tuple = ()) -> ProcessPoolExecutor:
    """A pool of ``workers`` processes: forked from this one where the platform forks, unless this process has
    started OpenMP threads, which a forked process would hang on (:func:`placement.dynamics.inverse.openmp_started`);
    then started afresh."""
    fresh = openmp_started() and "fork" in multiprocessing.get_all_start_methods()
    context = multiprocessing.get_context("spawn") if fresh else None
    return ProcessPoolExecutor(max_workers=workers, mp_context=context, initializer=initializer, initargs=initargs)


