"""Error-source models: ME convolution, elastica offset, inclinometer averaging."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats
from scipy.integrate import solve_bvp

from cadcog.method.errormodel import ErrorModel
from cadcog.method.mecog import me_cog_pdf
from cadcog.method.wire import wire_offset_mm
from cadcog.rig.parameters import me_cog_sigma_mm

PAPER_MASSES = (0.025, 0.085, 0.020, 0.046)


def test_two_equal_uniforms_convolve_to_a_triangle():
    pdf = me_cog_pdf([1.0, 1.0], [10.0, 10.0], points_per_mm=200)
    # Each term is U(±2.5 mm): the sum is a triangle on ±5 mm with peak 1/5.
    triangle = np.clip((5.0 - np.abs(pdf.x_mm)) / 25.0, 0, None)
    np.testing.assert_allclose(pdf.pdf, triangle, atol=2e-3)
    assert np.sum(pdf.pdf) * (pdf.x_mm[1] - pdf.x_mm[0]) == pytest.approx(1.0, abs=1e-9)


@given(st.lists(st.floats(0.005, 1.0), min_size=1, max_size=6), st.floats(2.0, 20.0))
@settings(max_examples=30, deadline=None)
def test_std_of_the_weighted_sum_is_exact(masses, edge):
    w = np.array(masses) / sum(masses)
    expected = np.sqrt(np.sum(w**2)) * edge / np.sqrt(12.0)
    assert me_cog_sigma_mm(masses, [edge] * len(masses)) == pytest.approx(expected, rel=1e-12)
    pdf = me_cog_pdf(masses, [edge] * len(masses), points_per_mm=100)
    dx = pdf.x_mm[1] - pdf.x_mm[0]
    numeric = np.sqrt(np.sum(pdf.x_mm**2 * pdf.pdf) * dx)
    # Discretising each box to a whole number of cells moves σ by at most ~dx.
    assert numeric == pytest.approx(expected, abs=2 * dx)


def test_paper_rig_me_pdf_is_close_to_normal_and_matches_sampling():
    pdf = me_cog_pdf(PAPER_MASSES, [10.0] * 4)
    assert pdf.sigma_mm == pytest.approx(1.66, abs=0.05)
    assert pdf.max_cdf_difference_from_normal < 0.05
    model = ErrorModel(PAPER_MASSES, (10.0,) * 4)
    samples = model.sample_me_errors(np.random.default_rng(3), 200_000)
    assert np.std(samples, axis=1) == pytest.approx([pdf.sigma_mm] * 3, rel=0.01)
    cdf = np.interp(np.sort(samples[0]), pdf.x_mm, pdf.cdf)
    ks = np.max(np.abs(cdf - np.arange(1, cdf.size + 1) / cdf.size))
    assert ks < 0.005


@pytest.mark.parametrize("theta_deg", [10.0, 45.0, 90.0, 135.0])
def test_elastica_offset_against_a_numerical_solution(theta_deg):
    """Solve EI φ'' = W sin φ as a boundary-value problem and find where the far-field
    vertical line meets the bolt axis; compare with Δ = λ/cos(θ/2)."""
    lam = 0.6
    theta = np.deg2rad(theta_deg)
    length = 30 * lam

    def rhs(s, y):  # y = (φ, φ', x): φ from the vertical, x the sideways drift
        return np.vstack([y[1], np.sin(y[0]) / lam**2, np.sin(y[0])])

    def bc(ya, yb):
        return np.array([ya[0] - theta, yb[0], ya[2]])

    s = np.linspace(0, length, 2000)
    guess = np.vstack([theta * np.exp(-s / lam), -theta / lam * np.exp(-s / lam), np.zeros_like(s)])
    sol = solve_bvp(rhs, bc, s, guess, tol=1e-10, max_nodes=200_000)
    assert sol.success
    drift = sol.sol(length)[2]  # sideways offset of the far-field vertical line
    delta_numeric = drift / np.sin(theta)
    assert delta_numeric == pytest.approx(float(wire_offset_mm(theta_deg, lam)), rel=1e-6)


def test_reading_error_models():
    paper = ErrorModel(PAPER_MASSES, (10.0,) * 4, samples=10, inclinometer_model="paper-averaged")
    bias = ErrorModel(PAPER_MASSES, (10.0,) * 4, samples=10, inclinometer_model="hang-bias")
    rng = np.random.default_rng(11)
    for model in (paper, bias, paper.paper()):
        e = model.sample_reading_errors(rng, (200_000,))
        assert np.std(e) == pytest.approx(model.reading_sigma_deg, rel=0.01)
    # Averaging helps the paper model by √n, not the per-hang bias.
    q = paper.lsb_deg
    assert paper.reading_sigma_deg == pytest.approx(
        np.sqrt((0.1**2 / 3 + q**2 / 12 + 0.05**2) / 10)
    )
    assert paper.paper().reading_sigma_deg == pytest.approx(np.sqrt((0.1**2 / 3 + q**2 / 12) / 10))
    assert bias.reading_sigma_deg > np.sqrt(0.1**2 / 3)
    single = ErrorModel(PAPER_MASSES, (10.0,) * 4, samples=1).paper()
    e = single.sample_reading_errors(rng, (100_000,))
    assert np.max(np.abs(e)) <= 0.1 + single.lsb_deg / 2  # bounded: sum of two uniforms
    assert stats.kurtosis(e) < 0  # platykurtic, unlike a normal
    with pytest.raises(ValueError, match="unknown inclinometer model 'paper'"):
        ErrorModel(PAPER_MASSES, (10.0,) * 4, inclinometer_model="paper")  # type: ignore[arg-type]


@pytest.mark.parametrize(("noise_deg", "samples"), [(0.0, 10), (0.02, 10), (0.05, 10), (0.03, 3)])
def test_hang_mean_reading_against_a_simulated_adc(noise_deg, samples):
    """The closed form of a hang's mean reading error (bias + shared quantisation + averaged
    part) against an ADC simulated sample by sample, as the virtual campaign does."""
    model = ErrorModel(PAPER_MASSES, (10.0,) * 4, samples=samples, sensor_noise_deg=noise_deg)
    q = model.lsb_deg
    rng = np.random.default_rng(2)
    hangs = 100_000
    true = rng.uniform(-40, 40, hangs)  # where the signal falls on the ADC grid: anywhere
    bias = rng.uniform(-0.1, 0.1, hangs)
    noisy = true[:, None] + bias[:, None] + rng.normal(0, noise_deg, (hangs, samples))
    mean = (q * np.round(noisy / q)).mean(axis=1)
    err = mean - true
    assert np.var(err) == pytest.approx(model.reading_var_deg2(), rel=0.02)
    _, shared, averaged = model.reading_parts_deg2()
    # The part the samples share: the variance of the mean minus the accuracy bias's, once the
    # averaged part is taken out (only testable where it is not negligible).
    if shared > 1e-4:
        assert np.var(err - bias) - averaged == pytest.approx(shared, rel=0.05)
