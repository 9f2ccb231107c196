"""What one sensor shares across the hangs: its definition, its draws, and the joint estimate
that calibrates it (cadcog.method.sharedfit)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from cadcog.method import gls, sym3
from cadcog.method.errormodel import ErrorModel
from cadcog.method.sharedfit import fit_shared
from cadcog.rig.inclinometer import (
    InclinometerConfig,
    corrected_verticals,
    rotation_matrix,
    sensor_readings,
)
from tests.method.pointgain import numeric_point_gain

angles = st.floats(-2.0, 2.0)


@given(st.lists(st.floats(-30.0, 30.0), min_size=3, max_size=3))
def test_rotation_matrix_is_scipys_rotation_of_the_same_vector(r_deg):
    want = Rotation.from_rotvec(np.radians(r_deg)).as_matrix()
    np.testing.assert_allclose(rotation_matrix(r_deg), want, atol=1e-12)


@given(
    st.floats(-0.7, 0.7),
    st.floats(-0.7, 0.7),
    st.booleans(),
    st.lists(angles, min_size=2, max_size=2),
    st.lists(st.floats(-0.05, 0.05), min_size=2, max_size=2),
    st.lists(angles, min_size=3, max_size=3),
    st.sampled_from([1, -1]),
    st.booleans(),
)
def test_corrected_verticals_invert_the_sensor(ux, uy, up, offset, scale, mount, sign, turned):
    """Readings of a sensor with any shared errors, turned on its mount or not, corrected with
    the same errors, give the vertical back (within the sensor's range, away from the
    horizontal); a turned sensor reads the other sign of the angle with the same offset."""
    uz = np.sqrt(max(1.0 - ux * ux - uy * uy, 0.09)) * (1 if up else -1)
    u = np.array([[ux, uy, uz]])
    u /= np.linalg.norm(u)
    shared = [*offset, *scale, *mount]
    cfg = InclinometerConfig(sign_x=sign)
    x, y, top = sensor_readings(u, shared, cfg, [turned])
    back = corrected_verticals(x, y, top, shared, cfg, [turned]).u
    np.testing.assert_allclose(back, u, atol=1e-10)
    if turned:
        x0, y0, _ = sensor_readings(u, shared, cfg)
        np.testing.assert_allclose([x + x0, y + y0], [[2 * offset[0]], [2 * offset[1]]], atol=1e-9)


def test_a_reversal_calibrates_the_zero_offset_a_plain_set_cannot():
    """Noise-free hangs of a 100 mm cube with a ±0.3° offset only: two plain hangs leave the
    offsets at their prior (four readings, three coordinates and two offsets); hanging one
    point again with the sensor turned determines them (the two readings' mean is the offset:
    only the play and reading errors of the re-hang blur it)."""
    g = np.array([50.0, 50.0, 40.0])
    p = np.array([[20.0, 50, 100], [100, 30, 80], [20.0, 50, 100]])
    n = np.array([[0, 0, 1.0], [1, 0, 0], [0, 0, 1.0]])
    u = (p - g) / np.linalg.norm(p - g, axis=1)[:, None]
    shared = [0.25, -0.2, 0, 0, 0, 0, 0]
    turned = [False, False, True]
    x, y, top = sensor_readings(u, shared, turned=turned)
    prior = [0.3 / np.sqrt(3)] * 2 + [0.0] * 5
    errors = gls.LineErrors(1e-4, 1e-4, np.radians(0.01) ** 2)
    plain = fit_shared(p[:2], x[:2], y[:2], top[:2], n[:2], errors, gls.WireTerm(), prior)
    rev = fit_shared(p, x, y, top, n, errors, gls.WireTerm(), prior, sensor_turned=turned)
    assert plain.shared_sigma[1] > 0.9 * prior[1]  # two lines leave Y's offset at its prior
    assert rev.shared_sigma[:2].max() < 0.1 * prior[0]
    # Noise-free: what is left is the prior's pull, well within the posterior σ.
    np.testing.assert_allclose(rev.shared[:2], shared[:2], atol=3 * rev.shared_sigma[:2].max())
    np.testing.assert_allclose(rev.cog_mm, g, atol=3 * np.sqrt(np.trace(rev.cov_mm2)))
    assert np.trace(rev.cov_mm2) < 0.05 * np.trace(plain.cov_mm2)
    assert rev.calibrated[:2].all() and not plain.calibrated[1]


def test_the_sensor_reads_its_errors_as_defined():
    """A level object (vertical along +z) read by a sensor turned 0.5° about x: X stays 0, Y
    reads the tilt, scaled and offset."""
    x, y, top = sensor_readings([[0.0, 0.0, 1.0]], [0.1, -0.2, 0.0, 0.02, 0.5, 0.0, 0.0])
    assert x[0] == pytest.approx(0.1, abs=1e-12)
    # R about +x by 0.5° turns +z towards −y: the sensor's y channel reads −0.5°.
    assert y[0] == pytest.approx(1.02 * -0.5 - 0.2, abs=1e-9)
    assert top[0]


def test_shared_draws_are_within_the_figures_and_repeatable():
    m = ErrorModel((1.0,), (10.0,), sensor_offset_deg=0.3, sensor_scale_rel=0.01,
                   mounting_misalignment_deg=0.5)  # fmt: skip
    a = m.sample_shared_sensor(np.random.default_rng(4), 20_000)
    b = m.sample_shared_sensor(np.random.default_rng(4), 20_000)
    np.testing.assert_array_equal(a, b)
    assert np.all(np.abs(a[:2]) <= 0.3) and np.all(np.abs(a[2:4]) <= 0.01)
    angle = np.linalg.norm(a[4:], axis=0)
    assert np.all(angle <= 0.5 + 1e-12)
    # uniform in angle: the mean angle is half the figure; components have the prior's σ
    assert angle.mean() == pytest.approx(0.25, rel=0.02)
    np.testing.assert_allclose(a.std(axis=1), m.shared_sensor_sigmas, rtol=0.03)


def test_no_figure_draws_nothing():
    rng = np.random.default_rng(1)
    state = rng.bit_generator.state
    out = ErrorModel((1.0,), (10.0,)).sample_shared_sensor(rng, 5)
    assert not out.any() and rng.bit_generator.state == state


def _cube_hangs():
    g = np.array([50.0, 50.0, 40.0])
    p = np.array([[20.0, 50, 100], [100, 30, 80], [70, 0, 70], [0, 60, 90], [80, 100, 60],
                  [45, 70, 100]])  # fmt: skip
    n = np.array([[0, 0, 1.0], [1, 0, 0], [0, -1, 0], [-1, 0, 0], [0, 1, 0], [0, 0, 1]])
    return g, p, n


#: The per-hang errors of :func:`_noisy_cube`'s readings as the fits take them.
CUBE_ERRORS = gls.LineErrors(0.08, 0.02, np.radians(0.06) ** 2)


def _noisy_cube(seed: int):
    """The cube's hangs read by a sensor with no shared error, each reading off by 0.05°."""
    g, p, n = _cube_hangs()
    u = (p - g) / np.linalg.norm(p - g, axis=1)[:, None]
    rng = np.random.default_rng(seed)
    x, y, top = sensor_readings(u, np.zeros(7))
    return p, n, x + rng.normal(0, 0.05, 6), y + rng.normal(0, 0.05, 6), top


