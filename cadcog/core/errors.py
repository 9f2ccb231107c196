"""Exceptions raised by cadcog.

Every error a user can cause derives from :class:`CadcogError`; the CLI turns it into a message on
stderr and exit status 2. Errors about an input file name the file and the offending key.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


class CadcogError(Exception):
    """Base class of all user-facing cadcog errors."""


class ParameterFileError(CadcogError, ValueError):
    """A parameter file is malformed or describes an impossible object.

    Parameters
    ----------
    path : path-like
        The file being read.
    key : str
        Dotted path of the offending key, e.g. ``suspension_points[2].position_mm``; empty for
        errors about the whole file (such as TOML syntax).
    message : str
        What was expected and what was found.
    """

    def __init__(self, path: str | Path, key: str, message: str) -> None:
        self.path = Path(path)
        self.key = key
        self.message = message
        where = f"{self.path}: key '{key}'" if key else f"{self.path}"
        super().__init__(f"{where}: {message}")


class UnsupportedSensorError(CadcogError):
    """A command that simulates or predicts readings was given a sensor it does not model."""


class DegenerateGeometryError(CadcogError, ArithmeticError):
    """A geometric computation has no meaningful answer (e.g. parallel lines)."""


class IllConditionedError(DegenerateGeometryError):
    """Plumb lines too close to parallel for their intersection to mean anything."""


class ReadingsError(CadcogError, ValueError):
    """A readings file is malformed; the message names the file and line."""


@contextmanager
def named_by(source: object | None, *, values: bool = True) -> Iterator[None]:
    """Refusals of a computation on ``source``'s data, each prefixed ``source: ``: a
    :class:`DegenerateGeometryError` as itself (the data do not determine the answer), and
    with ``values`` a ValueError (options and data the computation cannot combine) as a
    :class:`CadcogError` (without, it passes as it is: its message names its file already).
    An error whose message begins with ``source`` (a :class:`ReadingsError` naming its file and
    line) passes as it is, not named twice. With ``source`` None every error passes as it is.

    Examples
    --------
    >>> with named_by("r.csv"):
    ...     raise DegenerateGeometryError("the lines are parallel")
    Traceback (most recent call last):
    ...
    cadcog.core.errors.DegenerateGeometryError: r.csv: the lines are parallel
    """
    try:
        yield
    except DegenerateGeometryError as exc:
        if source is None or str(exc).startswith(str(source)):
            raise  # (an error that names ``source`` already is not named twice)
        raise type(exc)(f"{source}: {exc}") from None
    except ValueError as exc:
        if not values or source is None or str(exc).startswith(str(source)):
            raise
        raise CadcogError(f"{source}: {exc}") from None


#: The most characters of a value an error message quotes (longer ones are cut in the middle).
QUOTE_MAX_CHARS = 80

#: The most characters of one error line (the rest is cut, saying how much).
MESSAGE_MAX_CHARS = 600


def quote(value: object, limit: int = QUOTE_MAX_CHARS) -> str:
    """``repr(value)``, cut in the middle when longer than ``limit`` characters.

    Examples
    --------
    >>> quote("x_mm")
    "'x_mm'"
    >>> quote("a" * 1000, 20)
    "'aaaaaaa…(1002 characters)…aaaaaaa'"
    """
    text = repr(value)
    if len(text) <= limit:
        return text
    keep = max(1, (limit - 4) // 2)
    return f"{text[:keep]}…({len(text)} characters)…{text[-keep:]}"


def capped(message: str) -> str:
    """An error message with every long quoted value (``'…'`` or ``"…"``) and the whole line cut
    to a readable length: a 10 000-character value is not echoed whole.

    Examples
    --------
    >>> len(capped("key 'a': got '" + "x" * 10_000 + "'"))
    109
    >>> "(10002 characters)" in capped("got '" + "x" * 10_000 + "'")
    True
    >>> long = "overlaps: " + ", ".join(f"part {i} & part {i + 1}" for i in range(100))
    >>> capped(long + ": fix the model or --allow-overlap").endswith("--allow-overlap")
    True
    """
    import re

    def cut(m: re.Match[str]) -> str:
        text = m.group(0)
        keep = (QUOTE_MAX_CHARS - 4) // 2
        return f"{text[:keep]}…({len(text)} characters)…{text[-keep:]}"

    out = re.sub(rf"'[^'\n]{{{QUOTE_MAX_CHARS},}}'|\"[^\"\n]{{{QUOTE_MAX_CHARS},}}\"", cut, message)
    if len(out) > MESSAGE_MAX_CHARS:  # cut in the middle: the end says what to do
        tail = MESSAGE_MAX_CHARS // 3
        head = MESSAGE_MAX_CHARS - tail - 30
        out = f"{out[:head]}…({len(out)} characters in all)…{out[-tail:]}"
    return out
