"""The guided test run: the planned hangs in order, each checked against the others at once.

For each planned hang not yet in the readings file: tell the operator where to hang the object
(point, position, which face up, the readings the CAD expects), record it
(:class:`~cadcog.bench.recorder.Recorder`), refuse a saturated or out-of-range hang, estimate
the CoG from all hangs so far and test the new plumb line against the others; a line that does
not fit is redone at once (the operator decides; without one, up to ``max_redo`` times). Only
then is the hang appended to the file. The run ends with the compensated CoG.

Who hangs the object is an :class:`Operator`: a person at a terminal
(:class:`ConsoleOperator`), nobody (:class:`AutoOperator`: proceed as soon as the swing has
settled), or the simulated device's own operator (:class:`SimulatedOperator`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from cadcog.bench.readingsfile import (
    HangBlock,
    ReadingsFile,
    block_text,
    parse_block,
    suspension_of,
)
from cadcog.bench.recorder import DeviceUnits, HangData, Recorder
from cadcog.bench.swinglog import SwingLog, default_swing_path
from cadcog.bench.target import (
    REVERSAL_SUFFIX,
    BenchTarget,
    PlannedHang,
    estimate_hangs,
    estimate_summary,
    inconsistent_ids,
    inertia_hangs,
    line_check,
)
from cadcog.core.errors import CadcogError
from cadcog.core.results import JsonResult
from cadcog.method.cogestimate import CogEstimate
from cadcog.method.readings import Suspension, read_readings

#: A settled reading this far from the CAD expectation (degrees, either axis) is reported:
#: a wrong point, a wrong face up, or a CAD CoG far off.
EXPECTATION_WARNING_DEG = 5.0


class SessionQuit(CadcogError):
    """The operator stopped the run (what was recorded stays; run again to resume)."""


class Operator(Protocol):
    """Who hangs the object."""

    def hang(self, index: int, planned: PlannedHang, attempt: int) -> float | None:
        """Hang the object from ``planned``; return the device time it began, or None (unknown).

        Raise :class:`SessionQuit` to stop; return ``-inf`` to skip this point.
        """
        ...

    def redo(self, planned: PlannedHang, reason: str, attempt: int) -> bool:
        """Whether to redo a hang found bad for ``reason``."""
        ...


@dataclass
class AutoOperator:
    """No one to ask: go on at once; redo a bad hang up to ``max_redo`` times."""

    max_redo: int = 1

    def hang(self, index: int, planned: PlannedHang, attempt: int) -> float | None:
        return None

    def redo(self, planned: PlannedHang, reason: str, attempt: int) -> bool:
        return attempt <= self.max_redo


@dataclass
class SimulatedOperator(AutoOperator):
    """The simulated device's operator: moves the wire by telling the device (``hang``)."""

    device: Any = None

    def hang(self, index: int, planned: PlannedHang, attempt: int) -> float | None:
        return float(self.device.hang(index))


@dataclass
class ConsoleOperator:
    """A person at a terminal: Enter when hanging, ``s`` to skip, ``q`` to stop."""

    ask: Callable[[str], str] = input

    def hang(self, index: int, planned: PlannedHang, attempt: int) -> float | None:
        answer = self.ask("  press Enter once it hangs free (s = skip this point, q = stop): ")
        answer = answer.strip().lower()
        if answer == "q":
            raise SessionQuit("stopped by the operator")
        return -np.inf if answer == "s" else None

    def redo(self, planned: PlannedHang, reason: str, attempt: int) -> bool:
        answer = self.ask(f"  redo {planned.id}? [Y/n] ").strip().lower()
        return answer in ("", "y", "yes")


@dataclass(frozen=True)
class HangReport(JsonResult):
    """What happened to one attempt at a hang.

    Attributes
    ----------
    id : str
    attempt : int
    outcome : str
        ``recorded``, ``redone`` (bad, recorded as comments only), ``kept`` (bad but kept),
        ``refused`` (saturated or out of range) or ``skipped``.
    reason : str
    mean_deg : tuple of 2 floats or None
    samples : int
    settled_after_s, period_s, decay_time_s : float or None
    sigma : float or None
        The consistency statistic of its line (σ) when it was checked.
    """

    id: str
    attempt: int
    outcome: str
    reason: str = ""
    mean_deg: tuple[float, float] | None = None
    samples: int = 0
    settled_after_s: float | None = None
    period_s: float | None = None
    decay_time_s: float | None = None
    sigma: float | None = None

    def to_dict(self) -> dict[str, Any]:
        return dict(self.__dict__)


