"""``cadcog validate``: a measured campaign against the simulated error distribution."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from cadcog.errors import CadcogError
from cadcog.fileio import round_floats
from cadcog.readings import read_readings
from cadcog.rigfile import default_rig_path, load_rig
from cadcog.validation import DEFAULT_WINDOWS_MM, CampaignValidation, validate_campaign


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
        help="check a measured campaign against the simulated error distribution (eqs. 14-15)",
        description="Every pair of the campaign's suspensions gives a compensated CoG whose error "
        "against the rig's true CoG is a Bernoulli trial per window; compare p̂ = k/n with the "
        "simulated F(ε) (Clopper-Pearson 95 %), plus a KS test. See docs/validation.md.",
    )
    p.add_argument("campaign", type=Path, help="readings CSV of the campaign (3 or more points)")
    p.add_argument("--rig", type=Path, help="rig file (default: the paper's rig)")
    p.add_argument(
        "--windows",
        type=_windows,
        default=DEFAULT_WINDOWS_MM,
        help="error windows ε in mm (default 0.5,1,1.5,2,3)",
    )
    p.add_argument(
        "--trials-per-pair",
        type=int,
        default=20_000,
        dest="trials",
        help="Monte Carlo trials per pair (default 20000)",
    )
    p.add_argument("--seed", type=int, default=0, help="Monte Carlo seed (default 0)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    rig = load_rig(args.rig or default_rig_path())
    suspensions = read_readings(args.campaign, rig.inclinometer)
    if len(suspensions) < 3:
        raise CadcogError(
            f"{args.campaign}: validation needs 3 or more suspension points, got {len(suspensions)}"
        )
    if args.trials < 2 or args.seed < 0:
        raise CadcogError("--trials-per-pair must be ≥ 2 and --seed ≥ 0")
    try:
        result = validate_campaign(
            rig, suspensions, args.windows, trials_per_pair=args.trials, seed=args.seed
        )
    except ValueError as exc:
        raise CadcogError(f"{args.campaign}: {exc}") from None
    if args.json:
        print(json.dumps(round_floats(result.to_dict()), indent=2, ensure_ascii=False))
    else:
        print_validation(result)
    return 0


def print_validation(result: CampaignValidation) -> None:
    v = result.validation
    print(f"{len(v.pairs)} pairs, {result.simulated_norms_mm.size} simulated trials\n")
    print(f"{'eps_mm':>7}{'F(eps)':>9}{'k':>4}{'n':>4}{'p_hat':>8}   95% CI          consistent")
    for w in v.windows:
        print(
            f"{w.eps_mm:>7.2f}{w.F:>9.3f}{w.k:>4}{w.n:>4}{w.p_hat:>8.3f}   "
            f"[{w.ci_low:.3f}, {w.ci_high:.3f}]  {'yes' if w.consistent else 'NO'}"
        )
    print(
        f"\nKS test of the measured errors against the simulated CDF: D = {v.ks_statistic:.3f}, "
        f"p = {v.ks_p_value:.3f}"
    )
    print(
        "verdict: "
        + (
            "consistent with the simulation"
            if v.consistent
            else "NOT consistent with the simulation in every window"
        )
    )
    print(
        "caveat: pairs share hangs, so their errors are not independent; the intervals treat "
        "them as independent, as the paper does"
    )
