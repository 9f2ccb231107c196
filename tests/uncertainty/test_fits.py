"""The norm fits recover known parameters; KS separates the right model from the wrong one."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from cadcog.uncertainty.fits import fit_norms, ks_statistic, maxwell_cdf, rayleigh_cdf


def test_rayleigh_samples():
    r = stats.rayleigh.rvs(scale=0.8, size=100_000, random_state=np.random.default_rng(1))
    f = fit_norms(r)
    assert f.rayleigh_sigma_mm == pytest.approx(0.8, rel=0.01)
    assert f.ks_rayleigh < 0.01 < f.ks_maxwell
    assert f.q95_mm == pytest.approx(0.8 * np.sqrt(-2 * np.log(0.05)), rel=0.02)
    assert f.rayleigh_sigma_median_mm == pytest.approx(0.8, rel=0.02)
    assert f.ks_rayleigh_median < 0.01


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


def test_median_fit_resists_a_heavy_tail():
    rng = np.random.default_rng(4)
    body = stats.rayleigh.rvs(scale=0.5, size=99_000, random_state=rng)
    tail = rng.uniform(20, 80, 1_000)  # 1 % of wild values, as from near-parallel pairs
    f = fit_norms(np.concatenate([body, tail]))
    assert f.rayleigh_sigma_mm > 2 * 0.5  # maximum likelihood is dragged away
    assert f.rayleigh_sigma_median_mm == pytest.approx(0.5, rel=0.03)
    assert f.ks_rayleigh_median < f.ks_rayleigh


def test_closed_form_cdfs_match_scipy():
    r = np.linspace(0, 10, 1001)
    np.testing.assert_allclose(rayleigh_cdf(r, 1.3), stats.rayleigh.cdf(r, scale=1.3), atol=1e-14)
    np.testing.assert_allclose(maxwell_cdf(r, 0.7), stats.maxwell.cdf(r, scale=0.7), atol=1e-14)


def test_median_constants_match_scipy():
    from cadcog.uncertainty.fits import MAXWELL_MEDIAN, RAYLEIGH_MEDIAN

    assert stats.rayleigh.median() == pytest.approx(RAYLEIGH_MEDIAN, rel=1e-14)
    assert stats.maxwell.median() == pytest.approx(MAXWELL_MEDIAN, rel=1e-14)


def test_histogram_fits_match_the_exact_ones_within_the_bin_width():
    from cadcog.uncertainty.fits import fit_histogram
    from cadcog.uncertainty.montecarlo import NormHistogram

    r = stats.maxwell.rvs(scale=0.6, size=200_000, random_state=np.random.default_rng(5))
    h = NormHistogram()
    h.add(r)
    exact, streamed = fit_norms(r), fit_histogram(h, float(np.sum(r * r)))
    assert streamed.n == exact.n
    assert streamed.maxwell_a_mm == pytest.approx(exact.maxwell_a_mm, rel=1e-12)
    for key in ("q50_mm", "q95_mm", "maxwell_a_median_mm"):
        assert getattr(streamed, key) == pytest.approx(getattr(exact, key), rel=2 * h.REL_WIDTH)
    for key in ("ks_rayleigh", "ks_maxwell", "ks_maxwell_median"):
        assert getattr(streamed, key) == pytest.approx(getattr(exact, key), abs=1e-3)
