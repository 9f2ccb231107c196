"""The swing's model and its derivatives (dynamics/swingmodel.py) against finite differences."""

from __future__ import annotations

import numpy as np
import pytest

from cadcog.dynamics.swingmodel import basis, drift_time, jacobian

T = np.arange(400) / 20.0  # 20 s at 20 samples/s
F, S, D = np.array([1.3, 2.9]), np.array([0.05, 0.12]), np.array([0.004, -0.002])


def _model(f, s, d, coef, w):
    """Both channels' weighted model, stacked as the Jacobian's rows are."""
    b = basis(T, f, s, d)
    return np.concatenate([w[c] * (b @ coef[:, c]) for c in range(2)])


def test_the_jacobian_is_the_models_derivative():
    rng = np.random.default_rng(0)
    coef, w = rng.normal(0.0, 1.0, (5, 2)), np.array([2.0, 0.5])
    jac = jacobian(T, F, S, D, coef, w)
    x0 = np.concatenate([F, S, D, coef.T.ravel()])

    def at(x):
        return _model(x[:2], x[2:4], x[4:6], x[6:].reshape(2, 5).T, w)

    for j in range(len(x0)):
        h = 1e-6 * max(1.0, abs(x0[j]))
        step = np.eye(len(x0))[j] * h
        numeric = (at(x0 + step) - at(x0 - step)) / (2 * h)
        assert jac[:, j] == pytest.approx(numeric, rel=1e-5, abs=1e-6 * np.abs(numeric).max())


def test_the_drift_integral_is_continuous_where_its_series_takes_over():
    """``h = (1 − e^(−2σt))/(2σ)`` and its σ-derivative: the series used below 2σt = 1e-4 meets
    the closed form, and ``∂h/∂σ`` is h's derivative."""
    t = np.array([0.5, 10.0])
    for s in (0.99e-4 / 20.0, 1.01e-4 / 20.0):  # either side of the switch at t = 10 s
        h, dh = drift_time(t, np.array([s]))
        exact = -np.expm1(-2 * s * t) / (2 * s)
        assert h[:, 0] == pytest.approx(exact, rel=1e-12)
        eps = 1e-9
        hp, _ = drift_time(t, np.array([s + eps]))
        hm, _ = drift_time(t, np.array([s - eps]))
        assert dh[:, 0] == pytest.approx((hp - hm)[:, 0] / (2 * eps), rel=1e-4)
