"""The model of one hang's samples that :mod:`cadcog.dynamics.modalfit` fits, and its derivatives.

``y_c(t) = c_c + Σ_k e^(−σ_k t) (A_kc cos φ_k(t) + B_kc sin φ_k(t))``, ``c = x, y``, with
``φ_k(t) = 2π (f_k t + d_k (1 − e^(−2σ_k t))/(2σ_k))``: for given ``(f, σ, d)`` linear in the
coefficients ``c, A, B`` (the basis, :func:`basis`; columns: the constant, the k damped cosines,
the k damped sines), which :func:`solve` finds by least squares; :func:`projected_jacobian` is
the variable-projection Jacobian of the outer fit over ``(f, σ, d)``, :func:`jacobian` the full
model's (for the covariance).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]

Waves = tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]


def drift_time(t: FloatArray, s: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``h(t) = (1 − e^(−2σt))/(2σ)``, the time integral of a drift that fades as the squared
    amplitude does, and ``∂h/∂σ``, both (n, k) (series near σ = 0, where h → t)."""
    x = 2.0 * np.outer(t, s)
    tt = t[:, None] * np.ones_like(s)[None, :]
    small = np.abs(x) < 1e-4
    safe = np.where(small, 1.0, x)
    h = np.where(small, tt * (1.0 - x / 2.0 + x**2 / 6.0), tt * (-np.expm1(-safe)) / safe)
    # d/dσ of t·(1 − e^(−x))/x with x = 2σt: 2t² (x e^(−x) − (1 − e^(−x)))/x²
    dh = np.where(
        small,
        tt**2 * (-1.0 + 2.0 * x / 3.0),
        2.0 * tt**2 * (safe * np.exp(-safe) + np.expm1(-safe)) / safe**2,
    )
    return h, dh


def waves_at(t: FloatArray, f: FloatArray, s: FloatArray, d: FloatArray) -> Waves:
    """The basis (n, 1 + 2k) at ``(f, σ, d)``, with the envelopes, cosines and sines it is made
    of and the drift's ``h`` and ``∂h/∂σ`` (which the model's derivatives reuse). The phase of
    mode k is ``2π (f_k t + d_k h_k(t))``: its frequency ``f_k + d_k e^(−2σ_k t)`` drifts to
    ``f_k`` as its squared amplitude dies away."""
    env = np.exp(-np.outer(t, s))
    h, dh = drift_time(t, s)
    ph = 2.0 * np.pi * (np.outer(t, f) + h * d[None, :])
    cos, sin = np.cos(ph), np.sin(ph)
    return np.hstack([np.ones((len(t), 1)), env * cos, env * sin]), env, cos, sin, h, dh


def basis(t: FloatArray, f: FloatArray, s: FloatArray, d: FloatArray) -> FloatArray:
    return waves_at(t, f, s, d)[0]


def lstsq(b: FloatArray, rhs: FloatArray) -> FloatArray:
    """Least squares ``b x ≈ rhs`` through the small Gram matrix (a tall LAPACK solve is slow
    under a loaded machine's BLAS threads; the basis is well scaled)."""
    gram = b.T @ b
    sol, *_ = np.linalg.lstsq(gram, b.T @ rhs, rcond=None)
    return np.asarray(sol)


def solve(
    t: FloatArray, y: FloatArray, w: FloatArray, f: FloatArray, s: FloatArray, d: FloatArray
) -> tuple[FloatArray, FloatArray]:
    b = basis(t, f, s, d)
    coef = lstsq(b, y)
    resid = (y - b @ coef) * w[None, :]
    return coef, resid


def model_derivatives(
    t: FloatArray, waves: Waves, coef: FloatArray, d: FloatArray
) -> list[FloatArray]:
    """Per channel, the model's derivative w.r.t. ``(f, σ, d)`` at the linear coefficients
    ``coef``, from :func:`waves_at` at ``(f, σ, d)``: 2 × (n, 3k)."""
    _, env, cos, sin, h, dh = waves
    k = cos.shape[1]
    out = []
    for c in range(2):
        a = coef[1 : 1 + k, c]
        b = coef[1 + k :, c]
        turn = 2.0 * np.pi * env * (-a * sin + b * cos)  # ∂/∂(phase / 2π)
        out.append(
            np.hstack(
                [
                    t[:, None] * turn,
                    -t[:, None] * env * (a * cos + b * sin) + d[None, :] * dh * turn,
                    h * turn,
                ]
            )
        )
    return out


def projected_jacobian(
    t: FloatArray, y: FloatArray, w: FloatArray, f: FloatArray, s: FloatArray, d: FloatArray
) -> FloatArray:
    """Kaufman's variable-projection Jacobian of the weighted residuals w.r.t. (f, σ, d): the
    derivative of the model at the current linear coefficients, projected off the basis."""
    waves = waves_at(t, f, s, d)
    b = waves[0]
    derivs = model_derivatives(t, waves, lstsq(b, y), d)
    return np.vstack([-w[c] * (dv - b @ lstsq(b, dv)) for c, dv in enumerate(derivs)])


def jacobian(
    t: FloatArray, f: FloatArray, s: FloatArray, d: FloatArray, coef: FloatArray, w: FloatArray
) -> FloatArray:
    """Jacobian of both channels' weighted model (the residuals', up to its sign) w.r.t.
    ``(f, σ, d)`` and the linear coefficients (channel by channel), rows stacked by channel:
    shape (2n, 3k + 2(1 + 2k))."""
    waves = waves_at(t, f, s, d)
    basis = waves[0]
    derivs = model_derivatives(t, waves, coef, d)
    nlin = basis.shape[1]
    blocks = []
    for c, dv in enumerate(derivs):
        lin = np.zeros((len(t), 2 * nlin))
        lin[:, c * nlin : (c + 1) * nlin] = basis
        blocks.append(w[c] * np.hstack([dv, lin]))
    return np.vstack(blocks)
