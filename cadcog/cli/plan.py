"""``cadcog plan``: which suspensions will work on a spacecraft, and which set to use."""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from cadcog.cli._options import add_json
from cadcog.cli._output import print_json, warn
from cadcog.core import numformat
from cadcog.core.errors import CadcogError


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "plan",
        help="plan the suspension test of a spacecraft from its CAD",
        description="For each candidate suspension point: is the inclinometer in range? For "
        "each pair and set: the 95 % error the estimator's covariance predicts; the best sets "
        "are then simulated with the error model and the estimator of cadcog estimate, and the "
        "one with the smallest simulated 95 % error is recommended. See docs/spacecraft.md.",
    )
    p.add_argument("setup", type=Path, nargs="?", help="set-up file (TOML)")
    p.add_argument(
        "--setup",
        type=Path,
        dest="setup_option",
        metavar="SETUP",
        help="the set-up file, as campaign, estimate, inertia and update take it",
    )
    p.add_argument("--trials", type=int, default=10_000, help="Monte Carlo trials per finalist set")
    p.add_argument(
        "--max-set",
        type=int,
        default=4,
        help="largest set of hangs to consider (default 4; an accelerometer's plan shows at "
        "least 8: its shared errors need more hangs)",
    )
    p.add_argument(
        "--target-mm",
        type=float,
        help="an accelerometer's plan: the smallest set whose predicted 95 %% error is within "
        "this (exit 1 when none is)",
    )
    p.add_argument("--seed", type=int, default=0)
    p.add_argument(
        "--for",
        dest="goal",
        choices=("cog", "inertia", "both"),
        default="cog",
        help="what the hangs should determine best: the CoG (default), the inertia tensor from "
        "their swings (cadcog inertia), or both (the CoG's set, grown for the inertia)",
    )
    p.add_argument(
        "--max-inertia-set", type=int, default=8, help="largest set of hangs for the inertia"
    )
    p.add_argument(
        "--no-weighing",
        action="store_true",
        help="plan the inertia with the CAD's mass uncertainty instead of a 1 g weighing",
    )
    add_json(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from cadcog.runs.plan import check_plan_options, run_plan
    from cadcog.spacecraft.setup import load_setup

    if (args.setup is None) == (args.setup_option is None):
        raise CadcogError(
            "give the set-up file once: cadcog plan SETUP.toml (or --setup SETUP.toml)"
        )
    check_plan_options(args.trials, args.max_set, args.seed, args.max_inertia_set)  # before CAD
    setup = load_setup(args.setup if args.setup is not None else args.setup_option)
    if setup.rig.inclinometer.accelerometer:
        return _accelerometer_plan(args, setup)
    if args.target_mm is not None:
        raise CadcogError("--target-mm: for an accelerometer's set-up (see cadcog budget)")
    plan = run_plan(
        setup,
        trials=args.trials,
        max_set=args.max_set,
        seed=args.seed,
        goal=args.goal,
        weighed=not args.no_weighing,
        max_inertia_set=args.max_inertia_set,
    )
    inertia, inertia_refused = plan.inertia, plan.inertia_refused
    # --for inertia that no set of candidates can meet: the plan is said, exit 1 (as a
    # requirement that fails); valid input, so not 2
    status = 1 if args.goal == "inertia" and inertia is None else 0
    if args.json:
        print_json(plan.to_dict())
        return status
    m = setup.mass
    cog = ", ".join(f"{c:.3f}" for c in m.cog_mm)
    print(
        f"{setup.name}: {numformat.mass(m.mass_kg)}, CAD CoG [{cog}] mm; "
        f"ME {numformat.mass(setup.me_mass_kg)} (m_ME/m = {setup.me_mass_kg / m.mass_kg:.4g})"
    )
    for w in plan.warnings:
        warn(w)
    bad = [c for c in plan.checks if not c.usable]
    print(
        f"{len(plan.checks) - len(bad)} of {len(plan.checks)} candidates keep the "
        "inclinometer's readings in range and trustworthy"
    )
    _print_unusable(bad)
    if plan.model is not None:
        print(f"error model: {plan.model.summary()}")
    print("\nbest pairs (linearised 95 % error):")
    for p in plan.pairs[:5]:
        print(
            f"  {p['a']} + {p['b']}: lines at {p['angle_deg']:.1f}°, 95 % error "
            f"{p['linearised_q95_mm']:.3f} mm"
        )
    print(f"\nbest set of each size (joint estimate, {plan.trials} simulated trials each):")
    for s in plan.best_sets:
        print(
            f"  {len(s['points'])} hangs: {', '.join(s['points'])}: 95 % error {s['q95_mm']:.3f} mm"
            f" (linearised {s['linearised_q95_mm']:.3f})"
        )
    if plan.recommended is None:
        print(f"\nno recommendation: {plan.reason}")
        if inertia_refused:
            print(f"\ninertia from the swings: not planned: {inertia_refused}")
        return status
    if inertia is not None and args.goal == "both":  # one set: the CoG's, grown
        _print_inertia_plan(inertia, args.goal)
        _print_recommended_both(plan.recommended, inertia.recommended)
    else:
        print(
            f"\nrecommended{' for the CoG' if inertia is not None else ''}: hang from "
            f"{', '.join(plan.recommended['points'])} "
            f"(predicted 95 % error {plan.recommended['q95_mm']:.3f} mm)"
        )
        if inertia is not None:
            _print_inertia_plan(inertia, args.goal)
    rev = plan.reversal
    if rev is not None and rev.advised:
        print(
            f"then hang {rev.point} once more with the sensor turned 180° on its mount (a "
            f"reversal, docs/bench.md): the CoG's σ {rev.sigma_mm:.3f} → {rev.sigma_with_mm:.3f}"
            f" mm, the zero offsets' σ {rev.offset_sigma_deg[0]:.2f}° → "
            f"{rev.offset_sigma_with_deg[0]:.2f}° (linearised)"
        )
    if inertia is None and inertia_refused:
        print(f"\ninertia from the swings: not planned: {inertia_refused}")
    return status


def _accelerometer_plan(args: argparse.Namespace, setup: Any) -> int:
    """``plan`` for a set-up read by an accelerometer: the CoG's hangs, by the estimator's
    covariance at the CAD's readings."""
    from cadcog.cli.budget import print_accel_sizes
    from cadcog.runs.plan import run_accel_plan

    if args.goal != "cog":
        raise CadcogError(
            f"--for {args.goal}: an accelerometer's plan is for the CoG only (its swings give "
            "the inertia, cadcog acquire --log --swings, but the inertia's plan is not yet made "
            "for an accelerometer's set-up)"
        )
    checks, budget = run_accel_plan(setup, max_set=max(args.max_set, 8), target_mm=args.target_mm)
    status = 1 if args.target_mm is not None and budget.meets is None else 0
    if args.json:
        out = budget.to_dict()
        out["checks"] = [{"id": c.id, "usable": c.usable, "reason": c.reason} for c in checks]
        print_json(out)
        return status
    bad = [c for c in checks if not c.usable]
    print(f"{setup.name}: {len(checks) - len(bad)} of {len(checks)} candidates usable")
    _print_unusable(bad)
    print(f"error model: {setup.error_model().summary()}\n")
    print_accel_sizes(budget, args.target_mm)
    return status


def _print_inertia_plan(inertia: Any, goal: str) -> None:
    mass = "a 1 g weighing" if inertia.weighed else "the CAD's mass uncertainty"
    grown = " (the CoG's set, grown)" if goal == "both" else ""
    print(f"\ninertia from the swings{grown}: 1 σ of the principal moments, with {mass}:")
    for s in inertia.best_sets:
        rel = ", ".join(f"{100 * r:.2f}" for r in s["moments_sigma_rel"])
        axes = ", ".join(f"{a:.2g}" if a < 90 else "undetermined" for a in s["axes_sigma_deg"])
        print(f"  {len(s['points'])} hangs: {', '.join(s['points'])}: [{rel}] %, axes ± [{axes}]°")
    r = inertia.recommended
    if goal != "both":
        print(
            f"recommended for the inertia: hang from {', '.join(r['points'])} (worst moment "
            f"± {100 * r['worst_moment_sigma_rel']:.2f} % at 1 σ)"
        )


def _print_recommended_both(cog: dict[str, Any], inertia: dict[str, Any]) -> None:
    """One recommendation for ``--for both``: the inertia's set, grown from the CoG's (the
    CoG's hangs first, then what the swings add), with what each part predicts."""
    more = [p for p in inertia["points"] if p not in cog["points"]]
    added = f", then {', '.join(more)} for the inertia" if more else ""
    print(
        f"\nrecommended: hang from {', '.join([*cog['points'], *more])} (the CoG's "
        f"{len(cog['points'])}, predicted 95 % error {cog['q95_mm']:.3f} mm{added}; worst "
        f"moment ± {100 * inertia['worst_moment_sigma_rel']:.2f} % at 1 σ)"
    )


#: Unusable candidates listed one per line; the rest are counted (``--json`` has them all).
UNUSABLE_SHOWN = 10


def _print_unusable(bad: Sequence[Any]) -> None:
    """Why candidates cannot work: the first :data:`UNUSABLE_SHOWN`, then how many more."""
    for c in bad[:UNUSABLE_SHOWN]:
        print(f"  {c.id}: cannot work: {c.reason}")
    if len(bad) > UNUSABLE_SHOWN:
        print(f"  ... and {len(bad) - UNUSABLE_SHOWN} more (--json gives each one's reason)")
