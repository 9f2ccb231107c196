"""Argument types the commands share (argparse ``type=``) and the checks of parsed values they
share: one parser, or one check, for each kind of value."""

from __future__ import annotations

import argparse
import math

from cadcog.core.errors import CadcogError


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


def weighing_sigma_kg(weighed_mass_kg: float | None, mass_sigma_kg: float | None) -> float:
    """The weighing's 1 σ a command takes: ``--mass-sigma-kg`` only with ``--weighed-mass-kg``
    (alone it would be ignored), else the default
    (:data:`~cadcog.core.tolerances.DEFAULT_WEIGHING_SIGMA_KG`).

    Examples
    --------
    >>> weighing_sigma_kg(2.6, None), weighing_sigma_kg(2.6, 0.005)
    (0.001, 0.005)
    >>> weighing_sigma_kg(None, 0.5)
    Traceback (most recent call last):
    ...
    cadcog.core.errors.CadcogError: --mass-sigma-kg goes with --weighed-mass-kg (the weighing's 1 σ)
    """
    from cadcog.core.tolerances import DEFAULT_WEIGHING_SIGMA_KG

    if mass_sigma_kg is not None and weighed_mass_kg is None:
        raise CadcogError("--mass-sigma-kg goes with --weighed-mass-kg (the weighing's 1 σ)")
    return DEFAULT_WEIGHING_SIGMA_KG if mass_sigma_kg is None else mass_sigma_kg
