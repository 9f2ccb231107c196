"""The frequencies of a recorded swing: a sum of damped sinusoids fitted to both axes at once.

Model of one hang's samples (both channels share each mode's frequency, decay and drift):

``y_c(t) = c_c + Σ_k e^(−σ_k t) (A_kc cos φ_k(t) + B_kc sin φ_k(t))``, ``c = x, y``,
``φ_k(t) = 2π (f_k t + d_k (1 − e^(−2σ_k t))/(2σ_k))``.

Mode k's frequency ``f_k + d_k e^(−2σ_k t)`` drifts as its squared amplitude dies away: a
pendulum swings slower the larger its swing, and the wire's own swing, which a tilt sensor does
not see, raises the body modes while it lasts (docs/inertia_validation.md). ``f_k`` is the
small-swing limit the linear model of the hang predicts.

For given ``(f, σ, d)`` the model is linear in ``c, A, B`` (solved by least squares); the outer
fit is over ``(f, σ, d)`` only (variable projection), started from the periodogram's peak nearest
to each mode the CAD predicts. Each channel is weighted by its residual noise; the covariance of
``f`` is the Gauss-Newton one of the full model, scaled for the residuals' correlation in time
(quantisation and unmodelled motion are not white): each parameter by the density at its own
frequency of AR(1) noise with the residuals' lag-1 correlation (:func:`ar1_density`). A mode
whose amplitude is not above :data:`VISIBLE_AMPLITUDE_SIGMA` of its own uncertainty is dropped
(not excited, or not seen by the sensor) and the fit repeated without it.

The fit is then checked against itself: each half of the fitted stretch is fitted alone, and
what the halves' small-swing frequencies disagree by beyond their noise is the model's error
(a large swing's nonlinearity the drift does not follow, energy passing between modes), kept
per mode in :attr:`ModalFit.halves_excess_hz2` for the tensor fit to add to that frequency's
variance.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import DegenerateGeometryError
from cadcog.dynamics.swingfile import Swing
from cadcog.dynamics.swingmodel import jacobian, projected_jacobian, solve

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

#: The prior σ of a mode's frequency drift, a share of its frequency: the swing's own
#: nonlinearity moves a mode by up to about ``A²/8`` (0.35 % for a 10° wire swing, 0.2 % for a
#: 10° body swing: docs/inertia_validation.md), so a fitted drift of several times this is the
#: fit absorbing something else (a beat, energy passing between modes), not the amplitude.
DRIFT_PRIOR_REL = 0.003

#: A fitted drift is bounded by this many prior σ.
MAX_DRIFT_PRIORS = 5.0

#: The fit is repeated, each channel weighed by the last pass's residual noise, until that
#: noise moves by under 1 % or this many passes.
MAX_PASSES = 5

#: A channel's noise is taken as at least this share of the other's (a channel that does not
#: swing, constant or quantised to one value, has none; weighed infinitely it made the
#: frequencies' σ 1e-28 Hz).
NOISE_FLOOR_SHARE = 0.01

#: The two halves of a fit disagree when their frequencies differ by more than this many σ of
#: their noise (each half's own covariance): 3 σ, which noise alone exceeds in 0.27 % of modes.
HALVES_SIGNIFICANCE = 3.0

#: The share of the halves' squared disagreement beyond their noise taken as the whole fit's
#: model-error variance: a quarter, the variance of the halves' mean when their model errors are
#: independent (the whole record weighs both). On noise-free single hangs of the nonlinear
#: simulation the whole fit's squared errors summed to 0.05-0.33 of what the halves' excess
#: predicts with a share of 1 (docs/inertia_validation.md).
HALVES_SHARE = 0.25

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
    residual_lag1 : float
        ``ρ``, the residuals' lag-1 correlation (in [0, 0.95]): each parameter's covariance is
        the white-noise one scaled by :func:`ar1_density` at the parameter's frequency.
    drift_hz : ndarray, shape (k,) or None
        ``d_k``: how far each mode's frequency stood from ``frequencies_hz`` at the start of the
        fit, fading as its squared amplitude; None when the fit held each frequency fixed (then
        ``frequencies_hz`` are the record's mean frequencies, not the small-swing limit).
    halves_excess_hz2 : ndarray, shape (k,) or None
        Each mode's model-error variance from the halves' check (:data:`HALVES_SHARE` of what
        the two halves' frequencies disagree by beyond their noise, 0 when within
        :data:`HALVES_SIGNIFICANCE` σ); NaN where a half did not show the mode (not checked);
        None when not asked for.
    """

    point_id: str
    mode_index: npt.NDArray[np.int64]
    frequencies_hz: FloatArray
    frequency_cov_hz2: FloatArray
    decay_per_s: FloatArray
    amplitudes_deg: FloatArray
    noise_deg: FloatArray
    residual_lag1: float
    drift_hz: FloatArray | None = None
    halves_excess_hz2: FloatArray | None = None

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
            drift_hz=None if self.drift_hz is None else self.drift_hz[idx],
            halves_excess_hz2=(
                None if self.halves_excess_hz2 is None else self.halves_excess_hz2[idx]
            ),
        )


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


