"""One hang, from the device's byte stream to averaged samples and a swing record.

:class:`Recorder` opens the stream (waits for the device's header and checks it against the
inclinometer configuration), then for each hang: waits for the swing to settle
(:mod:`cadcog.bench.swing`), averages ``average_s`` seconds of samples, and returns them with
the swing's period and decay. It writes nothing: the caller appends a finished hang to the
readings file, so an interrupted hang leaves no trace.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from cadcog.bench.link import ByteLink, LinkError
from cadcog.bench.protocol import Header, LineParser, LinkStats, Sample
from cadcog.bench.swing import SettleCriterion, SettleDetector, SwingRecord, analyse_swing
from cadcog.core.errors import CadcogError
from cadcog.rig.geometry import axes_beyond_range
from cadcog.rig.inclinometer import InclinometerConfig

FloatArray = npt.NDArray[np.float64]

#: Longest wait for bytes in one read (s): the live display refreshes at least this often.
_READ_SLICE_S = 0.2


class HangError(CadcogError):
    """A hang could not be recorded (it never settled); nothing was recorded for it."""


@dataclass(frozen=True)
class DeviceUnits:
    """How a device's sample values become readings-CSV values and degrees.

    ``adc_sum`` devices: the CSV gets mean counts (``inc_x_counts``), converted to degrees by the
    rig's sensor model as ``cadcog estimate`` will. ``angle`` devices: degrees (``inc_x_deg``).
    """

    header: Header
    config: InclinometerConfig

    @property
    def counts(self) -> bool:
        return self.header.value == "adc_sum"

    @property
    def value_columns(self) -> tuple[str, str]:
        return ("inc_x_counts", "inc_y_counts") if self.counts else ("inc_x_deg", "inc_y_deg")

    def values(self, s: Sample) -> tuple[float, float]:
        """CSV values of a sample: mean counts, or degrees."""
        if self.counts:
            n = self.header.oversample
            return s.x / n, s.y / n
        lsb = self.header.deg_per_lsb or 0.0
        return s.x * lsb, s.y * lsb

    def degrees(self, values: npt.ArrayLike) -> FloatArray:
        """Device readings in degrees of CSV values (any shape)."""
        v = np.asarray(values, dtype=float)
        return self.config.sensor.counts_to_deg(v) if self.counts else v

    def range_problem(self, values: FloatArray) -> str | None:
        """Why samples (n, 2) of CSV values are unusable (saturation, beyond range), or None."""
        deg = self.degrees(values)
        if self.counts:
            top = self.config.sensor.max_counts
            if np.any(values <= 0.5) or np.any(values >= top - 0.5):
                return f"the ADC is at its rail (0 or {top} counts): the sensor is saturated"
        mean = deg.mean(axis=0)
        beyond = axes_beyond_range(float(mean[0]), float(mean[1]), self.config.range_deg)
        if beyond:
            return (
                f"{', '.join(beyond)} beyond the inclinometer's ±{self.config.range_deg:g}° range"
            )
        if np.any(np.abs(deg) > self.config.range_deg):
            return f"samples beyond the inclinometer's ±{self.config.range_deg:g}° range"
        return None


def device_units(header: Header, config: InclinometerConfig, port: str) -> DeviceUnits:
    """Check a device's header against the inclinometer configuration.

    Raises
    ------
    LinkError
        If an ADC device's resolution or reference differs from the configured sensor model
        (its counts would be converted to the wrong angles), or the device is an accelerometer
        (recorded as a log instead: :mod:`cadcog.bench.logrecorder`).
    """
    if header.value == "accel":
        raise LinkError(
            f"{port}: the device is a three-axis accelerometer ({header.describe()}), but the "
            "set-up's [inclinometer] declares an angle-reading inclinometer: declare "
            'device = "accelerometer" and its axes (docs/bench.md)'
        )
    if header.value == "adc_sum":
        s = config.sensor
        if header.adc_bits != s.adc_bits or abs((header.vref_v or 0.0) - s.adc_reference_v) > 1e-3:
            raise LinkError(
                f"{port}: the device reports a {header.adc_bits}-bit ADC at {header.vref_v:g} V, "
                f"the inclinometer configuration says {s.adc_bits}-bit at {s.adc_reference_v:g} V: "
                "fix adc_bits / adc_reference_v in the rig file's [inclinometer] table"
            )
    return DeviceUnits(header, config)


@dataclass(frozen=True)
class HangData:
    """A recorded hang, before it is written.

    Attributes
    ----------
    t_s : ndarray, shape (n,)
        Device times of the averaged samples.
    values : ndarray, shape (n, 2)
        CSV values of the averaged samples (mean counts or degrees).
    degrees : ndarray, shape (n, 2)
        The same as device readings in degrees.
    settled_after_s : float
        From the start of the hang to the settle (s, device time).
    swing : SwingRecord
    amplitude_deg : float
        Swing amplitude when it settled.
    range_problem : str or None
        Saturation or out-of-range readings: the hang is unusable.
    swing_t_s : ndarray, shape (m,)
        Device times of every sample from the start of the hang until it settled.
    swing_deg : ndarray, shape (m, 2)
        Those samples' readings (degrees): the swing file's rows (``cadcog inertia``).
    """

    t_s: FloatArray
    values: FloatArray
    degrees: FloatArray
    settled_after_s: float
    swing: SwingRecord
    amplitude_deg: float
    range_problem: str | None
    swing_t_s: FloatArray = field(default_factory=lambda: np.zeros(0))
    swing_deg: FloatArray = field(default_factory=lambda: np.zeros((0, 2)))

    @property
    def mean_deg(self) -> tuple[float, float]:
        m = self.degrees.mean(axis=0)
        return float(m[0]), float(m[1])

    @property
    def duration_s(self) -> float:
        return float(self.t_s[-1] - self.t_s[0]) if len(self.t_s) else 0.0


#: ``progress(state, t_s, x_deg, y_deg, amplitude_deg)``; state is swinging/settling/averaging.
Progress = Callable[[str, float, float, float, float], None]


class Recorder:
    """Reads a device through a :class:`ByteLink` and records hangs.

    Parameters
    ----------
    link : ByteLink
    config : InclinometerConfig
        Range, and the sensor model of ADC devices.
    criterion : SettleCriterion
    average_s : float
        Seconds of settled samples averaged per hang (device time).
    timeout_s : float
        A stream with no valid sample for this long (link clock) has stopped.
    progress : callable, optional
        Called about every 0.2 s of device time while recording.
    """

    def __init__(
        self,
        link: ByteLink,
        config: InclinometerConfig,
        criterion: SettleCriterion | None = None,
        average_s: float = 10.0,
        timeout_s: float = 5.0,
        progress: Progress | None = None,
    ) -> None:
        if not average_s > 0 or not timeout_s > 0:
            raise ValueError("average_s and timeout_s must be positive")
        self.link = link
        self.config = config
        self.criterion = criterion or SettleCriterion()
        self.average_s = average_s
        self.timeout_s = timeout_s
        self.progress = progress
        self.parser = LineParser()
        self.units: DeviceUnits | None = None

    @property
    def stats(self) -> LinkStats:
        return self.parser.stats

    def open(self) -> DeviceUnits:
        """Ask for the header and wait for it; check it against the configuration.

        Raises
        ------
        LinkError
            Silence, another protocol, or an incompatible device, each naming the link.
        """
        self.link.write(b"?\n")
        start = self.link.clock()
        received = 0
        while self.link.clock() - start < self.timeout_s:
            data = self.link.read(_READ_SLICE_S)
            received += len(data)
            for event in self.parser.feed(data):
                if isinstance(event, Header):
                    self.units = device_units(event, self.config, self.link.name)
                    return self.units
        st = self.stats
        name = self.link.name
        if received == 0:
            raise LinkError(
                f"{name}: no data in {self.timeout_s:g} s: is the device connected and powered, "
                "and running the firmware from firmware/?"
            )
        if st.headers == 0 and st.samples == 0 and st.before_header == 0:
            raise LinkError(
                f"{name}: the device does not speak the cadcog protocol: {st.lines} line(s) in "
                f"{self.timeout_s:g} s, none valid (first: {st.first_rejected or 'no line end'}); "
                "load the firmware from firmware/ and check the baud rate (--baud)"
            )
        raise LinkError(f"{name}: samples but no header in {self.timeout_s:g} s")

    def _samples(self) -> list[Sample]:
        """The next valid samples, waiting up to the timeout (link clock)."""
        start = self.link.clock()
        while True:
            events = self.parser.feed(self.link.read(_READ_SLICE_S))
            samples = []
            for e in events:
                if isinstance(e, Header):
                    if self.units is not None and e != self.units.header:
                        raise LinkError(
                            f"{self.link.name}: the device changed its header mid-run "
                            f"(now {e.describe()}); start again"
                        )
                else:
                    samples.append(e)
            if samples:
                return samples
            if self.link.clock() - start >= self.timeout_s:
                raise LinkError(
                    f"{self.link.name}: the stream stopped: no valid sample for "
                    f"{self.timeout_s:g} s ({self.stats.summary()})"
                )

    def record_hang(self, not_before_s: float | None = None) -> HangData:
        """Wait for the swing to settle, average, and return the hang.

        Parameters
        ----------
        not_before_s : float, optional
            Ignore samples older than this device time (the hang began then).

        Raises
        ------
        HangError
            If it has not settled within ``criterion.max_wait_s``.
        LinkError
            If the stream stops or the device changes.
        """
        if self.units is None:
            self.units = self.open()
        units = self.units
        crit = self.criterion
        detector = SettleDetector(crit)
        swing_t: list[float] = []
        swing_xy: list[tuple[float, float]] = []
        avg_t: list[float] = []
        avg_v: list[tuple[float, float]] = []
        t_start: float | None = None
        last_t = -np.inf
        next_report = -np.inf
        settled_after = amplitude = 0.0
        while True:
            for s in self._samples():
                if not_before_s is not None and s.t_s < not_before_s:
                    continue
                if s.t_s <= last_t:  # the device restarted: start this hang again
                    detector = SettleDetector(crit)
                    swing_t, swing_xy, avg_t, avg_v, t_start = [], [], [], [], None
                last_t = s.t_s
                if t_start is None:
                    t_start = s.t_s
                v = units.values(s)
                x_deg, y_deg = (float(a) for a in units.degrees(v))
                amp = detector.add(s.t_s, x_deg, y_deg)
                if detector.settled_at_s is None:
                    swing_t.append(s.t_s)
                    swing_xy.append((x_deg, y_deg))
                    state = "settling" if detector.calm_since_s is not None else "swinging"
                    if s.t_s - t_start > crit.max_wait_s:
                        raise HangError(
                            f"the swing did not settle in {crit.max_wait_s:g} s: amplitude still "
                            f"{amp:.3f}° (settled means below {crit.threshold_deg:g}° for "
                            f"{crit.hold_s:g} s); is the object touching something, or in a "
                            "draught? Nothing was recorded for this hang"
                        )
                else:
                    state = "averaging"
                    if detector.disturbed:
                        detector.restart()
                        avg_t, avg_v = [], []
                        continue
                    if not avg_t:
                        settled_after = detector.settled_at_s - t_start
                        amplitude = amp
                    avg_t.append(s.t_s)
                    avg_v.append(v)
                    if s.t_s - avg_t[0] >= self.average_s:
                        return self._finish(
                            units, swing_t, swing_xy, avg_t, avg_v, settled_after, amplitude
                        )
                if self.progress is not None and s.t_s >= next_report:
                    next_report = s.t_s + 0.2
                    self.progress(state, s.t_s, x_deg, y_deg, amp)

    def _finish(
        self,
        units: DeviceUnits,
        swing_t: list[float],
        swing_xy: list[tuple[float, float]],
        avg_t: list[float],
        avg_v: list[tuple[float, float]],
        settled_after: float,
        amplitude: float,
    ) -> HangData:
        values = np.array(avg_v)
        deg = units.degrees(values)
        rest = deg.mean(axis=0)
        noise = float(deg.std(axis=0).max())
        sw = np.array(swing_xy) if swing_xy else np.zeros((0, 2))
        swing = analyse_swing(
            swing_t, sw[:, 0], sw[:, 1], (float(rest[0]), float(rest[1])), noise,
            self.criterion.window_s,
        )  # fmt: skip
        return HangData(
            np.array(avg_t),
            values,
            deg,
            float(settled_after),
            swing,
            float(amplitude),
            units.range_problem(values),
            np.asarray(swing_t, dtype=float),
            sw,
        )
