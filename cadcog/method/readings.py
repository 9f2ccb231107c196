"""Readings CSV files: one row per inclinometer sample, grouped into suspensions.

Format (``docs/estimate.md``)::

    point_id,x_mm,y_mm,z_mm,inc_x_deg,inc_y_deg,top_face_up
    S1,45,20,82,-50.61,-14.22,true

``x_mm, y_mm, z_mm`` is the suspension point (where the wire leaves the object) in the body
frame. Instead of ``inc_x_deg, inc_y_deg`` a file may give raw ADC readings
``inc_x_counts, inc_y_counts``, converted by the configured
:class:`~cadcog.rig.inclinometer.SensorModel`.
``top_face_up`` is true/false/1/0. An optional column ``sensor_turned`` (true/false/1/0 on
every row when present; false for every hang when absent) marks a hang read with the sensor
turned 180° on its mount (a reversal, which cancels the sensor's zero offset: docs/bench.md); a
reversal is its own ``point_id`` at the same position. Rows with the same ``point_id`` are
samples of one suspension and are averaged. Blank lines and lines starting with ``#`` are
skipped; extra columns are ignored. Every error names the file and the line.

The file is read row by row and each suspension is kept as running sums (Welford's mean and
variance), so memory does not grow with the number of samples; a line longer than
:data:`MAX_LINE_CHARS` (``/dev/zero``, a binary file) is refused, not read into memory.
"""

from __future__ import annotations

import csv
import math
import unicodedata
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from cadcog.core import bounds
from cadcog.core.errors import ReadingsError, quote
from cadcog.core.fileio import not_a_regular_file, note_input
from cadcog.core.plainnumber import parse_float
from cadcog.core.units import rad_to_deg
from cadcog.rig.accelerometer import ACCEL_SHARED_PARAMETERS, accel_angles_deg, accel_verticals
from cadcog.rig.inclinometer import InclinometerConfig, Verticals, verticals_from_readings

# The format's columns, here only: the writers (cadcog.validation.campaign for virtual
# campaigns, cadcog.bench.readingsfile at the bench) build their headers from these.
#: Where the object hung from: the point's id and the wire's exit in the body frame (mm).
POSITION_COLUMNS = ("point_id", "x_mm", "y_mm", "z_mm")
#: Which way up the inclinometer's top face was (true/false/1/0).
FACE_COLUMN = "top_face_up"
#: The columns every readings file has.
BASE_COLUMNS = (*POSITION_COLUMNS, FACE_COLUMN)
#: Optional: whether the hang was read with the sensor turned 180° on its mount.
TURNED_COLUMN = "sensor_turned"
#: The two readings: angles in degrees, or raw ADC counts.
DEG_COLUMNS = ("inc_x_deg", "inc_y_deg")
COUNT_COLUMNS = ("inc_x_counts", "inc_y_counts")
#: An accelerometer's reading (``device = "accelerometer"``): the specific force along the
#: sensor's own x, y, z axes in g; such a file has no ``top_face_up`` (the reading says it).
ACC_COLUMNS = ("acc_x_g", "acc_y_g", "acc_z_g")
#: Largest accelerometer component a settled reading may have (g): far beyond any part's range.
MAX_ACC_G = 20.0


def header_columns(value_columns: Sequence[str], extra: Sequence[str] = ()) -> tuple[str, ...]:
    """The header a writer puts: the position, the two value columns, ``top_face_up``, then
    ``extra`` columns (which readers ignore).

    Examples
    --------
    >>> ",".join(header_columns(COUNT_COLUMNS))
    'point_id,x_mm,y_mm,z_mm,inc_x_counts,inc_y_counts,top_face_up'
    """
    return (*POSITION_COLUMNS, *value_columns, FACE_COLUMN, *extra)


def format_face(top_face_up: bool) -> str:
    """``top_face_up`` as writers put it: ``true`` or ``false``."""
    return "true" if top_face_up else "false"


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
    sensor_turned : bool
        Read with the sensor turned 180° on its mount (a reversal; default False).
    acc_g : tuple of 3 floats or None
        An accelerometer's mean reading (g, its own axes); None for an inclinometer. Then
        ``inc_x_deg``, ``inc_y_deg``, ``top_face_up`` and the standard deviations are what a
        dual-axis inclinometer in the sensor's axes would give
        (:func:`cadcog.rig.accelerometer.accel_angles_deg`), for display.
    std_acc_g : tuple of 3 floats or None
        The accelerometer's sample standard deviations (g; None for one sample).
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
    sensor_turned: bool = False
    acc_g: tuple[float, float, float] | None = None
    std_acc_g: tuple[float, float, float] | None = None


