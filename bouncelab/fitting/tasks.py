"""Independent fitting tasks, mapped by one function.

``compare``, ``bootstrap`` and ``cross_validate`` describe their work as a list
of independent tasks (each a small picklable tuple) and run them through
:func:`map_tasks`. Serially by default; given an ``executor`` (anything with a
``map(function, iterable)`` method returning results in order, such as a
``concurrent.futures`` executor or a dask client's executor), the tasks run there,
and the results are exactly the serial ones: each task carries its own seed.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

__all__ = ["map_tasks"]


def map_tasks(function: Callable[[Any], Any], tasks: Iterable[Any], executor: Any = None) -> list[Any]:
    """``[function(t) for t in tasks]``, serially or on ``executor`` (results in task order)."""
    tasks = list(tasks)
    if executor is None:
        return [function(t) for t in tasks]
    return list(executor.map(function, tasks))