def _lag1(resid: FloatArray) -> float:
    """Mean lag-1 autocorrelation of the residual channels (clipped to [0, 0.95])."""
    rho = []
    for c in range(resid.shape[1]):
        r = resid[:, c] - resid[:, c].mean()
        denom = float(r @ r)
        if denom > 0:
            rho.append(float(r[1:] @ r[:-1]) / denom)
    return float(np.clip(np.mean(rho) if rho else 0.0, 0.0, 0.95))


def ar1_density(rho: float, cycles: npt.ArrayLike) -> FloatArray:
    """The spectral density of AR(1) noise of lag-1 correlation ``rho`` at ``cycles`` per
    sample, over that of white noise of the same variance: ``(1 − ρ²)/(1 − 2ρ cos 2πν + ρ²)``,
    ``(1 + ρ)/(1 − ρ)`` at 0. A sinusoid's parameters are as uncertain as the noise is dense
    at its frequency.

    Examples
    --------
    >>> ar1_density(0.5, [0.0, 0.25, 0.5]).round(3).tolist()
    [3.0, 0.6, 0.333]
    >>> ar1_density(0.0, [0.1]).tolist()  # white
    [1.0]
    """
    nu = np.asarray(cycles, dtype=float)
    return (1.0 - rho**2) / (1.0 - 2.0 * rho * np.cos(2.0 * np.pi * nu) + rho**2)


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
    t: FloatArray,
    y: FloatArray,
    w: FloatArray,
    member: FloatArray,
    base: FloatArray,
    drift_sigma: FloatArray | None,
    drift: bool,
) -> tuple[Any, Any]:
    """Residuals and Jacobian in ``x = (group centres, decay rates[, group drifts])``: each
    mode's frequency is its group's centre plus its fixed offset ``base``; a group's modes
    drift alike (with ``drift``). With ``drift_sigma`` (one a group), the drifts have a normal
    prior of that σ about zero (one residual each, on the scale of the weighted residuals)."""
    k, ng = member.shape
    with_prior = drift and drift_sigma is not None
    ds = drift_sigma if drift_sigma is not None else np.ones(0)

    def split(x: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        d = member @ x[ng + k :] if drift else np.zeros(k)
        return member @ x[:ng] + base, x[ng : ng + k], d

    def fun(x: FloatArray) -> FloatArray:
        r = solve(t, y, w, *split(x))[1].T.ravel()
        return np.concatenate([r, x[ng + k :] / ds]) if with_prior else r

    def jac(x: FloatArray) -> FloatArray:
        j = projected_jacobian(t, y, w, *split(x))
        cols = [j[:, :k] @ member, j[:, k : 2 * k]]
        if not drift:
            return np.hstack(cols)
        cols.append(j[:, 2 * k :] @ member)
        if not with_prior:
            return np.hstack(cols)
        prior = np.hstack([np.zeros((ng, ng + k)), np.diag(1.0 / ds)])
        return np.vstack([np.hstack(cols), prior])

    return fun, jac


#: How to record longer, said where a record is too short to resolve its modes.
RECORD_LONGER = (
    "record longer (cadcog acquire records until the swing settles: a lower "
    "--settle-threshold-deg, or a firmer push at release, keeps it recording)"
)


def fit_swing(
    swing: Swing, predicted_hz: npt.ArrayLike, drift: bool = True, halves: bool = True
) -> ModalFit:
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
    drift : bool
        Follow each frequency as it drifts with the dying swing (``f_k + d_k e^(−2σ_k t)``, one
        more unknown a mode) and report its small-swing limit ``f_k`` (default); without,
        each frequency is held fixed and is the record's mean (kept for comparison: a large
        swing then reads slow, and the wire's own swing, which a tilt sensor does not see,
        makes the body modes read fast).
    halves : bool
        Check the fit against itself: fit each half of the fitted stretch alone and keep what
        their frequencies disagree by beyond their noise (:attr:`ModalFit.halves_excess_hz2`;
        default). Without, that attribute is None (three times faster).

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
    start = _small_swing_start(swing)
    t = swing.t_s[start:] - swing.t_s[start]
    y = swing.inc_deg[start:]
    predicted = np.sort(np.asarray(predicted_hz, dtype=float))
    nyquist = 0.5 * swing.rate_hz
    fit = _fit_stretch(swing.point_id, t, y, predicted, nyquist, drift)
    if not halves:
        return fit
    mid = len(t) // 2
    parts: list[ModalFit | None] = []
    for part in (slice(None, mid), slice(mid, None)):
        try:
            parts.append(
                _fit_stretch(
                    swing.point_id, t[part] - t[part][0], y[part], predicted, nyquist, drift
                )
            )
        except DegenerateGeometryError:
            parts.append(None)  # a half that shows no mode checks none
    return replace(fit, halves_excess_hz2=_halves_excess(fit, parts[0], parts[1]))


