"""Recorded accelerometer logs: a phone's (phyphox) or any board's, read and written.

Two formats, each read and written here (the writer for tests, examples and converters):

- ``phyphox``: the CSV export of phyphox's "Acceleration with g" experiment::

      "Time (s)","Acceleration x (m/s^2)","Acceleration y (m/s^2)","Acceleration z (m/s^2)",...
      0.000000000E0,1.232356191E-1,2.185449600E-1,9.792325974E0,...

  comma separated (phyphox also exports with ``;`` or a tab, each with a decimal point or a
  decimal comma: all are read); columns after the three accelerations (phyphox's absolute
  one) are not used.
  "Linear Acceleration" (without g) reads about 0 at rest and is refused.
- ``csv``: a plain CSV with a header ``t_s,ax,ay,az`` (m/s², as a phone reports) or
  ``t_s,ax_g,ay_g,az_g`` (g, as a board's firmware reports); further columns are not used.

Times are seconds from any origin and must increase; accelerations are the specific force
along the sensor's axes (at rest, +1 g along the upward axis). The reader converts m/s² to g
(:data:`cadcog.core.units.STANDARD_GRAVITY_M_S2`, the one place) and checks what a log must be
before anything is cut from it: a time column, times that increase, finite numbers, a sample
rate that can follow a swing, and a magnitude that can be gravity. Every error names the file
and the line.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import CadcogError
from cadcog.core.fileio import not_a_regular_file, note_input
from cadcog.core.plainnumber import parse_float
from cadcog.core.units import STANDARD_GRAVITY_M_S2

FloatArray = npt.NDArray[np.float64]
LogFormat = Literal["phyphox", "csv"]
LOG_FORMATS = ("phyphox", "csv")

#: phyphox's column titles ("Acceleration with g").
PHYPHOX_COLUMNS = (
    "Time (s)",
    "Acceleration x (m/s^2)",
    "Acceleration y (m/s^2)",
    "Acceleration z (m/s^2)",
)
PHYPHOX_ABSOLUTE = "Absolute acceleration (m/s^2)"
#: A plain log's columns: in m/s², or in g.
PLAIN_COLUMNS_M_S2 = ("t_s", "ax", "ay", "az")
PLAIN_COLUMNS_G = ("t_s", "ax_g", "ay_g", "az_g")

#: Slowest median sample rate accepted (Hz): a hung object swings at 0.3-5 Hz, and the settle
#: detection averages 0.05 s bins (:data:`cadcog.bench.logsegments.BIN_S`).
MIN_RATE_HZ = 10.0
#: A gap between two samples longer than this (s) is a gap in the log, never inside a hang.
MAX_GAP_S = 0.5
#: Largest file read (bytes): a phone at 500 Hz writes about 30 MB an hour.
MAX_LOG_BYTES = 500_000_000
#: Longest span a log may cover (s): a test is hours at most, and the cutting holds a few
#: hundred bytes per 0.05 s of it (a day-long gap in the times would ask for gigabytes).
MAX_LOG_SPAN_S = 12 * 3600.0
#: The median magnitude of a log must be within these (g) to be "acceleration with g".
GRAVITY_RANGE_G = (0.7, 1.3)


class LogError(CadcogError, ValueError):
    """A recorded log that cannot be read as an accelerometer's."""


@dataclass(frozen=True)
class AccelLog:
    """A recorded accelerometer log.

    Attributes
    ----------
    path : Path
    t_s : ndarray, shape (n,)
        Sample times (s), increasing.
    acc_g : ndarray, shape (n, 3)
        Specific force along the sensor's x, y, z (g).
    lines : ndarray of int, shape (n,)
        Each sample's line in the file (for messages).
    """

    path: Path
    t_s: FloatArray
    acc_g: FloatArray
    lines: npt.NDArray[np.int64]

    @property
    def rate_hz(self) -> float:
        """The median sample rate (Hz)."""
        return float(1.0 / np.median(np.diff(self.t_s)))

    def line_at(self, t_s: float) -> int:
        """The file line of the first sample at or after ``t_s``."""
        i = int(np.searchsorted(self.t_s, t_s))
        return int(self.lines[min(i, len(self.lines) - 1)])


