"""``cadcog simulate``: Monte Carlo of the method with distribution fits."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from cadcog.cli._options import add_json, add_rig, rig_of
from cadcog.cli._output import print_json, wrote
from cadcog.core.errors import CadcogError
from cadcog.core.fileio import refuse_overwriting_inputs, staged_file
from cadcog.core.numformat import signed
from cadcog.rig.parameters import INCLINOMETER_MODELS, WIRE_MODELS
from cadcog.runs.simulate import simulate_rig
from cadcog.uncertainty.random_points import SimulationReport


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "simulate",
        help="Monte Carlo of the CoG error: quantiles, and moment fits with their quality",
        description="Draw suspension points over the proof mass, perturb every error source of "
        "the rig's error model, estimate as cadcog estimate does, compensate and compare with "
        "the CAD ground truth. See docs/montecarlo.md.",
    )
    add_rig(p)
    p.add_argument(
        "--points",
        type=int,
        default=25,
        help="random suspension points (default 25; 0 = the rig's own points)",
    )
    p.add_argument(
        "--trials-per-pair",
        type=int,
        default=1000,
        dest="trials",
        help="simulated campaigns, each giving one trial of every pair or group (default 1000)",
    )
    p.add_argument("--seed", type=int, default=0, help="root seed (default 0)")
    p.add_argument(
        "--group-size",
        type=int,
        default=2,
        help="2: pairs (eq. 8 with --paper); K > 2: joint estimate over K points",
    )
    p.add_argument(
        "--min-angle-deg",
        type=float,
        default=0.0,
        help="screen out pairs/groups whose plumb lines meet at less than this",
    )
    p.add_argument(
        "--wire-correction",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="correct each point for the expected wire offset, as cadcog estimate does "
        "(default on)",
    )
    p.add_argument(
        "--self-calibrate-wire",
        action="store_true",
        help="estimate the wire offset scale with the CoG (groups of 3 or more)",
    )
    p.add_argument(
        "--paper",
        action="store_true",
        help="the paper's Monte Carlo: its averaged inclinometer model, no sensor noise, eq. 8 "
        "(equal weights) and no wire correction",
    )
    p.add_argument("--samples", type=int, help="readings averaged per suspension (overrides rig)")
    p.add_argument(
        "--inclinometer-model",
        choices=INCLINOMETER_MODELS,
        help="inclinometer error model (overrides the rig)",
    )
    p.add_argument(
        "--wire-model", choices=WIRE_MODELS, help="wire offset model (overrides the rig)"
    )
    p.add_argument("--workers", type=int, default=1, help="processes (default 1)")
    add_json(p)
    p.add_argument(
        "--plot", type=Path, help="write a histogram of |e| with fitted PDFs (PNG, SVG, PDF)"
    )
    p.set_defaults(func=run)


#: Figure formats of ``--plot`` (by suffix).
PLOT_SUFFIXES = (".png", ".svg", ".pdf")


def run(args: argparse.Namespace) -> int:
    if args.plot is not None:
        if args.plot.suffix.lower() not in PLOT_SUFFIXES:
            raise CadcogError(
                f"--plot {args.plot}: expected a file name ending in "
                f"{', '.join(PLOT_SUFFIXES)} (the suffix sets the format)"
            )
        refuse_overwriting_inputs(args.plot, {"--rig": args.rig})
    rig = rig_of(args)
    if args.points == 1:
        raise CadcogError("--points 1: give 0 (the rig's own points) or at least 2")
    if args.paper and args.self_calibrate_wire:
        raise CadcogError("--paper and --self-calibrate-wire exclude each other")
    if args.self_calibrate_wire and (args.group_size < 3 or not args.wire_correction):
        raise CadcogError("--self-calibrate-wire needs --group-size 3 or more and the correction")
    bar = None
    if sys.stderr.isatty():
        from tqdm import tqdm

        bar = tqdm(total=None, unit="trial", unit_scale=True, file=sys.stderr, leave=False)
    try:
        report = simulate_rig(
            rig,
            points=args.points,
            trials=args.trials,
            seed=args.seed,
            group_size=args.group_size,
            min_angle_deg=args.min_angle_deg,
            wire_correction=args.wire_correction,
            paper=args.paper,
            workers=args.workers,
            self_calibrate_wire=args.self_calibrate_wire,
            samples=args.samples,
            inclinometer_model=args.inclinometer_model,
            wire_model=args.wire_model,
            progress=bar.update if bar is not None else None,
            total=_set_total(bar) if bar is not None else None,
        )
    except ValueError as exc:
        raise CadcogError(str(exc)) from None
    finally:
        if bar is not None:
            bar.close()
    if args.plot is not None:
        from cadcog.reports.plots import error_histogram

        with staged_file(args.plot) as tmp:
            error_histogram(
                report.result.histogram,
                report.fits,
                tmp,
                f"{rig.name}: {report.fits.n} trials, {len(report.groups)} groups",
            )
        wrote(args.plot)
    if args.json:
        print_json(report.to_dict())
    else:
        print_report(report)
    return 0


def _set_total(bar: Any) -> Callable[[int], None]:
    """Give a tqdm bar its total once the simulation knows it (groups × trials)."""

    def set_total(n: int) -> None:
        bar.total = n
        bar.refresh()

    return set_total


def print_report(report: SimulationReport) -> None:
    f, r = report.fits, report.result
    s = report.settings
    kind = "pairs" if s.group_size == 2 else f"groups of {s.group_size} (joint estimate)"
    print(
        f"{f.n} trials: {len(report.groups)} {kind} of {len(report.scenario.ids)} points, "
        f"{s.trials_per_group} trials each, seed {s.seed}"
    )
    print(f"error model: {report.model.summary()}")
    est = s.options.describe()
    print(
        f"estimator: {est['estimator']}, wire correction {'on' if s.wire_correction else 'off'}"
        + (", wire self-calibrated" if s.self_calibrate else "")
    )
    if report.unidentifiable_groups:
        print(
            f"left out: {report.unidentifiable_groups} groups whose points cannot determine the "
            "wire scale (cadcog estimate --self-calibrate-wire refuses them)"
        )
    print(f"\n|e| median {f.q50_mm:.3f} mm, 95 % {f.q95_mm:.3f} mm, 99 % {report.q99_mm:.3f} mm")
    sc = report.screened
    if "q95_mm" in sc:
        print(
            f"groups with lines at ≥ {sc['min_angle_deg']:g}° ({sc['n_groups']} of "
            f"{len(report.groups)}): median {sc['q50_mm']:.3f} mm, 95 % {sc['q95_mm']:.3f} mm, "
            f"99 % {sc['q99_mm']:.3f} mm"
        )
    else:
        print(f"no group has lines at ≥ {sc['min_angle_deg']:g}°")
    axes = ", ".join(
        f"{signed(b, 3)} ± {sd:.3f}" for b, sd in zip(r.axis_mean_mm, r.axis_std_mm, strict=True)
    )
    print(f"per-axis bias ± std (x, y, z): {axes} mm")
    print("\nmoment fits (KS distance = their quality; the quantiles above are the result):")
    print(
        f"  maximum likelihood: Rayleigh σ = {f.rayleigh_sigma_mm:.3f} mm (KS "
        f"{f.ks_rayleigh:.3f}), Maxwell a = {f.maxwell_a_mm:.3f} mm (KS {f.ks_maxwell:.3f})"
    )
    print(
        f"  median-matched:     Rayleigh σ = {f.rayleigh_sigma_median_mm:.3f} mm "
        f"(KS {f.ks_rayleigh_median:.3f}), Maxwell a = {f.maxwell_a_median_mm:.3f} mm "
        f"(KS {f.ks_maxwell_median:.3f})"
    )
    print("worst groups by 95 % quantile:")
    for w in report.worst_groups():
        print(
            f"  {'-'.join(w['points']):<12} q95 {w['q95_mm']:.3f} mm, lines at "
            f"{w['angle_deg']:.1f}°"
        )
