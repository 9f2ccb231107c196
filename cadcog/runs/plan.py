"""A spacecraft's test plan for the CoG, the inertia or both: ``cadcog plan`` and
:func:`cadcog.plan`.

:func:`run_plan` plans the CoG's hangs (:func:`cadcog.spacecraft.plan.plan_test`) and, for
``goal`` ``"inertia"`` or ``"both"``, the hangs whose swings determine the inertia tensor
(:func:`cadcog.dynamics.hangplan.plan_inertia_for_setup`). A set-up whose swings cannot
determine the tensor keeps its CoG plan, and the reason is part of the result
(``Plan.inertia_refused``; ``cadcog plan --for inertia`` then exits 1).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Literal

from cadcog.core.errors import CadcogError, DegenerateGeometryError
from cadcog.spacecraft.plan import Plan, plan_test
from cadcog.spacecraft.setup import Setup

Goal = Literal["cog", "inertia", "both"]


def check_plan_options(trials: int, max_set: int, seed: int, max_inertia_set: int) -> None:
    """The plan's counts, checked (the command calls it before reading the CAD).

    Raises
    ------
    CadcogError
        Fewer than 2 trials or hangs a set, a negative seed, fewer than 3 hangs for the
        inertia.
    """
    if trials < 2 or max_set < 2 or seed < 0:
        raise CadcogError("--trials ≥ 2, --max-set ≥ 2, --seed ≥ 0")
    if max_inertia_set < 3:
        raise CadcogError(
            "--max-inertia-set must be at least 3 (six entries, two frequencies a hang)"
        )


def run_plan(
    setup: Setup,
    *,
    trials: int = 10_000,
    max_set: int = 4,
    seed: int = 0,
    goal: Goal = "cog",
    weighed: bool = True,
    max_inertia_set: int = 8,
) -> Plan:
    """The plan for ``goal``: the CoG's (always), and the inertia's (``Plan.inertia``) or why
    none (``Plan.inertia_refused``).

    Raises
    ------
    CadcogError
        Bad options.
    """
    check_plan_options(trials, max_set, seed, max_inertia_set)
    if goal not in ("cog", "inertia", "both"):
        raise CadcogError(f"--for {goal}: expected cog, inertia or both")
    plan = plan_test(setup, trials=trials, max_set=max_set, seed=seed)
    if goal == "cog":
        return plan
    from cadcog.dynamics.hangplan import plan_inertia_for_setup

    try:
        inertia = plan_inertia_for_setup(
            setup, plan, weighed=weighed, max_set=max_inertia_set, both=goal == "both"
        )
    except DegenerateGeometryError as exc:  # valid input, no useful set: said, not an error
        return replace(plan, goal=goal, inertia_refused=str(exc))
    return replace(plan, goal=goal, inertia=inertia)
