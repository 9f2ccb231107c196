"""``cadcog.spacecraft.items``: the CAD's first-order prior against the nonlinear model it
linearises, and the default CoG uncertainty against the picture it stands for (an item's mass
error sitting anywhere in the item)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cadcog.mass.properties import box_properties
from cadcog.spacecraft.items import Item, items_from_bodies, linear_prior, spread_mm

sizes = st.tuples(*[st.floats(0.0, 500.0)] * 3)


@given(sizes, st.floats(0.01, 100.0))
def test_the_spread_of_a_box_is_its_length_over_root_12(size, mass):
    got = spread_mm(box_properties(size, [1.0, -2.0, 3.0], mass_kg=mass))
    # A zero edge comes out as the root of a rounding of the others' moments: √ε of the box.
    atol = 3e-8 * max(size) + 1e-12
    np.testing.assert_allclose(got, np.array(size) / np.sqrt(12.0), rtol=1e-9, atol=atol)


def _items(rng: np.random.Generator, n: int) -> list[Item]:
    out = []
    for k in range(n):
        props = box_properties(rng.uniform(10, 100, 3), rng.uniform(-150, 150, 3),
                               mass_kg=float(rng.uniform(0.05, 1.0)))  # fmt: skip
        cog = rng.uniform(0.0, 2.0, 3) if k % 2 else None
        sigma = float(rng.uniform(0.005, 0.03))
        out.append(Item.with_default_cog(f"i{k}", props, sigma) if cog is None
                   else Item(f"i{k}", props, sigma, cog, "rule"))  # fmt: skip
    return out


def _nonlinear(items, fixed, theta):
    """M(θ) and G(θ) as the module's docstring defines them, computed item by item."""
    n = len(items)
    m_total = fixed.mass_kg
    s_total = fixed.mass_kg * fixed.cog_mm
    for k, it in enumerate(items):
        m, c = it.properties.mass_kg, it.properties.cog_mm
        delta, shift = theta[k], theta[n + 3 * k : n + 3 * k + 3]
        m_total = m_total + m * (1 + delta)
        s_total = s_total + m * (1 + delta) * (c + shift)
    return m_total, s_total / m_total


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_jacobians_are_the_nonlinear_model_s_derivatives(seed):
    rng = np.random.default_rng(seed)
    items = _items(rng, 5)
    fixed = box_properties([300, 100, 100], [0, 0, 50], mass_kg=2.0)
    prior = linear_prior(items, fixed)
    m0, g0 = _nonlinear(items, fixed, np.zeros(4 * len(items)))
    assert prior.mass_kg == pytest.approx(m0, rel=1e-12)
    np.testing.assert_allclose(prior.cog_mm, g0, rtol=1e-12, atol=1e-9)
    h = 1e-6
    for j in range(4 * len(items)):
        e = np.zeros(4 * len(items))
        e[j] = h
        mp, gp = _nonlinear(items, fixed, e)
        mm, gm = _nonlinear(items, fixed, -e)
        assert prior.jac_mass[j] == pytest.approx((mp - mm) / (2 * h), rel=1e-6, abs=1e-9)
        np.testing.assert_allclose(prior.jac_cog[:, j], (gp - gm) / (2 * h), rtol=1e-5,
                                   atol=1e-7)  # fmt: skip


def test_the_prior_covers_the_nonlinear_model_s_spread():
    """20 000 draws of θ through the nonlinear model: the stated σ of the mass and the CoG
    covariance within sampling error (the σ of a variance estimate from n draws is √(2/n))."""
    rng = np.random.default_rng(5)
    items = _items(rng, 6)
    fixed = box_properties([300, 100, 100], [0, 0, 50], mass_kg=2.0)
    prior = linear_prior(items, fixed)
    theta = rng.normal(size=(20_000, 4 * len(items))) * np.sqrt(np.diag(prior.prior_cov))
    draws = [_nonlinear(items, fixed, t) for t in theta]
    masses = np.array([d[0] for d in draws])
    cogs = np.array([d[1] for d in draws])
    assert np.std(masses) == pytest.approx(prior.mass_sigma_kg, rel=0.03)
    sd = np.sqrt(np.diag(prior.cog_cov_mm2))
    as_correlations = (np.cov(cogs.T) - prior.cog_cov_mm2) / np.outer(sd, sd)
    assert np.max(np.abs(as_correlations)) < 0.06, as_correlations
    cross = np.mean((cogs - cogs.mean(0)) * (masses - masses.mean())[:, None], axis=0)
    assert np.max(np.abs((cross - prior.cog_mass_cov_mm_kg) / (prior.mass_sigma_kg * sd))) < 0.06


@settings(max_examples=5, deadline=None)
@given(sizes.filter(lambda s: min(s) > 1.0), st.floats(0.005, 0.03))
def test_the_default_cog_sigma_is_a_mass_error_anywhere_in_the_item(size, sigma_rel):
    """An item of mass m whose mass error δm ~ N(0, (σ m)²) sits at a point drawn uniformly in
    its box: its CoG moves by δm (x − c)/(m + δm); σ_rel × spread is that shift's σ."""
    rng = np.random.default_rng(3)
    props = box_properties(size, [0.0, 0.0, 0.0], mass_kg=1.0)
    n = 40_000
    dm = sigma_rel * rng.normal(size=n)
    x = (rng.uniform(-0.5, 0.5, (n, 3))) * np.array(size)
    shift = dm[:, None] * x / (1.0 + dm[:, None])
    expected = Item.with_default_cog("a", props, sigma_rel).cog_sigma_mm
    # To first order: the shift's σ grows by ~3σ² (0.3 % at 3 %); sampling error 0.35 %.
    np.testing.assert_allclose(np.std(shift, axis=0), expected, rtol=0.015)


def test_items_group_bodies_and_leave_certain_ones_fixed():
    class Body:
        def __init__(self, item, props, sigma_rel, cog=None):
            self.item, self.properties, self.sigma_rel = item, props, sigma_rel
            if cog is not None:
                self.cog_sigma_mm = cog

    a1 = box_properties([10, 10, 10], [0, 0, 0], mass_kg=1.0)
    a2 = box_properties([10, 10, 10], [20, 0, 0], mass_kg=1.0)
    f = box_properties([10, 10, 10], [0, 40, 0], mass_kg=3.0)
    z = box_properties([10, 10, 10], [0, 0, 40], mass_kg=0.5)
    items, fixed = items_from_bodies(
        [Body("a", a1, 0.05), Body("a", a2, 0.2), Body("f", f, None), Body("z", z, 0.0, [0, 0, 0])]
    )
    assert [i.key for i in items] == ["a"]
    assert items[0].properties.mass_kg == pytest.approx(2.0)
    assert items[0].sigma_rel == 0.05  # the first body's rule holds for the item
    assert fixed is not None and fixed.mass_kg == pytest.approx(3.5)  # f, and z (no uncertainty)
