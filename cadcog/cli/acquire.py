"""``cadcog acquire``: the guided test run at the bench, from a serial port or a simulated one."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

from cadcog.core.errors import CadcogError
from cadcog.core.fileio import refuse_overwriting_inputs
from cadcog.core.jsontext import dumps_json, round_floats
from cadcog.rig.file import default_rig_path, load_rig

FAULTS = ("none", "slip", "never-settle", "stall", "foreign")


def add_parser(sub: Any) -> None:
    from cadcog.bench.link import DEFAULT_BAUD
    from cadcog.bench.swing import SettleCriterion

    c = SettleCriterion()
    p = sub.add_parser(
        "acquire",
        help="guided test run: record each hang from the inclinometer into a readings CSV",
        description="Walk through the planned hangs of a rig or spacecraft set-up: for each, "
        "wait for the swing to settle, average, check the new plumb line against the others, "
        "append the hang durably to the readings CSV; end with the compensated CoG. Run the "
        "same command again to resume an interrupted run. See docs/bench.md.",
    )
    p.add_argument("--out", type=Path, required=True, help="readings CSV to create or resume")
    p.add_argument(
        "--swings",
        type=Path,
        help="swing CSV to create or resume: each hang's samples from release to settle, for "
        "cadcog inertia (default: beside --out, NAME.swings.csv)",
    )
    p.add_argument("--rig", type=Path, help="rig file (default: the paper's rig)")
    p.add_argument("--setup", type=Path, help="spacecraft set-up file instead of a rig")
    p.add_argument(
        "--points",
        help="comma-separated point ids, in hanging order (default: every rig point; for a "
        "set-up, the set `cadcog plan` recommends)",
    )
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--port", help="serial port of the device (e.g. /dev/ttyACM0, COM3)")
    src.add_argument("--simulate", action="store_true", help="dry run against a simulated device")
    p.add_argument("--baud", type=int, default=DEFAULT_BAUD, help=f"default {DEFAULT_BAUD}")
    p.add_argument(
        "--average-s", type=float, default=10.0, help="seconds averaged per hang (default 10)"
    )
    p.add_argument(
        "--settle-threshold-deg",
        type=float,
        default=c.threshold_deg,
        help=f"settled: swing amplitude below this (default {c.threshold_deg:g})",
    )
    p.add_argument(
        "--settle-window-s",
        type=float,
        default=c.window_s,
        help=f"window of the amplitude estimate (default {c.window_s:g})",
    )
    p.add_argument(
        "--settle-hold-s",
        type=float,
        default=c.hold_s,
        help=f"... for this long (default {c.hold_s:g})",
    )
    p.add_argument(
        "--max-settle-s",
        type=float,
        default=c.max_wait_s,
        help=f"give up on a hang not settled after this (default {c.max_wait_s:g})",
    )
    p.add_argument(
        "--timeout-s",
        type=float,
        default=5.0,
        help="the stream has stopped after this long without a sample (default 5)",
    )
    p.add_argument(
        "--non-interactive",
        action="store_true",
        help="ask nothing: go on as soon as each hang has settled (implied when stdin is not "
        "a terminal)",
    )
    p.add_argument(
        "--max-redo",
        type=int,
        default=1,
        help="without an operator: redo a bad hang at most this many times (default 1)",
    )
    sim = p.add_argument_group("simulated device (--simulate)")
    sim.add_argument("--device", choices=("analog", "digital"), default="analog")
    sim.add_argument("--seed", type=int, default=0, help="seed of the simulation (default 0)")
    sim.add_argument(
        "--time-scale",
        type=float,
        default=20.0,
        help="simulated seconds per real second (default 20)",
    )
    sim.add_argument(
        "--sim-fault",
        choices=FAULTS,
        default="none",
        help="rehearse a failure: a slipped wire on the 3rd hang, a swing that never settles, "
        "a stream that stops, a device speaking another protocol",
    )
    p.add_argument(
        "--report",
        type=Path,
        metavar="DIR",
        help="write the test record (hangs, link, CoG, CAD comparison) as an HTML page to DIR",
    )
    p.add_argument("--json", action="store_true", help="print the run's summary as JSON")
    p.set_defaults(func=run)


def _target(args: argparse.Namespace) -> Any:
    from cadcog.bench.target import target_from_rig, target_from_setup

    ids = None if args.points is None else [i.strip() for i in args.points.split(",") if i.strip()]
    if args.setup is not None:
        if args.rig is not None:
            raise CadcogError("give --rig or --setup, not both")
        from cadcog.spacecraft.plan import plan_test
        from cadcog.spacecraft.setup import load_setup

        setup = load_setup(args.setup)
        if ids is None:
            print("no --points: planning the test (as `cadcog plan` does)", file=sys.stderr)
            rec = plan_test(setup).recommended
            if rec is None:
                raise CadcogError(f"{args.setup}: no usable set of suspension points")
            ids = list(rec["points"])
        known = {c.id: c for c in setup.candidates}
        _check_ids(ids, set(known), args.setup)
        from cadcog.spacecraft.plan import check_candidate

        bad = [k for k in (check_candidate(setup, known[i]) for i in ids) if not k.usable]
        if bad:  # the whole plan is checked before the first hang
            raise CadcogError(
                "--points: "
                + "; ".join(f"{k.id} cannot work: {k.reason}" for k in bad)
                + " (cadcog plan lists the usable candidates)"
            )
        return target_from_setup(setup, ids)
    rig = load_rig(args.rig or default_rig_path())
    if ids is not None:
        _check_ids(ids, {p.id for p in rig.suspension_points}, rig.source)
    return target_from_rig(rig, ids)


def _check_ids(ids: list[str], known: set[str], source: Path) -> None:
    unknown = [i for i in ids if i not in known]
    if unknown:
        raise CadcogError(f"--points: unknown point(s) {', '.join(unknown)} in {source}")
    if len(set(ids)) != len(ids) or len(ids) < 2:
        raise CadcogError("--points: give at least two distinct point ids")


def _check_numbers(args: argparse.Namespace) -> None:
    for name in (
        "average_s",
        "settle_threshold_deg",
        "settle_window_s",
        "settle_hold_s",
        "max_settle_s",
        "timeout_s",
        "time_scale",
    ):
        value = getattr(args, name)
        if not (np.isfinite(value) and value > 0):
            raise CadcogError(f"--{name.replace('_', '-')} must be positive, got {value}")
    if args.max_redo < 0 or args.seed < 0 or args.baud <= 0:
        raise CadcogError("--max-redo and --seed must be non-negative, --baud positive")


class _Live:
    """The live line on a terminal (stderr); silent when stderr is not a terminal."""

    def __init__(self) -> None:
        self.tty = sys.stderr.isatty()

    def __call__(self, state: str, t_s: float, x: float, y: float, amp: float) -> None:
        if self.tty:
            amp_s = "  ---  " if not np.isfinite(amp) else f"{amp:7.3f}"
            sys.stderr.write(f"\r  {state:<9} X {x:9.3f}°  Y {y:9.3f}°  swing {amp_s}°   ")
            sys.stderr.flush()

    def say(self, text: str) -> None:
        if self.tty:
            sys.stderr.write("\r" + " " * 70 + "\r")
        print(text, flush=True)


def default_or(swings: Path | None, out: Path) -> Path:
    """The swing file the run wrote: ``--swings``, else beside ``--out``."""
    from cadcog.bench.swinglog import default_swing_path

    return default_swing_path(out) if swings is None else swings


def run(args: argparse.Namespace) -> int:
    from cadcog.bench.link import SerialLink
    from cadcog.bench.recorder import Recorder
    from cadcog.bench.session import (
        AutoOperator,
        ConsoleOperator,
        Operator,
        SessionQuit,
        SimulatedOperator,
        run_session,
    )
    from cadcog.bench.swing import SettleCriterion

    _check_numbers(args)
    refuse_overwriting_inputs(args.out, {"--rig": args.rig, "--setup": args.setup})
    if args.swings is not None:
        refuse_overwriting_inputs(
            args.swings, {"--rig": args.rig, "--setup": args.setup, "--out": args.out}
        )
    if args.report is not None and args.report.exists() and not args.report.is_dir():
        raise CadcogError(f"--report {args.report}: exists and is not a directory")
    target = _target(args)
    try:
        criterion = SettleCriterion(
            args.settle_threshold_deg,
            args.settle_window_s,
            args.settle_hold_s,
            args.max_settle_s,
        )
    except ValueError as exc:
        raise CadcogError(f"settle options: {exc}") from None
    live = _Live()
    say = live.say if not args.json else (lambda text: print(text, file=sys.stderr))
    pty = None
    operator: Operator
    interactive = not args.non_interactive and sys.stdin.isatty()
    device = None
    inertia_target = None
    if args.simulate:
        from cadcog.bench.simulator import PtyDevice, SimulatedDevice, as_simulated

        inertia_target = as_simulated(target)  # the simulated object swings about a pivot

        device = SimulatedDevice(target, _spec(args), _faults(args), seed=args.seed)
        pty = PtyDevice(device, args.time_scale).__enter__()
        port = pty.port
        operator = SimulatedOperator(args.max_redo, pty)
        say(f"dry run: simulated {args.device} device on {port}, {args.time_scale:g}× real time")
    else:
        port = args.port
        operator = ConsoleOperator() if interactive else AutoOperator(args.max_redo)
    preamble = (
        f"cadcog acquire: {'set-up' if target.setup is not None else 'rig'} {target.name} "
        f"({target.source}); points {', '.join(h.id for h in target.hangs)}",
    )
    try:
        link = SerialLink(port, args.baud)
        try:
            recorder = Recorder(
                link,
                target.inclinometer,
                criterion,
                args.average_s,
                args.timeout_s,
                progress=None if args.json else live,
            )
            result = run_session(
                target, recorder, args.out, operator, say, preamble, args.swings, inertia_target
            )
        finally:
            link.close()
    except (KeyboardInterrupt, SessionQuit) as exc:
        why = "stopped" if isinstance(exc, SessionQuit) else "interrupted"
        say(
            f"\n{why}: the hang in progress was not recorded; {args.out} keeps every "
            "finished hang. Run the same command again to resume."
        )
        return 130
    finally:
        if pty is not None:
            pty.close()
    return _finish(args, target, result, device)


def _spec(args: argparse.Namespace) -> Any:
    from cadcog.bench.simulator import DeviceSpec

    return DeviceSpec(kind=args.device)


def _faults(args: argparse.Namespace) -> Any:
    from cadcog.bench.simulator import SimulatorSettings

    f = args.sim_fault
    return SimulatorSettings(
        slipped_hangs=(3,) if f == "slip" else (),
        never_settle=f == "never-settle",
        stall_after_s=60.0 if f == "stall" else None,
        foreign=f == "foreign",
    )


def _finish(args: argparse.Namespace, target: Any, result: Any, device: Any) -> int:
    from cadcog.cli.estimate import print_cad_comparison, print_estimate

    est = result.estimate
    cad = None
    truth = None
    if est is not None and target.setup is not None:
        from cadcog.spacecraft.compare import compare_with_cad

        cad = compare_with_cad(target.setup, est.cog_mm, est.cov_mm2, est.compensation)
    if est is not None and device is not None:
        truth = device.truth_check(est.cog_mm, est.cov_mm2)
    data = result.to_dict()
    if cad is not None:
        data["cad"] = cad
    if truth is not None:
        data["simulated_truth"] = truth
    page = None
    if args.report is not None and est is not None:
        from cadcog.bench.runreport import write_run_report

        page = write_run_report(result, target, round_floats(data), args.report)
    if args.json:
        print(dumps_json(data), end="")
    else:
        print(f"\nlink: {result.link}")
        if est is None:
            print(f"fewer than two hangs recorded in {args.out}: no estimate yet")
        else:
            print(f"\nestimate from {args.out}:\n")
            print_estimate(est)
            if cad is not None:
                print_cad_comparison(cad)
            if truth is not None:
                e = truth["error_mm"]
                print(
                    "simulated truth: error ["
                    + ", ".join(f"{v:+.3f}" for v in e)
                    + f"] mm, Mahalanobis distance {truth['mahalanobis']:.2f}"
                )
            if result.inertia is not None:
                from cadcog.cli.inertia import print_inertia

                print(f"\ninertia from the swings in {default_or(args.swings, args.out)}:\n")
                print_inertia(result.inertia)
            else:
                print(f"\nno inertia from the swings: {result.inertia_note}")
    if page is not None:
        print(f"report: {page}", file=sys.stderr)
    elif args.report is not None:
        print("no report: fewer than two hangs recorded", file=sys.stderr)
    if est is not None:
        for w in est.warnings:
            print(f"cadcog: warning: {w}", file=sys.stderr)
    return 0
