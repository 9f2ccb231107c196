"""Inertia objectives of the least ballast (cadcog.spacecraft.balance_inertia): the gradient
against finite differences, the reduced-mass closed forms for a product limit and a pair's
principal rotation, the confidence against spacecraft drawn item by item (the nonlinear tensor,
not the linearisation), the CoG's bound kept, and the refusals."""

from __future__ import annotations

import numpy as np
import pytest

from cadcog.core.errors import CadcogError
from cadcog.mass.properties import box_properties
from cadcog.spacecraft.balance_inertia import (
    InertiaObjectives,
    InertiaPrior,
    least_ballast_with_inertia,
    tensor_and_gradient,
)
from cadcog.spacecraft.ballast_spec import BallastPoint, BallastSpec, UncertainMass
from cadcog.spacecraft.explanations import Model, cad_joint_prior
from cadcog.spacecraft.items import Item, linear_prior, parameter_prior_cov

WIDE = np.array([500.0, 500.0, 500.0])  # an envelope that never binds


def _exact(mass_kg, inertia):
    state = UncertainMass(mass_kg, 0.0, np.zeros(3), np.zeros((3, 3)), np.zeros(3), "CAD")
    prior = InertiaPrior(
        np.asarray(inertia, dtype=float), np.zeros((6, 6)), np.zeros((6, 4)), "CAD"
    )
    return state, prior


@pytest.mark.parametrize("seed", range(5))
def test_the_gradient_is_the_finite_difference(seed):
    rng = np.random.default_rng(seed)
    mass = rng.uniform(0.5, 5.0)
    cog = rng.normal(0, 30, 3)
    a = rng.normal(0, 100, (3, 3))
    inertia = a @ a.T + 1000 * np.eye(3)
    positions = rng.normal(0, 80, (3, 3))
    masses = rng.uniform(0, 0.3, 3)
    base, grad = tensor_and_gradient(mass, cog, inertia, positions, masses)
    x0 = np.concatenate([[mass], cog, [inertia[0, 0], inertia[1, 1], inertia[2, 2]],
                         [inertia[0, 1], inertia[0, 2], inertia[1, 2]]])  # fmt: skip

    def entries(x):
        xx, yy, zz, xy, xz, yz = x[4:]
        t = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        out, _ = tensor_and_gradient(x[0], x[1:4], t, positions, masses)
        return np.array([out[0, 0], out[1, 1], out[2, 2], out[0, 1], out[0, 2], out[1, 2]])

    steps = np.array([1e-4, 1e-3, 1e-3, 1e-3, *[1e-2] * 6])
    numeric = np.column_stack(
        [
            (entries(x0 + h * e) - entries(x0 - h * e)) / (2 * h)
            for h, e in zip(steps, np.eye(10), strict=True)
        ]
    )
    np.testing.assert_allclose(grad, numeric, rtol=1e-6, atol=1e-6)
    assert entries(x0) == pytest.approx(
        [base[0, 0], base[1, 1], base[2, 2], base[0, 1], base[0, 2], base[1, 2]]
    )


BIG_M, ARM = 2.0, 60.0


def _reduced_mass_case():
    """A 2 kg spacecraft, exact, with P_yz = +600 kg·mm² (the tensor's entry −600) and
    I_yy − I_zz = 1000, and one ballast location at (0, a, −a): about the common CoG
    P'_yz = P_yz − a² M m / (M + m), the gap unchanged (the ballast adds a² m_r to both)."""
    inertia = np.diag([5000.0, 4000.0, 3000.0])
    inertia[1, 2] = inertia[2, 1] = -600.0
    state, prior = _exact(BIG_M, inertia)
    return state, prior, BallastSpec((BallastPoint("b", np.array([0.0, ARM, -ARM])),))


