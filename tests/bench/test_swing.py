"""Settle detection and swing analysis on signals whose answer is known."""

from __future__ import annotations

import numpy as np
import pytest

from cadcog.bench.swing import SettleCriterion, SettleDetector, analyse_swing


def _decay(seed, a0=3.0, tau=5.0, period=0.7, noise=0.01, rate=20.0, duration=60.0):
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration, 1.0 / rate)
    x = 12.0 + a0 * np.exp(-t / tau) * np.cos(2 * np.pi * t / period + 0.3)
    y = -4.0 + 0.5 * a0 * np.exp(-t / tau) * np.sin(2 * np.pi * t / period)
    return t, x + rng.normal(0, noise, t.size), y + rng.normal(0, noise, t.size)


@pytest.mark.parametrize("seed", range(5))
def test_settle_time_follows_the_true_envelope(seed):
    """The envelope A₀e^(−t/τ) crosses the threshold at t*; the window's amplitude lags it by
    about half a window, and the hold adds its length: settled at ≈ t* + w/2 + hold."""
    c = SettleCriterion(threshold_deg=0.1, window_s=2.0, hold_s=3.0)
    t, x, y = _decay(seed)
    det = SettleDetector(c)
    for ti, xi, yi in zip(t, x, y, strict=True):
        det.add(ti, xi, yi)
        if det.settled_at_s is not None:
            break
    t_star = 5.0 * np.log(3.0 / 0.1)
    assert det.settled_at_s == pytest.approx(t_star + 0.5 * c.window_s + c.hold_s, abs=0.6)


def test_noise_above_the_threshold_never_settles():
    c = SettleCriterion(threshold_deg=0.1)
    t, x, y = _decay(0, noise=0.1)  # √2·σ_noise = 0.14° > 0.1°
    det = SettleDetector(c)
    for ti, xi, yi in zip(t, x, y, strict=True):
        det.add(ti, xi, yi)
    assert det.settled_at_s is None
    assert det.amplitude_deg == pytest.approx(np.sqrt(2) * 0.1, rel=0.3)


def test_a_knock_while_averaging_is_a_disturbance():
    det = SettleDetector(SettleCriterion(threshold_deg=0.1, window_s=2.0, hold_s=1.0))
    for ti in np.arange(0, 10, 0.05):
        det.add(ti, 0.0, 0.0)
    assert det.settled_at_s is not None and not det.disturbed
    for ti in np.arange(10, 11, 0.05):
        det.add(ti, 0.5 * np.sin(9 * ti), 0.0)
    assert det.disturbed


@pytest.mark.parametrize(("period", "tau"), [(0.7, 5.0), (1.3, 9.0), (0.45, 2.5)])
def test_period_and_decay_are_measured(period, tau):
    t, x, y = _decay(1, tau=tau, period=period, duration=4 * tau)
    rec = analyse_swing(t, x, y, (12.0, -4.0), 0.01)
    assert rec.period_s == pytest.approx(period, rel=0.01)
    assert rec.decay_time_s == pytest.approx(tau, rel=0.1)
    assert rec.damping_ratio == pytest.approx(period / (2 * np.pi * tau), rel=0.1)
    assert rec.start_amplitude_deg == pytest.approx(3.0, rel=0.35)


def test_no_swing_no_period():
    t = np.arange(0, 20, 0.05)
    rec = analyse_swing(t, np.zeros_like(t), np.zeros_like(t), (0.0, 0.0), 0.01)
    assert rec.period_s is None and rec.decay_time_s is None


def test_criterion_is_validated():
    with pytest.raises(ValueError, match="threshold_deg must be positive"):
        SettleCriterion(threshold_deg=0.0)
