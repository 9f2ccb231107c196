"""Runs: one composition per command, shared by the command and the API (estimate, campaign,
setup init, acquire, plan, inertia, simulate, validate, update; massprops, budget and report
still compose one layer down).

A run takes checked, typed arguments (paths, a rig or a set-up, options), does the work through
the library below it, stages its outputs and puts them in place together, and returns a result
whose ``to_dict()`` is the command's ``--json``. The command parses and prints;
:mod:`cadcog.api` checks Python arguments; neither composes the work again.
"""

from collections.abc import Sequence

from cadcog.core.errors import CadcogError


def check_distinct_ids(ids: Sequence[str]) -> None:
    """A run's hangs: at least two point ids, none twice (``--points``).

    Examples
    --------
    >>> check_distinct_ids(["S1", "S2"])
    >>> check_distinct_ids(["S1"])
    Traceback (most recent call last):
    ...
    cadcog.core.errors.CadcogError: --points: give at least two distinct point ids
    """
    twice = sorted({i for i in ids if list(ids).count(i) > 1})
    if twice:
        raise CadcogError(f"--points: {', '.join(twice)} given more than once: each point once")
    if len(ids) < 2:
        raise CadcogError("--points: give at least two distinct point ids")
