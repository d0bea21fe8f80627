"""A small thread pool for compiled loops that release the GIL: fork-, spawn- and thread-safe.

Two functions share work between threads: :func:`run_rows` (rows whose results are independent, such
as predictions) and :func:`run_chunked` (partial sums, cut at fixed multiples of :data:`CHUNK`). Prediction
of large arrays, the error sums of large fits and the batched log posteriors of :func:`bouncelab.calibrate`
are cut into parts and run by serial ``nogil`` loops on a :class:`~concurrent.futures.ThreadPoolExecutor`
(no OpenMP or TBB runtime). A forked child starts with a fresh pool; a loop called from inside a shared
part, on a pool thread or on the calling thread, runs serially (no nested waiting). The number of threads
is the number of CPUs this process may use, or the environment variable ``BOUNCELAB_NUM_THREADS``, or
:func:`set_num_threads`; results never depend on it.

This pool is for the loops inside one computation. Independent tasks (fits of resamples, folds, chains)
go to a user's :class:`concurrent.futures.Executor` through :func:`bouncelab.fitting.map_tasks`.
"""

from __future__ import annotations

import itertools
import os
import threading
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

__all__ = ["CHUNK", "PARALLEL_MIN", "num_threads", "run_chunked", "run_rows", "set_num_threads"]

#: Rows per chunk of a loop whose partial results are combined (sums): every call of at least
#: :data:`PARALLEL_MIN` rows is cut at multiples of it, serial or threaded, so sums do not depend on threads.
CHUNK = 1 << 15
#: From this many rows, parts are shared by the thread pool (below, one serial call is cheaper).
PARALLEL_MIN = 2 * CHUNK

_pool: ThreadPoolExecutor | None = None
_pool_lock = threading.Lock()
_threads: int | None = None
_local = threading.local()


def _default_threads() -> int:
    env = os.environ.get("BOUNCELAB_NUM_THREADS")
    if env:
        try:
            return max(1, int(env))
        except ValueError:
            pass
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not Linux
        return max(1, os.cpu_count() or 1)


def num_threads() -> int:
    """Threads that share the chunks of a large prediction."""
    global _threads
    if _threads is None:
        _threads = _default_threads()
    return _threads


def set_num_threads(n: int) -> None:
    """Use ``n`` threads for large predictions (results do not depend on it)."""
    global _threads, _pool
    from bouncelab.core.errors import ParameterError  # (imported here: this module has no dependencies)

    try:
        n = int(n)
    except (TypeError, ValueError):
        n = 0
    if n < 1:
        raise ParameterError(f"the number of threads must be an integer of at least 1; got {n!r}")
    with _pool_lock:
        _threads = n
        old, _pool = _pool, None
    if old is not None:
        old.shutdown(wait=False)


def _reset_after_fork() -> None:
    # The parent's pool threads do not exist in a forked child: start afresh there.
    global _pool, _pool_lock
    _pool = None
    _pool_lock = threading.Lock()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_reset_after_fork)


def _get_pool() -> ThreadPoolExecutor:
    global _pool
    with _pool_lock:
        if _pool is None:
            _pool = ThreadPoolExecutor(max_workers=num_threads(), thread_name_prefix="bouncelab")
        return _pool


def _in_worker(fn: Callable, *args: Any) -> Any:  # marks pool threads: a loop called there runs serially
    _local.in_pool = True
    try:
        return fn(*args)
    finally:
        _local.in_pool = False


def _share(fn: Callable, args: tuple, cuts: list[int], results: list | None) -> None:
    """Run the parts ``[cuts[k], cuts[k+1])`` on the calling thread and ``num_threads() - 1`` pool threads.

    Each thread claims the next unclaimed part until none is left, so a pool thread that wakes
    late (a loaded machine) simply takes fewer parts. ``results[k]`` receives part k's result.
    """
    claim = itertools.count()  # next() on a count is atomic under the GIL
    parts = len(cuts) - 1

    def work() -> None:
        while True:
            k = next(claim)
            if k >= parts:
                return
            r = fn(*args, cuts[k], cuts[k + 1])
            if results is not None:
                results[k] = r

    threads = min(num_threads(), parts)
    pool = _get_pool() if threads > 1 else None
    futures = [pool.submit(_in_worker, work) for _ in range(threads - 1)] if pool is not None else []
    try:
        _in_worker(work)  # the calling thread shares the parts: loops inside them run serially there too
    finally:
        for f in futures:
            f.result()


def run_rows(fn: Callable, n: int, *args: Any, min_rows: int = PARALLEL_MIN, min_part: int = CHUNK // 2
             ) -> list[Any]:
    """Call ``fn(*args, start, stop)`` over ``[0, n)`` for a loop whose rows are independent (prediction).

    From ``min_rows`` rows (default :data:`PARALLEL_MIN`, right for loops of a microsecond a row; an
    expensive row, such as an integrated contact, pays for threads far sooner) the range is cut into
    parts of at least ``min_part`` rows, shared by the calling thread and the pool; where the cuts fall
    cannot change any row's result. Returns the parts' results in order (e.g. whether their rows were valid).
    """
    threads = num_threads()
    if n < max(min_rows, 2) or threads == 1 or getattr(_local, "in_pool", False):
        return [fn(*args, 0, n)]
    size = max(1, min_part, n // (16 * threads))
    cuts = [*range(0, n, size), n]
    results: list[Any] = [None] * (len(cuts) - 1)
    _share(fn, args, cuts, results)
    return results


def run_chunked(fn: Callable, n: int, *args: Any) -> list[Any]:
    """Call ``fn(*args, start, stop)`` over ``[0, n)`` in chunks of :data:`CHUNK`; return the results in order.

    Below :data:`PARALLEL_MIN` rows one call covers everything. Above it the chunk
    boundaries are always the same multiples of CHUNK, serial or threaded, so results
    combined in order do not depend on the number of threads.
    """
    if n < PARALLEL_MIN:
        return [fn(*args, 0, n)]
    cuts = [*range(0, n, CHUNK), n]
    results: list[Any] = [None] * (len(cuts) - 1)
    if num_threads() == 1 or getattr(_local, "in_pool", False):
        for k in range(len(cuts) - 1):
            results[k] = fn(*args, cuts[k], cuts[k + 1])
        return results
    _share(fn, args, cuts, results)
    return results
