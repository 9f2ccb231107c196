"""Output files that appear whole or not at all.

Commands write into a temporary directory beside the destination and move each finished file
into place with :func:`os.replace`, which is atomic on POSIX file systems. If anything fails on
the way, the temporary directory is removed and the destination is left as it was.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from cadcog import tolerances


@contextmanager
def staged_output_dir(out_dir: str | Path) -> Iterator[Path]:
    """Yield a scratch directory whose files are moved into ``out_dir`` on success.

    Existing files in ``out_dir`` that the command does not produce are left alone; produced
    files replace their namesakes atomically, one by one.
    """
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise NotADirectoryError(f"{out}: exists and is not a directory")
    parent = out.resolve().parent
    parent.mkdir(parents=True, exist_ok=True)
    stage = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".partial", dir=parent))
    try:
        yield stage
        out.mkdir(parents=True, exist_ok=True)
        for src in sorted(stage.rglob("*")):
            if src.is_file():
                dst = out / src.relative_to(stage)
                dst.parent.mkdir(parents=True, exist_ok=True)
                os.replace(src, dst)
    finally:
        shutil.rmtree(stage, ignore_errors=True)


def round_floats(value: Any, digits: int = tolerances.JSON_SIGNIFICANT_DIGITS) -> Any:
    """Round every float in a JSON-like structure to ``digits`` significant digits.

    Examples
    --------
    >>> round_floats({"a": [0.1 + 0.2, 1]}, 15)
    {'a': [0.3, 1]}
    """
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"refusing to write non-finite value {value!r} to JSON")
        return float(f"{value:.{digits}g}")
    if isinstance(value, dict):
        return {k: round_floats(v, digits) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [round_floats(v, digits) for v in value]
    return value


def dumps_json(data: Any) -> str:
    """Deterministic JSON text: floats rounded, two-space indent, trailing newline."""
    return json.dumps(round_floats(data), indent=2, ensure_ascii=False, allow_nan=False) + "\n"


@contextmanager
def staged_file(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path beside ``path`` (same suffix) that replaces ``path`` on success."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.stem}.", suffix=target.suffix, dir=target.parent)
    os.close(fd)
    try:
        yield Path(tmp)
        os.replace(tmp, target)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