@dataclass
class SessionResult(JsonResult):
    """The outcome of a run."""

    path: Path
    device: str
    hangs: list[HangReport] = field(default_factory=list)
    resumed: list[str] = field(default_factory=list)
    repaired_lines: int = 0
    estimate: CogEstimate | None = None
    link: str = ""
    inertia: Any = None  # cadcog.dynamics.result.InertiaResult, from 3 or more swings
    inertia_note: str = ""

    def to_dict(self) -> dict[str, Any]:
        return {
            "readings": str(self.path),
            "device": self.device,
            "resumed": self.resumed,
            "repaired_lines": self.repaired_lines,
            "hangs": [h.to_dict() for h in self.hangs],
            "link": self.link,
            "estimate": None if self.estimate is None else estimate_summary(self.estimate),
            "inertia": (
                self.inertia.to_dict()
                if self.inertia is not None
                else {"not_estimated": self.inertia_note}
            ),
        }


def _info(attempt: int, data: HangData, average_s: float, link: str) -> str:
    sw = data.swing

    def f(v: float | None, digits: int = 3) -> str:
        return "na" if v is None else f"{v:.{digits}f}"

    return (
        f"attempt={attempt} settled_after_s={data.settled_after_s:.2f} period_s={f(sw.period_s)} "
        f"decay_time_s={f(sw.decay_time_s, 2)} damping_ratio={f(sw.damping_ratio, 4)} "
        f"start_swing_deg={sw.start_amplitude_deg:.3f} "
        f"swing_at_settle_deg={data.amplitude_deg:.4f} "
        f"samples={len(data.t_s)} average_s={average_s:g} link=({link})"
    )


def run_session(
    target: BenchTarget,
    recorder: Recorder,
    out: str | Path,
    operator: Operator,
    say: Callable[[str], None] = print,
    preamble: tuple[str, ...] = (),
    swings_out: str | Path | None = None,
) -> SessionResult:
    """Run the guided test run; append each good hang to ``out`` (and its swing from release
    to settle to ``swings_out``, default beside ``out``: ``cadcog inertia``'s input); return
    what happened, with the inertia tensor from the swings when three hangs or more have one.

    Raises
    ------
    CadcogError
        Link failures, a hang that never settles (nothing is recorded for it), a readings file
        that belongs to another run. What was recorded before stays, and a new run resumes.
    """
    units = recorder.open()
    say(f"device: {units.header.describe()} on {recorder.link.name}")
    reversal = any(h.sensor_turned for h in target.hangs)  # the file gets sensor_turned
    swing_path = default_swing_path(out) if swings_out is None else swings_out
    SwingLog.check(swing_path)  # before the readings file is made: a refusal leaves nothing
    rfile, blocks, repaired = ReadingsFile.open(out, units, preamble, turned=reversal)
    swings = SwingLog.open(swing_path)
    result = SessionResult(Path(out), units.header.describe(), repaired_lines=repaired)
    suspensions = _resumed(blocks, target, units, out, result)
    if repaired:
        say(f"{out}: {repaired} line(s) of an interrupted hang turned into comments")
    if result.resumed:
        say(f"resuming {out}: already recorded {', '.join(result.resumed)}")
    done = set(result.resumed)
    todo = [(i, h) for i, h in enumerate(target.hangs) if h.id not in done]
    already = sum(h.id in done for h in target.hangs)  # of this plan (the file may hold others)
    run = _Run(target, recorder, operator, say, out, units, rfile, swings, result, suspensions)
    turned_before = bool(blocks) and blocks[-1].sensor_turned
    for n, (index, h) in enumerate(todo, 1):
        if run.hang(index, h, f"{already + n}/{len(target.hangs)}", turned_before):
            turned_before = h.sensor_turned
    result.link = recorder.stats.summary()
    if len(suspensions) >= 2:
        final = read_readings(out, target.inclinometer)
        result.estimate = estimate_hangs(target, final)
        result.inertia, result.inertia_note = _inertia(target, swings, final)
    return result


