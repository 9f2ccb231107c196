"""A simulated measurement device: the physics of a hang, the sensor, the link's faults.

Each hang draws, as :mod:`cadcog.validation.campaign` does, the suspension point's play and wire
offset and the inclinometer's bias (uniform ±accuracy per axis, fixed during the hang); the ME's CoG
error is drawn once per device (one physical object). The equilibrium vertical comes from
:func:`cadcog.uncertainty.montecarlo.hang`; about it the object swings on the set-up's (or rig's)
wire, in the modes :func:`cadcog.dynamics.hungbody.hang_modes` gives for the CAD mass properties
(the wire's own pendulum and the body's modes, as the inclinometer at its sensing point sees them:
what ``cadcog plan`` and ``cadcog inertia`` model), each released with a random amplitude and phase
and damped viscously. The sensor adds white noise per conversion, saturates at its range and
quantises (an analog sensor read by an ADC with oversampling, or a digital one sending angles). The
link drops lines, corrupts bytes and inserts noise. Everything is drawn from one seeded generator,
so a device with the same seed and the same sequence of calls gives the same bytes.

Two ways to run it:

- :class:`SimulatedLink`: the device as a :class:`~cadcog.bench.link.ByteLink` without a port,
  advancing its clock by each read (deterministic; simulated time, no waiting);
- :class:`PtyDevice`: a thread writing to a pseudo-terminal whose path pyserial opens as it opens
  a real port, running ``time_scale`` times faster than real time (``cadcog acquire --simulate``).
"""

from __future__ import annotations

import errno
import os
import threading
import time
import tty
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Literal

import numpy as np

from cadcog.bench.protocol import Header, format_header, format_sample
from cadcog.bench.target import BenchTarget
from cadcog.core.errors import ReadingsError
from cadcog.core.units import STANDARD_GRAVITY_M_S2
from cadcog.dynamics.hungbody import HangGeometry, hang_modes
from cadcog.rig.inclinometer import sensor_readings
from cadcog.uncertainty.montecarlo import draw_perturbations, hang

if TYPE_CHECKING:
    from cadcog.dynamics.context import InertiaContext

#: ``deg_per_lsb`` of the Murata SCL3300's angle outputs: angle = raw / 2¹⁴ × 90°.
SCL3300_DEG_PER_LSB = 90.0 / 2**14


@dataclass(frozen=True)
class DeviceSpec:
    """The simulated hardware.

    Attributes
    ----------
    kind : "analog" or "digital"
        ``analog``: an ADC reading an analog inclinometer with the rig's sensor model, summing
        ``oversample`` conversions per sample. ``digital``: an SCL3300-like sensor sending angles.
    rate_hz : float
        Samples per second (the firmware's default).
    oversample : int
        Conversions per sample (analog).
    noise_deg : float
        White noise per conversion (analog) or per sample (digital), degrees. The analog default,
        0.05°, is the paper rig's ``[error_model] sensor_noise_deg``; the digital one about the
        SCL3300's in its low-noise inclination mode (an assumption).
    """

    kind: Literal["analog", "digital"] = "analog"
    rate_hz: float = 20.0
    oversample: int = 16
    noise_deg: float | None = None

    @property
    def sample_noise_deg(self) -> float:
        if self.noise_deg is not None:
            return self.noise_deg
        return 0.05 if self.kind == "analog" else 0.005


@dataclass(frozen=True)
class SimulatorSettings:
    """Physics, link faults and injected failures of the simulated device.

    Attributes
    ----------
    damping_ratio : float
        ζ of both swing modes (an assumption: a steel block on a thin wire in still air decays
        by a factor e in about 8 periods at 0.02).
    start_amplitude_deg : (float, float)
        Each mode starts with an amplitude uniform in this range and a uniform phase.
    line_drop_probability, line_corrupt_probability, noise_burst_probability : float
        Per line: lost, one byte replaced, or preceded by 1-20 random bytes.
    header_every_s : float
        The header is repeated this often (device time), as the firmware does.
    slipped_hangs : tuple of int
        Hang attempts (1 for the first ``hang`` call) whose wire slips ``slip_mm`` along the
        face: a bad hang the consistency check must catch.
    slip_mm : float
    never_settle : bool
        A draught keeps the object swinging (no damping): no hang ever settles.
    stall_after_s : float or None
        The device falls silent at this device time.
    foreign : bool
        The device speaks another protocol (plain-text angles).
    """

    damping_ratio: float = 0.02
    start_amplitude_deg: tuple[float, float] = (1.0, 4.0)
    line_drop_probability: float = 0.002
    line_corrupt_probability: float = 0.002
    noise_burst_probability: float = 0.001
    header_every_s: float = 2.0
    slipped_hangs: tuple[int, ...] = ()
    slip_mm: float = 6.0
    never_settle: bool = False
    stall_after_s: float | None = None
    foreign: bool = False


