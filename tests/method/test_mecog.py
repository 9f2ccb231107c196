"""``cadcog.method.mecog``: the ME CoG error's exact PDF against closed forms and sampling."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cadcog.method.errormodel import ErrorModel
from cadcog.method.mecog import me_cog_pdf
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
