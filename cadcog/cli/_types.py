"""Argument types the commands share (argparse ``type=``): one parser for each kind of value."""

from __future__ import annotations

import argparse
import math


def positive_triple(text: str) -> tuple[float, float, float]:
    """Three positive numbers ``X,Y,Z`` (an envelope's half-widths, mm).

    Examples
    --------
    >>> positive_triple("20,20,70")
    (20.0, 20.0, 70.0)
    """
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 3 or not all(math.isfinite(v) for v in values) or min(values) <= 0:
        raise argparse.ArgumentTypeError(f"expected three positive numbers X,Y,Z, got {text!r}")
    return values[0], values[1], values[2]
