"""The fitted frequencies the tensor is fitted to, and their covariance (tensorfit.swing_data)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from cadcog.dynamics.modalfit import DRIFT_PRIOR_REL, ModalFit
from cadcog.dynamics.tensorfit import TRUSTED_DRIFT_PRIORS, amplitude_factor, swing_data


def _fit(freqs, drifts, amps=(2.0, 1.0), sigma=1e-3):
    k = len(freqs)
    return ModalFit(
        "S1",
        np.arange(k),
        np.asarray(freqs, float),
        np.eye(k) * sigma**2,
        np.full(k, 0.03),
        np.asarray(amps, float),
        np.full(2, 0.02),
        1.0,
        None if drifts is None else np.asarray(drifts, float),
    )


def test_a_drift_fit_is_taken_as_the_small_swing_limit_and_a_large_drift_widens_it():
    f = np.array([2.5, 3.5])
    limit = TRUSTED_DRIFT_PRIORS * DRIFT_PRIOR_REL * f
    d = np.array([0.9, 1.1]) * limit  # the first within the trusted drift, the second beyond
    data = swing_data([_fit(f, d)], [60.0], model_rel=5e-4)
    assert data.frequencies_hz.tolist() == f.tolist()
    expected = 1e-6 + (5e-4 * f) ** 2 + np.array([0.0, (d[1] - limit[1]) ** 2])
    assert np.diag(data.cov_hz2) == pytest.approx(expected, rel=1e-12)


def test_what_the_halves_disagree_by_is_added_and_an_unchecked_mode_adds_nothing():
    f = np.array([2.5, 3.5])
    fit = replace(_fit(f, np.zeros(2)), halves_excess_hz2=np.array([4e-6, np.nan]))
    data = swing_data([fit], [60.0], model_rel=1e-4)
    expected = 1e-6 + (1e-4 * f) ** 2 + np.array([4e-6, 0.0])
    assert np.diag(data.cov_hz2) == pytest.approx(expected, rel=1e-12)


def test_a_fixed_frequency_fit_is_corrected_for_its_amplitude():
    f = np.array([2.5, 3.5])
    fit = _fit(f, None)
    shift = amplitude_factor(fit, 60.0)
    data = swing_data([fit], [60.0], model_rel=0.0)
    assert data.frequencies_hz == pytest.approx(f / (1 - shift), rel=1e-12)
    assert np.all(data.frequencies_hz > f)  # a large swing reads slow
    assert np.diag(data.cov_hz2) == pytest.approx(
        1e-6 + (data.frequencies_hz * 0.5 * shift) ** 2, rel=1e-12
    )
