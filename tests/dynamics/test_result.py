"""Principal moments with their σ, and the nearly equal pairs a measurement cannot tell apart."""

import numpy as np
import pytest

from cadcog.dynamics.result import CLOSE_PAIR_SIGMAS, close_pairs, principal_with_sigma
from cadcog.dynamics.tensorfit import entries, tensor


def _rotated(moments, rng):
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return q @ np.diag(moments) @ q.T


def test_well_apart_moments_make_no_pair():
    rng = np.random.default_rng(1)
    p = entries(_rotated([3600.0, 24000.0, 30000.0], rng))
    cov = np.diag([100.0] * 3 + [50.0] * 3)
    assert close_pairs(principal_with_sigma(p, cov), cov) == []


def test_the_pair_is_flagged_within_the_threshold_and_not_beyond():
    """Two moments split by s under an isotropic noise of σ an entry: the split's noise is
    √(2σ² + 4σ²)·(…) from the closed form below, flagged below CLOSE_PAIR_SIGMAS of it."""
    sigma = 10.0
    cov = np.diag([sigma**2] * 3 + [sigma**2] * 3)
    # axes along x, y, z: v_iᵀ δJ v_i = δJ_ii, the coupling δJ_ij = the xy entry itself
    noise = np.sqrt(2 * sigma**2 + 4 * sigma**2)
    for factor, flagged in ((0.9, True), (1.1, False)):
        split = factor * CLOSE_PAIR_SIGMAS * noise
        p = entries(np.diag([1000.0, 5000.0, 5000.0 + split]))
        pairs = close_pairs(principal_with_sigma(p, cov), cov)
        assert bool(pairs) is flagged
        if flagged:
            (c,) = pairs
            assert c.lower == 1
            assert c.split_kg_mm2 == pytest.approx(split)
            assert c.split_sigma_kg_mm2 == pytest.approx(noise)
            assert c.mean_kg_mm2 == pytest.approx(5000.0 + split / 2)
            assert c.mean_sigma_kg_mm2 == pytest.approx(sigma / np.sqrt(2))


def test_sorted_equal_moments_are_pushed_apart_and_their_mean_is_not():
    """What the warning says, by simulation: two equal true moments measured with noise; the
    sorted larger reads high and the smaller low, by far more than the mean's error."""
    rng = np.random.default_rng(7)
    true = _rotated([3600.0, 24000.0, 24000.0], rng)
    sigma = 100.0  # kg·mm² per entry
    cov = np.eye(6) * sigma**2
    draws = rng.multivariate_normal(np.zeros(6), cov, size=4000, method="cholesky")
    lo, hi, mean, flagged = [], [], [], 0
    for d in draws:
        p = entries(true) + d
        pr = principal_with_sigma(p, cov)
        lo.append(pr.moments_kg_mm2[1])
        hi.append(pr.moments_kg_mm2[2])
        pairs = close_pairs(pr, cov)
        flagged += any(c.lower == 1 for c in pairs)
        mean.append(0.5 * (pr.moments_kg_mm2[1] + pr.moments_kg_mm2[2]))
    se = sigma / np.sqrt(len(draws))
    assert np.mean(hi) - 24000.0 > 0.5 * sigma  # pushed up
    assert np.mean(lo) - 24000.0 < -0.5 * sigma  # pushed down
    assert abs(np.mean(mean) - 24000.0) < 5 * se  # the mean is not
    assert flagged / len(draws) > 0.9
    assert np.allclose(tensor(entries(true)), true)