#: Longest line read (characters): a readings row is under 200.
MAX_LINE_CHARS = 100_000

#: Longest point id (characters).
MAX_ID_CHARS = 200


@dataclass
class _Running:
    """Welford's running mean and sum of squared deviations."""

    n: int = 0
    mean: float = 0.0
    m2: float = 0.0

    def add(self, value: float) -> None:
        self.n += 1
        delta = value - self.mean
        self.mean += delta / self.n
        self.m2 += delta * (value - self.mean)

    def std(self) -> float | None:
        return math.sqrt(self.m2 / (self.n - 1)) if self.n > 1 else None


@dataclass
class _Group:
    position: tuple[float, float, float]
    top_face_up: bool
    line: int
    x: _Running
    y: _Running
    raw_position: tuple[str, str, str] = ("", "", "")  # as written in the point's first row
    raw_flag: str = ""
    turned: bool = False
    raw_turned: str = ""
    z: _Running | None = None  # an accelerometer's third axis


def _number(fields: list[str], col: dict[str, int], column: str, line: int, fail: Any) -> float:
    """The number in ``column`` of a row, finite and within its name's bound."""
    text = fields[col[column]].strip()
    try:
        value = parse_float(text)
    except ValueError:
        raise fail(line, f"column {column}: expected a number, got {text!r}") from None
    if not math.isfinite(value) or (column[-3:] == "_mm" and abs(value) > bounds.LENGTH_MAX_MM):
        raise fail(line, f"column {column}: {bounds.check(column, value)}, got {text!r}")
    return value


def id_problem(text: str) -> str | None:
    """Why ``text`` cannot be a point id, or None: empty, too long, a comma (ids are listed
    comma-separated on the command line) or a control character.

    Examples
    --------
    >>> id_problem("S1") is None, id_problem("a,b")
    (True, 'a comma (ids are listed comma-separated)')
    >>> print(id_problem("S" + chr(0)))
    a control character ('\\x00')
    """
    if not text:
        return "empty"
    if len(text) > MAX_ID_CHARS:
        return f"longer than {MAX_ID_CHARS} characters"
    if "," in text:
        return "a comma (ids are listed comma-separated)"
    bad = next((c for c in text if unicodedata.category(c)[0] == "C"), None)
    if bad is not None:
        return f"a control character ({bad!r})"
    return None


def _lines(f: Any, p: Path) -> Iterator[str]:
    """The lines of a binary file, decoded one by one (so that an encoding error names its
    line), each at most :data:`MAX_LINE_CHARS` bytes long (else a ReadingsError)."""
    number = 0
    while True:
        raw = f.readline(MAX_LINE_CHARS + 1)
        if not raw:
            return
        number += 1
        if len(raw) > MAX_LINE_CHARS:
            raise ReadingsError(
                f"{p}, line {number}: longer than {MAX_LINE_CHARS} characters: not a readings "
                "CSV file"
            )
        try:
            line = raw.decode("utf-8-sig" if number == 1 else "utf-8")
        except UnicodeDecodeError as exc:
            raise ReadingsError(
                f"{p}, line {number}: not UTF-8 text ({exc.reason} at column {exc.start + 1})"
            ) from None
        yield line


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
        angle beyond ±90°, counts outside the ADC's range, a bad ``top_face_up`` or
        ``sensor_turned``, one ``point_id`` at two positions or with two orientations, fewer
        than two suspensions.
    """
    cfg = config or InclinometerConfig()
    p = Path(path)
    if p.is_dir():
        raise ReadingsError(f"{p}: is a directory, expected a readings CSV file")
    if p.exists() and not p.is_file():  # a device or a FIFO may never end: refuse it unread
        raise ReadingsError(f"{p}: {not_a_regular_file(p)} (a readings CSV file)")
    try:
        f = p.open("rb")
    except FileNotFoundError:
        raise ReadingsError(f"{p}: file not found") from None
    except OSError as exc:
        raise ReadingsError(f"{p}: cannot read ({exc.strerror or exc})") from None
    note_input(p, "the readings it reads")
    with f:
        header, groups = _read_groups(csv.reader(_lines(f, p)), p, cfg)
    if header is None:
        raise ReadingsError(f"{p}: empty file, expected a header and readings")
    if len(groups) < 2:
        raise ReadingsError(
            f"{p}: {len(groups)} distinct suspension point(s); the method needs at least two"
        )
    return [_average(pid, g, p) for pid, g in groups.items()]


def data_rows(rows: Any, fail: Any) -> Iterator[tuple[int, list[str]]]:
    """``(line, fields)`` of a ``csv.reader``'s rows, blank lines and ``#`` lines skipped; a
    row the CSV reader refuses raises ``fail(line, message)``."""
    fields_iter = iter(rows)
    while True:
        try:
            fields = next(fields_iter)
        except StopIteration:
            return
        except csv.Error as exc:
            raise fail(rows.line_num, f"not CSV ({exc})") from None
        if not fields or not "".join(fields).strip() or fields[0].lstrip().startswith("#"):
            continue
        yield rows.line_num, fields


@dataclass(frozen=True)
class _Layout:
    """Where a readings file's columns are, from its header."""

    header: list[str]
    col: dict[str, int]  # column name → field index
    angle_cols: tuple[str, ...]  # the two degree or count columns, or the three g columns
    counts: bool  # angles given as ADC counts


