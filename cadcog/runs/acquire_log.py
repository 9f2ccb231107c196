"""A test from a recorded log: ``cadcog acquire --log`` (a phone's phyphox export, or any
accelerometer's log).

:func:`acquire_log` reads the log (:mod:`cadcog.bench.accellog`), cuts it into hangs with the
bench's settle criterion (:mod:`cadcog.bench.logsegments`), gives them the planned points in
the order given, writes the readings CSV (an accelerometer's columns, one row per 0.05 s bin
of each averaged span) and estimates the CoG from that file exactly as ``cadcog estimate``
does. With ``swings``, each hang's swing (the log's samples from just after the release to the
end of its undisturbed decay, in object-axis angles:
:func:`cadcog.bench.logsegments.hang_swing`) goes to a swing file and the inertia tensor is
estimated from it as ``cadcog inertia`` does. Nothing is written unless every hang was found
and the estimate could be computed; the readings and the swings are written together or not
at all.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from cadcog.bench.accellog import LogError, LogFormat, read_log
from cadcog.bench.logsegments import BIN_S, LogHang, Segmentation, hang_swing, segment_log
from cadcog.core.errors import CadcogError
from cadcog.core.fileio import is_stream, staged_file, staged_files
from cadcog.core.results import JsonResult
from cadcog.core.units import rad_to_deg
from cadcog.method.readings import ACC_COLUMNS, POSITION_COLUMNS, TURNED_COLUMN, format_face
from cadcog.rig.accelerometer import axes_matrix

#: A found hang whose direction is further than this (degrees) from what the CAD predicts for
#: its planned point is reported: the order of the hangs may not be the order given.
ORDER_WARNING_DEG = 10.0
#: Further than this and the run is refused: no CAD is that wrong (a CoG 30° off a hang's
#: vertical is half the lever away); the order or the sensor's axes are.
ORDER_REFUSAL_DEG = 30.0


@dataclass(frozen=True, repr=False)
class LogRun(JsonResult):
    """What a log held and what it gives.

    Attributes
    ----------
    data : dict
        The command's ``--json``: the hangs found (time spans, samples, noise), what was not a
        hang, the estimate and (set-ups) the comparison with the CAD.
    estimate : CogEstimate
    cad : dict or None
    warnings : tuple of str
        About the log (the estimate's own are in ``estimate.warnings``).
    inertia : InertiaResult or None
        With swings written: the tensor from them, or None (``inertia_note`` says why).
    inertia_note : str
    """

    data: dict[str, Any]
    estimate: Any
    cad: dict[str, Any] | None
    warnings: tuple[str, ...]
    inertia: Any = None
    inertia_note: str = ""

    def to_dict(self) -> dict[str, Any]:
        return self.data


def _span(a: float, b: float) -> str:
    return f"{a:.0f}-{b:.0f} s"


def _spans(spans: Sequence[tuple[float, float]], most: int = 8) -> str:
    """Time spans, at most ``most`` of them (a message stays readable)."""
    shown = ", ".join(_span(a, b) for a, b in spans[:most])
    return shown + (f" and {len(spans) - most} more" if len(spans) > most else "")


def _count_problem(seg: Segmentation, hangs: Sequence[Any], log_path: Path) -> str | None:
    """Why the log's hangs cannot be given the planned points (None when they can): what was
    found, the most telling first, short enough to be read whole."""
    found, wanted = len(seg.hangs), len(hangs)
    if found == wanted:
        return None
    parts = [f"{log_path}: {found} settled hang(s) for {wanted} point(s)"]
    if seg.ends_in_hang is not None:
        parts.append(
            f"; the log ends during a hang (from {seg.ends_in_hang:.0f} s): record until it has "
            "been still for --average-s"
        )
    for u in seg.unsettled[:3]:
        parts.append(
            f"; a hang never settled at {_span(u.start_s, u.end_s)} (swing above "
            f"{u.amplitude_deg:.2f}°): redo it, or leave its point out of --points"
        )
    if seg.short_spans:
        parts.append(f"; still too briefly to average (< --average-s): {_spans(seg.short_spans)}")
    if seg.rests:
        parts.append(f"; still but never released (a rest?): {_spans(seg.rests, 4)}")
    numbered = [(h.settled_s, h.end_s) for h in seg.hangs]
    listed = ", ".join(f"#{i} {_span(a, b)}" for i, (a, b) in enumerate(numbered[:12], 1))
    parts.append(f"; hangs found: {listed or 'none'}")
    if found > wanted:
        parts.append("; leave out the extra ones with --drop-hangs (their # above)")
    return "".join(parts)


def readings_text(planned: Sequence[Any], found: Sequence[LogHang], log_path: Path) -> str:
    """The readings CSV of the hangs: one row per averaged bin, a comment per hang."""
    turned = any(h.sensor_turned for h in planned)
    head = [*POSITION_COLUMNS, *ACC_COLUMNS, *((TURNED_COLUMN,) if turned else ()), "t_s"]
    lines = [
        f"# cadcog acquire --log {log_path.name}: one row per {BIN_S:g} s bin of each settled span",
        ",".join(head),
    ]
    for p, h in zip(planned, found, strict=True):
        x, y, z = (f"{float(c):.3f}" for c in p.position_mm)
        flag = f",{format_face(p.sensor_turned)}" if turned else ""
        lines.append(
            f"# hang {p.id}: released {h.start_s:.2f} s, settled {h.settled_s:.2f} s, averaged "
            + ", ".join(_span(a, b) for a, b in h.spans_s)
            + f" ({len(h.t_s)} bins), swing {h.swing_start_deg:.2f}° after release"
        )
        for t, a in zip(h.t_s, h.acc_g, strict=True):
            lines.append(f"{p.id},{x},{y},{z},{a[0]:.7f},{a[1]:.7f},{a[2]:.7f}{flag},{t:.3f}")
    return "\n".join(lines) + "\n"


def _order_check(target: Any, found: Sequence[LogHang], log_path: Path) -> list[str]:
    """Warnings for hangs whose direction is far from the CAD's for their planned point.

    Raises
    ------
    LogError
        When one is further than :data:`ORDER_REFUSAL_DEG`.
    """
    cfg = target.inclinometer
    a = axes_matrix(cfg.axes)
    g = target.assembly.cog_mm
    out = []
    wrong = []
    for p, h in zip(target.hangs, found, strict=True):
        u = np.asarray(p.position_mm, dtype=float) - g
        expected = a @ (u / np.linalg.norm(u))
        if p.sensor_turned:
            expected[:2] *= -1.0
        angle = float(rad_to_deg(np.arccos(np.clip(expected @ h.direction, -1.0, 1.0))))
        if angle > ORDER_REFUSAL_DEG:
            wrong.append(f"{p.id} ({_span(h.settled_s, h.end_s)}) {angle:.0f}°")
        elif angle > ORDER_WARNING_DEG:
            out.append(
                f"hang {p.id} (settled {_span(h.settled_s, h.end_s)}) hangs {angle:.0f}° away "
                f"from what the CAD predicts for {p.id}: were the hangs made in the order of "
                "--points, and is [inclinometer] axes right?"
            )
    if wrong:
        raise LogError(
            f"{log_path}: hangs far from where the CAD says their points hang: "
            + ", ".join(wrong)
            + f" (more than {ORDER_REFUSAL_DEG:g}°): give --points in the order the hangs were "
            f"made, and check [inclinometer] axes = {list(cfg.axes)} (docs/bench.md §8)"
        )
    return out


def log_path_for(out: Path) -> Path:
    """Where a recording goes unless told: beside the readings ``out``, as ``NAME.log.csv``."""
    return out.with_name(out.stem + ".log.csv")


def refuse_taken_outputs(outputs: Sequence[tuple[str, Path | None]]) -> None:
    """A log's run writes new regular files only (a log is cut once, a recording made once):
    refuse, naming the option, one that is a stream or exists, or two that are one file.

    Raises
    ------
    CadcogError
    """
    given = [(option, path) for option, path in outputs if path is not None]
    for option, path in given:
        if is_stream(path):
            raise CadcogError(
                f"{option} {path}: expected a new file (a log's readings and swings are files "
                "that cadcog estimate and cadcog inertia read again)"
            )
        if path.exists() or path.is_symlink():
            raise CadcogError(
                f"{option} {path}: exists; a log's readings and swings go to new files, as a "
                f"recording does (remove it, or choose another {option})"
            )
    for i, (first, a) in enumerate(given):
        for second, b in given[i + 1 :]:
            if a.resolve() == b.resolve():
                raise CadcogError(f"{second} and {first} name the same file: {a}")


def acquire_log(
    target: Any,
    log_path: Path,
    out: Path,
    *,
    fmt: LogFormat = "phyphox",
    criterion: Any = None,
    min_average_s: float = 10.0,
    drop: Sequence[int] = (),
    swings: Path | None = None,
    say: Callable[[str], None] = lambda _text: None,
) -> LogRun:
    """Cut the log at ``log_path`` into ``target``'s hangs, write ``out``, estimate the CoG.

    ``drop`` are hangs to leave out, numbered from 1 in the log's order (a hang redone: the
    refusal lists the hangs with their numbers). ``swings``: also write each hang's swing
    there (a new file, as ``out``) and estimate the inertia tensor from it (a tensor that
    cannot be estimated is a note, ``LogRun.inertia_note``: the readings stand without it).

    Raises
    ------
    CadcogError
        The set-up's sensor is not an accelerometer; ``out`` or ``swings`` exists (a log is cut
        once: a new run is a new file), or they are one file; the log cannot be read
        (:class:`~cadcog.bench.accellog.LogError`); it holds more or fewer settled hangs than
        planned points (naming the spans found, a hang that never settled and its span); a hang
        points far from where the CAD says its point hangs; the estimate cannot be computed.
        Nothing is written then.
    """
    from cadcog.bench.swing import SettleCriterion
    from cadcog.bench.target import estimate_hangs
    from cadcog.method.readings import read_readings

    cfg = target.inclinometer
    if not cfg.accelerometer:
        raise CadcogError(
            f"--log: {target.source}: its [inclinometer] is an angle-reading inclinometer; a "
            'log is an accelerometer\'s: declare device = "accelerometer" and its axes '
            "(docs/bench.md: a phone or an accelerometer)"
        )
    refuse_taken_outputs((("--out", out), ("--swings", swings)))
    log = read_log(log_path, fmt)
    seg = segment_log(log, criterion or SettleCriterion(), min_average_s)
    if drop:
        bad = [d for d in drop if not 1 <= d <= len(seg.hangs)]
        if bad:
            raise CadcogError(
                f"--drop-hangs: {bad[0]} is not a hang of the log (it holds {len(seg.hangs)})"
            )
        seg = replace(seg, hangs=tuple(h for i, h in enumerate(seg.hangs, 1) if i not in set(drop)))
    problem = _count_problem(seg, target.hangs, log_path)
    if problem is not None:
        raise LogError(problem)
    say(
        f"{log_path}: {len(log.t_s)} samples at {log.rate_hz:.0f} Hz over "
        f"{log.t_s[-1] - log.t_s[0]:.0f} s; {len(seg.hangs)} hangs found"
    )
    warnings = _order_check(target, seg.hangs, log_path)
    inertia, note, n_swing = None, "", []
    outputs = [out] if swings is None else [out, swings]
    with staged_files(*outputs) as staged:
        staged[0].write_text(readings_text(target.hangs, seg.hangs, log_path))
        if swings is not None:
            from cadcog.dynamics.swingfile import swings_text

            hung = [
                hang_swing(log, h, p.id, cfg.axes, p.sensor_turned)
                for p, h in zip(target.hangs, seg.hangs, strict=True)
            ]
            staged[1].write_text(swings_text(hung), encoding="utf-8")
            n_swing = [len(s.t_s) for s in hung]
        suspensions = read_readings(staged[0], cfg)
        estimate = estimate_hangs(target, suspensions)
        cad = None
        if target.setup is not None:
            from cadcog.spacecraft.compare import compare_with_cad

            cad = compare_with_cad(
                target.setup, estimate.cog_mm, estimate.cov_mm2, estimate.compensation
            )
        if swings is not None:  # from the file as written, as cadcog inertia reads it
            from cadcog.bench.target import inertia_hangs
            from cadcog.dynamics.swingfile import read_swings

            inertia, note = inertia_hangs(
                target, read_swings(staged[1]), suspensions, source=str(swings)
            )
    data: dict[str, Any] = {
        "log": {
            "path": str(log_path),
            "samples": len(log.t_s),
            "rate_hz": log.rate_hz,
            "duration_s": float(log.t_s[-1] - log.t_s[0]),
        },
        "hangs": [
            {
                "id": p.id,
                "released_s": h.start_s,
                "settled_s": h.settled_s,
                "averaged_s": [list(s) for s in h.spans_s],
                "bins": len(h.t_s),
                "noise_g": float(np.max(h.acc_g.std(axis=0, ddof=1))),
                "swing_after_release_deg": h.swing_start_deg,
                **({"swing_samples": n_swing[i]} if n_swing else {}),
            }
            for i, (p, h) in enumerate(zip(target.hangs, seg.hangs, strict=True))
        ],
        "not_hangs": {
            "rests_s": [list(r) for r in seg.rests],
            "short_s": [list(r) for r in seg.short_spans],
        },
        "readings": str(out),
        "estimate": estimate.to_dict(),
        "warnings": warnings,
    }
    if cad is not None:
        data["cad"] = cad
    if swings is not None:
        data["swings"] = str(swings)
        data["inertia"] = inertia.to_dict() if inertia is not None else {"not_estimated": note}
    return LogRun(data, estimate, cad, tuple(warnings), inertia, note)


def acquire_recorded(
    target: Any,
    port: str,
    out: Path,
    log_out: Path,
    *,
    baud: int | None = None,
    duration_s: float | None = None,
    timeout_s: float = 5.0,
    criterion: Any = None,
    min_average_s: float = 10.0,
    swings: Path | None = None,
    say: Callable[[str], None] = lambda _text: None,
    link: Any = None,
) -> LogRun:
    """Record a three-axis accelerometer on ``port`` into the log ``log_out`` (until
    ``duration_s`` of device time, or Ctrl-C), then cut it as :func:`acquire_log` does.

    The log is written whole (staged, then renamed) before it is cut: if the hangs cannot be
    found in it, it stays for another try (``cadcog acquire --log LOG --log-format csv``) and
    the readings (and ``swings``) are not written.
    """
    from cadcog.bench.accellog import write_log
    from cadcog.bench.link import DEFAULT_BAUD, SerialLink
    from cadcog.bench.logrecorder import record_log

    if not target.inclinometer.accelerometer:
        raise CadcogError("recording a log needs a set-up whose sensor is an accelerometer")
    # before recording, not after
    refuse_taken_outputs((("--out", out), ("--log-out", log_out), ("--swings", swings)))
    say(
        f"recording {port} into {log_out}: hang {', '.join(h.id for h in target.hangs)} in this "
        "order, let each swing settle and hold still "
        + (f"(stopping after {duration_s:g} s)" if duration_s else "(Ctrl-C when done)")
    )
    own = link is None
    link = link if link is not None else SerialLink(port, baud or DEFAULT_BAUD)
    try:
        rec = record_log(link, duration_s=duration_s, timeout_s=timeout_s)
    finally:
        if own:
            link.close()
    if len(rec.t_s) < 2:
        raise CadcogError(f"{port}: {len(rec.t_s)} sample(s) recorded: nothing to cut")
    with staged_file(log_out) as staged:
        write_log(staged, rec.t_s, rec.acc_g, "csv")
    say(
        f"{log_out}: {len(rec.t_s)} samples over {rec.t_s[-1] - rec.t_s[0]:.0f} s from "
        f"{rec.header.describe()}"
        + (f"; {rec.flagged} flagged samples left out" if rec.flagged else "")
    )
    try:
        return acquire_log(
            target, log_out, out, fmt="csv", criterion=criterion,
            min_average_s=min_average_s, swings=swings, say=say,
        )  # fmt: skip
    except CadcogError as exc:
        raise CadcogError(
            f"{exc} (the recording is kept in {log_out}: cut it again with cadcog acquire "
            f"--log {log_out} --log-format csv)"
        ) from None
