"""Spreading independent OCCT computations over processes.

OCP holds Python's global interpreter lock while OCCT works, so threads do not run booleans or
integrations side by side. Processes do, and on POSIX a *forked* child inherits the parent's
shapes for free: :func:`fork_map` stores the work list in a module global, forks a pool, and
each child computes items by index and returns plain numbers. Results come back in input
order, so they do not depend on the number of workers.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
from collections.abc import Callable, Sequence
from typing import Any, TypeVar

T = TypeVar("T")
R = TypeVar("R")

#: Below this many items a pool costs more than it saves: run serially.
MIN_PARALLEL_ITEMS = 8

_WORK: tuple[Callable[[Any], Any], Sequence[Any]] | None = None


def available_workers() -> int:
    """CPUs this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def worker_signals() -> None:
    """Pool initializer: a worker dies quietly on SIGTERM (the pool's shutdown) and ignores
    Ctrl-C (the parent handles it and ends the pool), instead of inheriting ``cadcog.cli``'s
    handlers and printing tracebacks."""
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _run(index: int) -> Any:
    assert _WORK is not None
    func, items = _WORK
    return func(items[index])


def fork_map(
    func: Callable[[T], R],
    items: Sequence[T],
    *,
    workers: int,
    progress: Callable[[int], None] | None = None,
) -> list[R]:
    """``[func(x) for x in items]``, over ``workers`` forked processes when worthwhile.

    ``func`` must return picklable values (numbers, tuples, arrays). Serial when ``workers`` is
    1, when there are fewer than :data:`MIN_PARALLEL_ITEMS` items, or where ``fork`` is not
    available.
    """
    global _WORK
    n_workers = min(workers, len(items))
    if n_workers <= 1 or len(items) < MIN_PARALLEL_ITEMS or not _can_fork():
        out = []
        for item in items:
            out.append(func(item))
            if progress is not None:
                progress(1)
        return out
    _WORK = (func, items)
    try:
        with multiprocessing.get_context("fork").Pool(n_workers, worker_signals) as pool:
            results = []
            for r in pool.imap(_run, range(len(items)), chunksize=1):
                results.append(r)
                if progress is not None:
                    progress(1)
            return results
    finally:
        _WORK = None


def _can_fork() -> bool:
    return "fork" in multiprocessing.get_all_start_methods()
