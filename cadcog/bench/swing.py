"""When has a hung object stopped swinging, and how did it swing?

A freshly hung object swings about its suspension point and the swing decays. The readings are
averaged only once it has **settled**:

- the *swing amplitude* over the last ``window_s`` seconds is ``√2 × σ`` of each axis's readings
  in that window (σ the standard deviation; for a sinusoid of amplitude A, √2·σ = A), the larger
  of the two axes. It includes the sensor noise: ``√2·σ = √(A² + 2 σ_noise²)``, so the threshold
  must sit above ``√2 σ_noise`` (0.02° for the paper's equipment at 16× oversampling);
- the object has settled when that amplitude has stayed below ``threshold_deg`` for ``hold_s``
  seconds without a break;
- while averaging, an amplitude above ``disturb_factor × threshold_deg`` (someone touched the
  object or the table) discards the average and starts the settle wait again.

Averaging a residual swing of amplitude A over D seconds leaves an error of at most
``A·T/(π D)`` (T the period): 0.002° for A = 0.1°, T = 0.7 s, D = 10 s, so the threshold is
about patience, not accuracy. All times are device times (s), which lets a simulated device run
faster than real time. Reference: ``docs/bench.md``.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class SettleCriterion:
    """The documented settle criterion (defaults: ``docs/bench.md``).

    Attributes
    ----------
    threshold_deg : float
        Swing amplitude below which the object counts as still (degrees).
    window_s : float
        Window of the amplitude estimate (s); it should span at least one swing period.
    hold_s : float
        How long the amplitude must stay below the threshold (s).
    max_wait_s : float
        Give up on a hang that has not settled after this long (s).
    disturb_factor : float
        While averaging, an amplitude above ``disturb_factor × threshold_deg`` restarts the wait.
    """

    threshold_deg: float = 0.1
    window_s: float = 2.0
    hold_s: float = 3.0
    max_wait_s: float = 300.0
    disturb_factor: float = 2.0

    def __post_init__(self) -> None:
        for name in ("threshold_deg", "window_s", "hold_s", "max_wait_s", "disturb_factor"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be positive, got {value}")
        if self.disturb_factor < 1.0:
            raise ValueError("disturb_factor must be at least 1")


def swing_amplitude_deg(x_deg: npt.ArrayLike, y_deg: npt.ArrayLike) -> float:
    """``√2 × max(σ_x, σ_y)`` of readings (degrees): a sinusoid's amplitude.

    Examples
    --------
    >>> t = np.linspace(0.0, 10.0, 2001)
    >>> round(swing_amplitude_deg(0.3 * np.sin(2 * np.pi * t), np.zeros_like(t)), 3)
    0.3
    """
    x = np.asarray(x_deg, dtype=float)
    y = np.asarray(y_deg, dtype=float)
    return float(np.sqrt(2.0) * max(x.std(), y.std()))


class SettleDetector:
    """Streaming settle detection on (t_s, x_deg, y_deg) samples.

    Call :meth:`add` for each sample in time order; :attr:`settled_at_s` becomes the device
    time at which the criterion was met (the end of the hold), and stays None before.
    """

    def __init__(self, criterion: SettleCriterion) -> None:
        self.criterion = criterion
        self._window: deque[tuple[float, float, float]] = deque()
        self.calm_since_s: float | None = None
        self.settled_at_s: float | None = None
        self.amplitude_deg: float = float("inf")
        self._next_eval_s = -np.inf

    def add(self, t_s: float, x_deg: float, y_deg: float) -> float:
        """Add a sample; return the current amplitude estimate (inf until the window fills)."""
        c = self.criterion
        w = self._window
        w.append((t_s, x_deg, y_deg))
        while w and w[0][0] < t_s - c.window_s:
            w.popleft()
        if t_s < self._next_eval_s:
            return self.amplitude_deg
        self._next_eval_s = t_s + 0.05 * c.window_s  # 20 evaluations per window are plenty
        if w[-1][0] - w[0][0] < 0.9 * c.window_s or len(w) < 4:
            return self.amplitude_deg
        arr = np.array(w)
        self.amplitude_deg = swing_amplitude_deg(arr[:, 1], arr[:, 2])
        if self.amplitude_deg < c.threshold_deg:
            if self.calm_since_s is None:
                self.calm_since_s = t_s
            if self.settled_at_s is None and t_s - self.calm_since_s >= c.hold_s:
                self.settled_at_s = t_s
        else:
            self.calm_since_s = None
        return self.amplitude_deg

    @property
    def disturbed(self) -> bool:
        """True if the amplitude now exceeds the disturbance level."""
        c = self.criterion
        return self.amplitude_deg > c.disturb_factor * c.threshold_deg and np.isfinite(
            self.amplitude_deg
        )

    def restart(self) -> None:
        """Forget the calm period (after a disturbance); keep the window."""
        self.calm_since_s = None
        self.settled_at_s = None


@dataclass(frozen=True)
class SwingRecord:
    """How a hang swung before it settled, for the record.

    Attributes
    ----------
    period_s : float or None
        Dominant swing period (s), None if the swing was too small to measure.
    decay_time_s : float or None
        Time constant τ of the amplitude's exponential decay (s): A(t) = A₀ e^(−t/τ).
    damping_ratio : float or None
        ζ = T / (2π τ).
    start_amplitude_deg : float
        Swing amplitude over the first window after hanging.
    """

    period_s: float | None
    decay_time_s: float | None
    damping_ratio: float | None
    start_amplitude_deg: float


def analyse_swing(
    t_s: npt.ArrayLike,
    x_deg: npt.ArrayLike,
    y_deg: npt.ArrayLike,
    rest_deg: tuple[float, float],
    noise_deg: float,
    window_s: float = SettleCriterion.window_s,
) -> SwingRecord:
    """Period and decay of a swing from its samples (before the settle) and the rest position.

    The period is the peak of the summed power spectrum of both axes (Hann window, zero-padded
    ×8, parabolic refinement of the peak): the dominant mode when two swing modes share the
    motion. The decay time is the slope of ``ln(rms)`` over consecutive one-period blocks whose
    rms exceeds three times ``noise_deg``.

    Parameters
    ----------
    t_s, x_deg, y_deg : array_like, shape (n,)
        Samples in time order, roughly evenly spaced.
    rest_deg : (float, float)
        The settled readings (the average), subtracted from the swing.
    noise_deg : float
        Standard deviation of the readings at rest.
    """
    t = np.asarray(t_s, dtype=float)
    xy = np.stack([np.asarray(x_deg, float) - rest_deg[0], np.asarray(y_deg, float) - rest_deg[1]])
    first = t <= t[0] + window_s if len(t) else np.zeros(0, bool)
    start_amp = float(np.sqrt(2.0) * xy[:, first].std(axis=1).max()) if first.sum() > 3 else 0.0
    floor = 3.0 * max(noise_deg, 1e-9)
    if len(t) < 16 or start_amp < 2.0 * floor or t[-1] - t[0] < 2.0 * window_s:
        return SwingRecord(None, None, None, start_amp)
    dt = float(np.median(np.diff(t)))
    grid = np.arange(t[0], t[-1], dt)
    sig = np.stack([np.interp(grid, t, xy[0]), np.interp(grid, t, xy[1])])
    sig -= sig.mean(axis=1, keepdims=True)
    n = len(grid)
    nfft = 8 * int(2 ** np.ceil(np.log2(n)))
    spec = (np.abs(np.fft.rfft(sig * np.hanning(n), nfft, axis=1)) ** 2).sum(axis=0)
    spec[0] = 0.0
    k = int(np.argmax(spec))
    if 0 < k < len(spec) - 1:
        a, b, c = np.log(spec[k - 1 : k + 2] + 1e-300)
        denom = a - 2 * b + c
        k_ref = k + (0.5 * (a - c) / denom if denom != 0 else 0.0)
    else:
        k_ref = float(k)
    freq = k_ref / (nfft * dt)
    if not freq > 0:
        return SwingRecord(None, None, None, start_amp)
    period = 1.0 / freq
    # Decay: rms of the swing (both axes) in blocks of one period.
    per_block = max(round(period / dt), 2)
    blocks = n // per_block
    times, rms = [], []
    for i in range(blocks):
        seg = sig[:, i * per_block : (i + 1) * per_block]
        r = float(np.sqrt(2.0 * (seg**2).sum(axis=0).mean()))
        if r > floor:
            times.append(grid[i * per_block] + 0.5 * per_block * dt)
            rms.append(r)
    decay = None
    if len(rms) >= 3:
        slope = float(np.polyfit(times, np.log(rms), 1)[0])
        decay = -1.0 / slope if slope < 0 else None
    zeta = period / (2.0 * np.pi * decay) if decay else None
    return SwingRecord(float(period), decay, zeta, start_amp)
