"""The combination of mass properties in exact rational arithmetic, and the floating-point bound
a computed combination must meet against it.

An independent reference for :func:`cadcog.mass.properties.combine` and every node of the mass
budget: the definition (masses add, the CoG by mass, each part moved by the parallel-axis
theorem) evaluated with :class:`fractions.Fraction` on the parts' float inputs, so it carries no
rounding at all. A float computation of the same sums, in any order, differs from it by at most
a few units in the last place of the terms it adds; :func:`assert_close_to_exact` checks that
bound, which a wrong formula (a missing term, a sign, a part left out) exceeds by orders of
magnitude.
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction

import numpy as np

from cadcog.mass.properties import MassProperties

EPS = float(np.finfo(float).eps)

#: Rounding steps per term a float combination may take (differences, squares, products and
#: the running sums); a generous constant: the bound still sits ~10¹² below an error of formula.
STEPS = 16


def exact_combination(
    parts: Sequence[MassProperties], about_mm: Sequence[Fraction] | None = None
) -> tuple[Fraction, list[Fraction], list[list[Fraction]]]:
    """Mass, CoG and inertia (about the CoG, or about ``about_mm``) of ``parts``, exactly."""
    mass = sum((Fraction(p.mass_kg) for p in parts), Fraction(0))
    cog = [
        sum((Fraction(p.mass_kg) * Fraction(float(p.cog_mm[i])) for p in parts), Fraction(0)) / mass
        for i in range(3)
    ]
    point = cog if about_mm is None else list(about_mm)
    inertia = [[Fraction(0)] * 3 for _ in range(3)]
    for p in parts:
        m = Fraction(p.mass_kg)
        d = [point[i] - Fraction(float(p.cog_mm[i])) for i in range(3)]
        d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
        for i in range(3):
            for j in range(3):
                term = Fraction(float(p.inertia_kg_mm2[i, j]))
                term += m * ((d2 if i == j else 0) - d[i] * d[j])
                inertia[i][j] += term
    return mass, cog, inertia


def _scale(parts: Sequence[MassProperties], point_mm: np.ndarray) -> float:
    """The size of the terms a combination adds (kg·mm²): what its rounding is relative to."""
    total = 0.0
    for p in parts:
        reach = float(np.abs(p.cog_mm).max() + np.abs(point_mm).max())
        total += float(np.abs(p.inertia_kg_mm2).max()) + abs(p.mass_kg) * reach * reach
    return total


def assert_close_to_exact(
    got: MassProperties,
    parts: Sequence[MassProperties],
    *,
    inertia_about_mm: np.ndarray | None = None,
    about_value_kg_mm2: np.ndarray | None = None,
) -> None:
    """``got`` is the combination of ``parts`` within the float bound; optionally also
    ``about_value_kg_mm2`` is their inertia about ``inertia_about_mm``."""
    n = len(parts)
    mass, cog, inertia = exact_combination(parts)
    tol_mass = STEPS * n * EPS * sum(abs(p.mass_kg) for p in parts)
    assert abs(Fraction(got.mass_kg) - mass) <= Fraction(tol_mass), (got.mass_kg, float(mass))
    reach = sum(abs(p.mass_kg) * float(np.abs(p.cog_mm).max()) for p in parts)
    tol_cog = STEPS * n * EPS * reach / float(mass)
    for i in range(3):
        assert abs(Fraction(float(got.cog_mm[i])) - cog[i]) <= Fraction(tol_cog), (
            i,
            got.cog_mm,
            [float(c) for c in cog],
        )
    tol_inertia = STEPS * (n + 3) * EPS * _scale(parts, got.cog_mm)
    for i in range(3):
        for j in range(3):
            diff = abs(Fraction(float(got.inertia_kg_mm2[i, j])) - inertia[i][j])
            assert diff <= Fraction(tol_inertia), (i, j, got.inertia_kg_mm2, float(diff))
    if about_value_kg_mm2 is None:
        return
    assert inertia_about_mm is not None
    point = [Fraction(float(x)) for x in inertia_about_mm]
    _, _, about = exact_combination(parts, point)
    # The point is taken as the float it is (exactly), so only the sums' rounding remains.
    tol_about = STEPS * (n + 3) * EPS * _scale(parts, np.asarray(inertia_about_mm))
    for i in range(3):
        for j in range(3):
            diff = abs(Fraction(float(about_value_kg_mm2[i, j])) - about[i][j])
            assert diff <= Fraction(tol_about), (i, j, about_value_kg_mm2, float(diff))
