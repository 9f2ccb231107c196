"""The inertia context's hang terms: one λ for the pivots and the top clamp's hinge, and the
CoG that the same hangs give, with what it shares with their pivots."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import cadcog
from cadcog.dynamics.context import context_for_rig
from cadcog.method.estimate import estimate_for_rig
from cadcog.method.plumblines import JointEstimate, WireScale
from cadcog.method.readings import Suspension
from cadcog.rig.geometry import ideal_reading

RIG = cadcog.load_rig()
CTX = context_for_rig(RIG)
NOMINAL = np.array([RIG.wire_exit_mm(p) for p in RIG.suspension_points])
COG = RIG.analytic_assembly.cog_mm
WEIGHT_N = 90.0


def _fit_with(lam: float, var: float) -> JointEstimate:
    """A CoG fit that found λ ± √var and gives no gain (the CoG exact)."""
    return JointEstimate(
        COG, np.zeros((3, 3)), (), (), (), wire=WireScale(lam, float(np.sqrt(var)), True, 0.5)
    )


def _split(cov: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """The pivots' block, their covariance with the hinge (k, 3), the hinge's variance."""
    return cov[4:, 4:], cov[3, 4:].reshape(-1, 3), float(cov[3, 3])


@pytest.mark.parametrize("wire_model", ["one-wire", "elastica"])
def test_the_hinge_moves_with_the_pivots_as_one_wire_does(wire_model):
    """The covariances :meth:`hang_terms` states for the pivots and the hinge are those of
    their means moved by λ (finite differences of the positions it gives for a known λ):
    var(λ) ∂pᵢ/∂λ ∂pⱼ/∂λᵀ between pivots and var(λ) ∂pᵢ/∂λ ∂h/∂λ with the hinge, beside the
    play, which is each hang's own and the hinge's not at all."""
    ctx = replace(CTX, error_model=replace(CTX.error_model, wire_model=wire_model))
    lam, var = 0.4, 0.09
    step = 1e-4

    def means(scale_mm):
        t = ctx.hang_terms(NOMINAL, COG, WEIGHT_N, _fit_with(scale_mm, 0.0))
        return t.pivots_mm.ravel(), t.top_mm

    (p_hi, h_hi), (p_lo, h_lo) = means(lam + step), means(lam - step)
    dp, dh = (p_hi - p_lo) / (2 * step), (h_hi - h_lo) / (2 * step)
    assert dh == pytest.approx(1.0)  # the hinge is λ itself
    cov, cross, hinge_var = _split(
        ctx.hang_terms(NOMINAL, COG, WEIGHT_N, _fit_with(lam, var)).cov_mm2
    )
    own, _, _ = _split(ctx.hang_terms(NOMINAL, COG, WEIGHT_N, _fit_with(lam, 0.0)).cov_mm2)
    np.testing.assert_allclose(cross.ravel(), var * dp * dh, atol=1e-9)
    np.testing.assert_allclose(cov - own, var * np.outer(dp, dp), atol=1e-9)
    assert hinge_var == pytest.approx(var)


def test_a_wire_that_turns_out_at_the_exit_turns_down_at_the_clamp():
    """Along each bolt axis, the pivot's offset less its shape factor times the hinge does not
    depend on λ: with the shared term, its variance is the per-hang scatter alone (none for
    one wire), where independent terms would add both variances."""
    lam, var = 0.5, 0.25
    joint = CTX.hang_terms(NOMINAL, COG, WEIGHT_N, _fit_with(lam, var)).cov_mm2[3:, 3:]
    assert joint[0, 0] == pytest.approx(var)
    for i, p in enumerate(RIG.suspension_points):
        n = CTX.body.normal_at(NOMINAL[i])
        f = float(n @ joint[0, 1 + 3 * i : 4 + 3 * i]) / var  # the shape factor, from the cross
        g = np.zeros(len(joint))
        g[0], g[1 + 3 * i : 4 + 3 * i] = -f, n
        assert g @ joint @ g == pytest.approx(0.0, abs=1e-12), p.id
        assert 1.0 <= f < 1.2  # 1/cos(θ/2) for a bolt axis within 60° of the wire


def test_the_paper_model_draws_the_hinge_on_its_own():
    """The paper's wire model (an independent offset a hang): the hinge is one more such
    draw, U(0, 1 mm) (σ 1/√12 mm), and shares nothing with the pivots."""
    ctx = replace(CTX, error_model=replace(CTX.error_model, wire_model="paper"))
    t = ctx.hang_terms(NOMINAL, COG, WEIGHT_N)
    assert (t.top_mm, np.sqrt(t.cov_mm2[3, 3])) == pytest.approx((0.5, np.sqrt(1 / 12)))
    assert not np.any(t.cov_mm2[3, 4:])


@pytest.mark.parametrize("ids", [("S1", "S2", "S3", "S4", "S5", "S6"), ("S1", "S3", "S5")])
def test_the_cog_shares_its_error_with_the_pivots_as_the_fit_says(ids):
    """Where the wire's λ and the play put the true pivots, the CoG the plumb lines give
    follows (the same hangs make both): drawn 600 times (λ from its prior, the play and each
    reading's error as the rig's model states them), the errors of the fitted CoG, of λ (the
    hinge) and of the stated pivots (less the true ones) correlate as :meth:`hang_terms`
    states them, entry by entry within 0.2 (4 standard errors of a correlation from 600
    draws), and not by a little (taken independent, as before, the paper rig's products of
    inertia were stated with 1.5-3 times their variance). On S1, S3 and S5 the CoG and λ
    correlate strongly (0.85 along x), which six hangs hide: there the CoG-λ terms are
    checked too."""
    rng = np.random.default_rng(31)
    points = [p for p in RIG.suspension_points if p.id in ids]
    nominal = np.array([RIG.wire_exit_mm(p) for p in points])
    prior = CTX.hang_terms(nominal, COG, WEIGHT_N)
    lam0, lam_sigma = prior.top_mm, np.sqrt(prior.cov_mm2[3, 3])
    sig_play = np.sqrt(CTX.error_model.play_var_mm2)
    acc = CTX.error_model.accuracy_deg  # each hang's reading error, as the model states it
    errors, stated = [], []
    for _ in range(600):
        lam = rng.normal(lam0, lam_sigma)
        true_p = nominal + (prior.pivots_mm - nominal) * lam / lam0  # λ fᵢ nᵢ out of each exit
        for i in range(len(true_p)):
            n = CTX.body.normal_at(nominal[i])
            e = rng.normal(0.0, sig_play, 3)
            true_p[i] += e - (e @ n) * n  # the play, in the face plane
        sus = []
        for i, p in enumerate(points):
            r = ideal_reading(true_p[i], COG)
            x, y = np.array([r.inc_x_deg, r.inc_y_deg]) + rng.uniform(-acc, acc, 2)
            sus.append(Suspension(p.id, tuple(nominal[i]), r.top_face_up, 10, x, y, 0.01, 0.01, i))
        est = estimate_for_rig(RIG, sus)
        t = CTX.hang_terms(nominal, est.assembly_cog_mm, WEIGHT_N, est.joint)
        errors.append(
            np.r_[est.assembly_cog_mm - COG, t.top_mm - lam, (t.pivots_mm - true_p).ravel()]
        )
        stated.append(t.cov_mm2)
    emp = np.cov(np.array(errors).T)
    cov = np.mean(stated, axis=0)
    s_emp = np.sqrt(np.diag(emp))
    live = s_emp > 1e-9  # a coordinate the play and λ do not move (none here)
    corr_emp = emp / np.outer(s_emp, s_emp)
    corr_stated = cov / np.outer(s_emp, s_emp)  # the stated covariance on the drawn scales
    off = ~np.eye(len(cov), dtype=bool) & np.outer(live, live)
    np.testing.assert_allclose(corr_stated[off], corr_emp[off], atol=0.2)
    assert np.abs(corr_emp[:3, 4:]).max() > 0.4  # the CoG follows the pivots, strongly
    if len(ids) == 3:
        assert np.abs(corr_emp[:3, 3]).max() > 0.4  # and λ: the CoG-λ terms matter here
