"""The modal fit recovers known frequencies, and its σ are honest (coverage over seeds)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cadcog.core.errors import DegenerateGeometryError
from cadcog.dynamics.modalfit import fit_swing
from cadcog.dynamics.swingfile import Swing


def _signal(rng, freqs, decays, n=2400, rate=40.0, noise=0.02, jitter=0.002):
    t = np.arange(n) / rate + rng.uniform(-jitter, jitter, n)
    t.sort()
    y = np.tile([-30.0, 12.0], (n, 1))
    for f, s in zip(freqs, decays, strict=True):
        a, b = rng.normal(0, 1.0, 2), rng.normal(0, 1.0, 2)
        w = 2 * np.pi * f
        env = np.exp(-s * t)[:, None]
        y += env * (np.cos(w * t)[:, None] * a + np.sin(w * t)[:, None] * b)
    return Swing("S1", t, y + rng.normal(0, noise, y.shape))


def test_frequencies_cover_the_truth_over_seeds():
    freqs, decays = np.array([1.41, 1.68, 3.1]), np.array([0.05, 0.08, 0.1])
    z = []
    for seed in range(20):
        rng = np.random.default_rng(seed)
        fit = fit_swing(_signal(rng, freqs, decays), freqs * rng.uniform(0.95, 1.05, 3))
        assert fit.mode_index.tolist() == [0, 1, 2]
        err = fit.frequencies_hz - freqs
        z.append(err @ np.linalg.solve(fit.frequency_cov_hz2, err))
    # χ² with 3 dof: mean 3; the 95 % quantile 7.81 exceeded in about 1 of 20 seeds.
    assert 1.8 < np.mean(z) < 4.5
    assert sum(np.array(z) > 7.81) <= 4


def test_sigmas_follow_coloured_noise_at_each_modes_own_frequency():
    """AR(1) noise (ρ = 0.7) is ~4 times as dense as white at 1.41 Hz and 0.4 times at 9 Hz (40
    samples/s): each frequency's σ follows the density at its own frequency. The zero-frequency
    factor ``(1 + ρ)/(1 − ρ)`` = 5.7 for both over-stated the fast mode's variance ~14-fold."""
    from scipy.signal import lfilter

    freqs, decays, rho = np.array([1.41, 9.0]), np.array([0.03, 0.05]), 0.7
    z = []
    for seed in range(24):
        rng = np.random.default_rng(100 + seed)
        base = _signal(rng, freqs, decays, noise=0.0)
        white = rng.normal(0.0, 0.03 * np.sqrt(1 - rho**2), base.inc_deg.shape)
        swing = Swing("S1", base.t_s, base.inc_deg + lfilter([1.0], [1.0, -rho], white, axis=0))
        fit = fit_swing(swing, freqs, halves=False)
        assert fit.mode_index.tolist() == [0, 1]
        assert 0.6 < fit.residual_lag1 < 0.8
        z.append((fit.frequencies_hz - freqs) / np.sqrt(np.diag(fit.frequency_cov_hz2)))
    mean_z2 = np.mean(np.square(z), axis=0)
    # a mean of 24 χ²₁ draws: within [0.4, 1.9] with probability > 99 % when σ is right
    assert np.all((mean_z2 > 0.4) & (mean_z2 < 1.9)), mean_z2


def test_the_halves_agree_on_a_swing_the_model_describes():
    """Damped sinusoids in white noise: the halves differ beyond 3 σ of their noise in 0.27 %
    of modes when each half's σ is right; 40 modes here."""
    freqs, decays = np.array([1.41, 3.1]), np.array([0.03, 0.05])
    excess = []
    for seed in range(20):
        rng = np.random.default_rng(200 + seed)
        fit = fit_swing(_signal(rng, freqs, decays), freqs)
        assert fit.halves_excess_hz2 is not None and fit.mode_index.tolist() == [0, 1]
        excess += fit.halves_excess_hz2.tolist()
    assert sum(e > 0 for e in excess) <= 2, excess  # P(> 2 of 40 | p = 0.0027) ≈ 6e-4


