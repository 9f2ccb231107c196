"""``cadcog acquire``: the guided test run at the bench, from a serial port or a simulated one."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

from cadcog.cli._options import add_json, add_rig, rig_or_setup
from cadcog.cli._output import print_json, warn, wrote
from cadcog.core.errors import CadcogError
from cadcog.core.fileio import refuse_overwriting_inputs
from cadcog.core.numformat import signed

FAULTS = ("none", "slip", "never-settle", "stall", "foreign")


def add_parser(sub: Any) -> None:
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
        "cadcog inertia (default: beside --out, NAME.swings.csv); from a log or an "
        "accelerometer's recording, a new file written only when given (each hang from 2 s "
        "after its release to the end of its undisturbed decay)",
    )
    add_rig(p)
    p.add_argument("--setup", type=Path, help="spacecraft set-up file instead of a rig")
    p.add_argument(
        "--points",
        help="comma-separated point ids, in hanging order; ID~ hangs ID again with the sensor "
        "turned 180° on its mount (a reversal) (default: every rig point; for a set-up, the "
        "set `cadcog plan` recommends, with its reversal)",
    )
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--port", help="serial port of the device (e.g. /dev/ttyACM0, COM3)")
    src.add_argument("--simulate", action="store_true", help="dry run against a simulated device")
    src.add_argument(
        "--log",
        type=Path,
        metavar="LOG",
        help="a recorded accelerometer log instead of a device (a phone's phyphox export, or a "
        "t_s,ax,ay,az CSV): cut into the hangs of --points in that order; the set-up's "
        '[inclinometer] must declare device = "accelerometer" (docs/bench.md)',
    )
    _add_log_options(p.add_argument_group("an accelerometer's log (--log, or --port with one)"))
    _add_device_options(p.add_argument_group("the device, the settling and the operator"))
    _add_simulation_options(p.add_argument_group("simulated device (--simulate)"))
    p.add_argument(
        "--report",
        type=Path,
        metavar="DIR",
        help="write the test record (hangs, link, CoG, CAD comparison) as an HTML page to DIR "
        "(a device run with an inclinometer: not yet from --log or an accelerometer's recording)",
    )
    add_json(p, "print the run's summary as JSON")
    p.set_defaults(func=run, also_written=_also_written)


def _add_log_options(p: Any) -> None:
    p.add_argument(
        "--drop-hangs",
        metavar="N,N",
        help="--log: leave out these hangs of the log (numbered from 1 in its order, as a "
        "refusal lists them): a hang redone",
    )
    p.add_argument(
        "--log-out",
        type=Path,
        metavar="LOG",
        help="--port with an accelerometer: where the recording goes, a t_s,ax_g,ay_g,az_g CSV "
        "(default: beside --out, NAME.log.csv)",
    )
    p.add_argument(
        "--duration-s",
        type=float,
        help="--port with an accelerometer: record this long (device time), then cut the hangs "
        "(default: until Ctrl-C)",
    )
    p.add_argument(
        "--log-format",
        choices=("phyphox", "csv"),
        default="phyphox",
        help='phyphox: its "Acceleration with g" CSV export (default); csv: a header t_s,ax,ay,az '
        "(m/s²) or t_s,ax_g,ay_g,az_g (g)",
    )


def _add_device_options(p: Any) -> None:
    from cadcog.bench.link import DEFAULT_BAUD
    from cadcog.bench.swing import SettleCriterion

    c = SettleCriterion()
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


def _add_simulation_options(sim: Any) -> None:
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


def _also_written(args: argparse.Namespace) -> list[Path]:
    """What a run writes beside ``--out``: the swings of a device run; a recording's log."""
    swings = [] if args.swings is None else [args.swings]
    if args.log is not None:
        return swings
    if args.port is not None and (args.log_out is not None or args.duration_s is not None):
        return [default_log(args), *swings]
    return [default_or(args.swings, args.out)]


def default_log(args: argparse.Namespace) -> Path:
    """Where a recording goes: ``--log-out``, else beside ``--out`` as NAME.log.csv."""
    if args.log_out is not None:
        return Path(args.log_out)
    from cadcog.runs.acquire_log import log_path_for

    return log_path_for(Path(args.out))


