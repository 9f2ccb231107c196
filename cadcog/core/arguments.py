"""Checks of the kind of an API argument, before any work: a wrong kind is a
:class:`~cadcog.core.errors.CadcogError` naming the function and the argument as every API
refusal does (``plan(goal='foo'): ...``), never a bare
ValueError or AttributeError from deep inside (issue 21: ``overlaps='maybe'``, ``axes=[...]``).
"""

from __future__ import annotations

from collections.abc import Sequence

from cadcog.core.errors import CadcogError, quote


def check_choice(function: str, name: str, value: object, choices: Sequence[str]) -> None:
    """Refuse ``value`` unless it is one of ``choices`` (strings).

    Examples
    --------
    >>> check_choice("mass_properties", "overlaps", "allow", ("check", "allow", "resolve"))
    >>> check_choice("f", "overlaps", "maybe", ("check", "allow"))
    Traceback (most recent call last):
    ...
    cadcog.core.errors.CadcogError: f(overlaps='maybe'): expected one of check, allow
    """
    if not isinstance(value, str) or value not in choices:
        raise CadcogError(
            f"{function}({name}={quote(value)}): expected one of {', '.join(choices)}"
        )


def check_text(function: str, name: str, value: object, example: str) -> None:
    """Refuse ``value`` unless it is a str (``axes='+y,-x,+z'``, not a list).

    Examples
    --------
    >>> check_text("f", "axes", ["+x"], "'+y,-x,+z'")
    Traceback (most recent call last):
    ...
    cadcog.core.errors.CadcogError: f(axes=['+x']): expected a str such as '+y,-x,+z', got list
    """
    if not isinstance(value, str):
        raise CadcogError(
            f"{function}({name}={quote(value)}): expected a str such as {example}, got "
            f"{type(value).__name__}"
        )
