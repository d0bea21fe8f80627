"""Independent fitting tasks, mapped by one function.

``compare``, ``bootstrap``, ``cross_validate`` and ``sweep`` describe their work
as a list of independent tasks (each a small picklable tuple) and run them
through :func:`map_tasks`. Serially by default; given an ``executor`` the tasks
run there:

* a :class:`dask.distributed.Client` (a ``LocalCluster`` or a real cluster): the
  tasks are submitted in batches with ``client.map`` (about :data:`BATCHES_PER_WORKER`
  batches per worker thread, since each dask task costs milliseconds of scheduling, as much as
  a fit of a small law) and their futures gathered;
* anything else with a ``map(function, iterable)`` method returning results in
  order, such as a :mod:`concurrent.futures` executor.

The results are exactly the serial ones, whatever the executor and the number
of workers: each task carries its own seed and data, and every law computes the
same numbers wherever it runs (see :mod:`bouncelab.laws.compiled`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from typing import Any

from bouncelab.core.errors import FitError

__all__ = ["BATCHES_PER_WORKER", "is_dask_client", "map_tasks"]

#: On a dask cluster, the tasks go in about this many batches per worker thread (enough to balance the load).
BATCHES_PER_WORKER = 4


def is_dask_client(executor: Any) -> bool:
    """True for a :class:`dask.distributed.Client` (whose ``map`` returns futures, not results)."""
    return type(executor).__module__.split(".")[0] == "distributed" and hasattr(executor, "gather")


def _run_batch(batch: tuple[Callable[[Any], Any], list[Any]]) -> list[Any]:
    function, tasks = batch
    return [function(t) for t in tasks]


def map_tasks(function: Callable[[Any], Any], tasks: Iterable[Any], executor: Any = None) -> list[Any]:
    """``[function(t) for t in tasks]``, serially or on ``executor`` (results in task order).

    Parameters
    ----------
    function
        A module-level function (so that it can be pickled to other processes).
    tasks
        Its arguments, one per call.
    executor
        None (serial), a :class:`dask.distributed.Client`, or an object with a
        ``map(function, iterable)`` method such as a
        :class:`concurrent.futures.ProcessPoolExecutor`.

    Raises
    ------
    FitError
        ``executor`` has no ``map`` method.
    """
    tasks = list(tasks)
    if executor is None:
        return [function(t) for t in tasks]
    if is_dask_client(executor):
        slots = max(1, sum(executor.nthreads().values()))  # every worker thread (scheduler_info lists only some)
        size = max(1, math.ceil(len(tasks) / (BATCHES_PER_WORKER * slots)))
        batches = [(function, tasks[i:i + size]) for i in range(0, len(tasks), size)]
        # pure=False: every batch runs (no key hashing of large arguments; equal batches are not merged).
        futures = executor.map(_run_batch, batches, pure=False)
        return [r for batch in executor.gather(futures) for r in batch]
    if not callable(getattr(executor, "map", None)):
        raise FitError(f"executor must be None, a dask.distributed.Client or have a map(function, tasks) method; "
                       f"got {type(executor).__name__}", option="executor")
    return list(executor.map(function, tasks))
