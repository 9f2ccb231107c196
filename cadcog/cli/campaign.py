"""``cadcog campaign``: a virtual test campaign written as a readings CSV
(:func:`cadcog.runs.campaign.run_campaign`)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from cadcog.cli._options import add_json, add_rig, refuse_rig_and_setup, rig_of
from cadcog.cli._output import print_json, warn, wrote
from cadcog.core.errors import CadcogError
from cadcog.core.fileio import is_stream, refuse_overwriting_inputs
from cadcog.runs.campaign import CampaignRun, check_points, run_campaign, with_overrides


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "campaign",
        help="simulate the paper's experiment as a lab would record it (readings CSV)",
        description="One hang per suspension point of the rig, drawn from the rig's error model "
        "(the one every command uses): N raw ADC samples per axis with sensor noise and "
        "quantisation, the inclinometer's bias and the suspension point's play drawn once per "
        "hang, the wire's offset (one wire), the sensor's shared errors (one sensor) and the "
        "ME's CoG once per campaign. See docs/validation.md.",
    )
    add_rig(p)
    p.add_argument("--seed", type=int, default=0, help="seed (default 0)")
    p.add_argument(
        "--samples", type=int, help="raw samples per hang (default: the error model's, 10)"
    )
    p.add_argument(
        "--noise-deg",
        type=float,
        help="sensor noise of one sample (default: the error model's sensor_noise_deg, 0.05°)",
    )
    p.add_argument(
        "--setup",
        type=Path,
        help="simulate a spacecraft's test instead: its set-up file (needs --points)",
    )
    p.add_argument("--points", help="with --setup: comma-separated candidate ids to hang from")
    p.add_argument(
        "--out",
        type=Path,
        required=True,
        help="CSV file to write (an existing one is replaced only if a virtual campaign wrote it)",
    )
    p.add_argument(
        "--swings",
        type=Path,
        help="also write each hang's swing from release (a swing CSV for cadcog inertia), "
        "from the linear model with the CAD's inertia",
    )
    add_json(p, "print what was written as one JSON object")
    p.set_defaults(func=run, also_written=lambda a: [a.swings])


def run(args: argparse.Namespace) -> int:
    refuse_rig_and_setup(args)
    refuse_overwriting_inputs(args.out, {"--rig": args.rig, "--setup": args.setup})  # early
    options = {"samples": args.samples, "noise_deg": args.noise_deg}
    if args.setup is not None:
        from cadcog.method.errormodel import ErrorModel
        from cadcog.spacecraft.setup import load_setup

        points = check_points(args.points.split(",") if args.points else None)
        with_overrides(ErrorModel((1.0,), (0.0,)), **options)  # checked before the (slow) CAD
        run = run_campaign(
            args.out,
            setup=load_setup(args.setup),
            points=points,
            seed=args.seed,
            swings=args.swings,
            **options,
        )
    else:
        if args.points is not None:
            raise CadcogError("--points goes with --setup")

        rig = rig_of(args)
        run = run_campaign(args.out, rig=rig, seed=args.seed, swings=args.swings, **options)
    return _written(args, run)


def _written(args: argparse.Namespace, run: CampaignRun) -> int:
    """Say what was written: ``report: PATH`` on stderr, then a line or JSON on stdout (both on
    stderr when the CSV itself went to stdout)."""
    out = sys.stderr if is_stream(args.out) else sys.stdout
    if not is_stream(args.out):
        wrote(args.out)
    if run.swings is not None:
        wrote(run.swings)
    for w in run.warnings:
        warn(w)
    if args.json:
        print_json(run.to_dict(), out)
    else:
        print(f"wrote {run.n_samples} samples of {run.n_hangs} hangs to {args.out}", file=out)
        if run.swings is not None:
            print(f"wrote the swings of {run.n_hangs} hangs to {run.swings}", file=out)
    return 0