def _halves_excess(whole: ModalFit, first: ModalFit | None, second: ModalFit | None) -> FloatArray:
    """Each mode of ``whole``: :data:`HALVES_SHARE` of the halves' squared frequency difference
    beyond their noise when it exceeds :data:`HALVES_SIGNIFICANCE` σ, else 0; NaN where a half
    lacks the mode."""
    out = np.full(len(whole.mode_index), np.nan)
    if first is None or second is None:
        return out
    for j, mode in enumerate(whole.mode_index):
        a = np.flatnonzero(first.mode_index == mode)
        b = np.flatnonzero(second.mode_index == mode)
        if a.size == 0 or b.size == 0:
            continue
        diff = float(first.frequencies_hz[a[0]] - second.frequencies_hz[b[0]])
        noise = float(first.frequency_cov_hz2[a[0], a[0]] + second.frequency_cov_hz2[b[0], b[0]])
        beyond = diff**2 > HALVES_SIGNIFICANCE**2 * noise
        out[j] = HALVES_SHARE * (diff**2 - noise) if beyond else 0.0
    return out


def _fit_stretch(
    point_id: str,
    t: FloatArray,
    y: FloatArray,
    predicted: FloatArray,
    nyquist: float,
    drift: bool,
) -> ModalFit:
    """:func:`fit_swing` on the samples ``y`` (n, 2) at ``t`` (n,), from 0 s."""
    start_all, groups = _starts(t, y, predicted)
    groups = [g for g in groups if np.mean(start_all[g]) < 0.9 * nyquist]
    while True:
        fit = _fit_groups(t, y, groups, start_all, nyquist, drift)
        white, cov, rho = _parameter_cov(t, fit)
        amp, amp_se = _amplitudes(fit, white)
        visible = amp > VISIBLE_AMPLITUDE_SIGMA * amp_se
        if visible.all():
            break
        swung = np.std(y - y.mean(axis=0), axis=0) > VISIBLE_AMPLITUDE_SIGMA * fit.noise
        if not visible.any() and any(len(g) > 1 for g in groups) and swung.any():
            # the record swings well above its noise, but an unresolved pair's amplitudes are
            # not determined apart (a beat) and nothing else stands out: the record is too
            # short to see the modes, not the swing too weak
            raise DegenerateGeometryError(
                f"hang {point_id}: every mode has a neighbour closer than this "
                f"{t[-1]:.0f} s record can resolve, and no mode stands out alone; {RECORD_LONGER}"
            )
        groups = [g for g, v in zip(groups, visible, strict=True) if v]
        if not groups:
            seen = ", ".join(f"{a:.2g} ± {e:.2g}" for a, e in zip(amp, amp_se, strict=True))
            raise DegenerateGeometryError(
                f"hang {point_id}: no swing mode stands out of the noise (amplitudes "
                f"{seen}°, each under {VISIBLE_AMPLITUDE_SIGMA:g} σ); was the object released "
                "swinging?"
            )
        if not any(len(g) == 1 for g in groups):
            break  # what it sees are unresolved pairs: said below
    x_c, member, ng = fit.x_c, fit.member, fit.ng
    # Keep the labels in ascending frequency, as the model's modes are (a fit may cross two).
    order = np.argsort(x_c, kind="stable")
    if np.any(order != np.arange(ng)) and all(len(g) == 1 for g in groups):
        labels = list(groups)
        for i, j in enumerate(order):
            groups[int(j)] = labels[i]
    single = [j for j, g in enumerate(groups) if len(g) == 1]
    if not single:
        raise DegenerateGeometryError(
            f"hang {point_id}: every mode has a neighbour closer than this "
            f"{t[-1]:.0f} s record can resolve; {RECORD_LONGER}"
        )
    rows = [int(np.argmax(member[:, j])) for j in single]
    return ModalFit(
        point_id,
        np.array([groups[j][0] for j in single], dtype=np.int64),
        x_c[single],
        np.asarray(cov[np.ix_(single, single)], dtype=float),
        fit.s0[rows],
        amp[single],
        fit.noise,
        rho,
        fit.d_g[single] if drift else None,
    )


