"""``cadcog campaign``: a virtual test campaign written as a readings CSV."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from cadcog.campaign import DEFAULT_NOISE_DEG, virtual_campaign, write_campaign
from cadcog.errors import CadcogError
from cadcog.rigfile import default_rig_path, load_rig


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "campaign",
        help="simulate the paper's experiment as a lab would record it (readings CSV)",
        description="One hang per suspension point of the rig, N raw ADC samples per axis with "
        "sensor noise and quantisation, the inclinometer's bias and the suspension point's play "
        "and wire offset drawn once per hang. See docs/validation.md.",
    )
    p.add_argument("--rig", type=Path, help="rig file (default: the paper's rig)")
    p.add_argument("--seed", type=int, default=0, help="seed (default 0)")
    p.add_argument("--samples", type=int, default=10, help="raw samples per hang (default 10)")
    p.add_argument(
        "--noise-deg",
        type=float,
        default=DEFAULT_NOISE_DEG,
        help=f"sensor noise of one sample (default {DEFAULT_NOISE_DEG}°)",
    )
    p.add_argument(
        "--setup",
        type=Path,
        help="simulate a spacecraft's test instead: its set-up file (needs --points)",
    )
    p.add_argument("--points", help="with --setup: comma-separated candidate ids to hang from")
    p.add_argument("--out", type=Path, required=True, help="CSV file to write")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.seed < 0:
        raise CadcogError("--seed must be non-negative")
    if args.setup is not None:
        return run_setup(args)
    if args.points is not None:
        raise CadcogError("--points goes with --setup")
    rig = load_rig(args.rig or default_rig_path())
    try:
        rows = virtual_campaign(rig, args.seed, args.samples, args.noise_deg)
    except ValueError as exc:
        raise CadcogError(f"--samples/--noise-deg: {exc}") from None
    comment = (
        f"cadcog virtual campaign: rig {rig.name}, seed {args.seed}, "
        f"{args.samples} samples per hang, noise {args.noise_deg} deg"
    )
    write_campaign(args.out, rows, comment)
    print(f"wrote {len(rows)} samples of {len(rig.suspension_points)} hangs to {args.out}")
    return 0


def run_setup(args: argparse.Namespace) -> int:
    from cadcog.campaign import simulated_readings
    from cadcog.spacecraft import load_setup

    if not args.points:
        raise CadcogError("--setup needs --points ID,ID,... (see cadcog plan)")
    setup = load_setup(args.setup)
    by_id = {c.id: c for c in setup.candidates}
    ids = [i.strip() for i in args.points.split(",")]
    unknown = [i for i in ids if i not in by_id]
    if unknown:
        raise CadcogError(f"--points: unknown candidate(s) {', '.join(unknown)} in {args.setup}")
    scenario = setup.scenario(tuple(by_id[i] for i in ids))
    try:
        rows = simulated_readings(
            scenario,
            setup.error_model(),
            setup.rig.inclinometer,
            args.seed,
            args.samples,
            args.noise_deg,
        )
    except ValueError as exc:
        raise CadcogError(f"--samples/--noise-deg: {exc}") from None
    write_campaign(args.out, rows, f"cadcog virtual campaign: setup {setup.name}, seed {args.seed}")
    print(f"wrote {len(rows)} samples of {len(ids)} hangs to {args.out}")
    return 0
