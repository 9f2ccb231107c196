"""Readings CSV files: one row per inclinometer sample, grouped into suspensions.

Format (``docs/estimate.md``)::

    point_id,x_mm,y_mm,z_mm,inc_x_deg,inc_y_deg,top_face_up
    S1,45,20,82,-50.61,-14.22,true

``x_mm, y_mm, z_mm`` is the suspension point (where the wire leaves the object) in the body
frame. Instead of ``inc_x_deg, inc_y_deg`` a file may give raw ADC readings
``inc_x_counts, inc_y_counts``, converted by the configured
:class:`~cadcog.inclinometer.SensorModel`.
``top_face_up`` is true/false/1/0. Rows with the same ``point_id`` are samples of one suspension
and are averaged. Blank lines and lines starting with ``#`` are skipped; extra columns are
ignored. Every error names the file and the line.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from cadcog.errors import ReadingsError
from cadcog.inclinometer import InclinometerConfig, Verticals, verticals_from_readings

BASE_COLUMNS = ("point_id", "x_mm", "y_mm", "z_mm", "top_face_up")
DEG_COLUMNS = ("inc_x_deg", "inc_y_deg")
COUNT_COLUMNS = ("inc_x_counts", "inc_y_counts")
_BOOLS = {"true": True, "1": True, "false": False, "0": False}


@dataclass(frozen=True)
class Suspension:
    """The averaged samples of one suspension.

    Attributes
    ----------
    id : str
    position_mm : tuple of 3 floats
        Suspension point.
    top_face_up : bool
    n_samples : int
    inc_x_deg, inc_y_deg : float
        Mean readings, as the device reports them (degrees).
    std_x_deg, std_y_deg : float or None
        Sample standard deviations (None for a single sample).
    line : int
        Line of the file where the suspension first appears.
    """

    id: str
    position_mm: tuple[float, float, float]
    top_face_up: bool
    n_samples: int
    inc_x_deg: float
    inc_y_deg: float
    std_x_deg: float | None
    std_y_deg: float | None
    line: int


@dataclass
class _Group:
    position: tuple[float, float, float]
    top_face_up: bool
    line: int
    x: list[float]
    y: list[float]


def read_readings(path: str | Path, config: InclinometerConfig | None = None) -> list[Suspension]:
    """Read a readings CSV and average its samples per suspension point.

    Parameters
    ----------
    path : path-like
    config : InclinometerConfig, optional
        Needed for raw counts (its sensor model); defaults to the paper's.

    Returns
    -------
    list of Suspension
        In order of first appearance.

    Raises
    ------
    ReadingsError
        Naming the file and line: missing columns, a non-numeric, NaN or infinite value, an
        angle beyond ±90°, counts outside the ADC's range, a bad ``top_face_up``, one
        ``point_id`` at two positions or with two orientations, fewer than two suspensions.
    """
    cfg = config or InclinometerConfig()
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise ReadingsError(f"{p}: file not found") from None
    except (IsADirectoryError, UnicodeDecodeError) as exc:
        raise ReadingsError(f"{p}: cannot read as a UTF-8 CSV file ({exc})") from None

    def fail(line: int, message: str) -> ReadingsError:
        return ReadingsError(f"{p}, line {line}: {message}")

    rows = csv.reader(text.splitlines())
    header: list[str] | None = None
    groups: dict[str, _Group] = {}
    for fields in rows:
        line = rows.line_num
        if not fields or not "".join(fields).strip() or fields[0].lstrip().startswith("#"):
            continue
        if header is None:
            header = [f.strip() for f in fields]
            missing = [c for c in BASE_COLUMNS if c not in header]
            has_deg = all(c in header for c in DEG_COLUMNS)
            has_counts = all(c in header for c in COUNT_COLUMNS)
            if has_deg and has_counts:
                raise fail(line, "give angles either in degrees or in counts, not both")
            if not (has_deg or has_counts):
                missing += [c for c in DEG_COLUMNS if c not in header]
            if missing:
                raise fail(
                    line,
                    f"missing column(s) {', '.join(missing)}; expected header "
                    f"{','.join(BASE_COLUMNS[:4] + DEG_COLUMNS + BASE_COLUMNS[4:])} "
                    f"(or {', '.join(COUNT_COLUMNS)} instead of the degree columns)",
                )
            angle_cols = DEG_COLUMNS if has_deg else COUNT_COLUMNS
            continue
        if len(fields) != len(header):
            raise fail(line, f"expected {len(header)} fields as in the header, got {len(fields)}")
        row = dict(zip(header, (f.strip() for f in fields), strict=True))

        def number(column: str, row: dict[str, str] = row, line: int = line) -> float:
            try:
                value = float(row[column])
            except ValueError:
                raise fail(
                    line, f"column {column}: expected a number, got {row[column]!r}"
                ) from None
            if not math.isfinite(value):
                raise fail(line, f"column {column}: expected a finite number, got {row[column]!r}")
            return value

        pid = row["point_id"]
        if not pid:
            raise fail(line, "column point_id: empty")
        position = (number("x_mm"), number("y_mm"), number("z_mm"))
        flag = _BOOLS.get(row["top_face_up"].lower())
        if flag is None:
            raise fail(
                line,
                f"column top_face_up: expected true, false, 1 or 0, got {row['top_face_up']!r}",
            )
        angles = []
        for column in angle_cols:
            value = number(column)
            if angle_cols is COUNT_COLUMNS:
                if not 0 <= value <= cfg.sensor.max_counts:
                    raise fail(
                        line,
                        f"column {column}: {value:g} outside the "
                        f"{cfg.sensor.adc_bits}-bit ADC range 0..{cfg.sensor.max_counts}",
                    )
                value = float(cfg.sensor.counts_to_deg(value))
            if abs(value) > 90.0:
                raise fail(line, f"column {column}: angle {value:g}° is beyond ±90°")
            angles.append(value)
        group = groups.get(pid)
        if group is None:
            groups[pid] = _Group(position, flag, line, [angles[0]], [angles[1]])
            continue
        if position != group.position:
            raise fail(
                line,
                f"point {pid} at {list(position)} mm, but line {group.line} puts it at "
                f"{list(group.position)} mm: one point_id must have one position",
            )
        if flag != group.top_face_up:
            raise fail(line, f"point {pid}: top_face_up differs from line {group.line}")
        group.x.append(angles[0])
        group.y.append(angles[1])
    if header is None:
        raise ReadingsError(f"{p}: empty file, expected a header and readings")
    if len(groups) < 2:
        raise ReadingsError(
            f"{p}: {len(groups)} distinct suspension point(s); the method needs at least two"
        )
    return [_average(pid, g) for pid, g in groups.items()]


def _average(pid: str, g: _Group) -> Suspension:
    x, y = np.array(g.x), np.array(g.y)
    n = len(x)
    return Suspension(
        id=pid,
        position_mm=g.position,
        top_face_up=g.top_face_up,
        n_samples=n,
        inc_x_deg=float(x.mean()),
        inc_y_deg=float(y.mean()),
        std_x_deg=float(x.std(ddof=1)) if n > 1 else None,
        std_y_deg=float(y.std(ddof=1)) if n > 1 else None,
        line=g.line,
    )


def suspension_verticals(
    suspensions: Sequence[Suspension], config: InclinometerConfig | None = None
) -> Verticals:
    """Upward verticals (eq. 2) of averaged suspensions, in their order."""
    return verticals_from_readings(
        [s.inc_x_deg for s in suspensions],
        [s.inc_y_deg for s in suspensions],
        [s.top_face_up for s in suspensions],
        config,
    )
