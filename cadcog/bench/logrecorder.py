"""An accelerometer's stream recorded whole, as a log: what ``cadcog acquire --port`` does with
a three-axis device (``firmware/cadcog_adxl355``, ``firmware/cadcog_mpu6050``).

A dual-axis inclinometer is recorded hang by hang (:mod:`cadcog.bench.recorder`: settle,
average, check the line, next hang). An accelerometer's test is recorded as one log instead, from
the first sample to the end (a duration, or Ctrl-C), and then cut into hangs offline by the same
code that cuts a phone's log (:mod:`cadcog.bench.logsegments`). Samples the device flags
(``status`` not 0) are left out and counted; the device clock (unwrapped across its millisecond
wrap) is the log's time.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from cadcog.bench.link import ByteLink, LinkError
from cadcog.bench.protocol import Header, LineParser, LinkStats

FloatArray = npt.NDArray[np.float64]

#: Seconds of link time per read.
_READ_SLICE_S = 0.05


@dataclass(frozen=True)
class RecordedLog:
    """What a recording holds.

    Attributes
    ----------
    header : Header
    t_s : ndarray, shape (n,)
        Device times (s).
    acc_g : ndarray, shape (n, 3)
    flagged : int
        Samples the device flagged and the reader left out.
    stats : LinkStats
    interrupted : bool
        Stopped by Ctrl-C rather than at the duration.
    """

    header: Header
    t_s: FloatArray
    acc_g: FloatArray
    flagged: int
    stats: LinkStats
    interrupted: bool


def _check_header(h: Header, name: str) -> None:
    if h.value != "accel":
        raise LinkError(
            f"{name}: the device reports {h.describe()}, not a three-axis accelerometer; the "
            'set-up\'s [inclinometer] declares device = "accelerometer": load firmware/'
            "cadcog_adxl355 or cadcog_mpu6050, or fix the set-up"
        )
    if h.sensor.endswith("-FAULT"):
        raise LinkError(f"{name}: the device reports a fault ({h.sensor}): check the wiring")


def record_log(
    link: ByteLink,
    *,
    duration_s: float | None = None,
    timeout_s: float = 5.0,
    progress: Callable[[float, int], None] | None = None,
) -> RecordedLog:
    """Record an accelerometer's samples until ``duration_s`` of device time (or Ctrl-C).

    Raises
    ------
    LinkError
        Silence, another protocol, a device that is not an accelerometer or reports a fault, a
        stream that stops for ``timeout_s``, a header that changes mid-run.
    """
    parser = LineParser()
    link.write(b"?\n")
    header: Header | None = None
    t: list[float] = []
    acc: list[tuple[float, float, float]] = []
    last = link.clock()
    interrupted = False
    try:
        while True:
            data = link.read(_READ_SLICE_S)
            got = False
            for e in parser.feed(data):
                if isinstance(e, Header):
                    if header is None:
                        _check_header(e, link.name)
                        header = e
                    elif e != header:
                        raise LinkError(
                            f"{link.name}: the device changed its header mid-run (now "
                            f"{e.describe()}); start again"
                        )
                    continue
                if header is None or e.z is None:
                    continue
                got = True
                if t and e.t_s <= t[-1]:
                    raise LinkError(
                        f"{link.name}: the device restarted (its clock went back to "
                        f"{e.t_s:.3f} s); start again"
                    )
                lsb = float(header.lsb_g or 0.0)
                t.append(e.t_s)
                acc.append((e.x * lsb, e.y * lsb, e.z * lsb))
            now = link.clock()
            if got:
                last = now
                if progress is not None:
                    progress(t[-1] - t[0] if t else 0.0, len(t))
            elif now - last > timeout_s:
                if header is None and parser.stats.lines == 0:
                    raise LinkError(
                        f"{link.name}: no data in {timeout_s:g} s: is the device connected and "
                        "powered, and running the firmware from firmware/?"
                    )
                raise LinkError(
                    f"{link.name}: the stream stopped: no sample for {timeout_s:g} s "
                    f"({parser.stats.summary()})"
                )
            if duration_s is not None and t and t[-1] - t[0] >= duration_s:
                break
    except KeyboardInterrupt:
        interrupted = True
    if header is None:
        raise LinkError(f"{link.name}: no header from the device: nothing recorded")
    return RecordedLog(
        header,
        np.asarray(t, dtype=float),
        np.asarray(acc, dtype=float).reshape(-1, 3),
        parser.stats.faults,
        parser.stats,
        interrupted,
    )