def test_without_shared_figures_it_is_the_per_hang_estimator():
    """No shared figure, a known wire scale: the same minimum as plumb_gls (which weighs by the
    distances of its equal-weight pass, one step short of the fixed point: ~µm)."""
    p, n, x, y, top = _noisy_cube(2)
    errors = CUBE_ERRORS
    fit = fit_shared(p, x, y, top, n, errors, gls.WireTerm(), np.zeros(7))
    uu = corrected_verticals(x, y, top, np.zeros(7)).u
    batch = gls.plumb_gls(p.T[:, :, None], uu.T[:, :, None], n.T[:, :, None], errors,
                          gls.WireTerm())  # fmt: skip
    np.testing.assert_allclose(fit.cog_mm, batch.cog_mm[:, 0], atol=5e-3)
    np.testing.assert_allclose(fit.cov_mm2, sym3.sym_to_full(batch.cov_mm2[:, 0]), rtol=0.02)
    assert not fit.shared.any() and not fit.calibrated.any()


def test_noise_free_hangs_give_back_every_shared_error():
    """Six hangs of exact readings from a sensor with all seven errors and a weak prior: the
    joint estimate recovers the CoG and each error (the hangs identify all of them)."""
    g, p, n = _cube_hangs()
    u = (p - g) / np.linalg.norm(p - g, axis=1)[:, None]
    truth = np.array([0.3, -0.2, 0.01, -0.008, 0.4, -0.3, 0.2])
    x, y, top = sensor_readings(u, truth)
    errors = gls.LineErrors(1e-8, 1e-8, 1e-14)
    prior = np.array([5.0, 5.0, 0.1, 0.1, 5.0, 5.0, 5.0])
    fit = fit_shared(p, x, y, top, n, errors, gls.WireTerm(), prior)
    np.testing.assert_allclose(fit.cog_mm, g, atol=1e-5)
    np.testing.assert_allclose(fit.shared, truth, atol=1e-5)
    assert fit.calibrated.all()
    d = fit.to_dict()
    assert d["offset_x_deg"]["estimate"] == pytest.approx(0.3, abs=1e-5)
    assert d["offset_x_deg"]["calibrated_by_hangs"] is True