def _known_points(target: BenchTarget) -> set[str]:
    """Every point id of the target's object: its rig's points, or its set-up's candidates."""
    if target.setup is not None:
        return {c.id for c in target.setup.candidates}
    return {p.id for p in target.rig.suspension_points}


def _resumed(
    blocks: list[HangBlock],
    target: BenchTarget,
    units: DeviceUnits,
    out: str | Path,
    result: SessionResult,
) -> list[Suspension]:
    """The hangs an earlier run recorded in ``out``, each where the plan puts its point."""
    planned = {h.id: h for h in target.hangs}
    known = _known_points(target)
    suspensions: list[Suspension] = []
    for b in blocks:
        h = planned.get(b.point_id)
        if (
            h is None
            and b.point_id not in known
            and b.point_id.rstrip(REVERSAL_SUFFIX) not in known
        ):
            raise CadcogError(
                f"{out}, line {b.line}: {b.point_id} is none of {target.name}'s points: the "
                "file was recorded with another rig or set-up (give that one, or another --out)"
            )
        if h is not None and not np.allclose(b.position_mm, h.position_mm, atol=1e-3):
            raise CadcogError(
                f"{out}, line {b.line}: {b.point_id} was recorded at {list(b.position_mm)} mm, "
                f"the plan puts it at {list(h.position_mm)} mm: another rig or set-up? "
                "give another --out"
            )
        suspensions.append(suspension_of(b, units))
        result.resumed.append(b.point_id)
    return suspensions


@dataclass
class _Run:
    """What each hang of a run records into and reports to."""

    target: BenchTarget
    recorder: Recorder
    operator: Operator
    say: Callable[[str], None]
    out: str | Path
    units: DeviceUnits
    rfile: ReadingsFile
    swings: SwingLog
    result: SessionResult
    suspensions: list[Suspension]

    def hang(self, index: int, h: PlannedHang, counter: str, turned_before: bool) -> bool:
        """Hang ``h`` until it is recorded, skipped or given up; whether it was recorded."""
        attempt = 0
        while True:
            attempt += 1
            self.say(_prompt(h, counter, attempt, turned_before))
            self.recorder.link.flush_input()
            began = self.operator.hang(index, h, attempt)
            if began == -np.inf:
                self.result.hangs.append(HangReport(h.id, attempt, "skipped", "by the operator"))
                self.say(f"  {h.id}: skipped")
                return False
            try:
                data = self.recorder.record_hang(began)
            except CadcogError as exc:
                kept = [s.id for s in self.suspensions]
                where = (
                    f"{', '.join(kept)} recorded in {self.out}; run again to resume"
                    if kept
                    else "nothing recorded yet"
                )
                raise type(exc)(f"hang {h.id}: {exc} ({where})") from None
            text = block_text(
                h.id,
                h.position_mm,
                h.top_face_up,
                data,
                self.units,
                _info(attempt, data, self.recorder.average_s, self.recorder.stats.summary()),
                h.sensor_turned if self.rfile.turned_column else None,
            )
            # The new suspension is read back from the very text the file gets, so the running
            # estimate sees exactly what `cadcog estimate` will read.
            new = suspension_of(parse_block(text), self.units)
            report = _assess(self.target, h, data, new, self.suspensions, self.say)
            if report.outcome == "refused":
                self.result.hangs.append(report_with(report, attempt))
                if self.operator.redo(h, report.reason, attempt):
                    continue
                self.say(f"  {h.id}: not recorded")
                return False
            if report.outcome == "inconsistent":
                if self.operator.redo(h, report.reason, attempt):
                    self.rfile.append_rejected(text, report.reason)
                    self.result.hangs.append(report_with(report, attempt, "redone"))
                    continue
                report = report_with(report, attempt, "kept")
            else:
                report = report_with(report, attempt, "recorded")
            self.rfile.append(text)
            self.swings.append(h.id, data.swing_t_s, data.swing_deg)
            self.suspensions.append(new)
            self.result.hangs.append(report)
            self.say(f"  {h.id}: recorded {report.samples} samples in {self.out}")
            return True


