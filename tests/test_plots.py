"""The figures' closed forms match scipy's (the figures no longer import scipy.stats)."""

from __future__ import annotations

import numpy as np
from scipy import stats

from cadcog.reports.plots import K95_3D, maxwell_pdf, rayleigh_pdf


def test_k95_is_the_chi2_3_quantile():
    assert K95_3D**2 == stats.chi2.ppf(0.95, df=3)


def test_closed_form_densities_match_scipy():
    r = np.linspace(0.0, 6.0, 301)
    for s in (0.2, 0.46, 1.3):
        np.testing.assert_allclose(rayleigh_pdf(r, s), stats.rayleigh.pdf(r, scale=s), rtol=1e-12)
        np.testing.assert_allclose(maxwell_pdf(r, s), stats.maxwell.pdf(r, scale=s), rtol=1e-12)
