"""Warnings the commands print on stderr, worded once."""

from __future__ import annotations

import sys

from cadcog.method.errormodel import ErrorModel


def monte_carlo_caveat(model: ErrorModel) -> None:
    """Say what the Monte Carlo of ``model`` leaves out, if anything (``budget``, ``simulate``,
    ``plan``, ``validate``)."""
    caveat = model.monte_carlo_caveat()
    if caveat is not None:
        print(f"cadcog: warning: {caveat}", file=sys.stderr)
