"""Swing files: the raw inclinometer samples of each hang, from release to settle.

Format (``docs/inertia.md``)::

    point_id,t_s,inc_x_deg,inc_y_deg
    S1,12.000,-50.912,-13.804
    S1,12.020,-50.733,-13.911
    ...

One row per sample, the device's clock in seconds (increasing within a hang), the readings in
degrees as the device reports them (its signs applied). A hang's rows are contiguous; extra
columns are ignored; blank lines and lines starting with ``#`` are skipped. Every error names the
file and the line.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import ReadingsError, quote
from cadcog.core.fileio import not_a_regular_file, note_input, staged_file
from cadcog.core.plainnumber import parse_float
from cadcog.method.readings import _lines, data_rows, id_problem

FloatArray = npt.NDArray[np.float64]

COLUMNS = ("point_id", "t_s", "inc_x_deg", "inc_y_deg")

#: The fewest samples of a hang the modal fit accepts (10 s at 20 samples/s).
MIN_SAMPLES = 200


@dataclass(frozen=True)
class Swing:
    """The recorded swing of one hang.

    Attributes
    ----------
    point_id : str
    t_s : ndarray, shape (n,)
        Device time (s), increasing.
    inc_deg : ndarray, shape (n, 2)
        Readings (inc_x, inc_y), degrees.
    line : int
        Line of the file where the hang starts (0 when not from a file).
    """

    point_id: str
    t_s: FloatArray
    inc_deg: FloatArray
    line: int = 0

    @property
    def duration_s(self) -> float:
        return float(self.t_s[-1] - self.t_s[0])

    @property
    def rate_hz(self) -> float:
        """Mean sample rate."""
        return (len(self.t_s) - 1) / self.duration_s


def read_swings(path: str | Path) -> list[Swing]:
    """Read a swing file.

    Returns
    -------
    list of Swing
        In order of appearance.

    Raises
    ------
    ReadingsError
        Naming the file and line: missing columns, a non-numeric or non-finite value, an angle
        beyond ±90°, time not increasing within a hang, a hang's rows split in two blocks, a
        hang of a single sample, an empty file. (A hang with fewer than :data:`MIN_SAMPLES` is
        read: ``cadcog inertia`` leaves it out of the tensor and says so.)
    """
    p = Path(path)
    if not p.is_file():
        raise ReadingsError(f"{p}: {not_a_regular_file(p)}, expected a swing CSV file")
    try:
        f = p.open("rb")
    except OSError as exc:
        raise ReadingsError(f"{p}: cannot read ({exc.strerror or exc})") from None
    note_input(p, "the swings it reads")

    def fail(line: int, message: str) -> ReadingsError:
        return ReadingsError(f"{p}, line {line}: {message}")

    header: list[str] | None = None
    col: dict[str, int] = {}
    blocks: dict[str, tuple[int, list[float], list[float], list[float]]] = {}
    current: str | None = None
    with f:
        for line, fields in data_rows(csv.reader(_lines(f, p)), fail):
            if header is None:
                header = [c.strip() for c in fields]
                missing = [c for c in COLUMNS if c not in header]
                if missing:
                    raise fail(
                        line,
                        f"missing column(s) {', '.join(missing)}: expected a header with "
                        f"{','.join(COLUMNS)} (a swing file)",
                    )
                col = {c: header.index(c) for c in COLUMNS}
                continue
            if len(fields) < len(header):
                raise fail(line, f"{len(fields)} fields, expected {len(header)} (the header's)")
            pid = fields[col["point_id"]].strip()
            problem = id_problem(pid)
            if problem is not None:
                raise fail(line, f"column point_id: {quote(pid)} is {problem}")
            values = []
            for name in COLUMNS[1:]:
                text = fields[col[name]].strip()
                try:
                    value = parse_float(text)
                except ValueError:
                    raise fail(
                        line, f"column {name}: expected a number, got {quote(text)}"
                    ) from None
                if not math.isfinite(value):
                    raise fail(line, f"column {name}: expected a finite number, got {quote(text)}")
                if name != "t_s" and abs(value) > 90.0:
                    raise fail(line, f"column {name}: {value} is beyond ±90°, not an inclination")
                values.append(value)
            if pid != current:
                if pid in blocks:
                    raise fail(
                        line,
                        f"point {quote(pid)} again after other hangs (first at line "
                        f"{blocks[pid][0]}): a hang's rows must be contiguous",
                    )
                blocks[pid] = (line, [], [], [])
                current = pid
            first, ts, xs, ys = blocks[pid]
            if ts and values[0] <= ts[-1]:
                raise fail(
                    line,
                    f"column t_s: {values[0]} s is not after the previous sample of {quote(pid)} "
                    f"({ts[-1]} s): time must increase within a hang",
                )
            ts.append(values[0])
            xs.append(values[1])
            ys.append(values[2])
    if header is None:
        raise ReadingsError(f"{p}: empty file, expected a header and swing samples")
    if not blocks:
        raise ReadingsError(f"{p}: no samples after the header")
    out = []
    for pid, (first, ts, xs, ys) in blocks.items():
        if len(ts) < 2:
            raise fail(
                first,
                f"hang {quote(pid)} has 1 sample, expected a swing (at least {MIN_SAMPLES} "
                "samples from release to settle)",
            )
        out.append(Swing(pid, np.array(ts), np.column_stack([xs, ys]), first))
    return out


def swings_text(swings: Sequence[Swing]) -> str:
    """The file text of ``swings`` (times to the µs, angles to 10⁻⁵°)."""
    lines = [",".join(COLUMNS)]
    for s in swings:
        for t, (x, y) in zip(s.t_s, s.inc_deg, strict=True):
            lines.append(f"{s.point_id},{t:.6f},{x:.5f},{y:.5f}")
    return "\n".join(lines) + "\n"


def write_swings(path: str | Path, swings: Sequence[Swing]) -> None:
    """Write a swing file (staged: nothing partial on failure)."""
    with staged_file(path) as tmp:
        tmp.write_text(swings_text(swings), encoding="utf-8")
