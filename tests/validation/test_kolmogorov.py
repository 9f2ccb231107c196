"""The KS test without scipy.stats gives scipy's statistic and exact p-value to the bit, on every
branch of the exact distribution's algorithm, and its known closed forms."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from cadcog.validation.kolmogorov import kolmogorov_sf, ks_two_sided


def _grid(n: int) -> np.ndarray:
    """D from below the support to 1, dense where each branch of the algorithm applies."""
    return np.unique(
        np.concatenate(
            [
                np.linspace(0.0, 1.0, 41),
                np.linspace(0.5 / n, min(1.0, 3.0 / np.sqrt(n)), 41),
                [0.5 / n, 1.0 / n, 0.5, 1.0 - 1.0 / n, 1.0 - 1e-9],
            ]
        )
    )


@pytest.mark.parametrize("sizes", [range(1, 30), [33, 47, 64, 90, 121, 140], [141, 160, 400, 4000]])
def test_sf_is_scipy_kstwo_sf_to_the_bit(sizes):
    for n in sizes:
        d = _grid(n)
        ref = stats.kstwo.sf(d, n)
        ours = np.array([kolmogorov_sf(n, float(x)) for x in d])
        assert ours.tobytes() == ref.tobytes(), n


def test_sf_closed_forms():
    # one observation: D_1 = max(U, 1 − U) is uniform on [1/2, 1]
    assert kolmogorov_sf(1, 0.75) == pytest.approx(0.5, rel=1e-15)
    # Ruben-Gambino: P(D_n ≥ d) = 2 (1 − d)ⁿ for d ≥ 1 − 1/n
    assert kolmogorov_sf(5, 0.9) == pytest.approx(2 * 0.1**5, rel=1e-13)
    # and P(D_n < d) = n! (2d − 1/n)ⁿ for 1/(2n) ≤ d ≤ 1/n
    n, d = 4, 0.2
    assert 1 - kolmogorov_sf(n, d) == pytest.approx(24 * (2 * d - 1 / n) ** n, rel=1e-12)
    assert kolmogorov_sf(10, 0.0) == 1.0 and kolmogorov_sf(10, 1.0) == 0.0
    assert np.isnan(kolmogorov_sf(10, float("nan")))
    with pytest.raises(ValueError):
        kolmogorov_sf(0, 0.3)


def test_ks_two_sided_is_scipy_kstest_to_the_bit():
    rng = np.random.default_rng(3)
    sim = np.sort(rng.exponential(size=3000))

    def cdf(x):
        return np.searchsorted(sim, x, side="right") / sim.size

    for _ in range(60):
        n = int(rng.integers(1, 350))
        x = rng.exponential(size=n) * rng.uniform(0.5, 2.0)
        ref = stats.kstest(x, cdf)
        assert ks_two_sided(x, cdf) == (float(ref.statistic), float(ref.pvalue)), n
    ref = stats.kstest([0.1, 0.4, 0.7], stats.uniform.cdf)
    assert ks_two_sided([0.7, 0.1, 0.4], lambda x: x) == (ref.statistic, ref.pvalue)
    assert all(np.isnan(ks_two_sided([0.1, np.nan], lambda x: x)))
    with pytest.raises(ValueError, match="no observations"):
        ks_two_sided([], lambda x: x)
