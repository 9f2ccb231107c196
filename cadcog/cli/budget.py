"""``cadcog budget``: the error budget of a rig."""

from __future__ import annotations

import argparse
from typing import Any

from cadcog.cli._options import add_json, add_rig, rig_of
from cadcog.cli._output import print_json
from cadcog.core.errors import CadcogError
from cadcog.method.errormodel import ErrorModel
from cadcog.uncertainty.error_budget import error_budget
from cadcog.uncertainty.montecarlo import Scenario


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "budget",
        help="error budget: each source, its size and its share of the CoG error",
        description="Each error source's distribution and standard deviation, and its share "
        "of the CoG error for a representative pair of the rig's suspension points (linear "
        "propagation). See docs/montecarlo.md. For an accelerometer's rig (device = "
        '"accelerometer"): the 95 %% error the estimate will state, for every point and for the '
        "best set of each size, with and without the sensor's self-calibration (docs/bench.md "
        "section 8).",
    )
    add_rig(p)
    p.add_argument(
        "--target-mm",
        type=float,
        help="an accelerometer's rig: the smallest set of hangs whose predicted 95 %% error is "
        "within this (exit 1 when none is)",
    )
    add_json(p)
    p.set_defaults(func=run)


def _accelerometer(args: argparse.Namespace, rig: Any, model: ErrorModel) -> int:
    """An accelerometer's rig: the estimate's covariance at the CAD's readings, with and
    without self-calibration, for every point and for the best set of each size."""
    from cadcog.uncertainty.accel_budget import Hangs, accelerometer_budget

    sc = Scenario.from_rig(rig)
    hangs = Hangs(sc.ids, sc.points_mm, sc.normals, sc.assembly_cog_mm, sc.weight_n)
    budget = accelerometer_budget(hangs, rig.inclinometer, model, target_mm=args.target_mm)
    # A target no set reaches: said, exit 1 (valid input, as a requirement that fails).
    status = 1 if args.target_mm is not None and budget.meets is None else 0
    if args.json:
        print_json(budget.to_dict())
        return status
    print(f"predicted CoG error of rig {rig.name!r}, read by {model.summary()}\n")
    a = budget.all_hangs
    print(
        f"every point ({', '.join(a.hangs)}): 95 % error {a.q95_mm:.3f} mm, without "
        f"self-calibration {a.q95_uncalibrated_mm:.3f} mm\n"
    )
    print_accel_sizes(budget, args.target_mm)
    return status


def print_accel_sizes(budget: Any, target_mm: float | None) -> None:
    """The best set of each size, with and without self-calibration, and the target's."""
    print(f"{'hangs':<5} {'95 % error mm':>14} {'uncalibrated':>13}  best set (ID~: a reversal)")
    for s in budget.sizes:
        print(
            f"{len(s.hangs):<5} {s.q95_mm:>14.3f} {s.q95_uncalibrated_mm:>13.3f}  "
            f"{', '.join(s.hangs)}"
        )
    if target_mm is not None:
        m = budget.meets
        print(
            f"\nwithin {target_mm:g} mm: "
            + (
                f"{len(m.hangs)} hangs, {', '.join(m.hangs)}"
                if m is not None
                else "no set of these points gets there: declare a better sensor, or add points"
            )
        )
    best = budget.meets or budget.sizes[-1]
    calibrated = ", ".join(best.calibrated) or "none"
    print(
        f"\nrecommended: hang from {', '.join(best.hangs)} (predicted 95 % error "
        f"{best.q95_mm:.3f} mm; the hangs calibrate {calibrated})"
    )


def run(args: argparse.Namespace) -> int:
    rig = rig_of(args)
    model = ErrorModel.from_rig(rig)
    if rig.inclinometer.accelerometer:
        return _accelerometer(args, rig, model)
    if args.target_mm is not None:
        raise CadcogError("--target-mm: for an accelerometer's rig (cadcog plan --target-mm)")
    budget = error_budget(Scenario.from_rig(rig), model)
    if args.json:
        print_json(budget.to_dict())
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
