"""Independent fitting tasks, mapped by one function on one kind of executor.

``compare``, ``bootstrap``, ``cross_validate``, ``sweep``, ``assess`` and ``calibrate`` describe
their work as a list of independent tasks (each a small picklable tuple: a fit of a resample, a
fold, a law, a batch of sweep points, a chain) and run them through :func:`map_tasks`. Serially
by default; given ``executor=`` the tasks run there. An executor is

* any :class:`concurrent.futures.Executor`: a ``ThreadPoolExecutor`` (the built-in laws release
  the GIL in their loops), a ``ProcessPoolExecutor``, loky's reusable executor
  (``joblib.externals.loky.get_reusable_executor()``), dask's ``client.get_executor()``,
  mpi4py's ``MPIPoolExecutor``; the tasks go in about :data:`BATCHES_PER_WORKER` batches per
  worker (``submit`` of each batch; results gathered in task order);
* a :class:`dask.distributed.Client` itself, whose tasks are batched the same way over its
  worker threads (``client.map``), since each dask task costs milliseconds of scheduling, as
  much as a fit of a small law;
* anything else with a ``map(function, iterable)`` method returning results in order
  (``multiprocessing.Pool``).

The results are exactly the serial ones, whatever the executor and the number of workers: each
task carries its own seed and data, and every law computes the same numbers wherever it runs
(see :mod:`bouncelab.laws.compiled`). ``client=``, the earlier name of the argument on ``assess``
and ``calibrate``, is a deprecated alias (:func:`resolve_executor`).

This is the one interface for independent tasks; the loops inside one computation (a large
prediction, a batch of walkers) share the package's own thread pool (:mod:`bouncelab.core._parallel`).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Iterable
from concurrent.futures import Executor
from typing import Any

from bouncelab.core.errors import FitError

__all__ = ["BATCHES_PER_WORKER", "is_dask_client", "map_tasks", "resolve_executor"]

#: The tasks go in about this many batches per worker (enough to balance the load).
BATCHES_PER_WORKER = 4


def is_dask_client(executor: Any) -> bool:
    """True for a :class:`dask.distributed.Client` (whose ``map`` returns futures, not results)."""
    return type(executor).__module__.split(".")[0] == "distributed" and hasattr(executor, "gather")


def resolve_executor(executor: Any, client: Any, where: str) -> Any:
    """The executor of a call that still takes the deprecated ``client=`` alias (a DeprecationWarning).

    Raises
    ------
    FitError
        Both given, and not the same object.
    """
    if client is None:
        return executor
    warnings.warn(f"{where}(client=...) is deprecated and will be removed in the next release: pass the same object "
                  "as executor=, which takes any concurrent.futures.Executor or a dask Client", DeprecationWarning,
                  stacklevel=3)
    if executor is not None and executor is not client:
        raise FitError(f"{where} takes executor= or its deprecated alias client=, not both", option="client")
    return client


def _run_batch(batch: tuple[Callable[[Any], Any], list[Any]]) -> list[Any]:
    function, tasks = batch
    return [function(t) for t in tasks]


def _workers(executor: Any) -> int:
    """Worker threads of a dask Client (every one: scheduler_info lists only some) or of dask's ClientExecutor,
    or the workers of a concurrent.futures executor as far as it tells (1 if it does not)."""
    client = executor if is_dask_client(executor) else getattr(executor, "_client", None)  # (ClientExecutor's)
    if client is not None and is_dask_client(client):
        return max(1, sum(client.nthreads().values()))
    n = getattr(executor, "_max_workers", None)
    return int(n) if isinstance(n, int) and n > 0 else 1


def _batches(function: Callable[[Any], Any], tasks: list[Any], slots: int) -> list[tuple[Callable, list[Any]]]:
    size = max(1, math.ceil(len(tasks) / (BATCHES_PER_WORKER * max(1, slots))))
    return [(function, tasks[i:i + size]) for i in range(0, len(tasks), size)]


def map_tasks(function: Callable[[Any], Any], tasks: Iterable[Any], executor: Any = None) -> list[Any]:
    """``[function(t) for t in tasks]``, serially or on ``executor`` (results in task order).

    Parameters
    ----------
    function
        A module-level function (so that it can be pickled to other processes).
    tasks
        Its arguments, one per call.
    executor
        None (serial), a :class:`concurrent.futures.Executor`, a :class:`dask.distributed.Client`,
        or an object with a ``map(function, iterable)`` method (see the module documentation).

    Raises
    ------
    FitError
        ``executor`` is none of these.
    """
    tasks = list(tasks)
    if executor is None or not tasks:
        return [function(t) for t in tasks]
    if is_dask_client(executor):
        # pure=False: every batch runs (no key hashing of large arguments; equal batches are not merged).
        futures = executor.map(_run_batch, _batches(function, tasks, _workers(executor)), pure=False)
        return [r for batch in executor.gather(futures) for r in batch]
    if isinstance(executor, Executor):
        futures = [executor.submit(_run_batch, b) for b in _batches(function, tasks, _workers(executor))]
        return [r for f in futures for r in f.result()]
    if not callable(getattr(executor, "map", None)):
        raise FitError(f"executor must be None, a concurrent.futures.Executor, a dask.distributed.Client or have a "
                       f"map(function, tasks) method; got {type(executor).__name__}", option="executor")
    return list(executor.map(function, tasks))
