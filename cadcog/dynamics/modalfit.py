"""The frequencies of a recorded swing: a sum of damped sinusoids fitted to both axes at once.

Model of one hang's samples (both channels share each mode's frequency and decay):

``y_c(t) = c_c + Σ_k e^(−σ_k t) (A_kc cos 2πf_k t + B_kc sin 2πf_k t)``, ``c = x, y``.

For given ``(f, σ)`` the model is linear in ``c, A, B`` (solved by least squares); the outer
fit is over ``(f, σ)`` only (variable projection), started from the periodogram's peak nearest
to each mode the CAD predicts. Each channel is weighted by its residual noise; the covariance of
``f`` is the Gauss-Newton one of the full model, inflated for the residuals' correlation in time
(quantisation and unmodelled motion are not white). A mode whose amplitude is not above
:data:`VISIBLE_AMPLITUDE_SIGMA` of its own uncertainty is dropped (not excited, or not seen by
the sensor) and the fit repeated without it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import DegenerateGeometryError
from cadcog.dynamics.swingfile import Swing

FloatArray = npt.NDArray[np.float64]

#: A fitted mode is kept when its amplitude exceeds this many of its standard errors.
VISIBLE_AMPLITUDE_SIGMA = 5.0

#: The fit starts where the readings' swing amplitude has fallen below this (degrees): a
#: pendulum's frequency drifts with its amplitude, and a large swing is not linear.
MAX_FIT_AMPLITUDE_DEG = 3.0

#: The window of that amplitude (s).
AMPLITUDE_WINDOW_S = 2.0

#: The fit keeps at least this share of the record (the last part) whatever the amplitude.
MIN_FIT_SHARE = 0.5

#: Predicted modes closer than this many frequency bins (1/record length) start as one peak.
UNRESOLVED_BINS = 3.0

#: The periodogram peak for a predicted mode is searched within this relative band.
SEARCH_BAND = 0.15

#: Within the band, a peak is a candidate when its power is at least this share of the band's
#: strongest; the nearest candidate to the prediction is taken.
STRONG_PEAK = 0.1


@dataclass(frozen=True)
class ModalFit:
    """The fitted modes of one hang's swing.

    Attributes
    ----------
    point_id : str
    mode_index : ndarray of int, shape (k,)
        Which predicted mode (ascending frequency) each fitted mode is.
    frequencies_hz : ndarray, shape (k,)
    frequency_cov_hz2 : ndarray, shape (k, k)
    decay_per_s : ndarray, shape (k,)
        ``σ_k``: amplitude decay rates (1/s).
    amplitudes_deg : ndarray, shape (k,)
        Initial reading amplitude of each mode (both axes, degrees).
    noise_deg : ndarray, shape (2,)
        Residual standard deviation of each axis.
    correlation_inflation : float
        Factor applied to the covariance for the residuals' correlation in time (≥ 1).
    """

    point_id: str
    mode_index: npt.NDArray[np.int64]
    frequencies_hz: FloatArray
    frequency_cov_hz2: FloatArray
    decay_per_s: FloatArray
    amplitudes_deg: FloatArray
    noise_deg: FloatArray
    correlation_inflation: float

    def take(self, keep: npt.NDArray[np.bool_]) -> ModalFit:
        """The fit with only the modes the mask ``keep`` (k,) selects."""
        idx = np.flatnonzero(keep)
        return replace(
            self,
            mode_index=self.mode_index[idx],
            frequencies_hz=self.frequencies_hz[idx],
            frequency_cov_hz2=self.frequency_cov_hz2[np.ix_(idx, idx)],
            decay_per_s=self.decay_per_s[idx],
            amplitudes_deg=self.amplitudes_deg[idx],
        )


_Waves = tuple[FloatArray, FloatArray, FloatArray, FloatArray]


def _waves(t: FloatArray, f: FloatArray, s: FloatArray) -> _Waves:
    """The basis (n, 1 + 2k) at ``(f, σ)``, with the envelopes, cosines and sines it is made of
    (which the model's derivatives reuse)."""
    env = np.exp(-np.outer(t, s))
    ph = 2.0 * np.pi * np.outer(t, f)
    cos, sin = np.cos(ph), np.sin(ph)
    return np.hstack([np.ones((len(t), 1)), env * cos, env * sin]), env, cos, sin


def _basis(t: FloatArray, f: FloatArray, s: FloatArray) -> FloatArray:
    return _waves(t, f, s)[0]


def _lstsq(b: FloatArray, rhs: FloatArray) -> FloatArray:
    """Least squares ``b x ≈ rhs`` through the small Gram matrix (a tall LAPACK solve is slow
    under a loaded machine's BLAS threads; the basis is well scaled)."""
    gram = b.T @ b
    sol, *_ = np.linalg.lstsq(gram, b.T @ rhs, rcond=None)
    return np.asarray(sol)


def _solve(
    t: FloatArray, y: FloatArray, w: FloatArray, f: FloatArray, s: FloatArray
) -> tuple[FloatArray, FloatArray]:
    b = _basis(t, f, s)
    coef = _lstsq(b, y)
    resid = (y - b @ coef) * w[None, :]
    return coef, resid


def _model_derivatives(t: FloatArray, waves: _Waves, coef: FloatArray) -> list[FloatArray]:
    """Per channel, the model's derivative w.r.t. ``(f, σ)`` at the linear coefficients
    ``coef``, from :func:`_waves` at ``(f, σ)``: 2 × (n, 2k)."""
    _, env, cos, sin = waves
    k = cos.shape[1]
    out = []
    for c in range(2):
        a = coef[1 : 1 + k, c]
        b = coef[1 + k :, c]
        out.append(
            np.hstack(
                [
                    2.0 * np.pi * t[:, None] * env * (-a * sin + b * cos),
                    -t[:, None] * env * (a * cos + b * sin),
                ]
            )
        )
    return out


def _projected_jacobian(
    t: FloatArray, y: FloatArray, w: FloatArray, f: FloatArray, s: FloatArray
) -> FloatArray:
    """Kaufman's variable-projection Jacobian of the weighted residuals w.r.t. (f, σ): the
    derivative of the model at the current linear coefficients, projected off the basis."""
    waves = _waves(t, f, s)
    b = waves[0]
    derivs = _model_derivatives(t, waves, _lstsq(b, y))
    return np.vstack([-w[c] * (d - b @ _lstsq(b, d)) for c, d in enumerate(derivs)])


def _periodogram(t: FloatArray, y: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Power of both channels on a fine, zero-padded grid (uniform resampling)."""
    n = len(t)
    grid = np.linspace(t[0], t[-1], n)
    yy = np.column_stack([np.interp(grid, t, y[:, c]) for c in range(2)])
    yy = yy - yy.mean(axis=0)
    pad = int(2 ** np.ceil(np.log2(8 * n)))
    spec = np.abs(np.fft.rfft(yy * np.hanning(n)[:, None], n=pad, axis=0)) ** 2
    freqs = np.fft.rfftfreq(pad, d=(grid[1] - grid[0]))
    return freqs, spec.sum(axis=1)


def _starts(
    t: FloatArray, y: FloatArray, predicted_hz: FloatArray
) -> tuple[FloatArray, list[list[int]]]:
    """Initial frequencies and the groups of modes too close to resolve in this record: the
    periodogram's peak near each group, keeping the prediction's spacing within a group."""
    freqs, power = _periodogram(t, y)
    duration = t[-1] - t[0]
    starts = np.array(predicted_hz, dtype=float)
    order = np.argsort(starts)
    groups: list[list[int]] = []
    for i in order:
        if groups and starts[i] - starts[groups[-1][-1]] < UNRESOLVED_BINS / duration:
            groups[-1].append(int(i))
        else:
            groups.append([int(i)])
    # Local maxima of the periodogram; each group takes the nearest strong one not yet taken
    # (a strong neighbouring mode inside the search band must not be taken twice).
    is_peak = np.r_[False, (power[1:-1] > power[:-2]) & (power[1:-1] >= power[2:]), False]
    peaks = np.flatnonzero(is_peak)
    taken: set[int] = set()
    for group in groups:
        centre = float(np.mean(starts[group]))
        near = [
            int(i)
            for i in peaks
            if abs(freqs[i] - centre) < SEARCH_BAND * centre and int(i) not in taken
        ]
        if not near:
            continue
        strongest = max(power[i] for i in near)
        strong = [i for i in near if power[i] >= STRONG_PEAK * strongest]
        best = min(strong, key=lambda i: abs(freqs[i] - centre))
        taken.add(best)
        starts[group] = starts[group] - centre + float(freqs[best])
    return starts, groups


def _jacobian(
    t: FloatArray, f: FloatArray, s: FloatArray, coef: FloatArray, w: FloatArray
) -> FloatArray:
    """Jacobian of the weighted residuals of both channels w.r.t. (f, σ, linear coefficients)."""
    waves = _waves(t, f, s)
    basis = waves[0]
    derivs = _model_derivatives(t, waves, coef)
    nlin = basis.shape[1]
    blocks = []
    for c, d in enumerate(derivs):
        lin = np.zeros((len(t), 2 * nlin))
        lin[:, c * nlin : (c + 1) * nlin] = basis
        blocks.append(w[c] * np.hstack([d, lin]))
    return np.vstack(blocks)


def _lag1(resid: FloatArray) -> float:
    """Mean lag-1 autocorrelation of the residual channels (clipped to [0, 0.95])."""
    rho = []
    for c in range(resid.shape[1]):
        r = resid[:, c] - resid[:, c].mean()
        denom = float(r @ r)
        if denom > 0:
            rho.append(float(r[1:] @ r[:-1]) / denom)
    return float(np.clip(np.mean(rho) if rho else 0.0, 0.0, 0.95))


def _small_swing_start(swing: Swing) -> int:
    """Index of the first sample from which the swing stays small enough for the linear model:
    the readings' swing amplitude (``√2 ×`` the larger axis's standard deviation over
    :data:`AMPLITUDE_WINDOW_S`) below :data:`MAX_FIT_AMPLITUDE_DEG`, keeping at least
    :data:`MIN_FIT_SHARE` of the record."""
    t, y = swing.t_s, swing.inc_deg
    window = max(int(AMPLITUDE_WINDOW_S * swing.rate_hz), 4)
    latest = int(len(t) * (1.0 - MIN_FIT_SHARE))
    for i in range(0, max(latest, 1), max(window // 4, 1)):
        block = y[i : i + window]
        if np.sqrt(2.0) * float(np.max(block.std(axis=0))) < MAX_FIT_AMPLITUDE_DEG:
            return i
    return latest


def _objective(
    t: FloatArray, y: FloatArray, w: FloatArray, member: FloatArray, base: FloatArray
) -> tuple[Any, Any]:
    """Residuals and Jacobian in ``x = (group centres, decay rates)``: each mode's frequency is
    its group's centre plus its fixed offset ``base``."""
    k, ng = member.shape

    def fun(x: FloatArray) -> FloatArray:
        return _solve(t, y, w, member @ x[:ng] + base, x[ng:])[1].T.ravel()

    def jac(x: FloatArray) -> FloatArray:
        j = _projected_jacobian(t, y, w, member @ x[:ng] + base, x[ng:])
        return np.hstack([j[:, :k] @ member, j[:, k:]])

    return fun, jac


#: How to record longer, said where a record is too short to resolve its modes.
RECORD_LONGER = (
    "record longer (cadcog acquire records until the swing settles: a lower "
    "--settle-threshold-deg, or a firmer push at release, keeps it recording)"
)


def fit_swing(swing: Swing, predicted_hz: npt.ArrayLike) -> ModalFit:
    """Fit the modes of one hang's swing, starting from the predicted frequencies.

    Modes closer than :data:`UNRESOLVED_BINS` bins of the record are fitted as a group that
    keeps the predicted spacing (one free frequency for the group: two modes the record cannot
    tell apart make a beat, not two frequencies) and are not reported; the tensor fit uses the
    resolved modes only.

    Parameters
    ----------
    swing : Swing
    predicted_hz : array_like, shape (m,)
        The modes the model predicts for this hang, e.g. from the CAD's inertia.

    Returns
    -------
    ModalFit
        The resolved, visible modes only.

    Raises
    ------
    DegenerateGeometryError
        When no resolved mode is visible above the noise (the object did not swing, or the
        record is too short to see it).
    """
    from scipy.optimize import least_squares

    start = _small_swing_start(swing)
    t = swing.t_s[start:] - swing.t_s[start]
    y = swing.inc_deg[start:]
    predicted = np.sort(np.asarray(predicted_hz, dtype=float))
    start_all, groups = _starts(t, y, predicted)
    nyquist = 0.5 * swing.rate_hz
    groups = [g for g in groups if np.mean(start_all[g]) < 0.9 * nyquist]
    while True:
        modes = [k for g in groups for k in g]
        k = len(modes)
        ng = len(groups)
        member = np.zeros((k, ng))
        centre0 = np.array([np.mean(start_all[g]) for g in groups])
        base = np.zeros(k)
        pos = 0
        for j, g in enumerate(groups):
            for m in g:
                member[pos, j] = 1.0
                base[pos] = start_all[m] - centre0[j]
                pos += 1
        x_c, s0 = centre0.copy(), np.full(k, 0.05)
        w = np.ones(2)
        for _ in range(2):  # the second pass weighs each channel by its own noise
            lo = np.concatenate([x_c * (1 - SEARCH_BAND), np.zeros(k)])
            hi = np.concatenate([np.minimum(x_c * (1 + SEARCH_BAND), nyquist), member @ x_c + base])
            x0 = np.clip(np.concatenate([x_c, s0]), lo + 1e-12, hi - 1e-12)

            fun, jac = _objective(t, y, w, member, base)
            sol = least_squares(
                fun, x0, jac=jac, bounds=(lo, hi), x_scale="jac", xtol=1e-12, ftol=1e-12
            )
            x_c, s0 = sol.x[:ng], sol.x[ng:]
            f0 = member @ x_c + base
            coef, resid = _solve(t, y, np.ones(2), f0, s0)
            noise = np.sqrt(np.mean(resid**2, axis=0) * len(t) / (len(t) - (1 + 3 * k)))
            w = 1.0 / np.maximum(noise, 1e-12)
        full = _jacobian(t, f0, s0, coef, w)
        reduced = np.hstack([full[:, :k] @ member, full[:, k:]])
        white = np.linalg.pinv(reduced.T @ reduced)
        rho = _lag1(resid)
        inflation = (1.0 + rho) / (1.0 - rho)
        cov = white * inflation
        nlin = 1 + 2 * k
        off = ng + k  # first linear coefficient in the reduced parameters
        amp = np.zeros(ng)
        amp_se = np.zeros(ng)
        for j in range(ng):
            rows = [i for i in range(k) if member[i, j]]
            idx = [off + c * nlin + 1 + i for c in range(2) for i in rows] + [
                off + c * nlin + 1 + k + i for c in range(2) for i in rows
            ]
            vec = np.array(
                [coef[1 + i, c] for c in range(2) for i in rows]
                + [coef[1 + k + i, c] for c in range(2) for i in rows]
            )
            amp[j] = float(np.linalg.norm(vec))
            grad = vec / max(amp[j], 1e-300)
            # Visible against the noise (white): residual structure a linear model leaves
            # (a large swing's harmonics) inflates the frequencies' σ, not this test.
            amp_se[j] = float(np.sqrt(max(grad @ white[np.ix_(idx, idx)] @ grad, 0.0)))
        visible = amp > VISIBLE_AMPLITUDE_SIGMA * amp_se
        if visible.all():
            break
        swung = np.std(y - y.mean(axis=0), axis=0) > VISIBLE_AMPLITUDE_SIGMA * noise
        if not visible.any() and any(len(g) > 1 for g in groups) and swung.any():
            # the record swings well above its noise, but an unresolved pair's amplitudes are
            # not determined apart (a beat) and nothing else stands out: the record is too
            # short to see the modes, not the swing too weak
            raise DegenerateGeometryError(
                f"hang {swing.point_id}: every mode has a neighbour closer than this "
                f"{t[-1]:.0f} s record can resolve, and no mode stands out alone; {RECORD_LONGER}"
            )
        groups = [g for g, v in zip(groups, visible, strict=True) if v]
        if not groups:
            seen = ", ".join(f"{a:.2g} ± {e:.2g}" for a, e in zip(amp, amp_se, strict=True))
            raise DegenerateGeometryError(
                f"hang {swing.point_id}: no swing mode stands out of the noise (amplitudes "
                f"{seen}°, each under {VISIBLE_AMPLITUDE_SIGMA:g} σ); was the object released "
                "swinging?"
            )
        if not any(len(g) == 1 for g in groups):
            break  # what it sees are unresolved pairs: said below
    # Keep the labels in ascending frequency, as the model's modes are (a fit may cross two).
    order = np.argsort(x_c, kind="stable")
    if np.any(order != np.arange(ng)) and all(len(g) == 1 for g in groups):
        labels = list(groups)
        for i, j in enumerate(order):
            groups[int(j)] = labels[i]
    single = [j for j, g in enumerate(groups) if len(g) == 1]
    if not single:
        raise DegenerateGeometryError(
            f"hang {swing.point_id}: every mode has a neighbour closer than this "
            f"{t[-1]:.0f} s record can resolve; {RECORD_LONGER}"
        )
    rows = [int(np.argmax(member[:, j])) for j in single]
    return ModalFit(
        swing.point_id,
        np.array([groups[j][0] for j in single], dtype=np.int64),
        x_c[single],
        np.asarray(cov[np.ix_(single, single)], dtype=float),
        s0[rows],
        amp[single],
        noise,
        float(inflation),
    )