@dataclass(frozen=True)
class SwingTruth:
    """A hang's swing modes as the inclinometer sees them.

    Attributes
    ----------
    frequencies_hz : ndarray, shape (n,)
        Undamped, ascending (four on a wire, two on a pivot).
    reading_shapes_deg : ndarray, shape (n, 2)
        Each mode's readings per radian of the body's largest rotation in it.
    damping_ratio : float
    """

    frequencies_hz: np.ndarray
    reading_shapes_deg: np.ndarray
    damping_ratio: float

    @property
    def periods_s(self) -> np.ndarray:
        return np.asarray(1.0 / self.frequencies_hz)

    @property
    def decay_times_s(self) -> np.ndarray:
        """Amplitude time constants ``τ_k = 1/(ζ ω_k)`` (s)."""
        return np.asarray(1.0 / (2.0 * np.pi * self.frequencies_hz * self.damping_ratio))


@dataclass(frozen=True)
class HangTruth:
    """What the simulation knows about the current hang (for tests and studies):
    ``amplitudes_deg`` is each mode's largest reading at release, ``phases_rad`` its phase."""

    point_index: int
    started_s: float
    vertical: np.ndarray
    readings_deg: tuple[float, float]
    bias_deg: tuple[float, float]
    modes: SwingTruth
    amplitudes_deg: tuple[float, ...]
    slipped: bool
    phases_rad: tuple[float, ...] = ()


