"""The readings CSV as ``cadcog acquire`` writes it: appended hang by hang, durably, resumable.

The file is an ordinary readings CSV (``docs/estimate.md``): ``cadcog estimate`` reads it as it
is. Each hang is one block, appended with a single write followed by flush and fsync::

    # hang S1 begin attempt=1 settled_after_s=21.350 period_s=0.712 ...
    S1,45.000,20.000,82.000,168.2500,404.3750,true,123.450
    ...
    # hang S1 end samples=200

The ``end`` line commits the block. When a run starts on an existing file, completed blocks are
the hangs already done (they are not asked for again); an uncommitted tail (the machine died
during the write) is turned into comments by an atomic rewrite, so nothing is counted twice and
nothing half-written is read. A hang judged bad and redone is kept for the record as comments
only (``# rejected hang ...``), which the readings reader skips.
"""

from __future__ import annotations

import csv
import errno
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from cadcog.bench.recorder import DeviceUnits, HangData
from cadcog.core.errors import CadcogError
from cadcog.core.fileio import staged_file
from cadcog.method.readings import (
    FACE_COLUMN,
    POSITION_COLUMNS,
    TURNED_COLUMN,
    Suspension,
    format_face,
    header_columns,
)

_BEGIN = re.compile(r"^# hang (\S+) begin(.*)$")
_END = re.compile(r"^# hang (\S+) end samples=(\d+)\s*$")

BASE_COLUMNS = POSITION_COLUMNS  # the format's columns: cadcog.method.readings
TAIL_COLUMNS = (FACE_COLUMN, "t_s")  # t_s: the sample's time, which readers ignore

#: The largest readings file resumed (it is read whole): an hour at 100 samples/s is about
#: 20 MB, so this is ten hours of recording, and the memory it takes stays well under 1 GB.
MAX_RESUME_BYTES = 200_000_000


def columns(value_columns: tuple[str, str], turned: bool = False) -> tuple[str, ...]:
    """The CSV header for a device's value columns (and the ``sensor_turned`` column when the
    run has a reversal)."""
    return header_columns(value_columns, ("t_s", TURNED_COLUMN) if turned else ("t_s",))


@dataclass(frozen=True)
class HangBlock:
    """A committed hang as found in (or written to) the file.

    Attributes
    ----------
    point_id : str
    position_mm : tuple of 3 floats
    top_face_up : bool
    values : ndarray, shape (n, 2)
        Values as written (mean counts or degrees).
    info : str
        The ``begin`` line's record (attempt, settle time, period, decay, ...).
    line : int
        Line of the ``begin`` marker (1-based).
    sensor_turned : bool
        Read with the sensor turned on its mount (False in a file without the column).
    """

    point_id: str
    position_mm: tuple[float, float, float]
    top_face_up: bool
    values: np.ndarray
    info: str
    line: int
    sensor_turned: bool = False


def _fmt_value(v: float, counts: bool) -> str:
    return f"{v:.4f}" if counts else f"{v:.5f}"


def block_text(
    point_id: str,
    position_mm: Sequence[float],
    top_face_up: bool,
    data: HangData,
    units: DeviceUnits,
    info: str,
    sensor_turned: bool | None = None,
) -> str:
    """The text of one hang block (begin marker, one row per averaged sample, end marker);
    ``sensor_turned`` None: a file without that column."""
    x, y, z = (f"{float(c):.3f}" for c in position_mm)
    face = format_face(top_face_up)
    turned = "" if sensor_turned is None else "," + format_face(sensor_turned)
    lines = [f"# hang {point_id} begin {info}"]
    for t, (vx, vy) in zip(data.t_s, data.values, strict=True):
        lines.append(
            f"{point_id},{x},{y},{z},{_fmt_value(vx, units.counts)},"
            f"{_fmt_value(vy, units.counts)},{face},{t:.3f}{turned}"
        )
    lines.append(f"# hang {point_id} end samples={len(data.t_s)}")
    return "\n".join(lines) + "\n"


def parse_block(text: str) -> HangBlock:
    """The block written by :func:`block_text`, as it will be read back."""
    lines = text.splitlines()
    blocks, _ = _scan(lines, Path("<block>"), None)
    if len(blocks) != 1:
        raise ValueError("not one hang block")
    return blocks[0]


