"""The figures' closed forms match scipy's (the figures no longer import scipy.stats); the rig
view's boxes are their edges."""

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


def test_box_path_is_the_twelve_edges_of_the_box():
    from cadcog.reports.plots import _box_path

    lo, hi = np.array([1.0, -2.0, 0.5]), np.array([4.0, 3.0, 2.5])
    path = _box_path(lo, hi)
    assert path.shape == (3, 36)
    segments = path.T.reshape(12, 3, 3)
    assert np.isnan(segments[:, 2]).all()  # each edge ends with a break
    a, b = segments[:, 0], segments[:, 1]
    # every edge runs along one axis, over the box's whole length on that axis
    assert (np.count_nonzero(a != b, axis=1) == 1).all()
    assert sorted(np.abs(b - a).sum(axis=1)) == sorted([3.0] * 4 + [5.0] * 4 + [2.0] * 4)
    corners = {tuple(p) for p in np.vstack([a, b])}
    assert corners == {(x, y, z) for x in (1.0, 4.0) for y in (-2.0, 3.0) for z in (0.5, 2.5)}
    edges = {frozenset((tuple(p), tuple(q))) for p, q in zip(a, b, strict=True)}
    assert len(edges) == 12