class SimulatedDevice:
    """The simulated device: physics, sensor and protocol; no I/O and no wall clock.

    Parameters
    ----------
    target : BenchTarget
        Masses, CoGs, inertia, error model and the planned hangs (the points it can hang from).
    spec : DeviceSpec
    settings : SimulatorSettings
    seed : int or numpy.random.Generator
    """

    def __init__(
        self,
        target: BenchTarget,
        spec: DeviceSpec = DeviceSpec(),
        settings: SimulatorSettings = SimulatorSettings(),
        seed: int | np.random.Generator = 0,
    ) -> None:
        self.target = target
        self.spec = spec
        self.settings = settings
        self.rng = np.random.default_rng(seed)
        self.scenario = target.scenario()
        self.model = target.error_model()
        self.config = target.inclinometer
        self.assembly = target.assembly
        # One physical ME: its CoG error is drawn once.
        self.me_error_mm = self.model.sample_me_errors(self.rng, 1)  # (3, 1)
        # One wire and one sensor for the whole test, like the ME: drawn once, from a stream of
        # their own (spawned: the device's other draws are as they were).
        test_rng = self.rng.spawn(1)[0]
        self.wire = self.model.sample_wire(test_rng, 1, 1)  # unused by the paper's per-hang model
        self.shared_sensor = self.model.sample_shared_sensor(test_rng, 1)[:, 0]
        self.time_s = float(self.rng.uniform(1.0, 5.0))  # the device has been on for a while
        self._seq = int(self.rng.integers(0, 1000))
        self._next_sample_s = self.time_s
        self._next_header_s = self.time_s
        self._attempts = 0
        self._turned = False
        self.truth: HangTruth | None = None
        self._context = _swing_context(target)
        sensor = self.config.sensor
        if spec.kind == "analog":
            self.header = Header(
                "sim-uno",
                "ACS-060",
                "adc_sum",
                spec.rate_hz,
                sensor.adc_bits,
                sensor.adc_reference_v,
                spec.oversample,
            )
        else:
            self.header = Header(
                "sim-uno", "SCL3300", "angle", spec.rate_hz, deg_per_lsb=SCL3300_DEG_PER_LSB
            )

    @property
    def true_object_cog_mm(self) -> np.ndarray:
        """The object's true CoG (the ME is compensated from CAD, so the truth is the CAD's)."""
        return np.asarray(self.scenario.pm_cog_mm)

    def truth_check(self, cog_mm: np.ndarray, cov_mm2: np.ndarray) -> dict[str, object]:
        """How far an estimate of this device's object lies from the truth: the error (mm) and
        its Mahalanobis distance under the estimate's covariance (about 1-2 when it covers)."""
        diff = np.asarray(cog_mm, dtype=float) - self.true_object_cog_mm
        return {
            "object_cog_mm": self.true_object_cog_mm.tolist(),
            "error_mm": diff.tolist(),
            "mahalanobis": float(np.sqrt(diff @ np.linalg.solve(cov_mm2, diff))),
        }

    def request_header(self) -> None:
        """Answer a ``?``: the header goes out with the next sample."""
        self._next_header_s = min(self._next_header_s, self._next_sample_s)

    def hang(self, index: int) -> float:
        """The operator hangs the object from planned point ``index``; return the device time."""
        s = self.settings
        self._attempts += 1
        model = self.model.only("point_play", "wire_offset")
        pert = draw_perturbations(model, self.rng, 1, 1)
        pert = replace(pert, me_mm=self.me_error_mm)
        if self.model.wire_model != "paper":  # one wire: the same on every hang
            pert = replace(pert, wire=self.wire)
        scenario = self.scenario
        slipped = self._attempts in s.slipped_hangs
        if slipped:
            pts = scenario.points_mm.copy()
            t1 = scenario.tangents[0][index]
            pts[index] = pts[index] + s.slip_mm * t1
            scenario = scenario.with_points(scenario.ids, pts, scenario.normals)
        self._turned = self.target.hangs[index].sensor_turned
        u = hang(scenario, model, [index], pert)[:, 0, 0]
        ratio = scenario.me_mass_kg / scenario.total_mass_kg
        g_true = scenario.assembly_cog_mm + ratio * self.me_error_mm[:, 0]
        zeta = 0.0 if s.never_settle else s.damping_ratio
        modes = self._swing(scenario.points_mm[index], g_true, zeta)
        lo, hi = s.start_amplitude_deg
        amps = self.rng.uniform(lo, hi, len(modes.frequencies_hz))
        if s.never_settle:
            amps = np.maximum(amps, 1.0)
        phases = self.rng.uniform(0.0, 2.0 * np.pi, len(modes.frequencies_hz))
        a = self.config.accuracy_deg if "inclinometer" in self.model.sources else 0.0
        bias = self.rng.uniform(-a, a, 2)
        x, y = self._angles(u[None, :])
        self.truth = HangTruth(
            index,
            self._next_sample_s,
            u,
            (float(x[0]), float(y[0])),
            (float(bias[0]), float(bias[1])),
            modes,
            tuple(float(v) for v in amps),
            slipped,
            tuple(float(v) for v in phases),
        )
        return self._next_sample_s

    def _swing(self, point_mm: np.ndarray, cog_mm: np.ndarray, zeta: float) -> SwingTruth:
        """The hang's modes: on the set-up's wire, about its expected pivot (the exit moved by
        the wire's offset), seen at the inclinometer's sensing point (a pivot at the point,
        the sensor at the CoG, when the set-up does not say where it senses)."""
        mass = self.assembly.mass_kg
        ctx = self._context
        if ctx is None:
            geo = HangGeometry(
                np.asarray(point_mm, dtype=float),
                np.asarray(cog_mm, dtype=float),
                0.0,
                0.0,
                self.config.sign_x,
                self.config.sign_y,
            )
        else:
            weight = mass * STANDARD_GRAVITY_M_S2
            top, _ = ctx.top_hinge_mm(weight)
            pivot, _ = ctx.pivots(np.asarray(point_mm, dtype=float)[None, :], cog_mm, weight)
            geo = HangGeometry(pivot[0], ctx.sensor_mm, ctx.swing.wire_length_mm, top, *ctx.signs)
        hm = hang_modes(self.assembly.inertia_kg_mm2, mass, cog_mm, geo)
        return SwingTruth(hm.frequencies_hz, hm.reading_shapes_deg, zeta)

    def _angles(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Device readings (degrees, configured signs) of upward verticals (n, 3), with the
        sensor's shared errors (zeros when the model declares none), turned on its mount for a
        reversal."""
        turned = np.full(len(u), self._turned)
        x, y, _ = sensor_readings(u, self.shared_sensor, self.config, turned)
        return x, y

    def _readings(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Noise-free device readings at device times ``t`` (with the hang's bias)."""
        tr = self.truth
        if tr is None:  # resting flat on the table before the first hang
            return np.zeros_like(t), np.zeros_like(t)
        m = tr.modes
        tau = np.asarray(t, dtype=float) - tr.started_s
        w = 2.0 * np.pi * m.frequencies_hz
        zeta = m.damping_ratio
        waves = np.exp(-zeta * w[None, :] * tau[:, None]) * np.cos(
            w[None, :] * np.sqrt(1.0 - zeta**2) * tau[:, None] + np.asarray(tr.phases_rad)
        )  # (n, modes)
        peak = np.maximum(np.max(np.abs(m.reading_shapes_deg), axis=1), 1e-12)
        swing = waves @ ((np.asarray(tr.amplitudes_deg) / peak)[:, None] * m.reading_shapes_deg)
        if self._turned:  # the sensor turned 180° on its mount sees both axes reversed
            swing = -swing
        x = tr.readings_deg[0] + swing[:, 0]
        y = tr.readings_deg[1] + swing[:, 1]
        return x + tr.bias_deg[0], y + tr.bias_deg[1]

    def _raw(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Integer sample values of both axes at times ``t``."""
        x, y = self._readings(t)
        spec = self.spec
        noise = spec.sample_noise_deg
        rng_deg = self.config.range_deg
        if spec.kind == "analog":
            sensor = self.config.sensor
            shape = (len(t), spec.oversample)
            out = []
            for a in (x, y):
                conv = a[:, None] + self.rng.normal(0.0, noise, shape)
                conv = np.clip(conv, -rng_deg, rng_deg)  # the sensor's output saturates
                counts = np.clip(np.floor(sensor.deg_to_counts(conv) + 0.5), 0, sensor.max_counts)
                out.append(counts.sum(axis=1).astype(np.int64))
            return out[0], out[1]
        vals = []
        for a in (x, y):
            noisy = np.clip(a + self.rng.normal(0.0, noise, len(t)), -rng_deg, rng_deg)
            vals.append(np.clip(np.round(noisy / SCL3300_DEG_PER_LSB), -32768, 32767))
        return vals[0].astype(np.int64), vals[1].astype(np.int64)

    def emit_until(self, t_end_s: float) -> bytes:
        """Advance the device clock to ``t_end_s`` and return the bytes it sent meanwhile."""
        dt = 1.0 / self.spec.rate_hz
        n = int(np.floor((t_end_s - self._next_sample_s) / dt)) + 1
        self.time_s = max(self.time_s, t_end_s)
        if n <= 0:
            return b""
        t = self._next_sample_s + dt * np.arange(n)
        self._next_sample_s = float(t[-1] + dt)
        s = self.settings
        if s.stall_after_s is not None:
            t = t[t < s.stall_after_s]
            if len(t) == 0:
                return b""
        xs, ys = self._raw(t)
        out = bytearray()
        drops = self.rng.random(len(t)) < s.line_drop_probability
        corrupt = self.rng.random(len(t)) < s.line_corrupt_probability
        bursts = self.rng.random(len(t)) < s.noise_burst_probability
        for i, ti in enumerate(t):
            if ti >= self._next_header_s and not s.foreign:
                out += self._line(format_header(self.header))
                self._next_header_s = float(ti + s.header_every_s)
            self._seq += 1
            if s.foreign:
                x_deg, y_deg = self._readings(np.array([ti]))
                out += f"X:{x_deg[0]:+.2f} Y:{y_deg[0]:+.2f}\r\n".encode()
                continue
            if bursts[i]:
                burst = self.rng.integers(0, 256, int(self.rng.integers(1, 21)))
                out += burst.astype(np.uint8).tobytes()
            if drops[i]:
                continue
            line = bytearray(
                format_sample(self._seq, round(float(ti) * 1000), int(xs[i]), int(ys[i])).encode()
            )
            if corrupt[i]:
                j = int(self.rng.integers(0, len(line)))
                line[j] = 32 + (line[j] - 32 + int(self.rng.integers(1, 95))) % 95
            out += self._line(bytes(line))
        return bytes(out)

    @staticmethod
    def _line(text: str | bytes) -> bytes:
        return (text.encode("ascii") if isinstance(text, str) else text) + b"\r\n"


class SimulatedLink:
    """A :class:`SimulatedDevice` as a byte link, in simulated time.

    Each :meth:`read` advances the device by ``chunk_s`` and returns what it sent; the link's
    clock is the device clock, so a stalled device times out at once in real time.
    """

    def __init__(self, device: SimulatedDevice, chunk_s: float = 0.25) -> None:
        self.device = device
        self.chunk_s = chunk_s
        self.name = "simulated device"

    def read(self, max_wait_s: float) -> bytes:
        return self.device.emit_until(self.device.time_s + min(self.chunk_s, max_wait_s))

    def write(self, data: bytes) -> None:
        if b"?" in data:
            self.device.request_header()

    def flush_input(self) -> None:
        pass  # nothing is buffered: bytes exist only once read

    def clock(self) -> float:
        return self.device.time_s

    def close(self) -> None:
        pass

    def hang(self, index: int) -> float:
        return self.device.hang(index)


class PtyDevice:
    """Run a :class:`SimulatedDevice` on a pseudo-terminal, ``time_scale`` × real time.

    ``port`` is the path to open with pyserial. Bytes the reader does not take in time are lost
    (the master side never blocks), as on a real serial link. Use as a context manager.
    """

    def __init__(self, device: SimulatedDevice, time_scale: float = 1.0) -> None:
        if not time_scale > 0:
            raise ValueError("time_scale must be positive")
        self.device = device
        self.time_scale = time_scale
        self.lost_bytes = 0
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._master, self._slave = os.openpty()
        tty.setraw(self._slave)
        os.set_blocking(self._master, False)
        self.port = os.ttyname(self._slave)
        self._thread = threading.Thread(target=self._run, name="cadcog-sim", daemon=True)

    def __enter__(self) -> PtyDevice:
        self._wall0 = time.monotonic()
        self._t0 = self.device.time_s
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def hang(self, index: int) -> float:
        with self._lock:
            return self.device.hang(index)

    def _run(self) -> None:
        while not self._stop.is_set():
            target = self._t0 + (time.monotonic() - self._wall0) * self.time_scale
            with self._lock:
                try:
                    if b"?" in os.read(self._master, 256):
                        self.device.request_header()
                except BlockingIOError:
                    pass
                except OSError:
                    return
                data = self.device.emit_until(target)
            while data:
                try:
                    written = os.write(self._master, data)
                except BlockingIOError:
                    self.lost_bytes += len(data)
                    break
                except OSError as exc:  # pragma: no cover - the pty went away
                    if exc.errno in (errno.EIO, errno.EBADF):
                        return
                    raise
                data = data[written:]
            self._stop.wait(0.005)

    def close(self) -> None:
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(timeout=2.0)
        for fd in (self._master, self._slave):
            try:
                os.close(fd)
            except OSError:
                pass


def _swing_context(target: BenchTarget) -> InertiaContext | None:
    """The swing's context (wire, sensing point, pivots) of the target's set-up or rig, or None
    when it does not say where the inclinometer senses."""
    from cadcog.dynamics.context import context_for_rig, context_for_setup

    try:
        if target.setup is not None:
            return context_for_setup(target.setup, np.zeros((6, 6)))
        return context_for_rig(target.rig)
    except ReadingsError:
        return None
