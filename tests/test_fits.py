"""The norm fits recover known parameters; KS separates the right model from the wrong one."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from cadcog.fits import fit_norms, ks_statistic


def test_rayleigh_samples():
    r = stats.rayleigh.rvs(scale=0.8, size=100_000, random_state=np.random.default_rng(1))
    f = fit_norms(r)
    assert f.rayleigh_sigma_mm == pytest.approx(0.8, rel=0.01)
    assert f.ks_rayleigh < 0.01 < f.ks_maxwell
    assert f.q95_mm == pytest.approx(0.8 * np.sqrt(-2 * np.log(0.05)), rel=0.02)


def test_maxwell_samples_from_isotropic_3d_normal():
    e = np.random.default_rng(2).normal(0, 0.5, (100_000, 3))
    f = fit_norms(np.linalg.norm(e, axis=1))
    assert f.maxwell_a_mm == pytest.approx(0.5, rel=0.01)
    assert f.ks_maxwell < 0.01 < f.ks_rayleigh
    assert f.q50_mm == pytest.approx(stats.maxwell.median(scale=0.5), rel=0.02)


def test_ks_statistic_matches_scipy():
    x = np.sort(np.random.default_rng(3).normal(size=500))
    assert ks_statistic(x, stats.norm.cdf(x)) == pytest.approx(stats.kstest(x, "norm").statistic)


def test_fit_needs_samples():
    with pytest.raises(ValueError, match="at least two"):
        fit_norms([1.0])
