"""The inertia context's wire: one λ for the pivots and the top clamp's hinge."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import cadcog
from cadcog.dynamics.context import context_for_rig

RIG = cadcog.load_rig()
CTX = context_for_rig(RIG)
NOMINAL = np.array([RIG.wire_exit_mm(p) for p in RIG.suspension_points])
COG = RIG.analytic_assembly.cog_mm
WEIGHT_N = 90.0


@pytest.mark.parametrize("wire_model", ["one-wire", "elastica"])
def test_the_hinge_moves_with_the_pivots_as_one_wire_does(wire_model):
    """The covariances :meth:`pivot_terms` states for the pivots and the hinge are those of
    their means moved by λ (finite differences of the positions it gives for a known λ):
    var(λ) ∂pᵢ/∂λ ∂pⱼ/∂λᵀ between pivots and var(λ) ∂pᵢ/∂λ ∂h/∂λ with the hinge, beside the
    play, which is each hang's own and the hinge's not at all."""
    ctx = replace(CTX, error_model=replace(CTX.error_model, wire_model=wire_model))
    lam, var = 0.4, 0.09
    step = 1e-4

    def means(scale_mm):
        p, _, _ = ctx.pivot_terms(NOMINAL, COG, WEIGHT_N, (scale_mm, 0.0))
        return p.ravel(), ctx.top_hinge_mm(WEIGHT_N, (scale_mm, 0.0))[0]

    (p_hi, h_hi), (p_lo, h_lo) = means(lam + step), means(lam - step)
    dp, dh = (p_hi - p_lo) / (2 * step), (h_hi - h_lo) / (2 * step)
    assert dh == pytest.approx(1.0)  # the hinge is λ itself
    _, cov, cross = ctx.pivot_terms(NOMINAL, COG, WEIGHT_N, (lam, var))
    _, own, _ = ctx.pivot_terms(NOMINAL, COG, WEIGHT_N, (lam, 0.0))
    np.testing.assert_allclose(cross.ravel(), var * dp * dh, atol=1e-9)
    np.testing.assert_allclose(cov - own, var * np.outer(dp, dp), atol=1e-9)
    assert ctx.top_hinge_mm(WEIGHT_N, (lam, var))[1] == pytest.approx(np.sqrt(var))


def test_a_wire_that_turns_out_at_the_exit_turns_down_at_the_clamp():
    """Along each bolt axis, the pivot's offset less its shape factor times the hinge does not
    depend on λ: with the shared term, its variance is the per-hang scatter alone (none for
    one wire), where independent terms would add both variances."""
    lam, var = 0.5, 0.25
    _, cov, cross = CTX.pivot_terms(NOMINAL, COG, WEIGHT_N, (lam, var))
    _, hinge_sigma = CTX.top_hinge_mm(WEIGHT_N, (lam, var))
    assert hinge_sigma**2 == pytest.approx(var)
    for i, p in enumerate(RIG.suspension_points):
        n = CTX.body.normal_at(NOMINAL[i])
        f = float(n @ cross[i]) / var  # the shape factor, from the cross-term
        g = np.zeros(len(cov) + 1)
        g[3 * i : 3 * i + 3], g[-1] = n, -f
        joint = np.block([[cov, cross.reshape(-1, 1)], [cross.reshape(1, -1), np.array([[var]])]])
        assert g @ joint @ g == pytest.approx(0.0, abs=1e-12), p.id
        assert 1.0 <= f < 1.2  # 1/cos(θ/2) for a bolt axis within 60° of the wire


def test_the_paper_model_draws_the_hinge_on_its_own():
    """The paper's wire model (an independent offset a hang): the hinge is one more such
    draw, U(0, 1 mm) (σ 1/√12 mm), and shares nothing with the pivots."""
    ctx = replace(CTX, error_model=replace(CTX.error_model, wire_model="paper"))
    hinge, sigma = ctx.top_hinge_mm(WEIGHT_N)
    assert (hinge, sigma) == pytest.approx((0.5, np.sqrt(1 / 12)))
    _, _, cross = ctx.pivot_terms(NOMINAL, COG, WEIGHT_N)
    assert not np.any(cross)