def _target(args: argparse.Namespace) -> Any:
    from cadcog.runs.acquire import acquire_target

    ids = None if args.points is None else args.points.split(",")

    def say(text: str) -> None:
        print(text, file=sys.stderr)

    rig, setup = rig_or_setup(args)
    return acquire_target(rig=rig, setup=setup, points=ids, say=say)


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


def _criterion(args: argparse.Namespace) -> Any:
    from cadcog.bench.swing import SettleCriterion

    try:
        return SettleCriterion(
            args.settle_threshold_deg,
            args.settle_window_s,
            args.settle_hold_s,
            args.max_settle_s,
        )
    except ValueError as exc:
        raise CadcogError(f"settle options: {exc}") from None


def _log_checks(args: argparse.Namespace, what: str) -> None:
    """What a run from a log (or recorded as one) does not take."""
    if args.report is not None:
        raise CadcogError(f"--report: not written from {what} yet (an inclinometer's is)")
    if args.setup is not None and args.points is None:
        raise CadcogError(
            f"{what} with --setup: give --points, the hangs in the order they are made"
        )


def _run_log(args: argparse.Namespace) -> int:
    """``--log``: the hangs cut from a recorded log."""
    from cadcog.runs.acquire_log import acquire_log

    _log_checks(args, "a log")
    for option in ("--log-out", "--duration-s"):
        if getattr(args, option[2:].replace("-", "_")) is not None:
            raise CadcogError(f"{option}: for recording from --port, not with --log")
    for output in (args.out, args.swings):
        if output is not None:
            refuse_overwriting_inputs(
                output, {"--rig": args.rig, "--setup": args.setup, "--log": args.log}
            )
    target = _target(args)
    run = acquire_log(
        target,
        args.log,
        args.out,
        fmt=args.log_format,
        criterion=_criterion(args),
        min_average_s=args.average_s,
        drop=_drops(args.drop_hangs),
        swings=args.swings,
        say=lambda text: print(text, file=sys.stderr),
    )
    return _print_log_run(args, run, args.log)


def _drops(text: str | None) -> tuple[int, ...]:
    """``--drop-hangs N,N``: positive whole numbers."""
    if text is None:
        return ()
    try:
        out = tuple(int(x) for x in text.split(","))
    except ValueError:
        raise CadcogError(
            f"--drop-hangs: expected numbers of hangs such as 3 or 3,5, got {text[:40]!r}"
        ) from None
    if any(x < 1 for x in out):
        raise CadcogError("--drop-hangs: hangs are numbered from 1")
    return out


def _run_recorded(args: argparse.Namespace, target: Any) -> int:
    """``--port`` with an accelerometer: the test recorded as one log, then cut."""
    from cadcog.runs.acquire_log import acquire_recorded

    _log_checks(args, "an accelerometer's recording")
    log_out = default_log(args)
    refuse_overwriting_inputs(
        log_out, {"--rig": args.rig, "--setup": args.setup, "--out": args.out}
    )
    if args.swings is not None:
        refuse_overwriting_inputs(
            args.swings, {"--rig": args.rig, "--setup": args.setup, "--log-out": log_out}
        )
    run = acquire_recorded(
        target,
        args.port,
        args.out,
        log_out,
        baud=args.baud,
        duration_s=args.duration_s,
        timeout_s=args.timeout_s,
        criterion=_criterion(args),
        min_average_s=args.average_s,
        swings=args.swings,
        say=lambda text: print(text, file=sys.stderr),
    )
    return _print_log_run(args, run, log_out)


def _print_log_run(args: argparse.Namespace, run: Any, log: Path) -> int:
    from cadcog.cli.estimate import print_cad_comparison, print_estimate

    est = run.estimate
    if args.json:
        print_json(run.data)
    else:
        print(f"hangs cut from {log}:")
        for h in run.data["hangs"]:
            spans = ", ".join(f"{a:.1f}-{b:.1f}" for a, b in h["averaged_s"])
            print(
                f"  {h['id']:<8} settled {h['settled_s']:8.1f} s  averaged {spans} s "
                f"({h['bins']} bins, noise {1000 * h['noise_g']:.2f} mg)"
            )
        print(f"\nestimate from {args.out}:\n")
        print_estimate(est)
        if run.cad is not None:
            print_cad_comparison(run.cad)
        if args.swings is not None:
            _print_log_inertia(run, args.swings)
    for path in (args.out, args.swings):
        if path is not None:
            wrote(path)
    for w in (*run.warnings, *est.warnings):
        warn(w)
    if run.inertia is not None:
        for w in run.inertia.warnings:
            warn(f"inertia: {w}")
    return 0