def _read_groups(
    rows: Any, p: Path, cfg: InclinometerConfig
) -> tuple[list[str] | None, dict[str, _Group]]:
    """The header and the running sums of each point's samples, in order of appearance."""

    def fail(line: int, message: str) -> ReadingsError:
        return ReadingsError(f"{p}, line {line}: {message}")

    layout: _Layout | None = None
    groups: dict[str, _Group] = {}
    for line, fields in data_rows(rows, fail):
        if layout is None:
            layout = _layout([f.strip() for f in fields], cfg, line, fail)
            continue
        if len(fields) != len(layout.header):
            raise fail(
                line, f"expected {len(layout.header)} fields as in the header, got {len(fields)}"
            )
        group = _point_of(fields, layout, groups, line, fail)
        _add_samples(fields, layout, group, cfg, line, fail)
    return (None if layout is None else layout.header), groups


def _layout(header: list[str], cfg: InclinometerConfig, line: int, fail: Any) -> _Layout:
    """The columns a header names, checked: each once, all the chain needs, one kind of angle."""
    twice = next((c for i, c in enumerate(header) if c and c in header[:i]), None)
    if twice is not None:
        first, second = [i + 1 for i, c in enumerate(header) if c == twice][:2]
        raise fail(
            line,
            f"column {quote(twice)} appears twice (fields {first} and {second}): "
            "expected each column once",
        )
    acc = _accelerometer_header(header, cfg, line, fail)
    missing = [c for c in (POSITION_COLUMNS if acc else BASE_COLUMNS) if c not in header]
    has_deg = all(c in header for c in DEG_COLUMNS)
    has_counts = all(c in header for c in COUNT_COLUMNS)
    if has_deg and has_counts:
        raise fail(line, "give angles either in degrees or in counts, not both")
    if not (has_deg or has_counts or acc):
        missing += [c for c in DEG_COLUMNS if c not in header]
    if missing:
        expected = (
            ",".join(POSITION_COLUMNS + ACC_COLUMNS)
            if acc
            else f"{','.join(BASE_COLUMNS[:4] + DEG_COLUMNS + BASE_COLUMNS[4:])} "
            f"(or {', '.join(COUNT_COLUMNS)} instead of the degree columns)"
        )
        raise fail(line, f"missing column(s) {', '.join(missing)}; expected header {expected}")
    angle_cols = ACC_COLUMNS if acc else DEG_COLUMNS if has_deg else COUNT_COLUMNS
    col = {name: header.index(name) for name in (*POSITION_COLUMNS, *angle_cols)}
    if not acc:
        col[FACE_COLUMN] = header.index(FACE_COLUMN)
    if TURNED_COLUMN in header:
        col[TURNED_COLUMN] = header.index(TURNED_COLUMN)
    return _Layout(header, col, angle_cols, has_counts and not has_deg)