def _open_text(path: Path) -> str:
    if path.is_dir():
        raise LogError(f"{path}: is a directory, expected a log CSV file")
    if path.exists() and not path.is_file():
        raise LogError(f"{path}: {not_a_regular_file(path)} (a log CSV file)")
    try:
        with path.open("rb") as f:
            data = f.read(MAX_LOG_BYTES + 1)
    except FileNotFoundError:
        raise LogError(f"{path}: file not found") from None
    except OSError as exc:
        raise LogError(f"{path}: cannot read ({exc.strerror or exc})") from None
    if len(data) > MAX_LOG_BYTES:
        raise LogError(f"{path}: larger than {MAX_LOG_BYTES // 1_000_000} MB; cut the log")
    if data.startswith(b"PK\x03\x04"):
        raise LogError(
            f'{path}: a zip archive (phyphox\'s share): unzip it and give its "Raw Data.csv"'
        )
    if b"\0" in data:
        raise LogError(f"{path}: a binary file, expected a log CSV (text)")
    note_input(path, "the log it reads")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise LogError(f"{path}, line {line}: not UTF-8 text") from None


def _dialect(first_line: str) -> tuple[str, bool]:
    """The separator of a header line, and whether numbers use a decimal comma."""
    for sep in ("\t", ";", ","):
        if sep in first_line:
            return sep, sep != ","
    return ",", False


def _header_problem(header: list[str], fmt: LogFormat) -> str | None:
    if fmt == "phyphox":
        if list(header[:4]) != list(PHYPHOX_COLUMNS):
            hint = ""
            if header and header[0] == PHYPHOX_COLUMNS[0] and "Linear" in ",".join(header):
                hint = ' (a "Linear Acceleration" log, without g: record "Acceleration with g")'
            elif tuple(header[:4]) in (PLAIN_COLUMNS_M_S2, PLAIN_COLUMNS_G):
                hint = " (a plain log: --log-format csv)"
            return (
                "expected phyphox's columns "
                + ",".join(f'"{c}"' for c in PHYPHOX_COLUMNS)
                + " first"
                + hint
            )
        return None
    if tuple(header[:4]) not in (PLAIN_COLUMNS_M_S2, PLAIN_COLUMNS_G):
        hint = " (phyphox's export: --log-format phyphox)" if header[:1] == ["Time (s)"] else ""
        return (
            f"expected the columns {','.join(PLAIN_COLUMNS_M_S2)} (m/s²) or "
            f"{','.join(PLAIN_COLUMNS_G)} (g) first{hint}"
        )
    return None


