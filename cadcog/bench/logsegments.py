"""A recorded log cut into hangs: where the object hung still, and what happened in between.

The settle criterion is the bench's (:class:`cadcog.bench.swing.SettleCriterion`): the swing
amplitude, √2 × the largest standard deviation of the tilt along any direction over the last
``window_s``, must stay below ``threshold_deg`` for ``hold_s``; what follows, until the
amplitude exceeds the threshold again, is averaged. On a log the whole record is at hand, so
it is cut offline:

1. the samples are averaged into bins of :data:`BIN_S`, or two samples' time for a log slower
   than 40 Hz (:func:`bin_width_s`; a phone's 100-500 Hz noise would
   otherwise hide a settled swing of 0.1°), bins of a gap stay empty;
2. each bin's amplitude is taken over the window ending at it, frame-free: the tilt's
   covariance on the plane ⊥ the window's mean direction, and the magnitude's spread (a
   translation that does not tilt is not stillness either), each less the sensor noise's share
   (estimated in the same window from consecutive bins' differences, which a swing of a few Hz
   hardly moves): a phone's noise alone would otherwise read as a swing of 0.1°;
3. a run of still bins longer than ``hold_s`` is settled from ``hold_s`` after its start to one
   window before its end (the window that ended it already held the start of the motion);
4. consecutive settled spans whose mean directions agree within :data:`SAME_HANG_DEG` are one
   hang (a knock during the averaging, the swing settling again at the same rest); one whose
   spans add up to less than ``min_average_s`` is a pause in the handling, not a hang;
5. a hang was released: between the end of the handling before it (the last bin whose
   magnitude strays more than :data:`SWING_MAGNITUDE_G` from the hang's own rest magnitude: an
   uncalibrated part reads 1 g within its offsets and sensitivities) and its settling, once the
   window is clear of the handling, it swung above :data:`SWING_FACTOR` × the threshold. A
   settled stretch without that swing is a rest (the object set down on a table, the phone
   before it was fixed), not a hang;
6. what lies between two hangs is handling, unless it looks like a swing that never settled:
   magnitude within :data:`SWING_MAGNITUDE_G` of the hangs' median rest magnitude and the
   amplitude above the threshold throughout, for longer than twice ``hold_s``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from cadcog.bench.accellog import MAX_GAP_S, AccelLog
from cadcog.bench.swing import SettleCriterion
from cadcog.core.units import rad_to_deg
from cadcog.dynamics.swingfile import Swing
from cadcog.rig.accelerometer import swing_angles_deg

FloatArray = npt.NDArray[np.float64]

#: Width of the bins the samples are averaged into (s): 20 per second, the rate of the bench's
#: devices (a swing of 0.3-5 Hz is still resolved).
BIN_S = 0.05


def bin_width_s(rate_hz: float) -> float:
    """The bins of a log sampled at ``rate_hz``: :data:`BIN_S`, or two samples' time when that
    is longer (a bin must hold a sample even when a clock of whole milliseconds or a little
    jitter moves one across a boundary: at 20 Hz, 0.05 s bins are a quarter empty).

    Examples
    --------
    >>> bin_width_s(200.0), bin_width_s(20.0)
    (0.05, 0.1)
    """
    return max(BIN_S, 2.0 / rate_hz)


#: Two settled spans whose mean directions agree within this angle (degrees) are one hang; a
#: re-hang from another point tilts the object by far more (``cadcog plan`` wants its lines 20°
#: or more apart).
SAME_HANG_DEG = 1.0
#: A stretch between hangs whose magnitude stays within this of 1 g (g) is a swing, not
#: handling (handling carries the object: its magnitude swings by tenths of g).
SWING_MAGNITUDE_G = 0.05
#: A hang swings after its release: its amplitude exceeds this many thresholds at least once
#: between the release and the settling (a gentle release of 0.5° is 5 thresholds of 0.1°).
SWING_FACTOR = 2.0


@dataclass(frozen=True)
class LogHang:
    """One hang found in a log.

    Attributes
    ----------
    start_s, end_s : float
        From the end of the handling before it (the release) to the end of its last settled
        span (log time).
    settled_s : float
        When it first settled (log time).
    spans_s : tuple of (float, float)
        The averaged spans (more than one when a knock interrupted the averaging).
    t_s : ndarray, shape (m,)
        The averaged bins' times.
    acc_g : ndarray, shape (m, 3)
        The averaged bins' mean readings (g, the sensor's axes).
    swing_start_deg : float
        Amplitude over the first window after the release.
    swing_max_deg : float
        The largest amplitude between the release (once the window is clear of the handling)
        and the settling: 0 when nothing swung (a rest, not a hang).
    swing_end_s : float
        The end of the release's undisturbed decay: the end of its first averaged span, or of
        a later one when the amplitude between them stayed below :data:`SWING_FACTOR` × the
        threshold (a swing hovering at the threshold, not a knock). NaN: not known (the first
        span's end is taken).
    """

    start_s: float
    end_s: float
    settled_s: float
    spans_s: tuple[tuple[float, float], ...]
    t_s: FloatArray
    acc_g: FloatArray
    swing_start_deg: float
    swing_max_deg: float = 0.0
    swing_end_s: float = float("nan")

    @property
    def averaged_s(self) -> float:
        return float(sum(b - a for a, b in self.spans_s))

    @property
    def direction(self) -> FloatArray:
        m = self.acc_g.mean(axis=0)
        return np.asarray(m / np.linalg.norm(m))


@dataclass(frozen=True)
class Unsettled:
    """A stretch between hangs that swung without settling: a hang that never settled.

    Attributes
    ----------
    start_s, end_s : float
    amplitude_deg : float
        The smallest amplitude it reached.
    """

    start_s: float
    end_s: float
    amplitude_deg: float


@dataclass(frozen=True)
class Segmentation:
    """A log cut into hangs, and what was not a hang."""

    hangs: tuple[LogHang, ...]
    unsettled: tuple[Unsettled, ...]
    short_spans: tuple[tuple[float, float], ...]
    rests: tuple[tuple[float, float], ...]
    bin_t_s: FloatArray
    amplitude_deg: FloatArray
    ends_in_hang: float | None = None
    bin_s: float = BIN_S


def _bins(log: AccelLog, width: float) -> tuple[FloatArray, FloatArray, npt.NDArray[np.bool_]]:
    """Bin times, bin means (g) and which bins hold samples."""
    t0 = log.t_s[0]
    idx = np.floor((log.t_s - t0) / width).astype(np.int64)
    n = int(idx[-1]) + 1
    count = np.bincount(idx, minlength=n).astype(float)
    sums = np.stack([np.bincount(idx, log.acc_g[:, j], minlength=n) for j in range(3)], axis=1)
    full = count > 0
    mean = np.where(full[:, None], sums / np.maximum(count, 1.0)[:, None], np.nan)
    return t0 + (np.arange(n) + 0.5) * width, mean, full


def _window_sums(x: FloatArray, w: int) -> FloatArray:
    """Sums of ``x`` (n, ...) over the trailing windows of ``w`` rows (fewer at the start)."""
    c = np.concatenate([np.zeros((1, *x.shape[1:])), np.cumsum(x, axis=0)])
    lo = np.maximum(np.arange(1, len(x) + 1) - w, 0)
    return np.asarray(c[1:] - c[lo])


def amplitudes_deg(mean_g: FloatArray, full: npt.NDArray[np.bool_], window: int) -> FloatArray:
    """Each bin's swing amplitude over the ``window`` bins ending at it (degrees; inf where the
    window is not at least 90 % full).

    √2 × the root of the largest eigenvalue of the tilt's covariance on the plane ⊥ the mean
    direction, or of the magnitude's variance (in g, read as radians) if that is larger, each
    less the noise's variance: a quarter of the mean squared difference of consecutive bins'
    directions (white noise of σ on each of the two tilt axes gives 4σ²), half of the
    magnitudes'.

    Examples
    --------
    >>> t = np.arange(0.0, 4.0, 0.05)
    >>> th = np.radians(0.3) * np.sin(2 * np.pi * t)
    >>> a = np.stack([np.sin(th), np.zeros_like(th), np.cos(th)], axis=1)
    >>> round(float(amplitudes_deg(a, np.ones(len(t), bool), 40)[-1]), 2)
    0.3
    """
    return _spreads(mean_g, full, window)[0]


def _spreads(
    mean_g: FloatArray, full: npt.NDArray[np.bool_], window: int
) -> tuple[FloatArray, FloatArray]:
    """:func:`amplitudes_deg`, and the magnitude's own amplitude (g): handling (the object carried
    or set down) moves the magnitude by tenths of g, a hung swing hardly at all."""
    ok = full[:, None]
    mag = np.where(full, np.linalg.norm(np.where(ok, mean_g, 1.0), axis=1), 1.0)
    d = np.where(ok, mean_g / mag[:, None], 0.0)
    n = _window_sums(full.astype(float)[:, None], window)[:, 0]
    s1 = _window_sums(d, window)
    s2 = _window_sums(d[:, :, None] * d[:, None, :], window)
    m1 = _window_sums(np.where(full, mag, 0.0)[:, None], window)[:, 0]
    m2 = _window_sums(np.where(full, mag * mag, 0.0)[:, None], window)[:, 0]
    # Consecutive bins' differences (a pair with an empty bin counts for nothing).
    pair = np.concatenate([[False], full[1:] & full[:-1]])
    dd = np.where(pair, np.sum(np.diff(d, axis=0, prepend=d[:1]) ** 2, axis=1), 0.0)
    dm = np.where(pair, np.diff(mag, prepend=mag[:1]) ** 2, 0.0)
    npair = np.maximum(_window_sums(pair.astype(float)[:, None], window)[:, 0], 1.0)
    tilt_noise = _window_sums(dd[:, None], window)[:, 0] / npair / 4.0
    mag_noise = _window_sums(dm[:, None], window)[:, 0] / npair / 2.0
    nn = np.maximum(n, 1.0)
    mean = s1 / nn[:, None]
    cov = s2 / nn[:, None, None] - mean[:, :, None] * mean[:, None, :]
    unit = mean / np.maximum(np.linalg.norm(mean, axis=1), 1e-12)[:, None]
    proj = np.eye(3)[None] - unit[:, :, None] * unit[:, None, :]
    tilt = np.einsum("kij,kjl,klm->kim", proj, cov, proj)
    lam = np.linalg.eigvalsh(tilt)[:, -1]
    mag_var = m2 / nn - (m1 / nn) ** 2
    spread = np.maximum(lam - tilt_noise, mag_var - mag_noise)
    amp = np.sqrt(2.0 * np.maximum(spread, 0.0))
    mag_amp = np.sqrt(2.0 * np.maximum(mag_var - mag_noise, 0.0))
    filled = n >= 0.9 * window
    return np.where(filled, rad_to_deg(amp), np.inf), np.where(filled, mag_amp, np.inf)


def _runs(flag: npt.NDArray[np.bool_]) -> list[tuple[int, int]]:
    """``[start, end)`` index ranges of the True runs of ``flag``."""
    edges = np.diff(np.concatenate([[0], flag.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True))


def segment_log(
    log: AccelLog, criterion: SettleCriterion, min_average_s: float = 10.0
) -> Segmentation:
    """Cut ``log`` into hangs (module docstring).

    Parameters
    ----------
    log : AccelLog
    criterion : SettleCriterion
        The bench's settle criterion (its ``max_wait_s`` is not used: a log has no waiting).
    min_average_s : float
        A settled stretch shorter than this is not a hang (a pause while handling).
    """
    width = bin_width_s(log.rate_hz)
    t, mean, full = _bins(log, width)
    # A gap in the log breaks any span that would straddle it.
    gaps = np.flatnonzero(np.diff(log.t_s) > MAX_GAP_S)
    for g in gaps:
        full[(t > log.t_s[g]) & (t < log.t_s[g + 1])] = False
    window = max(round(criterion.window_s / width), 4)
    amp, mag_amp = _spreads(mean, full, window)
    handled = full & (mag_amp > SWING_MAGNITUDE_G)  # the window holds handling
    still = full & (amp < criterion.threshold_deg)
    hold = round(criterion.hold_s / width)
    # A run ends when the window ending at a bin first spreads beyond the threshold: the motion
    # began up to a window earlier, so the run's last window is not averaged.
    spans = [(a + hold, b - window) for a, b in _runs(still) if b - window - a > hold]
    found = _merge(spans, t, mean, full, amp, window, width, handled, criterion.threshold_deg)
    short = [(h.settled_s, h.end_s) for h in found if h.averaged_s < min_average_s]
    found = [h for h in found if h.averaged_s >= min_average_s]
    threshold = SWING_FACTOR * criterion.threshold_deg
    hangs = [h for h in found if h.swing_max_deg > threshold]
    rests = [(h.start_s, h.end_s) for h in found if not h.swing_max_deg > threshold]
    stills = [(h.settled_s, h.end_s) for h in found] + short
    swings = _swinging(found, t, mean, full & ~handled, amp, criterion.threshold_deg, width)
    unsettled = _unsettled(swings, stills, criterion.hold_s, width)
    # A swing of a window or more (or a stillness too short to average) that the log's end
    # cuts: the recording stopped during a hang.
    ends = None
    tail = t[-1] - window * width
    last = [
        u.start_s for u in swings if u.end_s >= tail and u.end_s - u.start_s >= criterion.window_s
    ] + [a for a, b in short if b >= tail]
    if last:
        ends = min(last)
        unsettled = [u for u in unsettled if u.end_s < tail]
        short = [(a, b) for a, b in short if b < tail]
    return Segmentation(
        tuple(hangs), tuple(unsettled), tuple(short), tuple(rests), t, amp, ends, width
    )


def _direction(mean: FloatArray, full: npt.NDArray[np.bool_], a: int, b: int) -> FloatArray:
    m = np.nanmean(np.where(full[a:b, None], mean[a:b], np.nan), axis=0)
    return np.asarray(m / np.linalg.norm(m))


def _merge(
    spans: list[tuple[int, int]],
    t: FloatArray,
    mean: FloatArray,
    full: npt.NDArray[np.bool_],
    amp: FloatArray,
    window: int,
    width: float,
    handled: npt.NDArray[np.bool_],
    threshold_deg: float,
) -> list[LogHang]:
    groups: list[list[tuple[int, int]]] = []
    for s in spans:
        if groups:
            d0, d1 = _direction(mean, full, *groups[-1][-1]), _direction(mean, full, *s)
            angle = float(rad_to_deg(np.arccos(np.clip(d0 @ d1, -1.0, 1.0))))
            # the same rest, and no handling between: a knock, not a re-hang that happens to
            # point the same way
            if angle < SAME_HANG_DEG and not handled[groups[-1][-1][1] : s[0]].any():
                groups[-1].append(s)
                continue
        groups.append([s])
    hangs = []
    previous_end = 0
    for group in groups:
        first, last = group[0][0], group[-1][1]
        # The release: the last bin before the settle where the magnitude left 1 g (handling),
        # or the end of the previous hang.
        lo = previous_end
        mag = np.linalg.norm(np.where(full[:, None], mean, 1.0), axis=1)
        idx = np.concatenate([np.arange(a, b) for a, b in group])
        idx = idx[full[idx]]
        rest = float(np.linalg.norm(mean[idx].mean(axis=0)))
        away = np.flatnonzero(np.abs(mag[lo:first] - rest) > SWING_MAGNITUDE_G)
        release = lo + (int(away[-1]) + 1 if len(away) else 0)
        start_amp = amp[min(release + window, first)]
        swung = amp[release + window : first]
        swung = swung[np.isfinite(swung)]
        end = group[0][1]
        for a, b in group[1:]:  # the decay goes on through a span that only hovered
            between = amp[end:a]
            if np.any(between[np.isfinite(between)] > SWING_FACTOR * threshold_deg):
                break
            end = b
        hangs.append(
            LogHang(
                float(t[release] - 0.5 * width),
                float(t[last - 1] + 0.5 * width),
                float(t[first] - 0.5 * width),
                tuple((float(t[a] - 0.5 * width), float(t[b - 1] + 0.5 * width)) for a, b in group),
                t[idx],
                mean[idx],
                float(start_amp) if np.isfinite(start_amp) else float("nan"),
                float(swung.max()) if len(swung) else 0.0,
                float(t[end - 1] + 0.5 * width),
            )
        )
        previous_end = last
    return hangs


def _swinging(
    hangs: list[LogHang],
    t: FloatArray,
    mean: FloatArray,
    full: npt.NDArray[np.bool_],
    amp: FloatArray,
    threshold_deg: float,
    width: float,
) -> list[Unsettled]:
    """Every stretch outside the hangs where the object hung swinging: the magnitude near its
    rest and no handling in the window (``full`` has those bins off), the amplitude at or above
    the threshold."""
    inside = np.zeros(len(t), dtype=bool)
    for h in hangs:
        inside[(t >= h.start_s) & (t <= h.end_s)] = True
    mag = np.linalg.norm(np.where(full[:, None], mean, 0.0), axis=1)
    rest = float(np.median([np.linalg.norm(h.acc_g.mean(axis=0)) for h in hangs])) if hangs else 1.0
    swinging = (
        full
        & ~inside
        & (np.abs(mag - rest) <= SWING_MAGNITUDE_G)
        & np.isfinite(amp)
        & (amp >= threshold_deg)
    )
    return [
        Unsettled(float(t[a] - 0.5 * width), float(t[b - 1] + 0.5 * width), float(amp[a:b].min()))
        for a, b in _runs(swinging)
    ]


def _unsettled(
    swings: list[Unsettled], stills: list[tuple[float, float]], hold_s: float, width: float
) -> list[Unsettled]:
    """The swings longer than twice the hold not followed by a stillness (a swing that then
    settled, however briefly, is a hang's release, not a hang that never settled)."""
    starts = np.array(sorted(a for a, _ in stills)) if stills else np.zeros(0)
    out = []
    for u in swings:
        after = starts[(starts >= u.end_s - width) & (starts <= u.end_s + hold_s + width + 5.0)]
        if not len(after) and u.end_s - u.start_s > 2 * hold_s:
            out.append(u)
    return out


#: A swing taken from a log starts this long (s) after the release found: the hand's last
#: motion before it let go stays within the magnitude test (0.7-0.9 s in the study's logs) and
#: is not a swing (the fit took it for a mode of 1.6 Hz and 2°).
SWING_SKIP_S = 2.0


def hang_swing(
    log: AccelLog, hang: LogHang, point_id: str, axes: tuple[str, str, str], turned: bool = False
) -> Swing:
    """The swing of a found hang, as a swing file holds it (``cadcog inertia``): the log's own
    samples (not the bins) from :data:`SWING_SKIP_S` after the release to the end of its
    undisturbed decay (``LogHang.swing_end_s``: the swing goes on decaying below the settle
    threshold, and a longer record resolves its modes better; a knock ends it), in object-axis
    angles (:func:`cadcog.rig.accelerometer.swing_angles_deg`), the log's clock. ``turned``: the
    hang was read with the sensor turned 180° about its own z axis on its mount (a reversal):
    its x and y readings change sign before they are turned into object axes.

    Examples
    --------
    >>> from pathlib import Path
    >>> t = np.arange(0.0, 5.0, 0.5)
    >>> log = AccelLog(Path("x.csv"), t, np.tile([0.0, 0.5, 0.75**0.5], (10, 1)), np.arange(10))
    >>> hang = LogHang(0.5, 5.0, 3.5, ((3.5, 5.0),), t[7:], log.acc_g[7:], 0.0)
    >>> sw = hang_swing(log, hang, "S1", ("-y", "+x", "+z"))
    >>> sw.t_s.tolist(), sw.inc_deg.round(6).tolist()
    ([2.5, 3.0, 3.5, 4.0, 4.5], [[30.0, 0.0], [30.0, 0.0], [30.0, 0.0], [30.0, 0.0], [30.0, 0.0]])

    A reversal turns the sensor about its own z axis; here that is the object's x axis, about
    which the reading's x angle does not change:

    >>> hang_swing(log, hang, "S1", ("+y", "+z", "+x"), turned=True).inc_deg[0].round(6).tolist()
    [60.0, 0.0]
    """
    end = hang.swing_end_s if np.isfinite(hang.swing_end_s) else hang.spans_s[0][1]
    keep = (log.t_s >= hang.start_s + SWING_SKIP_S) & (log.t_s <= end)
    acc = log.acc_g[keep] * (np.array([-1.0, -1.0, 1.0]) if turned else 1.0)
    return Swing(point_id, log.t_s[keep], swing_angles_deg(acc, axes))