@dataclass(frozen=True)
class _GroupFit:
    """One fit of a record by groups of modes (a group: modes too close to resolve, fitted with
    one free frequency and the predicted spacing). ``member`` (k, ng) maps groups to modes and
    ``base`` (k,) is each mode's offset from its group's centre; ``x_c`` the groups' centres,
    ``s0`` the modes' decays, ``d_g`` the groups' drifts; ``f0``, ``d0`` per mode; ``coef`` and
    ``resid`` the linear coefficients and residuals at them; ``noise`` and ``w`` each
    channel's; ``drift_sigma`` the drifts' prior σ (None without drifts)."""

    member: FloatArray
    base: FloatArray
    x_c: FloatArray
    s0: FloatArray
    d_g: FloatArray
    f0: FloatArray
    d0: FloatArray
    coef: FloatArray
    resid: FloatArray
    noise: FloatArray
    w: FloatArray
    drift_sigma: FloatArray | None

    @property
    def k(self) -> int:
        return int(self.member.shape[0])

    @property
    def ng(self) -> int:
        return int(self.member.shape[1])

    @property
    def nd(self) -> int:
        return 0 if self.drift_sigma is None else self.ng


def _fit_groups(
    t: FloatArray,
    y: FloatArray,
    groups: list[list[int]],
    start_all: FloatArray,
    nyquist: float,
    drift: bool,
) -> _GroupFit:
    """Fit the record by ``groups`` from their periodogram starts, reweighing each channel by
    its noise until the noise settles (at most :data:`MAX_PASSES` passes)."""
    from scipy.optimize import least_squares

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
    x_c, s0, d_g = centre0.copy(), np.full(k, 0.05), np.zeros(ng)
    nd = ng if drift else 0
    drift_sigma = DRIFT_PRIOR_REL * centre0 if drift else None
    # The first pass weighs both channels alike and leaves the drifts free (within their
    # bounds): its residuals give each channel's noise. Later passes weigh each channel by
    # it, with the drifts' prior (whose σ is only on the scale of noise-weighted residuals),
    # until the noise settles.
    w, prior, previous = np.ones(2), None, None
    # the search band stays where the periodogram put each group: a frequency that moved
    # within it each pass could walk away (a 3.40 Hz mode reached a 2.35 Hz combination
    # tone over five passes)
    lo = np.concatenate(
        [
            centre0 * (1 - SEARCH_BAND),
            np.zeros(k),
            -MAX_DRIFT_PRIORS * DRIFT_PRIOR_REL * centre0[:nd],
        ]
    )
    hi_f = np.minimum(centre0 * (1 + SEARCH_BAND), nyquist)
    for _ in range(MAX_PASSES):
        hi = np.concatenate(
            [hi_f, member @ x_c + base, MAX_DRIFT_PRIORS * DRIFT_PRIOR_REL * centre0[:nd]]
        )
        x0 = np.clip(np.concatenate([x_c, s0, d_g[:nd]]), lo + 1e-12, hi - 1e-12)

        fun, jac = _objective(t, y, w, member, base, prior, drift)
        sol = least_squares(
            fun, x0, jac=jac, bounds=(lo, hi), x_scale="jac", xtol=1e-12, ftol=1e-12
        )
        x_c, s0 = sol.x[:ng], sol.x[ng : ng + k]
        if drift:
            d_g = sol.x[ng + k :]
        f0, d0 = member @ x_c + base, member @ d_g
        coef, resid = solve(t, y, np.ones(2), f0, s0, d0)
        nparam = 1 + 3 * k + nd
        noise = np.sqrt(np.mean(resid**2, axis=0) * len(t) / (len(t) - nparam))
        settled = previous is not None and bool(np.all(np.abs(noise - previous) <= 0.01 * previous))
        previous = noise
        # a channel that does not swing (constant, quantised) has no noise of its own: it
        # is weighed as a hundredth of the other's, not infinitely
        w = 1.0 / np.maximum(noise, max(NOISE_FLOOR_SHARE * float(np.max(noise)), 1e-12))
        prior = drift_sigma
        if settled:
            break
    return _GroupFit(member, base, x_c, s0, d_g, f0, d0, coef, resid, noise, w, drift_sigma)