def _point_of(
    fields: list[str], layout: _Layout, groups: dict[str, _Group], line: int, fail: Any
) -> _Group:
    """The group a row belongs to: a new point is added; a row that differs from its point's
    first row is checked in full and must agree with it (one position, one orientation)."""
    col = layout.col
    pid = fields[col["point_id"]].strip()
    raw_position = (fields[col["x_mm"]], fields[col["y_mm"]], fields[col["z_mm"]])
    raw_flag = fields[col[FACE_COLUMN]] if FACE_COLUMN in col else "true"
    raw_turned = fields[col[TURNED_COLUMN]] if TURNED_COLUMN in col else ""
    group = groups.get(pid)
    if (
        group is not None
        and raw_position == group.raw_position
        and raw_flag == group.raw_flag
        and raw_turned == group.raw_turned
    ):
        return group  # as its point's first row, already checked
    problem = id_problem(pid)
    if problem is not None:
        raise fail(line, f"column point_id: {problem}")
    position = (
        _number(fields, col, "x_mm", line, fail),
        _number(fields, col, "y_mm", line, fail),
        _number(fields, col, "z_mm", line, fail),
    )
    flag = _BOOLS.get(raw_flag.strip().lower())
    if flag is None:
        raise fail(
            line, f"column top_face_up: expected true, false, 1 or 0, got {raw_flag.strip()!r}"
        )
    turned = _BOOLS.get(raw_turned.strip().lower()) if TURNED_COLUMN in col else False
    if turned is None:
        raise fail(
            line,
            f"column {TURNED_COLUMN}: expected true, false, 1 or 0, got {raw_turned.strip()!r}",
        )
    if group is None:
        group = groups[pid] = _Group(
            position, flag, line, _Running(), _Running(), raw_position, raw_flag,
            turned, raw_turned, _Running() if FACE_COLUMN not in col else None,
        )  # fmt: skip
    elif position != group.position:
        raise fail(
            line,
            f"point {pid} at {list(position)} mm, but line {group.line} puts it at "
            f"{list(group.position)} mm: one point_id must have one position",
        )
    elif flag != group.top_face_up:
        raise fail(line, f"point {pid}: top_face_up differs from line {group.line}")
    elif turned != group.turned:
        raise fail(
            line,
            f"point {pid}: {TURNED_COLUMN} differs from line {group.line} (a reversal "
            "is its own point_id at the same position)",
        )
    return group


def _add_samples(
    fields: list[str], layout: _Layout, group: _Group, cfg: InclinometerConfig, line: int,
    fail: Any,
) -> None:  # fmt: skip
    """A row's angles (degrees, or counts converted) or specific forces (g), checked against
    their range, added to its point's running sums."""
    runs = (group.x, group.y) if group.z is None else (group.x, group.y, group.z)
    for column, running in zip(layout.angle_cols, runs, strict=True):
        value = _number(fields, layout.col, column, line, fail)
        if group.z is not None:
            if abs(value) > MAX_ACC_G:
                raise fail(line, f"column {column}: {value:g} g is beyond ±{MAX_ACC_G:g} g at rest")
            running.add(value)
            continue
        if layout.counts:
            max_counts = cfg.sensor.max_counts
            if not 0 <= value <= max_counts:
                raise fail(
                    line,
                    f"column {column}: {value:g} outside the "
                    f"{cfg.sensor.adc_bits}-bit ADC range 0..{max_counts}",
                )
            value = cfg.sensor.count_to_deg(value)
        if abs(value) > 90.0:
            raise fail(line, f"column {column}: angle {value:g}° is beyond ±90°")
        running.add(value)