def suspension_of(block: HangBlock, units: DeviceUnits) -> Suspension:
    """The averaged suspension of a block, computed as :func:`cadcog.method.readings.read_readings`
    does.

    Each row is converted to degrees, then averaged (mean and sample standard deviation).
    """
    deg = units.degrees(block.values)
    n = len(deg)
    std = deg.std(axis=0, ddof=1) if n > 1 else (None, None)
    return Suspension(
        block.point_id,
        block.position_mm,
        block.top_face_up,
        n,
        float(deg[:, 0].mean()),
        float(deg[:, 1].mean()),
        None if std[0] is None else float(std[0]),
        None if std[1] is None else float(std[1]),
        block.line,
        block.sensor_turned,
    )


def _scan(
    lines: Sequence[str], path: Path, header: tuple[str, ...] | None
) -> tuple[list[HangBlock], int]:
    """Committed blocks, and the index of the first line after the last commit (or header)."""
    blocks: list[HangBlock] = []
    commit = 0
    current: tuple[str, str, int] | None = None
    rows: list[list[str]] = []
    for i, line in enumerate(lines):
        stripped = line.strip()
        if not stripped:
            continue
        m = _BEGIN.match(stripped)
        if m:
            current, rows = (m.group(1), m.group(2).strip(), i + 1), []
            continue
        m = _END.match(stripped)
        if m and current is not None and m.group(1) == current[0]:
            if int(m.group(2)) != len(rows) or not rows:
                raise CadcogError(f"{path}, line {i + 1}: hang {current[0]} has {len(rows)} rows")
            blocks.append(_block(current, rows, path))
            current, commit = None, i + 1
            continue
        if stripped.startswith("#"):
            continue
        fields = next(csv.reader([stripped]))
        if header is not None and tuple(f.strip() for f in fields) == header and not blocks:
            commit = i + 1 if current is None else commit
            continue
        if current is None:
            raise CadcogError(
                f"{path}, line {i + 1}: a reading outside a recorded hang; this file was not "
                "written by cadcog acquire: give another --out"
            )
        rows.append(fields)
    return blocks, commit


def _block(current: tuple[str, str, int], rows: list[list[str]], path: Path) -> HangBlock:
    pid, info, line = current
    try:
        first = rows[0]
        position = (float(first[1]), float(first[2]), float(first[3]))
        values = np.array([[float(r[4]), float(r[5])] for r in rows])
        face = first[6].strip() == "true"
        turned = len(first) > 8 and first[8].strip() == "true"
    except (IndexError, ValueError):
        raise CadcogError(f"{path}, line {line}: hang {pid} has malformed rows") from None
    return HangBlock(pid, position, face, values, info, line, turned)