def _parameter_cov(t: FloatArray, fit: _GroupFit) -> tuple[FloatArray, FloatArray, float]:
    """The reduced parameters' Gauss-Newton covariance (centres, decays, drifts, linear
    coefficients) with the drifts' prior: as white noise would leave it, and scaled for the
    residuals' lag-1 correlation ρ (returned), each parameter by :func:`ar1_density` at its
    own frequency (a group's centre, drift and a mode's decay and sinusoid at the mode's, the
    constant at 0)."""
    k, ng, nd, member = fit.k, fit.ng, fit.nd, fit.member
    full = jacobian(t, fit.f0, fit.s0, fit.d0, fit.coef, fit.w)
    cols = [full[:, :k] @ member, full[:, k : 2 * k]]
    if fit.drift_sigma is not None:
        cols.append(full[:, 2 * k : 3 * k] @ member)
    reduced = np.hstack([*cols, full[:, 3 * k :]])
    info = reduced.T @ reduced
    if fit.drift_sigma is not None:  # the drifts' prior
        info[ng + k : ng + k + nd, ng + k : ng + k + nd] += np.diag(fit.drift_sigma**-2)
    white = np.linalg.pinv(info)
    rho = _lag1(fit.resid)
    channel = np.concatenate([[0.0], fit.f0, fit.f0])  # constant, cosines, sines
    freq = np.concatenate([fit.x_c, fit.f0, fit.x_c[:nd], channel, channel])
    step_s = float(t[-1] - t[0]) / (len(t) - 1)
    scale = np.sqrt(ar1_density(rho, freq * step_s))
    return white, white * np.outer(scale, scale), rho


def _amplitudes(fit: _GroupFit, white: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Each group's amplitude (both channels' cosine and sine coefficients of its modes) and
    its standard error against white noise: residual structure a linear model leaves (a large
    swing's harmonics) inflates the frequencies' σ, not this test."""
    k, ng, member, coef = fit.k, fit.ng, fit.member, fit.coef
    nlin = 1 + 2 * k
    off = ng + k + fit.nd  # first linear coefficient in the reduced parameters
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
        amp_se[j] = float(np.sqrt(max(grad @ white[np.ix_(idx, idx)] @ grad, 0.0)))
    return amp, amp_se
