"""``cadcog campaign``: a virtual test campaign written as a readings CSV."""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from cadcog.core.errors import CadcogError
from cadcog.core.fileio import is_stream, refuse_overwriting_inputs
from cadcog.core.jsontext import dumps_json
from cadcog.method.errormodel import ErrorModel
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.uncertainty.montecarlo import Scenario
from cadcog.validation.campaign import simulated_readings, write_campaign


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
    p.add_argument("--rig", type=Path, help="rig file (default: the paper's rig)")
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
    p.add_argument("--out", type=Path, required=True, help="CSV file to write")
    p.add_argument(
        "--swings",
        type=Path,
        help="also write each hang's swing from release (a swing CSV for cadcog inertia), "
        "from the linear model with the CAD's inertia",
    )
    p.add_argument("--json", action="store_true", help="print what was written as one JSON object")
    p.set_defaults(func=run)


def _write_swings(args: argparse.Namespace, context: Any, rows: list[Any], config: Any) -> None:
    """``--swings``: the campaign's hangs' swings (seeded from ``--seed``)."""
    if args.swings is None:
        return
    from cadcog.dynamics.swingfile import write_swings
    from cadcog.dynamics.virtual import virtual_swings
    from cadcog.validation.campaign import campaign_suspensions

    hangs = campaign_suspensions(rows, config)
    write_swings(args.swings, virtual_swings(context, hangs, seed=args.seed))
    print(f"report: {args.swings}", file=sys.stderr)


def _model(args: argparse.Namespace, model: ErrorModel) -> ErrorModel:
    """The error model with the command's overrides (the same keys as the rig file's)."""
    if args.samples is not None:
        if args.samples < 1:
            raise CadcogError(f"--samples must be at least 1, got {args.samples}")
        model = replace(model, samples=args.samples)
    if args.noise_deg is not None:
        if not args.noise_deg >= 0:
            raise CadcogError(f"--noise-deg must be non-negative, got {args.noise_deg}")
        model = replace(model, sensor_noise_deg=args.noise_deg)
    return model


def run(args: argparse.Namespace) -> int:
    refuse_overwriting_inputs(args.out, {"--rig": args.rig, "--setup": args.setup})
    if args.swings is not None:
        refuse_overwriting_inputs(args.swings, {"--rig": args.rig, "--setup": args.setup})
        if args.swings.resolve() == args.out.resolve():
            raise CadcogError("--swings and --out name the same file")
    if args.seed < 0:
        raise CadcogError("--seed must be non-negative")
    if args.setup is not None:
        return run_setup(args)
    if args.points is not None:
        raise CadcogError("--points goes with --setup")
    rig = load_rig(args.rig or default_rig_path())
    model = _model(args, ErrorModel.from_rig(rig))
    rows = simulated_readings(Scenario.from_rig(rig), model, rig.inclinometer, args.seed)
    comment = (
        f"cadcog virtual campaign: rig {rig.name}, seed {args.seed}, "
        f"{model.samples} samples per hang; {model.summary()}"
    )
    write_campaign(args.out, rows, comment)
    if args.swings is not None:
        from cadcog.dynamics.measure import context_for_rig

        _write_swings(args, context_for_rig(rig), rows, rig.inclinometer)
    return _written(args, len(rows), len(rig.suspension_points))


def run_setup(args: argparse.Namespace) -> int:
    from cadcog.spacecraft.setup import load_setup

    if not args.points:
        raise CadcogError("--setup needs --points ID,ID,... (see cadcog plan)")
    ids = [i.strip() for i in args.points.split(",")]
    if len(set(ids)) != len(ids) or len(ids) < 2:  # before the (slow) CAD, as acquire does
        raise CadcogError("--points: give at least two distinct point ids")
    _model(args, ErrorModel((1.0,), (0.0,)))  # check the overrides before the (slow) CAD
    setup = load_setup(args.setup)
    by_id = {c.id: c for c in setup.candidates}
    unknown = [i for i in ids if i not in by_id]
    if unknown:
        raise CadcogError(f"--points: unknown candidate(s) {', '.join(unknown)} in {args.setup}")
    scenario = setup.scenario(tuple(by_id[i] for i in ids))
    model = _model(args, setup.error_model())
    rows = simulated_readings(scenario, model, setup.rig.inclinometer, args.seed)
    write_campaign(
        args.out,
        rows,
        f"cadcog virtual campaign: setup {setup.name}, seed {args.seed}; {model.summary()}",
    )
    if args.swings is not None:
        from cadcog.dynamics.measure import context_for_setup

        _write_swings(
            args, context_for_setup(setup, np.zeros((6, 6))), rows, setup.rig.inclinometer
        )
    return _written(args, len(rows), len(ids))


def _written(args: argparse.Namespace, n_samples: int, n_hangs: int) -> int:
    """Say what was written: ``report: PATH`` on stderr, then a line or JSON on stdout (both on
    stderr when the CSV itself went to stdout)."""
    out = sys.stderr if is_stream(args.out) else sys.stdout
    if not is_stream(args.out):
        print(f"report: {args.out}", file=sys.stderr)
    if args.json:
        data = {"out": str(args.out), "n_samples": n_samples, "n_hangs": n_hangs, "seed": args.seed}
        if args.swings is not None:
            data["swings"] = str(args.swings)
        print(dumps_json(data), end="", file=out)
    else:
        print(f"wrote {n_samples} samples of {n_hangs} hangs to {args.out}", file=out)
        if args.swings is not None:
            print(f"wrote the swings of {n_hangs} hangs to {args.swings}", file=out)
    return 0
