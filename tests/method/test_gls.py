"""The generalised least squares of plumb lines against an independent dense implementation,
the wire scale's self-calibration, and the vectorised path against ``estimate_cog``."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from cadcog.core.errors import DegenerateGeometryError
from cadcog.method import gls, preparedlines, sym3
from cadcog.method.errormodel import ErrorModel
from cadcog.method.estimate import BodyBox, MEData, estimate_cog
from cadcog.method.readings import Suspension
from cadcog.rig.inclinometer import readings_from_verticals, verticals_from_readings
from cadcog.uncertainty.montecarlo import (
    EstimatorOptions,
    Scenario,
    _measured_verticals,
    compensated_errors,
    draw_perturbations,
    estimate_trials,
    hang,
)
from tests.method.pointgain import numeric_point_gain


def _jacobian_by_differences(u: np.ndarray) -> np.ndarray:
    """∂u/∂(X, Y) (3 × 2, per radian) by central differences of eq. 2, the library's own
    readings → vertical function: independent of the closed form in gls."""
    x, y, up = readings_from_verticals(u[None, :])
    h = 1e-6
    cols = []
    for dx, dy in ((h, 0.0), (0.0, h)):
        plus = verticals_from_readings(x + np.rad2deg(dx), y + np.rad2deg(dy), up).u[0]
        minus = verticals_from_readings(x - np.rad2deg(dx), y - np.rad2deg(dy), up).u[0]
        cols.append((plus - minus) / (2 * h))
    return np.array(cols).T


def dense_gls(p, u, n, f, play_var, axial_var, reading_var, lam0, lam_var, estimate):
    """The estimator written plainly: full 3 × 3 matrices, pseudo-inverses, a 4-state solve."""
    k = len(p)
    eye = np.eye(3)
    # Equal-weight pass on the corrected points for the distances.
    q0 = p + lam0 * f[:, None] * n
    a = sum(eye - np.outer(ui, ui) for ui in u)
    b = sum((eye - np.outer(ui, ui)) @ qi for ui, qi in zip(u, q0, strict=True))
    g0 = np.linalg.solve(a, b)
    rows, rhs, weights = [], [], []
    for i in range(k):
        proj = eye - np.outer(u[i], u[i])
        sp = play_var * (eye - np.outer(n[i], n[i])) + axial_var * np.outer(n[i], n[i])
        jac = _jacobian_by_differences(u[i])
        dist = np.linalg.norm(g0 - q0[i])
        s = proj @ sp @ proj + dist**2 * jac @ np.diag([reading_var, reading_var]) @ jac.T
        w = np.linalg.pinv(s, hermitian=True, rcond=1e-10)
        weights.append(w)
        rows.append(np.hstack([eye, -f[i] * n[i][:, None]]))  # r = G − λ f n − p
        rhs.append(p[i])
    normal = sum(r.T @ w @ r for r, w in zip(rows, weights, strict=True))
    vec = sum(r.T @ w @ y for r, w, y in zip(rows, weights, rhs, strict=True))
    if lam_var == 0 and not estimate:
        normal = normal[:3, :3]
        vec = sum(w @ (y + lam0 * fi * ni) for w, y, fi, ni in zip(weights, p, f, n, strict=True))
        cov = np.linalg.inv(normal)
        return cov @ vec, cov, lam0, 0.0, np.linalg.cond(normal)
    if not estimate:
        normal[3, 3] += 1 / lam_var
        vec[3] += lam0 / lam_var
    cov = np.linalg.inv(normal)
    x = cov @ vec
    return x[:3], cov[:3, :3], x[3], cov[3, 3], np.linalg.cond(normal)


unit = st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)).filter(
    lambda v: 0.3 < np.linalg.norm(v)
)


@settings(max_examples=60)
@given(
    st.lists(st.tuples(unit, unit, st.floats(40, 300)), min_size=3, max_size=6),
    st.sampled_from(["fixed", "prior", "estimate"]),
    st.sampled_from(["paper", "elastica"]),
    st.integers(0, 2**31),
)
def test_kernel_equals_a_dense_implementation(spokes, mode, wire_model, seed):
    rng = np.random.default_rng(seed)
    cog = np.array([10.0, -20.0, 5.0])
    u_list, p_list, n_list = [], [], []
    for d, nrm, dist in spokes:
        d = np.array(d) / np.linalg.norm(d)
        if abs(d[2]) < 0.25:  # keep eq. 2 well conditioned (|u_z| away from 0)
            d[2] = 0.25 if d[2] >= 0 else -0.25
            d /= np.linalg.norm(d)
        u_list.append(d)
        p_list.append(cog + dist * d)
        n_list.append(np.array(nrm) / np.linalg.norm(nrm))
    u = np.array(u_list) + rng.normal(0, 2e-3, (len(u_list), 3))  # readings with errors
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    p, n = np.array(p_list), np.array(n_list)
    f = np.ones(len(p)) if wire_model == "paper" else np.sqrt(2 / (1 + np.sum(u * n, axis=1)))
    play_var, axial_var, reading_var = 0.08, 0.05, 1.2e-6
    lam0, lam_var = 0.6, (0.0 if mode == "fixed" else 0.01)
    errors = gls.LineErrors(play_var, axial_var, reading_var)
    wire = gls.WireTerm(wire_model, lam0, lam_var, mode == "estimate")
    batch = gls.plumb_gls(p.T[:, :, None], u.T[:, :, None], n.T[:, :, None], errors, wire)
    try:
        x, cov, lam, lam_var_dense, cond = dense_gls(p, u, n, f, play_var, axial_var, reading_var,
                                                     lam0, lam_var, mode == "estimate")  # fmt: skip
    except np.linalg.LinAlgError:
        assume(False)  # exactly parallel lines: the reference itself has no answer
    assume(cond < 1e8)  # near-parallel lines (or λ unidentifiable): round-off decides
    scale = np.sqrt(np.max(np.diag(cov)))
    np.testing.assert_allclose(batch.cog_mm[:, 0], x, atol=1e-6 * scale + 1e-9)
    # An entry that cancels to near zero is compared at the covariance's own scale (a fresh
    # local run found one at −2.0e-7 of 0.086, off by 7e-11).
    np.testing.assert_allclose(
        sym3.sym_to_full(batch.cov_mm2[:, 0]), cov, rtol=1e-5, atol=1e-8 * np.max(np.abs(cov))
    )
    assert batch.scale_mm[0] == pytest.approx(lam, abs=1e-6 * np.sqrt(lam_var_dense) + 1e-9)


def test_noise_free_lines_give_the_true_cog_and_scale(paper_rig):
    """Lines through virtual points λ·f·n above the nominal ones meet at the CoG: the
    self-calibrated estimate finds λ and the CoG exactly, whatever the prior says."""
    sc = Scenario.from_rig(paper_rig)
    g = sc.assembly_cog_mm
    for wire_model, lam in (("paper", 0.83), ("elastica", 1.7)):
        f = 1.0
        virtual = sc.points_mm + lam * sc.normals
        for _ in range(20):  # the elastica's f depends on θ, which depends on the point
            u = (virtual - g) / np.linalg.norm(virtual - g, axis=1, keepdims=True)
            f = 1.0 if wire_model == "paper" else np.sqrt(2 / (1 + np.sum(u * sc.normals, 1)))
            virtual = sc.points_mm + lam * np.atleast_1d(f)[:, None] * sc.normals
        errors = gls.LineErrors(0.08, 0.08, 1e-6)
        wire = gls.WireTerm(wire_model, 0.5, 0.0, estimate=True)
        b = gls.plumb_gls(sc.points_mm.T[:, :, None], u.T[:, :, None], sc.normals.T[:, :, None],
                          errors, wire)  # fmt: skip
        np.testing.assert_allclose(b.cog_mm[:, 0], g, atol=1e-9)
        assert b.scale_mm[0] == pytest.approx(lam, abs=1e-9)


def test_self_calibrated_scale_covers_a_known_stiffer_wire(paper_rig):
    """The wire is twice as stiff as the rig file says; over 4000 simulated campaigns the
    self-calibrated λ lands within ±1.96 σ of the truth 93-97 % of the time (binomial 99.9 %
    range for a calibrated σ: 94.2-95.8 %), and its mean error is a small fraction of σ."""
    model = replace(ErrorModel.from_rig(paper_rig), wire_model="elastica")
    truth = replace(model, wire_bending_stiffness_n_mm2=60.0, wire_stiffness_rel_uncertainty=0.0)
    sc = Scenario.from_rig(paper_rig)
    k, n = 6, 4000
    pert = draw_perturbations(truth, np.random.default_rng(3), n, k)
    u = _measured_verticals(hang(sc, truth, range(k), pert), *pert.reading_deg)
    wire = gls.WireTerm.from_model(model, sc.weight_n, estimate=True)
    b = gls.plumb_gls(
        sc.points_mm.T[:, :, None], u, sc.normals.T[:, :, None], gls.LineErrors.from_model(model),
        wire,
    )  # fmt: skip
    lam_true = truth.wire_length_mm(sc.weight_n)
    assert lam_true == pytest.approx(np.sqrt(2) * model.wire_length_mm(sc.weight_n))
    z = (b.scale_mm - lam_true) / np.sqrt(b.scale_var_mm2)
    assert 0.93 <= np.mean(np.abs(z) <= 1.96) <= 0.97
    assert abs(np.mean(z)) < 0.1


def _suspensions(points: np.ndarray, u: np.ndarray, samples: int = 10) -> list[Suspension]:
    x, y, up = readings_from_verticals(u)
    return [
        Suspension(
            f"P{i}",
            tuple(points[i]),
            bool(up[i]),
            samples,
            float(x[i]),
            float(y[i]),
            None,
            None,
            i + 2,
        )
        for i in range(len(points))
    ]


@pytest.mark.parametrize(
    ("group", "options"),
    [
        ((0, 1, 2, 3, 4, 5), EstimatorOptions()),
        ((0, 2, 4), EstimatorOptions()),
        ((0, 1), EstimatorOptions()),
        ((0, 2, 4, 5), EstimatorOptions(self_calibrate=True)),
        ((1, 3), EstimatorOptions(wire_correction=False)),
    ],
)
def test_monte_carlo_runs_the_estimate_commands_estimator(paper_rig, group, options):
    """Trials of the vectorised Monte Carlo, fed one by one to estimate_cog (what
    `cadcog estimate --rig` runs on a readings file), give the same CoG and covariance."""
    model = ErrorModel.from_rig(paper_rig)
    sc = Scenario.from_rig(paper_rig)
    pert = draw_perturbations(model, np.random.default_rng(1), 5, len(group))
    batch = estimate_trials(sc, model, group, pert, options)
    errors = compensated_errors(sc, batch.cog_mm)
    u = _measured_verticals(hang(sc, model, group, pert), *pert.reading_deg)
    pts = sc.points_mm[list(group)]
    for t in range(5):
        est = estimate_cog(
            _suspensions(pts, u[:, :, t].T),
            paper_rig.inclinometer,
            MEData.from_rig(paper_rig),
            model=model,
            body=BodyBox.of_rig(paper_rig),
            wire_correction=options.wire_correction,
            self_calibrate=options.self_calibrate,
        )
        np.testing.assert_allclose(est.assembly_cog_mm, batch.cog_mm[:, t], atol=1e-9)
        np.testing.assert_allclose(est.cog_mm - sc.pm_cog_mm, errors[t], atol=1e-9)
        np.testing.assert_allclose(
            est.joint.cov_mm2, sym3.sym_to_full(batch.cov_mm2[:, t]), rtol=1e-9, atol=1e-15
        )


def test_self_calibration_refuses_what_it_cannot_do(paper_rig):
    model = ErrorModel.from_rig(paper_rig)
    me = MEData.from_rig(paper_rig)
    body = BodyBox.of_rig(paper_rig)
    g = paper_rig.analytic_assembly.cog_mm
    # Every bolt axis along its vertical: a wire offset slides each line along itself.
    dirs = np.array([[0.3, 0.2, 1.0], [-0.4, 0.3, 1.0], [0.1, -0.5, 1.0], [0.5, 0.5, 1.0]])
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    pts = g + 60.0 * dirs
    sus = _suspensions(pts, dirs)
    radial = BodyBox(g - 1e3, g + 1e3, "test")
    normals = dirs

    class Radial(BodyBox):
        def normals(self, suspensions):  # type: ignore[override]
            return normals

    box = Radial(radial.lo_mm, radial.hi_mm, "radial bolts")
    with pytest.raises(DegenerateGeometryError, match="wire offset scale cannot be estimated"):
        estimate_cog(sus, paper_rig.inclinometer, me, model=model, body=box, self_calibrate=True)
    two = _suspensions(pts[:2], dirs[:2])
    with pytest.raises(ValueError, match="three or more suspensions"):
        estimate_cog(two, paper_rig.inclinometer, me, model=model, body=body, self_calibrate=True)
    with pytest.raises(ValueError, match="needs the bolt axes"):
        estimate_cog(sus, paper_rig.inclinometer, me, model=model, self_calibrate=True)


@settings(max_examples=40)
@given(
    st.integers(2, 5),
    st.sampled_from(["paper", "elastica"]),
    st.booleans(),
    st.floats(0.0, 1.0),
    st.integers(0, 2**31),
)
def test_prepared_lines_give_the_full_estimators_cog(k, wire_model, weighted, scale, seed):
    """The Monte Carlo's path (each hang prepared once, several groups combined from the
    prepared hangs in one call) against plumb_gls, which `cadcog estimate` runs, on random
    lines."""
    rng = np.random.default_rng(seed)
    n, hangs = 7, k + 2
    cog = rng.normal(0, 20, 3)
    d = rng.normal(size=(hangs, 3))
    d[:, 2] = np.abs(d[:, 2]) + 0.5  # upward verticals, |u_z| away from 0 (eq. 2)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    p = cog + rng.uniform(60, 200, (hangs, 1)) * d
    nrm = rng.normal(size=(hangs, 3))
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    u = d.T[:, :, None] + rng.normal(0, 3e-3, (3, hangs, n))
    u /= np.linalg.norm(u, axis=0, keepdims=True)
    errors = gls.LineErrors(0.08, 0.05, 1.2e-6)
    wire = gls.WireTerm(wire_model, scale)
    prepared = preparedlines.prepare_lines(p.T[:, :, None], u, nrm.T[:, :, None], errors, wire,
                                 weighted=weighted)  # fmt: skip
    groups = [sorted(rng.choice(hangs, size=k, replace=False).tolist()) for _ in range(3)]
    idx = np.array(groups)  # three groups at once: slot i holds the i-th hang of each
    combined = preparedlines.combine_lines([prepared.take(idx[:, i]) for i in range(k)])
    assert combined.shape == (3, 3, n)
    for j, group in enumerate(groups):
        full = gls.plumb_gls(p[group].T[:, :, None], u[:, group], nrm[group].T[:, :, None],
                             errors, wire, weighted=weighted)  # fmt: skip
        scale_mm = np.sqrt(np.max(sym3.sym_to_full(full.cov_mm2[:, 0]).diagonal()))
        np.testing.assert_allclose(combined[:, j], full.cog_mm, atol=1e-9 * max(scale_mm, 1.0))
    with pytest.raises(ValueError, match="at least two lines"):
        preparedlines.combine_lines([prepared.take(0)])
    with pytest.raises(ValueError, match="known wire scale"):
        preparedlines.prepare_lines(p.T[:, :, None], u, nrm.T[:, :, None], errors,
                          gls.WireTerm(wire_model, scale, 0.01))  # fmt: skip


def test_the_estimate_s_point_gain_is_how_its_cog_follows_each_point():
    """``estimate_for_rig``'s ``joint.point_gain`` (the per-hang GLS, λ an unknown with its
    prior) against refitting with each suspension's position moved ±0.01 mm: within 1 % of
    the largest gain (the weights the GLS takes from its first pass move too, second order)."""
    import cadcog
    from cadcog.method.estimate import estimate_for_rig
    from cadcog.rig.geometry import ideal_reading

    rig = cadcog.load_rig()
    exits = np.array([rig.wire_exit_mm(p) for p in rig.suspension_points])
    cog = rig.analytic_assembly.cog_mm
    rng = np.random.default_rng(3)
    reads = []
    for e in exits:
        r = ideal_reading(e, cog)
        reads.append((r.top_face_up, r.inc_x_deg + rng.normal(0, 0.05), r.inc_y_deg))

    def joint(points):
        sus = [
            Suspension(p.id, tuple(points[i]), t, 10, x, y, 0.01, 0.01, i)
            for i, (p, (t, x, y)) in enumerate(zip(rig.suspension_points, reads, strict=True))
        ]
        return estimate_for_rig(rig, sus).joint

    def cog_and_scale(points):
        j = joint(points)
        return j.cog_mm, j.wire.scale_mm

    base = joint(exits)
    assert base.wire is not None and base.wire.sigma_mm > 0  # λ is an unknown here
    numeric = numeric_point_gain(cog_and_scale, exits, 0.01)
    np.testing.assert_allclose(base.point_gain, numeric, atol=0.01 * np.abs(numeric).max())
