"""``cadcog.core.parallel``: ``fork_map`` is the serial map, in input order, whatever the
number of workers; the work list does not outlive the call."""

from __future__ import annotations

import os

import numpy as np
import pytest

from cadcog.core import parallel


def _work(x: int) -> tuple[int, float, int]:
    """Different time per item (so workers finish out of order), and which process ran it."""
    rng = np.random.default_rng(x)
    total = float(rng.normal(size=2000 * (1 + x % 5)).sum())
    return x, total, os.getpid()


@pytest.mark.parametrize("workers", [1, 2, 3])
def test_the_result_is_the_serial_map_in_order(workers):
    items = list(range(3 * parallel.MIN_PARALLEL_ITEMS))
    ticks: list[int] = []
    got = parallel.fork_map(_work, items, workers=workers, progress=ticks.append)
    serial = [_work(x) for x in items]
    assert [g[:2] for g in got] == [s[:2] for s in serial]  # the same numbers, to the bit
    assert ticks == [1] * len(items)
    others = {g[2] for g in got} - {os.getpid()}
    if workers > 1 and parallel._can_fork():
        assert others  # it did fork
    else:
        assert not others
    assert parallel._WORK is None


def test_few_items_run_here():
    items = list(range(parallel.MIN_PARALLEL_ITEMS - 1))
    got = parallel.fork_map(_work, items, workers=4)
    assert {g[2] for g in got} == {os.getpid()}


def test_an_error_in_a_worker_reaches_the_caller_and_the_list_is_cleared():
    def fails(x: int) -> int:
        if x == 5:
            raise ValueError("item 5")
        return x

    with pytest.raises(ValueError, match="item 5"):
        parallel.fork_map(fails, list(range(2 * parallel.MIN_PARALLEL_ITEMS)), workers=2)
    assert parallel._WORK is None


def test_available_workers_is_at_least_one():
    assert parallel.available_workers() >= 1
