"""Exceptions raised by cadcog.

Every error a user can cause derives from :class:`CadcogError`; the CLI turns it into a message on
stderr and exit status 2. Errors about an input file name the file and the offending key.
"""

from __future__ import annotations

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


class DegenerateGeometryError(CadcogError, ArithmeticError):
    """A geometric computation has no meaningful answer (e.g. parallel lines)."""


class IllConditionedError(DegenerateGeometryError):
    """Plumb lines too close to parallel for their intersection to mean anything."""


class ReadingsError(CadcogError, ValueError):
    """A readings file is malformed; the message names the file and line."""
