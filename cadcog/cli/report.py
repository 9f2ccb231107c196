"""``cadcog report``: the whole chain on a rig, and its HTML report."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

from cadcog.cli._options import add_json, add_rig, rig_of
from cadcog.cli._output import print_json, wrote
from cadcog.core.errors import CadcogError
from cadcog.core.fileio import not_a_regular_file


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "report",
        help="run parts, budget, simulate, campaign, validate, estimate and write an HTML report",
        description="The whole chain on a rig: CAD ground truth, error budget, Monte Carlo, a "
        "campaign (yours with --campaign, else a virtual one), validation and the compensated "
        "estimate, written as a self-contained HTML page. See docs/validation.md.",
    )
    add_rig(p)
    p.add_argument("--campaign", type=Path, help="measured readings CSV (default: virtual)")
    p.add_argument("--seed", type=int, default=0, help="seed of the simulations (default 0)")
    p.add_argument("--out", type=Path, required=True, help="output directory")
    add_json(p, "print the summary as one JSON object (report path included)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from cadcog.reports.rig_report import build_report

    rig = rig_of(args)
    if args.campaign is not None and not args.campaign.is_file():
        raise CadcogError(f"{args.campaign}: {not_a_regular_file(args.campaign)}")
    try:
        result = build_report(
            rig,
            args.out,
            args.campaign,
            seed=args.seed,
            log=lambda m: print(f"  {m}", file=sys.stderr),
        )
    except ValueError as exc:
        raise CadcogError(str(exc)) from None
    est, sim = result.estimate, result.simulation
    val, verdict = result.validation.validation, result.validation.verdict
    sigma = np.sqrt(np.diag(est.cov_mm2))
    truth = np.array(result.ground_truth["bodies"]["proof_mass"]["cog_mm"])
    kind = "virtual" if result.campaign_is_virtual else "measured"
    wrote(result.report)
    if args.json:
        summary = {
            "rig": rig.name,
            "report": str(result.report),
            "cad_proof_mass_cog_mm": truth.tolist(),
            "simulated_pair_error_mm": {"q50": sim.fits.q50_mm, "q95": sim.fits.q95_mm},
            "campaign": {
                "kind": kind,
                "n_pairs": len(val.pairs),
                "consistent": bool(verdict.consistent),
                "p_value": verdict.p_value,
            },
            "cog_mm": est.cog_mm.tolist(),
            "cog_sigma_mm": sigma.tolist(),
        }
        print_json(summary)
        return 0
    print(f"rig {rig.name!r}: CAD proof-mass CoG {np.round(truth, 3).tolist()} mm")
    print(f"simulated pair error: median {sim.fits.q50_mm:.2f} mm, 95 % {sim.fits.q95_mm:.2f} mm")
    print(
        f"{kind} campaign: {len(val.pairs)} pairs, "
        f"{'consistent' if verdict.consistent else 'NOT consistent'} with the error model "
        f"(p = {verdict.p_value:.3f})"
    )
    print(
        f"compensated CoG {np.round(est.cog_mm, 3).tolist()} mm ± "
        f"{np.round(sigma, 3).tolist()} mm (1 σ)"
    )
    return 0
