"""Output files that appear whole or not at all.

Commands write into a temporary directory (or file) beside the destination and move each
finished file into place with :func:`os.replace`, which is atomic on POSIX file systems. If
anything fails on the way, including an interrupt (Ctrl-C) or a SIGTERM (``cadcog.cli`` turns it
into an exception), the temporary files are removed and the destination is left as it was.
Finished files get the permissions the user's umask gives a new file, not the 0600 of a
temporary file; errors name the destination the user gave, never the temporary name.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from contextvars import ContextVar
from pathlib import Path
from typing import Any

from cadcog.core import tolerances
from cadcog.core.errors import CadcogError

#: The files the running command has read (resolved path → what it was), while a command runs
#: inside :func:`guarding_inputs`; staged outputs refuse to replace any of them.
_INPUTS: ContextVar[dict[Path, str] | None] = ContextVar("cadcog_inputs", default=None)


@contextmanager
def guarding_inputs() -> Iterator[None]:
    """While inside, every file read through :func:`note_input` is protected from the outputs.

    The command line runs each command inside one: whatever a command reads (a rig file, a
    set-up and the model it names, readings, a STEP file, a materials file), no staged output of
    the same command may replace it, however the output's name was given.
    """
    token = _INPUTS.set({})
    try:
        yield
    finally:
        _INPUTS.reset(token)


def note_input(path: str | Path, what: str) -> None:
    """Record ``path`` as an input of the running command (a no-op outside
    :func:`guarding_inputs`)."""
    inputs = _INPUTS.get()
    if inputs is not None:
        with suppress(OSError, RuntimeError):
            inputs.setdefault(Path(path).resolve(), what)


def _refuse_inputs(destinations: list[Path]) -> None:
    """Raise, before anything is replaced, if a destination is a file the command read."""
    inputs = _INPUTS.get()
    if not inputs:
        return
    for dst in destinations:
        what = inputs.get(dst.resolve())
        if what is not None:
            raise CadcogError(f"{dst}: is the command's input ({what}); write elsewhere")


def _new_file_mode() -> int:
    """The mode a new file gets under the current umask (0666 & ~umask)."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def _cannot_write(target: Path, exc: OSError) -> CadcogError:
    return CadcogError(f"{target}: cannot write here ({exc.strerror or exc})")


def _make_dirs(folder: Path) -> list[Path]:
    """Create ``folder`` and its missing parents; the ones created, outermost first."""
    missing = []
    p = folder
    while not p.exists():
        missing.append(p)
        if p.parent == p:
            break
        p = p.parent
    folder.mkdir(parents=True, exist_ok=True)
    return missing[::-1]


def _remove_empty(created: list[Path]) -> None:
    """Remove the folders a failed command created (innermost first), if still empty."""
    for d in reversed(created):
        try:
            d.rmdir()
        except OSError:
            return


@contextmanager
def staged_output_dir(out_dir: str | Path) -> Iterator[Path]:
    """Yield a scratch directory whose files are moved into ``out_dir`` on success.

    Existing files in ``out_dir`` that the command does not produce are left alone; produced
    files replace their namesakes atomically, one by one.

    Raises
    ------
    CadcogError
        If ``out_dir`` is a file, or its parent cannot be written (naming ``out_dir``).
    """
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise CadcogError(f"{out}: exists and is not a directory")
    parent = out.resolve().parent
    created: list[Path] = []
    try:
        created = _make_dirs(parent)
        stage = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".partial", dir=parent))
    except OSError as exc:
        _remove_empty(created)
        raise _cannot_write(out, exc) from None
    done = False
    try:
        yield stage
        produced = [p for p in sorted(stage.rglob("*")) if p.is_file()]
        _refuse_inputs([out / p.relative_to(stage) for p in produced])
        try:
            created += _make_dirs(out.resolve())
            for src in produced:
                dst = out / src.relative_to(stage)
                dst.parent.mkdir(parents=True, exist_ok=True)
                os.replace(src, dst)
        except OSError as exc:
            raise _cannot_write(out, exc) from None
        done = True
    finally:
        shutil.rmtree(stage, ignore_errors=True)
        if not done:
            _remove_empty(created)


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
    """Yield a temporary path beside ``path`` (same suffix) that replaces ``path`` on success.

    Raises
    ------
    CadcogError
        If ``path`` is a directory or its folder cannot be written (naming ``path``).
    """
    target = Path(path)
    if target.is_dir():
        raise CadcogError(f"{target}: is a directory, expected a file name")
    created: list[Path] = []
    try:
        created = _make_dirs(target.parent)
        fd, tmp = tempfile.mkstemp(
            prefix=f".{target.stem}.", suffix=target.suffix, dir=target.parent
        )
    except OSError as exc:
        _remove_empty(created)
        raise _cannot_write(target, exc) from None
    os.close(fd)
    done = False
    try:
        yield Path(tmp)
        _refuse_inputs([target])
        try:
            os.chmod(tmp, _new_file_mode())
            os.replace(tmp, target)
        except OSError as exc:
            raise _cannot_write(target, exc) from None
        done = True
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
        if not done:
            _remove_empty(created)


def refuse_overwriting_inputs(output: str | Path, inputs: dict[str, str | Path | None]) -> None:
    """Refuse an output that is one of the command's own inputs.

    Parameters
    ----------
    output : path-like
    inputs : mapping of option or argument name → path (or None when not given)

    Raises
    ------
    CadcogError
        Naming both, if ``output`` resolves to the same file as an input.
    """
    out = Path(output).resolve()
    for name, value in inputs.items():
        if value is not None and Path(value).resolve() == out:
            raise CadcogError(f"{output}: is the command's input ({name}); write elsewhere")