def read_log(path: str | Path, fmt: LogFormat = "phyphox") -> AccelLog:
    """Read a recorded accelerometer log.

    Parameters
    ----------
    path : path-like
    fmt : "phyphox" or "csv"

    Raises
    ------
    LogError
        Naming the file and line: an unknown header (no time column), a bad number, time that
        does not increase, fewer than two samples, a median rate below :data:`MIN_RATE_HZ`, a
        magnitude that cannot be gravity.

    Examples
    --------
    >>> import tempfile
    >>> d = Path(tempfile.mkdtemp())
    >>> t = np.arange(0.0, 2.0, 0.01)
    >>> a = np.tile([0.0, 0.0, 1.0], (len(t), 1))
    >>> write_log(d / "log.csv", t, a, "phyphox")
    >>> log = read_log(d / "log.csv")
    >>> round(log.rate_hz), log.acc_g[0].tolist()
    (100, [0.0, 0.0, 1.0])
    """
    if fmt not in LOG_FORMATS:
        raise ValueError(f"unknown log format {fmt!r}; known: {', '.join(LOG_FORMATS)}")
    p = Path(path)
    text = _open_text(p)
    first = text.split("\n", 1)[0]
    sep, decimal_comma = _dialect(first)
    rows = csv.reader(io.StringIO(text), delimiter=sep)
    header: list[str] | None = None
    scale = 1.0 / STANDARD_GRAVITY_M_S2
    t: list[float] = []
    acc: list[tuple[float, float, float]] = []
    lines: list[int] = []
    try:
        for fields in rows:
            line = rows.line_num
            if not fields or not "".join(fields).strip():
                continue
            if header is None:
                header = [f.strip() for f in fields]
                problem = _header_problem(header, fmt)
                if problem is not None:
                    got = ",".join(header)
                    got = got if len(got) <= 240 else got[:240] + "…"
                    raise LogError(f"{p}, line {line}: {problem}; got {got}")
                if fmt == "csv" and tuple(header[:4]) == PLAIN_COLUMNS_G:
                    scale = 1.0
                continue
            if len(fields) != len(header):
                raise LogError(
                    f"{p}, line {line}: expected {len(header)} fields as in the header, "
                    f"got {len(fields)}"
                )
            values = []
            for name, field in zip(header[:4], fields[:4], strict=True):
                text_value = field.strip().replace(",", ".") if decimal_comma else field.strip()
                try:
                    v = parse_float(text_value)
                except ValueError:
                    raise LogError(
                        f"{p}, line {line}: column {name!r}: expected a number, got "
                        f"{field.strip()[:40]!r}"
                    ) from None
                if not math.isfinite(v):
                    raise LogError(f"{p}, line {line}: column {name!r}: {v} is not finite")
                values.append(v)
            if t and values[0] <= t[-1]:
                raise LogError(
                    f"{p}, line {line}: time {values[0]:g} s does not increase (the line "
                    f"before is at {t[-1]:g} s): one log, in time order"
                )
            t.append(values[0])
            acc.append((values[1] * scale, values[2] * scale, values[3] * scale))
            lines.append(line)
    except csv.Error as exc:
        raise LogError(f"{p}, line {rows.line_num}: not CSV ({exc})") from None
    if header is None:
        raise LogError(f"{p}: empty file, expected a header and samples")
    if len(t) < 2:
        raise LogError(f"{p}: {len(t)} sample(s), expected a recording")
    log = AccelLog(p, np.array(t), np.array(acc), np.array(lines, dtype=np.int64))
    span = float(log.t_s[-1] - log.t_s[0])
    if span > MAX_LOG_SPAN_S:
        raise LogError(
            f"{p}: its times span {span / 3600.0:.3g} h (lines {log.lines[0]}-{log.lines[-1]}), "
            f"more than {MAX_LOG_SPAN_S / 3600.0:g} h: cut it to the test"
        )
    rate = log.rate_hz
    if rate < MIN_RATE_HZ:
        raise LogError(
            f"{p}: samples every {1000.0 / rate:.0f} ms ({rate:.2g} Hz, the median): too slow to "
            f"follow a swing; record at {MIN_RATE_HZ:g} Hz or faster"
        )
    magnitude = float(np.median(np.linalg.norm(log.acc_g, axis=1)))
    lo, hi = GRAVITY_RANGE_G
    if not lo <= magnitude <= hi:
        unit = "m/s²" if scale != 1.0 else "g"
        raise LogError(
            f"{p}: the median magnitude is {magnitude / scale:.3g} {unit}, which cannot be "
            f"gravity ({1.0 / scale:.4g} {unit}): is it a log of acceleration with g, in "
            f"{unit}?"
        )
    return log


def log_text(t_s: npt.ArrayLike, acc_g: npt.ArrayLike, fmt: LogFormat = "phyphox") -> str:
    """A log as text in ``fmt``: phyphox's export (m/s², with the absolute column, numbers as
    phyphox writes them) or the plain CSV in g."""
    t = np.asarray(t_s, dtype=float)
    a = np.asarray(acc_g, dtype=float)
    if fmt == "phyphox":
        m = a * STANDARD_GRAVITY_M_S2
        head = ",".join(f'"{c}"' for c in (*PHYPHOX_COLUMNS, PHYPHOX_ABSOLUTE))
        rows = (
            ",".join(f"{v:.9E}" for v in (ti, *mi, float(np.linalg.norm(mi))))
            for ti, mi in zip(t, m, strict=True)
        )
        return head + "\n" + "\n".join(rows) + "\n"
    rows = (f"{ti:.6f},{ai[0]:.7f},{ai[1]:.7f},{ai[2]:.7f}" for ti, ai in zip(t, a, strict=True))
    return ",".join(PLAIN_COLUMNS_G) + "\n" + "\n".join(rows) + "\n"


def write_log(path: str | Path, t_s: npt.ArrayLike, acc_g: npt.ArrayLike, fmt: LogFormat) -> None:
    """Write a log in ``fmt`` (:func:`log_text`)."""
    Path(path).write_text(log_text(t_s, acc_g, fmt))