def _print_log_inertia(run: Any, swings: Path) -> None:
    if run.inertia is None:
        print(f"\nno inertia from the swings: {run.inertia_note}")
        return
    from cadcog.cli.inertia import print_inertia

    print(f"\ninertia from the swings in {swings}:\n")
    print_inertia(run.inertia)


def run(args: argparse.Namespace) -> int:
    from cadcog.bench.session import ConsoleOperator, SessionQuit
    from cadcog.runs.acquire import Recording, Simulation, check_report_folder, run_acquire

    if args.log is not None:
        return _run_log(args)
    refuse_overwriting_inputs(args.out, {"--rig": args.rig, "--setup": args.setup})
    if args.swings is not None:
        refuse_overwriting_inputs(
            args.swings, {"--rig": args.rig, "--setup": args.setup, "--out": args.out}
        )
    check_report_folder(args.report)  # before the CAD
    if args.drop_hangs is not None:
        raise CadcogError("--drop-hangs: for a log (--log); cut a recording again with --log")
    target = _target(args)
    if target.inclinometer.accelerometer and args.port is not None:
        return _run_recorded(args, target)
    for option in ("--log-out", "--duration-s"):
        if getattr(args, option[2:].replace("-", "_")) is not None:
            raise CadcogError(f"{option}: for an accelerometer's recording from --port")

    criterion = _criterion(args)
    live = _Live()
    say = live.say if not args.json else (lambda text: print(text, file=sys.stderr))
    interactive = not args.non_interactive and sys.stdin.isatty()
    simulation = (
        Simulation(args.device, _faults(args), args.seed, args.time_scale, args.max_redo)
        if args.simulate
        else None
    )
    try:
        run = run_acquire(
            target,
            args.out,
            swings=args.swings,
            port=None if args.simulate else args.port,
            simulation=simulation,
            recording=Recording(
                criterion, args.average_s, args.timeout_s, args.baud, args.max_redo
            ),
            operator=ConsoleOperator() if interactive and not args.simulate else None,
            say=say,
            progress=None if args.json else live,
            report=args.report,
        )
    except (KeyboardInterrupt, SessionQuit) as exc:
        why = "stopped" if isinstance(exc, SessionQuit) else "interrupted"
        say(
            f"\n{why}: the hang in progress was not recorded; {args.out} keeps every "
            "finished hang. Run the same command again to resume."
        )
        return 130
    return _finish(args, run)


def _faults(args: argparse.Namespace) -> Any:
    from cadcog.bench.simulator import SimulatorSettings

    f = args.sim_fault
    return SimulatorSettings(
        slipped_hangs=(3,) if f == "slip" else (),
        never_settle=f == "never-settle",
        stall_after_s=60.0 if f == "stall" else None,
        foreign=f == "foreign",
    )


def _finish(args: argparse.Namespace, run: Any) -> int:
    from cadcog.cli.estimate import print_cad_comparison, print_estimate

    result, est, cad, truth, page, data = (
        run.result,
        run.result.estimate,
        run.cad,
        run.truth,
        run.page,
        run.data,
    )
    if args.json:
        print_json(data)
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
                    + ", ".join(signed(v, 3) for v in e)
                    + f"] mm, Mahalanobis distance {truth['mahalanobis']:.2f}"
                )
            if result.inertia is not None:
                from cadcog.cli.inertia import print_inertia

                print(f"\ninertia from the swings in {default_or(args.swings, args.out)}:\n")
                print_inertia(result.inertia)
            else:
                print(f"\nno inertia from the swings: {result.inertia_note}")
    if page is not None:
        wrote(page)
    elif args.report is not None:
        print("no report: fewer than two hangs recorded", file=sys.stderr)
    if est is not None:
        for w in est.warnings:
            warn(w)
    if result.inertia is not None:
        for w in result.inertia.warnings:
            warn(f"inertia: {w}")
    return 0