def test_a_frequency_that_jumps_mid_record_is_seen_by_the_halves():
    """One mode whose frequency steps up by 0.3 % half-way (phase continuous), which no drift
    that fades with the swing describes: the halves see the step, and a quarter of its square
    (the variance of the halves' mean) is added to the frequency's."""
    f1, step, rate, n = 1.5, 0.003, 40.0, 2400
    t = np.arange(n) / rate
    mid = t[n // 2]
    f = np.where(t < mid, f1, f1 * (1 + step))
    phase = 2 * np.pi * np.concatenate([[0.0], np.cumsum(f[:-1] * np.diff(t))])
    y = np.exp(-0.03 * t)[:, None] * np.column_stack([np.cos(phase), 0.5 * np.sin(phase)])
    rng = np.random.default_rng(5)
    fit = fit_swing(Swing("S1", t, y + rng.normal(0.0, 0.005, y.shape)), [f1])
    assert fit.halves_excess_hz2 == pytest.approx([0.25 * (f1 * step) ** 2], rel=0.05)
    assert fit_swing(Swing("S1", t, y), [f1], halves=False).halves_excess_hz2 is None


def test_modes_too_close_to_resolve_are_fitted_together_and_not_reported():
    rng = np.random.default_rng(3)
    freqs = np.array([0.806, 0.810, 2.4])
    fit = fit_swing(_signal(rng, freqs, [0.02, 0.02, 0.05]), freqs)
    assert fit.mode_index.tolist() == [2]
    assert fit.frequencies_hz[0] == pytest.approx(2.4, abs=5 * np.sqrt(fit.frequency_cov_hz2[0, 0]))


def test_a_mode_that_is_not_there_is_dropped():
    rng = np.random.default_rng(4)
    swing = _signal(rng, [1.5], [0.05])
    fit = fit_swing(swing, [1.5, 2.9])
    assert fit.mode_index.tolist() == [0]


def test_no_swing_is_refused():
    rng = np.random.default_rng(5)
    t = np.arange(2000) / 40.0
    still = Swing("S9", t, np.tile([1.0, 2.0], (2000, 1)) + rng.normal(0, 0.02, (2000, 2)))
    with pytest.raises(DegenerateGeometryError, match="hang S9: no swing mode stands out"):
        fit_swing(still, [1.5, 2.9])


def test_a_swing_of_unresolved_pairs_only_asks_for_a_longer_record():
    # Two modes 0.004 Hz apart swinging strongly, nothing else: the record cannot tell them
    # apart. The refusal says so (it said "no swing mode stands out of the noise", with the
    # pair's large amplitude beside it).
    rng = np.random.default_rng(3)
    freqs = np.array([0.806, 0.810])
    swing = _signal(rng, freqs, [0.02, 0.02])
    expected = r"hang S1: every mode has a neighbour.*record longer"
    with pytest.raises(DegenerateGeometryError, match=expected):
        fit_swing(swing, [*freqs, 2.4])


def _drifting(rng, freqs, decays, drifts, n=2400, rate=40.0, noise=0.02):
    """Modes whose frequency ``f + d e^(−2σt)`` drifts as the squared amplitude dies away,
    the phase integrated numerically on a fine grid (not the fit's closed form)."""
    t = np.arange(n) / rate
    fine = np.linspace(0.0, t[-1], 40 * n)
    y = np.tile([3.0, -1.0], (n, 1))
    for f, s, d in zip(freqs, decays, drifts, strict=True):
        inst = f + d * np.exp(-2 * s * fine)
        phase = np.concatenate([[0.0], np.cumsum(0.5 * (inst[1:] + inst[:-1]) * np.diff(fine))])
        ph = 2 * np.pi * np.interp(t, fine, phase)
        a, b = rng.normal(0, 0.5, 2), rng.normal(0, 0.5, 2)  # under 3°: fitted from t = 0
        env = np.exp(-s * t)[:, None]
        y += env * (np.cos(ph)[:, None] * a + np.sin(ph)[:, None] * b)
    return Swing("S1", t, y + rng.normal(0, noise, y.shape))


def test_a_drifting_frequency_is_fitted_at_its_small_swing_limit():
    """A swing whose modes start 0.4 % slow (a large swing): the drift fit covers the
    small-swing limit over seeds; holding each frequency fixed reads the record's mean, many
    σ away."""
    freqs, decays = np.array([1.41, 3.1]), np.array([0.03, 0.04])
    drifts = -0.004 * freqs
    z_drift, z_fixed = [], []
    for seed in range(12):
        rng = np.random.default_rng(100 + seed)
        swing = _drifting(rng, freqs, decays, drifts)
        fit = fit_swing(swing, freqs)
        assert fit.mode_index.tolist() == [0, 1]
        assert fit.drift_hz is not None
        err = fit.frequencies_hz - freqs
        z_drift.append(err @ np.linalg.solve(fit.frequency_cov_hz2, err))
        fixed = fit_swing(swing, freqs, drift=False)
        assert fixed.drift_hz is None
        err = fixed.frequencies_hz - freqs
        z_fixed.append(err @ np.linalg.solve(fixed.frequency_cov_hz2, err))
        assert fit.drift_hz == pytest.approx(drifts, rel=0.3)  # the drift itself
    # χ² with 2 dof: mean 2, the 95 % quantile 5.99
    assert 1.0 < np.mean(z_drift) < 3.5
    assert sum(np.array(z_drift) > 5.99) <= 3
    assert np.median(z_fixed) > 50


def test_a_quiet_record_with_a_large_drift_is_covered():
    """Low noise (0.0005°) and a 1.2 % drift: the drifts' prior is applied on the scale of the
    noise-weighted residuals (an audit found it applied with the first pass's weights: z of
    −14 and −3 on seed 0)."""
    freqs, decays = np.array([1.41, 3.1]), np.array([0.03, 0.04])
    z = []
    for seed in range(6):
        rng = np.random.default_rng(seed)
        swing = _drifting(rng, freqs, decays, -0.012 * freqs, noise=0.0005)
        fit = fit_swing(swing, freqs)
        z.extend((fit.frequencies_hz - freqs) / np.sqrt(np.diag(fit.frequency_cov_hz2)))
    assert np.max(np.abs(z)) < 3.5, z


def test_a_channel_that_does_not_swing_leaves_the_sigmas_honest():
    """One axis constant (quantised to one value): its residuals are zero, and weighed by them
    the frequencies' σ came out 1e-28 Hz."""
    rng = np.random.default_rng(2)
    freqs = np.array([1.41, 3.1])
    swing = _drifting(rng, freqs, [0.03, 0.04], [0.0, 0.0])
    flat = Swing(
        swing.point_id,
        swing.t_s,
        np.column_stack([swing.inc_deg[:, 0], np.full(len(swing.t_s), 0.25)]),
    )
    fit = fit_swing(flat, freqs)
    sigma = np.sqrt(np.diag(fit.frequency_cov_hz2))
    assert np.all(sigma > 1e-6)
    assert np.all(np.abs(fit.frequencies_hz - freqs) < 5 * sigma)


def test_a_mode_stays_in_its_search_band_whatever_the_passes():
    """One hang of the 3U CubeSat from the nonlinear simulation (benchmarks/study_inertia.py's
    CubeSat row, seed 68, hang +y_30_-30; written by cadcog's swing writer): its faster body
    mode (3.41 Hz predicted) is barely excited, and a tone at 2.36 Hz, the slower body mode
    plus the wire's, stands out. With the search band re-centred at every weighting pass the
    fit walked from 3.41 Hz to that tone, and the tensor came out turned by 26° with a χ² of
    0.47; the band stays where the periodogram put the mode."""
    from cadcog.dynamics.modalfit import SEARCH_BAND
    from cadcog.dynamics.swingfile import read_swings

    (swing,) = read_swings(Path(__file__).parent / "data" / "cubesat_combination_tone.swings.csv")
    # the set-up's CAD modes for that hang on its 300 mm wire (cadcog.dynamics.hungbody)
    predicted = [0.77071, 0.803287, 1.586258, 3.409688]
    fit = fit_swing(swing, predicted)
    found = dict(zip(fit.mode_index.tolist(), fit.frequencies_hz.tolist(), strict=True))
    assert found[2] == pytest.approx(1.586, rel=0.01)
    assert 3 in found  # a weak mode, fitted with a large σ, not another tone
    assert 3.409688 * (1 - 1.01 * SEARCH_BAND) <= found[3] <= 3.409688 * (1 + SEARCH_BAND)