def _prompt(h: PlannedHang, counter: str, attempt: int, turned_before: bool) -> str:
    """What the operator is told before a hang: where, which face up, what to expect."""
    face = "UP" if h.top_face_up else "DOWN"
    turn = (
        ", the sensor TURNED 180° on its mount (a reversal: docs/bench.md)"
        if h.sensor_turned
        else (", the sensor turned BACK to its normal orientation" if turned_before else "")
    )
    return (
        f"\n[{counter}] hang from {h.id} at "
        f"({h.position_mm[0]:g}, {h.position_mm[1]:g}, {h.position_mm[2]:g}) mm{turn}, "
        f"inclinometer top face {face}; expect X ≈ {h.expected_x_deg:.1f}°, "
        f"Y ≈ {h.expected_y_deg:.1f}°" + (f" (attempt {attempt})" if attempt > 1 else "")
    )


def _inertia(
    target: BenchTarget, swings: SwingLog, suspensions: list[Suspension]
) -> tuple[Any, str]:
    """The tensor from the recorded swings, or why there is none."""
    from cadcog.dynamics.swingfile import read_swings

    if len(swings.done) < 3:
        return None, f"{len(swings.done)} hang(s) with a swing: the tensor needs 3 or more"
    try:
        recorded = read_swings(swings.path)
    except CadcogError as exc:
        return None, str(exc)
    return inertia_hangs(target, recorded, suspensions, source=str(swings.path))


def report_with(report: HangReport, attempt: int, outcome: str | None = None) -> HangReport:
    """``report`` for attempt ``attempt``, with another outcome if given."""
    return replace(report, attempt=attempt, outcome=report.outcome if outcome is None else outcome)


def _assess(
    target: BenchTarget,
    h: PlannedHang,
    data: HangData,
    new: Suspension,
    previous: list[Suspension],
    say: Callable[[str], None],
) -> HangReport:
    """Range check, expectation check and consistency with the previous hangs."""
    sw = data.swing
    mean = data.mean_deg
    per = "" if sw.period_s is None else f", swing period {sw.period_s:.3f} s"
    dec = "" if sw.decay_time_s is None else f", decay time {sw.decay_time_s:.1f} s"
    say(
        f"  settled after {data.settled_after_s:.1f} s{per}{dec}; averaged "
        f"{len(data.t_s)} samples over {data.duration_s:.1f} s: X = {mean[0]:.3f}°, "
        f"Y = {mean[1]:.3f}°"
    )
    base = HangReport(
        h.id,
        1,
        "recorded",
        mean_deg=mean,
        samples=len(data.t_s),
        settled_after_s=data.settled_after_s,
        period_s=sw.period_s,
        decay_time_s=sw.decay_time_s,
    )
    if data.range_problem is not None:
        say(f"  {h.id}: unusable: {data.range_problem}")
        return replace(base, outcome="refused", reason=data.range_problem)
    off = max(abs(mean[0] - h.expected_x_deg), abs(mean[1] - h.expected_y_deg))
    if off > EXPECTATION_WARNING_DEG:
        say(
            f"  note: {off:.1f}° from what the CAD expects: the right point, "
            f"top face {'up' if h.top_face_up else 'down'}?"
        )
    if not previous:
        return base
    try:
        est = estimate_hangs(target, [*previous, new])
    except CadcogError as exc:
        say(f"  no estimate yet: {exc}")
        return base
    chk = line_check(est, h.id)
    sigma = np.sqrt(np.diag(est.cov_mm2))
    say(
        f"  running estimate ({len(previous) + 1} hangs): CoG "
        f"[{', '.join(f'{v:.2f}' for v in est.cog_mm)}] mm ± "
        f"[{', '.join(f'{v:.2f}' for v in sigma)}] mm"
    )
    others = [i for i in inconsistent_ids(est) if i != h.id]
    if others and len(previous) >= 2:
        say(f"  note: {', '.join(others)} now look(s) inconsistent with the rest")
    verdict = "consistent" if chk.consistent else "INCONSISTENT"
    say(
        f"  {h.id}: its line passes {chk.distance_mm:.2f} mm from the estimate "
        f"({chk.sigma:.1f} σ, p = {chk.p_value:.2g}): {verdict} with the previous hangs"
    )
    base = replace(base, sigma=chk.sigma)
    if chk.consistent:
        return base
    reason = f"its line is {chk.sigma:.1f} σ from the others (p = {chk.p_value:.2g})"
    return replace(base, outcome="inconsistent", reason=reason)
