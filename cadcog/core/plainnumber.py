"""A number as a data file writes it: decimal notation (or ``nan``/``inf``, which the callers
refuse as not finite, with that reason), nothing else Python's ``float`` also takes (digit
separators: ``4_5`` is 45 to Python)."""

from __future__ import annotations

import re

_PLAIN = re.compile(
    r"[+-]?(?:(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?|nan|inf|infinity)", re.IGNORECASE
)


def parse_float(text: str) -> float:
    """``text`` as a float when it is a decimal number (or a spelling of nan or infinity), else
    ValueError.

    Examples
    --------
    >>> parse_float("-1.5e3"), parse_float(".5"), parse_float("45"), parse_float("NaN") != 0
    (-1500.0, 0.5, 45.0, True)
    >>> parse_float("4_5")
    Traceback (most recent call last):
    ...
    ValueError: not a decimal number: '4_5'
    """
    if not _PLAIN.fullmatch(text):
        raise ValueError(f"not a decimal number: {text!r}")
    return float(text)