def test_two_hangs_cannot_calibrate_and_the_prior_is_carried():
    """Two hangs leave nothing to calibrate with: the parameters keep their prior σ, and the
    CoG's covariance grows by their share."""
    g, p, n = _cube_hangs()
    p, n = p[:2], n[:2]
    u = (p - g) / np.linalg.norm(p - g, axis=1)[:, None]
    x, y, top = sensor_readings(u, np.zeros(7))
    errors = gls.LineErrors(0.08, 0.02, np.radians(0.06) ** 2)
    prior = ErrorModel((1.0,), (1.0,), sensor_offset_deg=0.3).shared_sensor_sigmas
    with_prior = fit_shared(p, x, y, top, n, errors, gls.WireTerm(), prior)
    without = fit_shared(p, x, y, top, n, errors, gls.WireTerm(), np.zeros(7))
    assert not with_prior.calibrated.any()
    assert with_prior.shared_sigma[0] == pytest.approx(prior[0], rel=0.3)
    assert np.trace(with_prior.cov_mm2) > 1.2 * np.trace(without.cov_mm2)


def test_an_outlier_hang_is_flagged_with_shared_figures():
    g, p, n = _cube_hangs()
    u = (p - g) / np.linalg.norm(p - g, axis=1)[:, None]
    x, y, top = sensor_readings(u, np.zeros(7))
    x = x.copy()
    x[3] += 3.0  # one hang read 3° off: no shared error explains one hang alone
    errors = gls.LineErrors(0.08, 0.02, np.radians(0.06) ** 2)
    prior = ErrorModel((1.0,), (1.0,), sensor_offset_deg=0.3, sensor_scale_rel=0.01,
                       mounting_misalignment_deg=0.5).shared_sensor_sigmas  # fmt: skip
    fit = fit_shared(p, x, y, top, n, errors, gls.WireTerm(), prior, ids=list("abcdef"))
    assert [r.id for r in fit.residuals if r.inconsistent] == ["d"]


def test_a_wild_hang_under_wide_figures_gives_finite_verdicts_and_says_so(tmp_path, capsys):
    """Three hangs, one read ~10° off, under the widest figures the rig file accepts: the fit
    drives a sensitivity far beyond its figure; the verdicts stay finite (the design lives on
    the plane ⊥ u) and the command says the shared parameters left their figures (an audit's
    case: it once wrote NaN)."""
    import json

    from cadcog.cli import main
    from support.rigtools import paper_rig_dict, write_csv, write_rig

    data = paper_rig_dict()
    data["inclinometer"].update(offset_deg=5.0, scale_error_rel=0.2, mounting_misalignment_deg=10.0)
    rig = write_rig(tmp_path / "wide.toml", data)
    csv = write_csv(
        tmp_path / "r.csv",
        [
            "S5,55.000,-4.000,60.000,-45.0879,-34.1748,true",
            "S1,45.000,20.000,82.000,-53.2484,-24.1407,true",
            "S4,140.000,15.000,-4.000,45.0000,-22.2803,false",
        ],
    )
    assert main(["estimate", str(csv), "--rig", str(rig), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert all(np.isfinite(s["residual_sigma"]) for s in out["suspensions"])
    assert any(s["inconsistent"] for s in out["suspensions"])
    assert any("beyond its declared figures" in w for w in out["warnings"])


@pytest.mark.parametrize("shared", [False, True])
def test_the_point_gain_is_how_the_fit_follows_each_assumed_point(shared):
    """``point_gain`` (∂(G, λ)/∂pᵢ at the solution, the weights held) against refitting with
    each hang's point moved by ±0.01 mm, λ an unknown with a prior: within 1 % of the largest
    gain (what moving a point changes in the weights is second order), for the per-hang GLS
    and for the fit with the sensor's shared parameters. It is what the swing's tensor takes
    as the CoG's share of each pivot's error (cadcog.dynamics.context.hang_terms)."""
    p, n, x, y, top = _noisy_cube(7)
    errors = CUBE_ERRORS
    wire = gls.WireTerm("elastica", 0.5, 0.25)
    prior = np.array([0.3, 0.3, 0.01, 0.01, 0.5, 0.5, 0.5]) if shared else np.zeros(7)

    def fit(points):
        return fit_shared(points, x, y, top, n, errors, wire, prior)

    def cog_and_scale(points):
        f = fit(points)
        return f.cog_mm, f.scale_mm

    base = fit(p)
    numeric = numeric_point_gain(cog_and_scale, p, 0.01)
    scale = np.abs(numeric).max()
    np.testing.assert_allclose(base.point_gain, numeric, atol=0.01 * scale)
    assert np.abs(numeric[:3]).max() > 0.1  # the CoG follows the points, not by a little
    assert base.cog_scale_cov_mm2 is not None and np.any(base.cog_scale_cov_mm2)
