"""What every entry point of :mod:`cadcog.api` shares: one BLAS thread while it runs, and
the checks of its arguments (each names the function and the argument)."""

from __future__ import annotations

import functools
import numbers
import os
import threading
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np

from cadcog.core.errors import CadcogError

if TYPE_CHECKING:
    pass

_F = TypeVar("_F", bound=Callable[..., Any])


class _BlasLimit:
    """One BLAS thread while any entry point runs, however many run at once (threads) or
    inside each other: the limit is process-wide (threadpoolctl), so it is set when the first
    call enters and restored when the last one leaves, never by a call that ends while another
    still runs."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._depth = 0
        self._limiter: Any = None

    def __enter__(self) -> None:
        with self._lock:
            if self._depth == 0:
                from threadpoolctl import threadpool_limits

                self._limiter = threadpool_limits(limits=1, user_api="blas")
            self._depth += 1

    def __exit__(self, *exc: object) -> None:
        with self._lock:
            self._depth -= 1
            if self._depth == 0 and self._limiter is not None:
                self._limiter.restore_original_limits()
                self._limiter = None


_BLAS_LIMIT = _BlasLimit()


def _one_blas_thread(function: _F) -> _F:
    """Run ``function`` with the BLAS libraries' thread pools limited to one thread, as the
    console command runs (:data:`cadcog.cli.BLAS_THREAD_VARIABLES`): cadcog's matrices are
    small, and a default pool of many threads made ``update`` 9× slower from Python than from
    the command. The limit holds for the whole process while any entry point runs. A limit the
    user set in the environment wins, as it does for the command."""
    from cadcog.cli import BLAS_THREAD_VARIABLES

    @functools.wraps(function)
    def limited(*args: Any, **kwargs: Any) -> Any:
        if any(name in os.environ for name in BLAS_THREAD_VARIABLES):
            return function(*args, **kwargs)
        with _BLAS_LIMIT:
            return function(*args, **kwargs)

    return limited  # type: ignore[return-value]


def _refuse_none(function: _F) -> _F:
    """Refuse ``None`` for every argument of ``function`` whose signature does not allow it (a
    default other than None, no ``None`` in its annotation) with the one-line error, before
    the call: as the command refuses an empty option, not a TypeError deep inside, nor a
    ``seed=None`` taken as a fresh random seed where the signature promises ``int = 0``."""
    import inspect

    signature = inspect.signature(function)
    words = {"float": "a number", "int": "an integer", "bool": "True or False"}
    refused = {
        name: words.get(str(p.annotation), str(p.annotation))
        for name, p in signature.parameters.items()
        if p.default is not None and "None" not in str(p.annotation)
    }

    @functools.wraps(function)
    def checked(*args: Any, **kwargs: Any) -> Any:
        try:
            bound = signature.bind(*args, **kwargs)
        except TypeError:  # a missing or unknown argument: Python's own message says it
            return function(*args, **kwargs)
        for name, value in bound.arguments.items():
            if value is None and name in refused:
                raise _fail(function.__name__, name, value, f"expected {refused[name]}, got None")
        return function(*args, **kwargs)

    return checked  # type: ignore[return-value]


def _public(function: _F) -> _F:
    """A public entry point: ``None`` refused where the signature does not take it
    (:func:`_refuse_none`), run with one BLAS thread (:func:`_one_blas_thread`)."""
    return _one_blas_thread(_refuse_none(function))


def _fail(function: str, name: str, value: object, expected: str) -> CadcogError:
    """The one-line error about argument ``name`` of ``function``."""
    shown = repr(value)
    if len(shown) > 60:
        shown = shown[:57] + "..."
    return CadcogError(f"{function}({name}={shown}): {expected}")


#: The keyword arguments that take several numbers (a list or tuple); every other number is one.
VECTOR_ARGUMENTS = frozenset({"unmodelled_region_mm", "cog_limits_mm", "windows_mm"})


def _numbers(function: str, **values: object) -> None:
    """The checks the command line applies to its numeric options (types, then the bounds of
    :mod:`cadcog.core.bounds`, by the same names), for keyword arguments; a list only for the
    names of :data:`VECTOR_ARGUMENTS`."""
    from cadcog.core import bounds

    for name, value in values.items():
        if value is None:
            continue
        if isinstance(value, (list, tuple)):
            if name not in VECTOR_ARGUMENTS:
                raise _fail(function, name, value, "expected one number")
            items = list(value)
        else:
            items = [value]
        bound = bounds.bound_for(name)
        for v in items:
            if isinstance(v, bool) or not isinstance(v, numbers.Real):  # numpy's count too
                raise _fail(function, name, value, f"expected a number, got {type(v).__name__}")
            if bound is not None and bound.integer and not isinstance(v, numbers.Integral):
                raise _fail(function, name, value, "expected an integer")
            problem = bounds.check(name, float(v))
            if problem is not None:
                raise _fail(function, name, value, problem)


def _flags(function: str, **values: object) -> None:
    """Yes/no arguments: a bool (numpy's too), never None, a string or a number (``"no"`` is
    true to Python)."""
    for name, value in values.items():
        if not isinstance(value, (bool, np.bool_)):
            got = type(value).__name__
            raise _fail(function, name, value, f"expected True or False, got {got}")


def _given(function: str, **values: object) -> None:
    """Arguments that have no default meaning for None (a mass, a σ): None is refused as the
    command refuses an empty option, not left to fail as a TypeError deep inside."""
    for name, value in values.items():
        if value is None:
            raise _fail(function, name, value, "expected a number, got None")


def _weighing(function: str, weighed_mass_kg: object, mass_sigma_kg: object) -> None:
    """A weighing's two arguments, as the commands check them: numbers within their bounds
    (both more than zero), and a σ other than the default only with a weighed mass (the
    command refuses ``--mass-sigma-kg`` alone; it would be ignored)."""
    from cadcog.core.tolerances import DEFAULT_WEIGHING_SIGMA_KG

    _given(function, mass_sigma_kg=mass_sigma_kg)
    _numbers(function, weighed_mass_kg=weighed_mass_kg, mass_sigma_kg=mass_sigma_kg)
    if weighed_mass_kg is None and mass_sigma_kg != DEFAULT_WEIGHING_SIGMA_KG:
        raise _fail(function, "mass_sigma_kg", mass_sigma_kg, "goes with weighed_mass_kg (its 1 σ)")


def _point_ids(function: str, points: Sequence[str] | None) -> None:
    """``points``: None, or a sequence of point ids (a string alone is refused: its letters
    are not ids)."""
    if points is not None and (
        isinstance(points, str) or not all(isinstance(p, str) for p in points)
    ):
        raise _fail(function, "points", points, "expected a sequence of point ids (str)")


def _path(function: str, name: str, value: object) -> Path:
    """A file argument: a str or path-like, else a clear error (with the keyword it may be)."""
    if isinstance(value, (str, os.PathLike)):
        return Path(value)
    kind = type(value).__name__
    hint = {"Setup": " (a set-up goes in setup=)", "Rig": " (a rig goes in rig=)"}.get(kind, "")
    raise _fail(function, name, value, f"expected a file path (str or Path), got {kind}{hint}")


def _as_user_error(function: str, source: object, exc: ValueError) -> CadcogError:
    """A ValueError about the data (not the arguments), as the command reports it."""
    return CadcogError(f"{source}: {exc}" if source is not None else f"{function}: {exc}")