class ReadingsFile:
    """A readings CSV being recorded into.

    Use :meth:`open`; then :meth:`append` each finished hang. ``turned_column``: whether its
    rows carry ``sensor_turned`` (a run with a reversal, or a file that already had it).
    """

    def __init__(self, path: Path, units: DeviceUnits, turned_column: bool = False) -> None:
        self.path = path
        self.units = units
        self.turned_column = turned_column

    @classmethod
    def open(
        cls,
        path: str | Path,
        units: DeviceUnits,
        preamble: Sequence[str] = (),
        turned: bool = False,
    ) -> tuple[ReadingsFile, list[HangBlock], int]:
        """Create the file, or take up an existing one.

        Returns
        -------
        file : ReadingsFile
        blocks : list of HangBlock
            Hangs already recorded, in file order.
        repaired : int
            Lines of an uncommitted tail turned into comments (0 normally).

        A file recorded without ``sensor_turned`` that a run with a reversal resumes gets the
        column (every earlier row ``false``) by one atomic rewrite; a file with it keeps it.

        Raises
        ------
        CadcogError
            If the file was written for another kind of device, or not by ``cadcog acquire``.
        """
        p = Path(path)
        header = columns(units.value_columns, turned)
        if str(path) in ("", "-"):
            raise CadcogError(
                f"{str(path)!r}: a recording is resumed and appended hang by hang, which "
                "standard output cannot be: give a file name"
            )
        if p.is_dir():
            raise CadcogError(f"{p}: is a directory, expected a readings CSV file to write")
        if not p.exists():
            text = "".join(f"# {c}\n" for c in preamble) + ",".join(header) + "\n"
            p.parent.mkdir(parents=True, exist_ok=True)
            with staged_file(p) as tmp:
                _write_durably(tmp, text, "w")
            _sync_dir(p.parent)
            return cls(p, units, turned), [], 0
        if not p.is_file():  # /dev/zero, a FIFO: nothing to resume, nothing to append to
            raise CadcogError(f"{p}: exists and is not a regular file: give another --out")
        if p.stat().st_size > MAX_RESUME_BYTES:
            raise CadcogError(
                f"{p}: {p.stat().st_size / 1e6:.0f} MB, larger than a test run writes "
                f"({MAX_RESUME_BYTES // 1_000_000} MB): give another --out"
            )
        try:
            text = p.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise CadcogError(f"{p}: cannot read it to resume ({exc})") from None
        lines = text.splitlines()
        at = next(
            (i for i, ln in enumerate(lines) if ln.strip() and not ln.lstrip().startswith("#")),
            None,
        )
        found = None if at is None else tuple(f.strip() for f in next(csv.reader([lines[at]])))
        plain, with_turn = columns(units.value_columns), columns(units.value_columns, True)
        if at is None or found not in (plain, with_turn):
            shown = None if at is None else lines[at]
            raise CadcogError(
                f"{p}: exists with columns {shown!r}, but this device records "
                f"{','.join(header)}: give another --out"
            )
        upgrade = turned and found == plain
        if upgrade:  # the run adds a reversal: every row so far was read unturned
            lines = [
                ln if i < at or not ln.strip() or ln.lstrip().startswith("#") else ln + ",false"
                for i, ln in enumerate(lines)
            ]
            lines[at] = ",".join(with_turn)
        header = with_turn if upgrade or found == with_turn else plain
        blocks, commit = _scan(lines, p, header)
        tail = [ln for ln in lines[commit:] if ln.strip()]
        if tail or upgrade:
            kept = lines[:commit] + [f"# incomplete hang, not used: {ln}" for ln in lines[commit:]]
            with staged_file(p) as tmp:
                _write_durably(tmp, "\n".join(kept) + "\n", "w")
            _sync_dir(p.parent)
        return cls(p, units, header == with_turn), blocks, len(tail)

    def append(self, text: str) -> None:
        """Append a block durably: one write, flush, fsync."""
        _write_durably(self.path, text, "a")

    def append_rejected(self, text: str, reason: str) -> None:
        """Keep a rejected hang for the record, as comments only."""
        commented = "".join(f"# rejected: {ln}\n" for ln in text.splitlines())
        self.append(f"# rejected hang ({reason}):\n{commented}")


def _write_durably(path: Path, text: str, mode: str) -> None:
    data = text.encode("utf-8")
    flags = os.O_WRONLY | os.O_CREAT | (os.O_APPEND if mode == "a" else os.O_TRUNC)
    try:
        fd = os.open(path, flags, 0o666)
        try:
            size = os.fstat(fd).st_size
            try:
                view = memoryview(data)
                while view:  # unbuffered: nothing is left to be written later
                    view = view[os.write(fd, view) :]
                os.fsync(fd)
            except OSError:
                if mode == "a":  # cut a half-written block off: the file stays as it was
                    os.ftruncate(fd, size)
                raise
        finally:
            os.close(fd)
    except OSError as exc:
        if mode != "a":
            raise  # a staged temporary file: staged_file names the destination
        why = exc.strerror or str(exc)
        if exc.errno in (errno.EFBIG, errno.ENOSPC, errno.EDQUOT):
            why += ": the disk is full or a file-size limit (ulimit -f) was reached"
        raise CadcogError(
            f"{path}: cannot append the hang ({why}); the hangs recorded before it are kept: "
            "run the same command again to resume"
        ) from None


def _sync_dir(directory: Path) -> None:
    """fsync a directory so a new or renamed file's entry survives a power cut (POSIX)."""
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:  # pragma: no cover - not possible on every platform
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover
        pass
    finally:
        os.close(fd)
