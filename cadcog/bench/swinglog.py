"""The swing file as ``cadcog acquire`` writes it: each recorded hang's swing, appended durably.

An ordinary swing file (:mod:`cadcog.dynamics.swingfile`, ``docs/inertia.md``) whose hangs are
framed by comment lines, which its reader skips::

    point_id,t_s,inc_x_deg,inc_y_deg
    # hang S1 begin
    S1,12.000,-50.912,-13.804
    ...
    # hang S1 end samples=812

A hang is appended (one write, fsync) after its readings are committed to the readings CSV, so
the swing file never has a hang the readings lack. A run that resumes keeps the committed hangs
and turns an uncommitted tail (a power cut during a write) into comments.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import numpy.typing as npt

from cadcog.bench.readingsfile import _sync_dir, _write_durably
from cadcog.core.errors import CadcogError
from cadcog.core.fileio import staged_file
from cadcog.dynamics.swingfile import COLUMNS

_END = re.compile(r"^# hang (\S+) end samples=(\d+)\s*$")


def default_swing_path(readings: str | Path) -> Path:
    """``test_day.csv`` → ``test_day.swings.csv``, beside the readings."""
    p = Path(readings)
    return p.with_name(f"{p.stem}.swings{p.suffix or '.csv'}")


class SwingLog:
    """A swing file being recorded into; :meth:`open` it, then :meth:`append` each hang."""

    def __init__(self, path: Path, done: list[str]) -> None:
        self.path = path
        self.done = done

    @staticmethod
    def check(path: str | Path) -> None:
        """Refuse, creating nothing, a path :meth:`open` could not take up: a folder, or an
        existing node that is not a regular file (a run checks it before its readings file)."""
        p = Path(path)
        if p.is_dir():
            raise CadcogError(f"{p}: is a directory, expected a swing CSV file to write")
        if p.exists() and not p.is_file():
            raise CadcogError(f"{p}: exists and is not a regular file: give another --swings")

    @classmethod
    def open(cls, path: str | Path) -> SwingLog:
        """Create the file, or take up an existing one (its committed hangs in ``done``)."""
        p = Path(path)
        header = ",".join(COLUMNS)
        cls.check(p)
        if not p.exists():
            p.parent.mkdir(parents=True, exist_ok=True)
            with staged_file(p) as tmp:
                _write_durably(tmp, header + "\n", "w")
            _sync_dir(p.parent)
            return cls(p, [])
        try:
            lines = p.read_text(encoding="utf-8").splitlines()
        except (OSError, UnicodeDecodeError) as exc:
            raise CadcogError(f"{p}: cannot read it to resume ({exc})") from None
        first = next((ln for ln in lines if ln.strip() and not ln.startswith("#")), None)
        if first is None or first.strip() != header:
            raise CadcogError(
                f"{p}: exists and is not a swing file ({header}): give another --swings"
            )
        done, commit = [], lines.index(first) + 1
        for i, ln in enumerate(lines):
            m = _END.match(ln)
            if m:
                done.append(m.group(1))
                commit = i + 1
        if any(ln.strip() for ln in lines[commit:]):
            kept = lines[:commit] + [f"# incomplete hang, not used: {ln}" for ln in lines[commit:]]
            with staged_file(p) as tmp:
                _write_durably(tmp, "\n".join(kept) + "\n", "w")
            _sync_dir(p.parent)
        return cls(p, done)

    def append(self, point_id: str, t_s: npt.ArrayLike, deg: npt.ArrayLike) -> None:
        """Append one hang's swing durably."""
        t = np.asarray(t_s, dtype=float)
        d = np.asarray(deg, dtype=float).reshape(-1, 2)
        rows = "".join(
            f"{point_id},{a:.4f},{x:.5f},{y:.5f}\n" for a, (x, y) in zip(t, d, strict=True)
        )
        _write_durably(
            self.path,
            f"# hang {point_id} begin\n{rows}# hang {point_id} end samples={len(t)}\n",
            "a",
        )
        self.done.append(point_id)
