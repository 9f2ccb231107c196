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
from typing import Any, Literal

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


def run_accel_plan(
    setup: Setup, *, max_set: int = 8, target_mm: float | None = None
) -> tuple[list[Any], Any]:
    """An accelerometer's plan (``device = "accelerometer"``): each candidate checked as
    :func:`cadcog.spacecraft.plan.check_candidate` checks it, then the best set of each size up
    to ``max_set`` hangs (reversals included) by the estimator's covariance at the CAD's
    readings (:mod:`cadcog.uncertainty.accel_budget`), and the smallest within ``target_mm``.

    Raises
    ------
    CadcogError
        Fewer than two usable candidates, or no pair of them determines the CoG.
    """
    import numpy as np

    from cadcog.spacecraft.plan import check_candidate
    from cadcog.uncertainty.accel_budget import Hangs, accelerometer_budget

    checks = [check_candidate(setup, c) for c in setup.candidates]
    usable = [c for c, k in zip(setup.candidates, checks, strict=True) if k.usable]
    if len(usable) < 2:
        raise CadcogError(
            f"{setup.source}: {len(usable)} of {len(checks)} candidates usable, two at least "
            "are needed"
        )
    hangs = Hangs(
        tuple(c.id for c in usable),
        np.array([c.position_mm for c in usable], dtype=float),
        np.array([c.normal for c in usable], dtype=float),
        np.asarray(setup.assembly_cog_mm, dtype=float),
        setup.scenario().weight_n,
    )
    try:
        budget = accelerometer_budget(
            hangs, setup.rig.inclinometer, setup.error_model(), target_mm=target_mm,
            max_hangs=max_set,
        )  # fmt: skip
    except DegenerateGeometryError as exc:
        raise CadcogError(f"{setup.source}: {exc}") from None
    return checks, budget