def test_a_product_limit_meets_the_reduced_mass_closed_form():
    # Meeting 200 needs M m / (M + m) = 400 / a².
    big_m, a, limit = BIG_M, ARM, 200.0
    state, prior, spec = _reduced_mass_case()
    k = (600.0 - limit) / a**2
    want = k * big_m / (big_m - k)
    r = least_ballast_with_inertia(
        state, prior, spec, np.zeros(3), WIDE, 0.95, InertiaObjectives(max_product_kg_mm2=limit)
    )
    assert r.feasible and r.total_ballast_kg == pytest.approx(want, rel=1e-6)
    assert r.inertia["after"]["products_kg_mm2"]["Pyz"] == pytest.approx(limit, rel=1e-6)
    assert r.inertia["before"]["products_kg_mm2"]["Pyz"] == pytest.approx(600.0)
    assert r.bound_kg == 0.0 and not r.optimal  # the CoG alone needs none: nothing proven


def test_a_principal_rotation_limit_meets_its_closed_form():
    # The yz pair turns by ½ atan(2 |P'| / (I_yy − I_zz)), the gap staying 1000 kg·mm²:
    # θ = 5° needs |P'| = ½ tan(10°) · 1000.
    big_m, a, theta = BIG_M, ARM, 5.0
    state, prior, spec = _reduced_mass_case()
    target = 0.5 * np.tan(np.deg2rad(2 * theta)) * 1000.0
    k = (600.0 - target) / a**2
    r = least_ballast_with_inertia(
        state, prior, spec, np.zeros(3), WIDE, 0.95, InertiaObjectives(max_axis_angle_deg=theta)
    )
    assert r.total_ballast_kg == pytest.approx(k * big_m / (big_m - k), rel=1e-6)
    assert r.inertia["after"]["pair_rotation_deg"]["yz"] == pytest.approx(theta, rel=1e-6)
    assert r.inertia["before"]["pair_rotation_deg"]["yz"] > 25.0


def _spacecraft():
    """Four uncertain items (5-15 %, CoG σ 1-3 mm) of a 3 kg box-ish spacecraft with a
    product P_yz the limit below needs ballast for."""
    items = [
        Item("bus", box_properties([90, 90, 200], [0, 0, 0], mass_kg=1.5), 0.05, _s(1.0)),
        Item("cam", box_properties([40, 40, 60], [10, 25, 70], mass_kg=0.8), 0.10, _s(2.0)),
        Item("bat", box_properties([60, 30, 40], [-5, -20, -60], mass_kg=0.5), 0.05, _s(1.0)),
        Item("rw", box_properties([30, 30, 30], [20, 30, 40], mass_kg=0.2), 0.15, _s(3.0)),
    ]
    return items


def _s(sigma_mm):
    return np.full(3, sigma_mm)


def test_the_confidence_holds_for_spacecraft_drawn_item_by_item():
    items = _spacecraft()
    mean, cov = cad_joint_prior(items, None)
    state = UncertainMass.from_prior(linear_prior(items, None))
    prior = InertiaPrior.from_joint(mean, cov)
    pyz = -prior.inertia_kg_mm2[1, 2]
    limit = 0.5 * abs(pyz)
    spec = BallastSpec(
        (
            BallastPoint("a", np.array([0.0, -45.0, 100.0])),
            BallastPoint("b", np.array([0.0, 45.0, -100.0])),
            BallastPoint("c", np.array([0.0, -45.0, -100.0])),
        )
    )
    objectives = InertiaObjectives(max_product_kg_mm2=limit, confidence=0.9)
    r = least_ballast_with_inertia(state, prior, spec, np.zeros(3), WIDE, 0.95, objectives)
    assert r.feasible and r.total_ballast_kg > 0 and r.inertia["after"]["met"]
    # Draw the items (mass scale and CoG shift), the tensor by the items' own nonlinear sum,
    # then the ballast about the drawn spacecraft's own CoG.
    model = Model(items, None, None, False)
    rng = np.random.default_rng(11)
    theta = rng.multivariate_normal(np.zeros(model.size), parameter_prior_cov(items), 20_000)
    drawn = model.derived(theta, np.zeros(3))  # M, G, xx, xy, xz, yy, yz, zz
    positions = np.array([p.position_mm for p in spec.points])
    products = []
    for row in drawn:
        xx, xy, xz, yy, yz, zz = row[4:]
        t = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        after, _ = tensor_and_gradient(row[0], row[1:4], t, positions, r.masses_kg)
        products.append([-after[0, 1], -after[0, 2], -after[1, 2]])
    products = np.array(products)
    n = len(products)
    rate = float(np.mean(np.all(np.abs(products) <= limit, axis=1)))
    assert rate >= 0.9 - 3 * np.sqrt(0.9 * 0.1 / n), rate
    # The condition that binds (P_yz's upper side, its miss budget (1 − 0.9)/6) is missed
    # as often as the linearised σ says: the first order is right here, the union bound
    # the only margin.
    after = r.inertia["after"]
    assert after["products_kg_mm2"]["Pyz"] + objectives.quantile * after["products_sigma_kg_mm2"][
        "Pyz"
    ] == pytest.approx(limit, rel=1e-6)
    budget = 0.1 / 6
    miss = float(np.mean(products[:, 2] > limit))
    assert abs(miss - budget) < 4 * np.sqrt(budget * (1 - budget) / n), (miss, budget)


