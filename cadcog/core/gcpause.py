"""Python's cyclic garbage collector paused for one bounded computation.

CPython runs its cycle collector after every few hundred new container objects, and each
older-generation pass walks every object alive. ``massprops`` on a 5000-body model keeps about
a million objects (bodies, placements, the budget tree, the JSON text) alive to the end and
makes almost no reference cycles, so those passes find nothing and cost 0.4-0.8 s of its
~4 s (``benchmarks/bench_massprops.py``; docs/performance.md). Reference counting still frees
every object that is not in a cycle as soon as it is unused; a cycle made inside the pause is
freed by the first collection after it.

Only for computations of bounded length: never around a command that runs for hours (``acquire``,
``session``).
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def gc_paused() -> Iterator[None]:
    """Disable the cycle collector for the ``with`` block; restore its previous state after,
    however the block ends.

    Examples
    --------
    >>> import gc
    >>> with gc_paused():
    ...     gc.isenabled()
    False
    >>> gc.isenabled()
    True
    """
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()
