"""One test of fit for every comparison: a χ² with its degrees of freedom, its tail
probability, the level it is judged at, and the verdict.

Every place cadcog says whether data agree with a model (the measured CoG against the CAD,
the measured tensor against the CAD's, the swings' frequencies against their fit, the update's
explanations) judges at :data:`TEST_LEVEL` through :class:`FitTest`, and computes the tail by
:func:`chi2_sf` (closed forms; no scipy.stats, whose import costs a second).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: The level of every test of fit that decides "consistent" against "differs": 5 %.
TEST_LEVEL = 0.05


#: Degrees of freedom up to which :func:`chi2_sf` sums its closed form (scipy beyond).
CHI2_CLOSED_FORM_MAX_DOF = 100


def chi2_sf(x: float, dof: int) -> float:
    """Tail probability of a χ² variable with ``dof`` degrees of freedom.

    Closed forms for whole degrees of freedom (no scipy, which takes a second to import): even
    ``e^(−x/2) Σ_{k<dof/2} (x/2)^k / k!``, odd ``erfc(√(x/2)) + √(2x/π) e^(−x/2) Σ x^(k−1) /
    (3·5⋯(2k−1))``; scipy beyond :data:`CHI2_CLOSED_FORM_MAX_DOF`.
    ``tests/core/test_fittest.py`` compares them with scipy.

    Examples
    --------
    >>> round(chi2_sf(5.991464547107979, 2), 12), round(chi2_sf(3.841458820694124, 1), 12)
    (0.05, 0.05)
    >>> round(chi2_sf(7.814727903251178, 3), 12), round(chi2_sf(9.487729036781154, 4), 12)
    (0.05, 0.05)
    """
    x = max(float(x), 0.0)
    if dof < 1:
        raise ValueError(f"χ² needs at least one degree of freedom, got {dof}")
    if dof > CHI2_CLOSED_FORM_MAX_DOF:
        from scipy.special import chdtrc  # what scipy.stats.chi2.sf calls, without its import

        return float(chdtrc(dof, x))
    half = x / 2.0
    if dof % 2 == 0:
        term, total = 1.0, 1.0
        for k in range(1, dof // 2):
            term *= half / k
            total += term
        return min(math.exp(-half) * total, 1.0)
    total = math.erfc(math.sqrt(half))
    term = math.sqrt(2.0 * x / math.pi) * math.exp(-half)
    for k in range(1, (dof + 1) // 2):
        total += term
        term *= x / (2 * k + 1)
    return min(total, 1.0)


@dataclass(frozen=True)
class FitTest:
    """A χ² test of fit: ``chi2`` with ``dof`` degrees of freedom, judged at ``level``.

    Examples
    --------
    >>> t = FitTest(7.814727903251178, 3)
    >>> round(t.p, 12), t.passes, FitTest(9.0, 3).passes, FitTest(0.0, 0).p
    (0.05, True, False, 1.0)
    """

    chi2: float
    dof: int
    level: float = TEST_LEVEL

    @property
    def p(self) -> float:
        """P(χ² ≥ observed) under the model (1.0 with no degree of freedom: nothing tested)."""
        return chi2_sf(self.chi2, self.dof) if self.dof > 0 else 1.0

    @property
    def passes(self) -> bool:
        """The data agree with the model at ``level`` (``p ≥ level``)."""
        return self.p >= self.level