def test_the_cog_s_least_ballast_is_kept_when_it_meets_the_objectives():
    inertia = np.diag([5000.0, 4000.0, 3000.0])
    state = UncertainMass(2.0, 0.0, np.array([0.0, 0.0, 30.0]), np.zeros((3, 3)), np.zeros(3), "")
    prior = InertiaPrior(inertia, np.zeros((6, 6)), np.zeros((6, 4)), "CAD")
    spec = BallastSpec((BallastPoint("zm", np.array([0.0, 0.0, -100.0])),))
    limits = np.array([50.0, 50.0, 20.0])
    obj = InertiaObjectives(max_product_kg_mm2=10.0)
    r = least_ballast_with_inertia(state, prior, spec, np.zeros(3), limits, 0.95, obj)
    # (2 · 30 − 100 m) / (2 + m) = 20: m = 20/120 kg, on the axis: no product at all
    assert r.total_ballast_kg == pytest.approx(20 / 120, rel=1e-9) and r.optimal
    assert r.inertia["search"] == "the CoG's least ballast meets them"


def test_an_uncertainty_beyond_the_limit_and_pieces_are_said():
    items = _spacecraft()
    mean, cov = cad_joint_prior(items, None)
    state = UncertainMass.from_prior(linear_prior(items, None))
    prior = InertiaPrior.from_joint(mean, cov)
    spec = BallastSpec((BallastPoint("b", np.array([0.0, 45.0, -100.0])),))
    r = least_ballast_with_inertia(
        state, prior, spec, np.zeros(3), WIDE, 0.95, InertiaObjectives(max_product_kg_mm2=1.0)
    )
    assert not r.feasible and r.total_ballast_kg == 0.0
    assert any("own uncertainty" in n and "exceeds the limit 1 kg·mm²" in n for n in r.notes)
    pieces = BallastSpec(spec.points, sizes_kg=(0.01,))
    limit = 0.5 * abs(prior.inertia_kg_mm2[1, 2])
    r = least_ballast_with_inertia(
        state, prior, pieces, np.zeros(3), WIDE, 0.95, InertiaObjectives(max_product_kg_mm2=limit)
    )
    assert not r.feasible and any("checked, not searched" in n for n in r.notes)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({}, "give a product limit or an axis angle"),
        ({"max_product_kg_mm2": 0.0}, "--max-product-kg-mm2 0.0: expected a positive"),
        ({"max_axis_angle_deg": 45.0}, "--max-axis-angle-deg 45.0: expected an angle"),
        ({"max_axis_angle_deg": 1.0, "confidence": 1.0}, "--inertia-confidence 1.0"),
    ],
)
def test_bad_objectives_are_refused(kwargs, match):
    with pytest.raises(CadcogError, match=match):
        InertiaObjectives(**kwargs)
