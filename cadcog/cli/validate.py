"""``cadcog validate``: a measured campaign against the simulated error distribution."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from cadcog.cli._options import add_json, add_rig, rig_of
from cadcog.cli._output import print_json
from cadcog.core.errors import CadcogError
from cadcog.runs.validate import validate_readings
from cadcog.validation.verification import DEFAULT_WINDOWS_MM, CampaignValidation


def _windows(text: str) -> tuple[float, ...]:
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected comma-separated numbers, got {text!r}"
        ) from None
    if not values or any(not v > 0 for v in values):
        raise argparse.ArgumentTypeError(f"windows must be positive numbers, got {text!r}")
    return values


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "validate",
        help="check a measured campaign against simulated campaigns (eqs. 14-15, and one "
        "campaign-level test)",
        description="Every pair of the campaign's suspensions gives a compensated CoG whose error "
        "against the rig's true CoG is a Bernoulli trial per window (the paper's table); whole "
        "campaigns simulated on the same points give each window's null range and one "
        "campaign-level p-value of stated size. See docs/validation.md.",
    )
    p.add_argument("campaign", type=Path, help="readings CSV of the campaign (3 or more points)")
    add_rig(p)
    p.add_argument(
        "--windows",
        type=_windows,
        default=DEFAULT_WINDOWS_MM,
        help="error windows ε in mm (default 0.5,1,1.5,2,3)",
    )
    p.add_argument(
        "--campaigns",
        type=int,
        default=2000,
        help="whole campaigns simulated for the null distribution (default 2000)",
    )
    p.add_argument(
        "--level",
        type=float,
        default=0.05,
        help="false-alarm rate of the campaign verdict (default 0.05)",
    )
    p.add_argument("--seed", type=int, default=0, help="Monte Carlo seed (default 0)")
    add_json(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.campaigns < 20 or args.seed < 0 or not 0 < args.level < 1:
        raise CadcogError("--campaigns must be ≥ 20, --seed ≥ 0 and --level in (0, 1)")
    rig = rig_of(args)
    result = validate_readings(
        rig,
        args.campaign,
        args.windows,
        campaigns=args.campaigns,
        seed=args.seed,
        level=args.level,
    )
    if args.json:
        print_json(result.to_dict())
    else:
        print_validation(result)
    return 0


def print_validation(result: CampaignValidation) -> None:
    v, c = result.validation, result.verdict
    print(
        f"{len(v.pairs)} pairs; null: {result.null.n_campaigns} simulated campaigns on the same "
        f"points ({result.model.inclinometer_model} inclinometer model)\n"
    )
    print(
        f"{'eps_mm':>7}{'F(eps)':>9}{'k':>4}{'n':>4}{'p_hat':>8}   95% CI (indep.)  "
        "null k range  consistent"
    )
    for w in v.windows:
        print(
            f"{w.eps_mm:>7.2f}{w.F:>9.3f}{w.k:>4}{w.n:>4}{w.p_hat:>8.3f}   "
            f"[{w.ci_low:.3f}, {w.ci_high:.3f}]  {w.null_k_low:>4}-{w.null_k_high:<4}     "
            f"{'yes' if w.consistent else 'NO'}"
        )
    print(
        f"\nKS of the pair errors against F (pairs taken as independent): D = "
        f"{v.ks_statistic:.3f}, p = {v.ks_p_value:.3f}"
    )
    print(
        f"campaign test (every hang's line against the known CoG): T = {c.statistic:.2f}, "
        f"p = {c.p_value:.3f} at level {c.level:g}"
    )
    print(
        "verdict: "
        + (
            "consistent with the error model"
            if c.consistent
            else "NOT consistent with the error model"
        )
    )
