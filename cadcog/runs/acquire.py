"""The guided test run at the bench, from a serial port or a simulated device: ``cadcog acquire``
and :func:`cadcog.acquire` (a simulated run, as a notebook would use it).

:func:`acquire_target` chooses and checks the hangs (a rig's points, or a set-up's candidates,
every one checked as ``cadcog plan`` checks it before the first hang; without ``points``, the
set ``plan`` recommends). :func:`run_acquire` records them through the session
(:func:`cadcog.bench.session.run_session`: settle, average, check each line, append each hang
durably to the readings CSV, keep each swing) and composes what the command reports: the
estimate, its comparison with the CAD, the simulated device's truth, the inertia from the
swings, and the record page. The command prints it; the API returns it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

from cadcog.core.errors import CadcogError
from cadcog.core.jsontext import round_floats
from cadcog.core.results import JsonResult
from cadcog.rig.parameters import Rig
from cadcog.runs import check_distinct_ids
from cadcog.spacecraft.setup import Setup


@dataclass(frozen=True, repr=False)  # JsonResult's one-line repr
class AcquireRun(JsonResult):
    """What a run recorded and found.

    Attributes
    ----------
    data : dict
        The run's summary, the command's ``--json``: the hangs, the link's counts, the
        estimate, ``cad`` (set-ups) and ``simulated_truth`` (simulated runs) when there are.
    result : SessionResult
        The session's own result (:class:`cadcog.bench.session.SessionResult`): the estimate,
        the inertia or why none, the link's counts.
    target : BenchTarget
        The hangs that were planned.
    cad : dict or None
        The estimate against the CAD (set-ups with an estimate).
    truth : dict or None
        The simulated device's truth against the estimate (simulated runs).
    page : Path or None
        The record page, when one was asked for and there is an estimate.
    """

    data: dict[str, Any]
    result: Any
    target: Any
    cad: dict[str, Any] | None = None
    truth: dict[str, Any] | None = None
    page: Path | None = None

    def to_dict(self) -> dict[str, Any]:
        return self.data


def acquire_target(
    *,
    rig: Rig | None = None,
    setup: Setup | None = None,
    points: Sequence[str] | None = None,
    say: Callable[[str], None] = lambda _text: None,
) -> Any:
    """The hangs of a run: ``points`` of the rig or the set-up, checked before any is hung.

    A point's id followed by ``~`` is that point hung again with the sensor turned 180° on its
    mount (a reversal: :data:`cadcog.bench.target.REVERSAL_SUFFIX`). Without ``points`` a
    set-up's test is planned, with the reversal the plan advises.

    Raises
    ------
    CadcogError
        Unknown or repeated ids, fewer than two, or a set-up point ``plan`` would not use
        (its readings out of range or untrustworthy), naming each and why.
    """
    from cadcog.bench.target import REVERSAL_SUFFIX, point_of, target_from_rig, target_from_setup

    ids = None if points is None else [i.strip() for i in points if i.strip()]
    if setup is not None and ids is None and setup.rig.inclinometer.accelerometer:
        raise CadcogError(
            "--points: an accelerometer's test takes its hangs in order (cadcog plan SETUP "
            "recommends them)"
        )
    if setup is not None:
        if rig is not None:
            raise CadcogError("give --rig or --setup, not both")
        from cadcog.spacecraft.plan import check_candidate, plan_test

        if ids is None:
            say("no --points: planning the test (as `cadcog plan` does)")
            planned = plan_test(setup)
            rec = planned.recommended
            if rec is None:
                raise CadcogError(f"{setup.source}: no usable set of suspension points")
            ids = list(rec["points"])
            say(
                f"planned: hang from {', '.join(ids)} (predicted 95 % error "
                f"{float(rec['q95_mm']):.3f} mm)"
            )
            rev = planned.reversal
            if rev is not None and rev.advised:
                ids.append(rev.point + REVERSAL_SUFFIX)
                say(
                    f"and {rev.point} once more with the sensor turned (a reversal: the CoG's σ "
                    f"{rev.sigma_mm:.3f} → {rev.sigma_with_mm:.3f} mm, linearised)"
                )
        known = {c.id: c for c in setup.candidates}
        _check_ids(ids, set(known), setup.source)
        hung = list(dict.fromkeys(point_of(i, known)[0] for i in ids))  # in order, once each
        bad = [k for k in (check_candidate(setup, known[i]) for i in hung) if not k.usable]
        if bad:  # the whole plan is checked before the first hang
            raise CadcogError(
                "--points: "
                + "; ".join(f"{k.id} cannot work: {k.reason}" for k in bad)
                + " (cadcog plan lists the usable candidates)"
            )
        return target_from_setup(setup, ids)
    if rig is None:
        raise CadcogError("give a rig or a set-up")
    if ids is not None:
        _check_ids(ids, {p.id for p in rig.suspension_points}, rig.source)
    return target_from_rig(rig, ids)


def _check_ids(ids: list[str], known: set[str], source: Path) -> None:
    from cadcog.bench.target import point_of
    from cadcog.method.readings import id_problem

    for i in ids:
        problem = id_problem(i)  # what the readings file will be read back with
        if problem is not None:
            raise CadcogError(f"--points: {i[:40]!r}: {problem}")
    try:
        points = [point_of(i, known)[0] for i in ids]
    except ValueError as exc:
        raise CadcogError(f"--points: {exc} in {source}") from None
    unknown = [i for i, p in zip(ids, points, strict=True) if p not in known]
    if unknown:
        raise CadcogError(f"--points: unknown point(s) {', '.join(unknown)} in {source}")
    check_distinct_ids(ids)
    if len(set(points)) < 2:
        raise CadcogError(
            "--points: a point and its reversal hang alike: give at least two distinct points"
        )


@dataclass(frozen=True)
class Simulation:
    """A simulated device instead of a serial port (``--simulate``).

    Attributes
    ----------
    device : str
        ``"analog"`` or ``"digital"``.
    faults : SimulatorSettings
        Faults to inject (:class:`cadcog.bench.simulator.SimulatorSettings`); none by default.
    seed : int
    time_scale : float
        Simulated seconds per real second.
    max_redo : int
        Redos of a hang the simulated operator allows.
    """

    device: Literal["analog", "digital"] = "analog"
    faults: Any = None
    seed: int = 0
    time_scale: float = 20.0
    max_redo: int = 1


@dataclass(frozen=True)
class Recording:
    """How the hangs are recorded: the settle criterion, the averaging and the link.

    Attributes
    ----------
    criterion : SettleCriterion
        When a swing has settled (:class:`cadcog.bench.swing.SettleCriterion`).
    average_s : float
        Seconds averaged once settled.
    timeout_s : float
        Seconds without a sample before the link counts as lost.
    baud : int
        The serial line's rate (default: :data:`cadcog.bench.link.DEFAULT_BAUD`).
    max_redo : int
        Without an operator: redos of a bad hang.
    """

    criterion: Any = field(default=None)
    average_s: float = 10.0
    timeout_s: float = 5.0
    baud: int | None = None
    max_redo: int = 1


def check_report_folder(report: Path | None) -> None:
    """Refuse a record folder that cannot be one (the command calls it before the CAD)."""
    if report is not None and report.exists() and not report.is_dir():
        raise CadcogError(f"--report {report}: exists and is not a directory")


def run_acquire(
    target: Any,
    out: Path,
    *,
    swings: Path | None = None,
    port: str | None = None,
    simulation: Simulation | None = None,
    recording: Recording | None = None,
    operator: Any = None,
    say: Callable[[str], None] = lambda _text: None,
    progress: Any = None,
    report: Path | None = None,
) -> AcquireRun:
    """Record ``target``'s hangs into ``out`` (and their swings), from ``port`` or a simulated
    device, and compose what the run found.

    ``operator`` guides the hangs (:mod:`cadcog.bench.session`; default: the simulated
    operator for a simulated device, else one that takes every hang as it comes). A run that
    is stopped (``KeyboardInterrupt``, :class:`~cadcog.bench.session.SessionQuit`) raises it,
    with every finished hang kept in ``out``: the same call resumes.
    """
    from cadcog.bench.link import DEFAULT_BAUD, SerialLink
    from cadcog.bench.recorder import Recorder
    from cadcog.bench.session import AutoOperator, SimulatedOperator, run_session
    from cadcog.bench.swing import SettleCriterion

    rec = recording or Recording()
    criterion = rec.criterion if rec.criterion is not None else SettleCriterion()
    check_report_folder(report)
    pty = None
    device = None
    if simulation is not None:
        from cadcog.bench.simulator import (
            DeviceSpec,
            PtyDevice,
            SimulatedDevice,
            SimulatorSettings,
        )

        faults = simulation.faults if simulation.faults is not None else SimulatorSettings()
        device = SimulatedDevice(
            target, DeviceSpec(kind=simulation.device), faults, seed=simulation.seed
        )
        pty = PtyDevice(device, simulation.time_scale).__enter__()
        port = pty.port
        operator = operator or SimulatedOperator(simulation.max_redo, pty)
        say(
            f"dry run: simulated {simulation.device} device on {port}, "
            f"{simulation.time_scale:g}× real time"
        )
    elif port is None:
        raise CadcogError("give a serial port or a simulated device")
    operator = operator or AutoOperator(rec.max_redo)
    preamble = (
        f"cadcog acquire: {'set-up' if target.setup is not None else 'rig'} {target.name} "
        f"({target.source}); points {', '.join(h.id for h in target.hangs)}",
    )
    try:
        link = SerialLink(port, rec.baud if rec.baud is not None else DEFAULT_BAUD)
        try:
            recorder = Recorder(
                link, target.inclinometer, criterion, rec.average_s, rec.timeout_s, progress
            )
            result = run_session(target, recorder, out, operator, say, preamble, swings)
        finally:
            link.close()
    finally:
        if pty is not None:
            pty.close()
    return _found(target, result, device, report)


def _found(target: Any, result: Any, device: Any, report: Path | None) -> AcquireRun:
    """The run's summary: the estimate against the CAD and the simulated truth, the page."""
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
    if report is not None and est is not None:
        from cadcog.bench.runreport import write_run_report

        page = write_run_report(result, target, round_floats(data), report)
    return AcquireRun(data, result, target, cad, truth, page)
