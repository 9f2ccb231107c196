"""``cadcog budget``: the error budget of a rig."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from cadcog.core.jsontext import dumps_json
from cadcog.method.errormodel import ErrorModel
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.uncertainty.error_budget import error_budget
from cadcog.uncertainty.montecarlo import Scenario


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "budget",
        help="error budget: each source, its size and its share of the CoG error",
        description="Each error source's distribution and standard deviation, and its share "
        "of the CoG error for a representative pair of the rig's suspension points (linear "
        "propagation). See docs/montecarlo.md.",
    )
    p.add_argument("--rig", type=Path, help="rig file (default: the paper's rig)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    rig = load_rig(args.rig or default_rig_path())
    model = ErrorModel.from_rig(rig)
    budget = error_budget(Scenario.from_rig(rig), model)
    if args.json:
        print(dumps_json(budget.to_dict()), end="")
        return 0
    a, b = budget.pair
    print(
        f"error budget of rig {rig.name!r}; shares for pair {a}-{b} "
        f"(lines at {budget.pair_angle_deg:.1f}°, the median of the rig's pairs)\n"
    )
    print(f"{'source':<14}{'sigma':>10} {'unit':<13}{'CoG sigma_mm':>13}{'share':>8}  distribution")
    for s in budget.sources:
        print(
            f"{s.source:<14}{s.sigma:>10.4f} {s.unit:<13}{s.cog_sigma_mm:>13.3f}"
            f"{s.share:>8.1%}  {s.distribution}"
        )
    d = budget.to_dict()
    bias = ", ".join(f"{v:.3f}" for v in budget.bias_mm)
    print(
        f"\ntotal CoG sigma (√trace): {d['cog_sigma_mm']:.3f} mm; bias with every source at "
        f"its mean: [{bias}] mm"
    )
    return 0