def _accelerometer_header(header: list[str], cfg: InclinometerConfig, line: int, fail: Any) -> bool:
    """Whether a header is an accelerometer's (its three columns), checked against the
    sensor the set-up declares."""
    acc = [c for c in ACC_COLUMNS if c in header]
    if not acc:
        if cfg.accelerometer:
            raise fail(
                line,
                f'the set-up\'s sensor is an accelerometer (device = "accelerometer"): expected '
                f"the columns {', '.join(ACC_COLUMNS)} (g, the sensor's axes)",
            )
        return False
    if len(acc) < 3:
        missing = [c for c in ACC_COLUMNS if c not in header]
        raise fail(line, f"missing column(s) {', '.join(missing)} beside {', '.join(acc)}")
    if not cfg.accelerometer:
        raise fail(
            line,
            f"columns {', '.join(ACC_COLUMNS)} are an accelerometer's readings, but the "
            "[inclinometer] they are read with (the set-up's or rig's given; with neither, the "
            "paper rig's) reads angles: give the --rig or --setup whose [inclinometer] declares "
            'device = "accelerometer" (docs/bench.md §8)',
        )
    clash = [c for c in (*DEG_COLUMNS, *COUNT_COLUMNS, FACE_COLUMN) if c in header]
    if clash:
        raise fail(
            line,
            f"column {clash[0]} beside an accelerometer's {', '.join(ACC_COLUMNS)}: the "
            "acceleration is the whole reading (which face is up included); drop it",
        )
    return True


def suspension_from_samples(
    pid: str,
    position_mm: tuple[float, float, float],
    top_face_up: bool,
    x_deg: Iterable[float],
    y_deg: Iterable[float],
    line: int,
) -> Suspension:
    """The :class:`Suspension` of samples in degrees, averaged exactly as a readings file's are
    (the same running sums, so the same numbers to the last bit)."""
    g = _Group(position_mm, top_face_up, line, _Running(), _Running())
    for x, y in zip(x_deg, y_deg, strict=True):
        g.x.add(float(x))
        g.y.add(float(y))
    return _average(pid, g)


def _average(pid: str, g: _Group, path: Path | None = None) -> Suspension:
    if g.z is not None:
        mean = (g.x.mean, g.y.mean, g.z.mean)
        if math.hypot(*mean) < 0.1:
            where = f"{path}, line {g.line}" if path is not None else f"line {g.line}"
            raise ReadingsError(
                f"{where}: point {pid}: the mean acceleration is {math.hypot(*mean):.3g} "
                "g, not gravity: are the columns in g (not m/s²), and was the object at rest?"
            )
        x, y, top = accel_angles_deg([mean])
        stds = (g.x.std(), g.y.std(), g.z.std())
        std_acc = None if stds[0] is None else (stds[0], stds[1] or 0.0, stds[2] or 0.0)
        std_deg = None if std_acc is None else float(rad_to_deg(max(std_acc[:2])))
        return Suspension(
            id=pid,
            position_mm=g.position,
            top_face_up=bool(top[0]),
            n_samples=g.x.n,
            inc_x_deg=float(x[0]),
            inc_y_deg=float(y[0]),
            std_x_deg=std_deg,
            std_y_deg=std_deg,
            line=g.line,
            sensor_turned=g.turned,
            acc_g=mean,
            std_acc_g=std_acc,
        )
    return Suspension(
        id=pid,
        position_mm=g.position,
        top_face_up=g.top_face_up,
        n_samples=g.x.n,
        inc_x_deg=g.x.mean,
        inc_y_deg=g.y.mean,
        std_x_deg=g.x.std(),
        std_y_deg=g.y.std(),
        line=g.line,
        sensor_turned=g.turned,
    )


def suspension_verticals(
    suspensions: Sequence[Suspension], config: InclinometerConfig | None = None
) -> Verticals:
    """Upward verticals (eq. 2) of averaged suspensions, in their order (a hang read with the
    sensor turned has its angles negated first: :func:`cadcog.rig.inclinometer.sensor_readings`)."""
    if config is not None and config.accelerometer:
        return accel_verticals(
            [_acc(s) for s in suspensions],
            np.zeros(len(ACCEL_SHARED_PARAMETERS)),
            config.axes,
            [s.sensor_turned for s in suspensions],
        )
    flip = [-1.0 if s.sensor_turned else 1.0 for s in suspensions]
    return verticals_from_readings(
        [f * s.inc_x_deg for f, s in zip(flip, suspensions, strict=True)],
        [f * s.inc_y_deg for f, s in zip(flip, suspensions, strict=True)],
        [s.top_face_up for s in suspensions],
        config,
    )


def _acc(s: Suspension) -> tuple[float, float, float]:
    if s.acc_g is None:
        raise ReadingsError(
            f"suspension {s.id}: an inclinometer's angles, but the set-up's sensor is an "
            "accelerometer: read the file with its set-up"
        )
    return s.acc_g
