"""The Bayesian update of the mass budget, against independent computations and coverage."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from cadcog.mass.properties import box_properties, combine
from cadcog.spacecraft.update import Item, Measurement, UnmodelledPrior, recompensate, update_budget

ME_MASS = 0.176
ME_COG = np.array([0.0, 0.0, 190.0])
ME_COV = np.eye(3) * 1.67**2


def _items():
    """A 3U-like spacecraft: six items with 2-10 % mass uncertainty, and a fixed harness."""
    box = box_properties
    return [
        Item("structure", box([100, 100, 340], [0, 0, 0], mass_kg=0.78), 0.02),
        Item("battery", box([70, 38, 66], [0, -12, -102], mass_kg=0.456), 0.03),
        Item("eps", box([82, 82, 2], [0, 0, -140], mass_kg=0.020), 0.05),
        Item("obc", box([82, 82, 2], [0, 0, -60], mass_kg=0.020), 0.05),
        Item("adcs", box([70, 70, 30], [5, 0, 0], mass_kg=0.413), 0.10),
        Item("camera", box([60, 60, 110], [0, 5, 95], mass_kg=0.874), 0.10),
    ]


FIXED = box_properties([10, 10, 10], [30, 30, 0], mass_kg=0.05)


def _truth(deltas, extra=None):
    parts = [
        box_properties([1, 1, 1], i.properties.cog_mm, mass_kg=i.properties.mass_kg * (1 + d))
        for i, d in zip(_items(), deltas, strict=True)
    ]
    parts.append(FIXED)
    if extra is not None:
        parts.append(extra)
    return combine(parts)


def _measure(truth, cov, mass_sigma, rng=None):
    """The assembly CoG and the weighing of ``truth``, with noise drawn by ``rng``."""
    mt = truth.mass_kg + ME_MASS
    g = (truth.mass_kg * truth.cog_mm + ME_MASS * ME_COG) / mt
    mass = truth.mass_kg
    if rng is not None:
        g = g + rng.multivariate_normal(np.zeros(3), cov)
        mass = mass + rng.normal(0.0, mass_sigma)
    return Measurement(g, cov, mass, mass_sigma, ME_MASS, ME_COG, np.zeros((3, 3)))


def test_no_discrepancy_leaves_the_cad_unchanged():
    meas = _measure(_truth(np.zeros(6)), np.eye(3) * 0.09, 0.002)
    r = update_budget(_items(), FIXED, meas)
    assert max(abs(c.delta_rel) for c in r.items) < 1e-12
    np.testing.assert_allclose(r.posterior.cog_mm, r.cad.cog_mm, atol=1e-10)
    assert r.posterior.mass_kg == pytest.approx(r.cad.mass_kg, rel=1e-14)
    assert r.chi2 < 1e-16 and r.consistent
    assert r.posterior_mass_sigma_kg < r.cad_mass_sigma_kg  # the weighing pins the mass down


def test_map_matches_an_independent_linear_gaussian_update():
    """For a small gap the model is nearly linear: the MAP equals a Kalman update computed
    here from a finite-difference Jacobian of the forward model written independently."""
    items = _items()
    truth = _truth([0.0, 0.005, 0.0, 0.0, -0.003, 0.002])
    cov = np.eye(3) * 0.04
    meas = _measure(truth, cov, 0.001)
    r = update_budget(items, FIXED, meas)

    def forward(d):
        t = _truth(d)
        return np.concatenate(
            [[t.mass_kg], (t.mass_kg * t.cog_mm + ME_MASS * ME_COG) / (t.mass_kg + ME_MASS)]
        )

    p0 = np.diag([i.sigma_rel**2 for i in items])
    jac = np.column_stack(
        [(forward(np.eye(6)[k] * 1e-6) - forward(-np.eye(6)[k] * 1e-6)) / 2e-6 for k in range(6)]
    )
    rr = np.zeros((4, 4))
    rr[0, 0] = 0.001**2
    rr[1:, 1:] = cov
    y = np.concatenate([[meas.mass_kg], meas.assembly_cog_mm])
    gain = p0 @ jac.T @ np.linalg.inv(jac @ p0 @ jac.T + rr)
    delta = gain @ (y - forward(np.zeros(6)))
    np.testing.assert_allclose([c.delta_rel for c in r.items], delta, atol=3e-6)


def test_posterior_intervals_cover_truths_drawn_from_the_prior():
    """Bayesian calibration: truths from the prior, noisy measurements; 95 % posterior
    intervals of each item and the 95 % CoG ellipsoid must cover about 95 % of the time."""
    rng = np.random.default_rng(11)
    items = _items()
    sig = np.array([i.sigma_rel for i in items])
    cov = np.eye(3) * 0.09
    n, hits_items, hits_cog = 400, np.zeros(6), 0
    k95 = stats.chi2.ppf(0.95, df=3)
    for _ in range(n):
        d = rng.normal(0.0, sig)
        truth = _truth(d)
        r = update_budget(items, FIXED, _measure(truth, cov, 0.002, rng))
        z = np.array(
            [(c.delta_rel - t) / c.delta_sigma_rel for c, t in zip(r.items, d, strict=True)]
        )
        hits_items += np.abs(z) <= 1.96
        e = r.posterior.cog_mm - truth.cog_mm
        hits_cog += float(e @ np.linalg.solve(r.posterior_cog_cov_mm2, e)) <= k95
    # 400 trials: the binomial 99.9 % band around 95 % is about ±3.6 %.
    assert np.all(hits_items / n > 0.91) and np.all(hits_items / n < 0.99), hits_items / n
    assert 0.91 < hits_cog / n < 0.99, hits_cog / n


def test_a_hidden_harness_is_found_within_its_stated_uncertainty():
    items = _items()
    harness = box_properties([1, 1, 1], [35.0, -30.0, -120.0], mass_kg=0.060)
    truth = _truth(np.zeros(6), harness)
    prior = UnmodelledPrior(np.array([20.0, -45, -170]), np.array([45.0, -20, -90]), 0.03, 0.05)
    meas = _measure(truth, np.eye(3) * 0.01, 0.0005)
    r = update_budget(items, FIXED, meas, unmodelled=prior)
    assert abs(r.unmodelled_mass_kg - 0.060) < 3 * r.unmodelled_mass_sigma_kg
    e = r.posterior.cog_mm - truth.cog_mm
    assert float(e @ np.linalg.solve(r.posterior_cog_cov_mm2, e)) < stats.chi2.ppf(0.999, df=3)
    assert not update_budget(items, FIXED, meas).consistent  # without the harness: too far


def test_the_item_that_changed_is_ranked_first():
    deltas = [0.0, 0.0, 0.0, 0.0, 0.25, 0.0]  # the ADCS unit weighs 25 % more than in CAD
    r = update_budget(_items(), FIXED, _measure(_truth(deltas), np.eye(3) * 0.01, 0.001))
    assert r.ranked_items()[0].key == "adcs"


def test_recompensation_uses_the_weighed_mass():
    meas = Measurement(np.array([0, 0, 10.0]), np.eye(3), 9.0, 0.01, 1.0, np.array([0, 0, 100.0]))
    cog, cov = recompensate(meas)
    np.testing.assert_allclose(cog, [0, 0, 0])  # (10·10 − 1·100) / 9
    np.testing.assert_allclose(cov, np.eye(3) * (10 / 9) ** 2)


def test_nothing_to_update_is_refused():
    with pytest.raises(ValueError, match="nothing to update"):
        update_budget([], FIXED, _measure(FIXED, np.eye(3), 0.01))


def test_unmodelled_mass_and_position_intervals_cover_drawn_truths():
    """Harnesses drawn from the prior (mass, uniform position in the region), item masses
    from theirs, noisy measurements: the stated 95 % intervals of the unmodelled mass and
    the 95 % ellipsoid of its position hold the truth about 95 % of the time."""
    rng = np.random.default_rng(1)
    lo, hi = np.array([20.0, -45, -170]), np.array([45.0, -20, -90])
    prior = UnmodelledPrior(lo, hi, 0.06, 0.03)
    sigmas = [i.sigma_rel for i in _items()]
    k95 = stats.chi2.ppf(0.95, df=3)
    n, hits_mass, hits_position = 300, 0, 0
    for _ in range(n):
        mass = max(rng.normal(0.06, 0.03), 0.005)
        where = rng.uniform(lo, hi)
        truth = _truth(rng.normal(0.0, sigmas), box_properties([1, 1, 1], where, mass_kg=mass))
        meas = _measure(truth, np.eye(3) * 0.01, 0.0005, rng)
        r = update_budget(_items(), FIXED, meas, unmodelled=prior)
        hits_mass += abs(r.unmodelled_mass_kg - mass) <= 1.96 * r.unmodelled_mass_sigma_kg
        e = r.unmodelled_cog_mm - where
        hits_position += float(e @ np.linalg.solve(r.unmodelled_cog_cov_mm2, e)) <= k95
    # 300 trials: the binomial 99.9 % band around 95 % is about ±4.1 %.
    assert 0.905 < hits_mass / n < 0.99, hits_mass / n
    assert 0.905 < hits_position / n < 0.99, hits_position / n
