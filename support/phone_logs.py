"""Independent forward model of a phone's (or a MEMS board's) accelerometer log of a whole CoG test.

It shares no code and no assumption with cadcog's estimator and imports nothing from ``cadcog``:
numpy, scipy and the independent rigid-body simulator :mod:`support.swing_truth` only.

The test, as one continuous log
-------------------------------
A quiet start (the object on a table, ``table_up`` up); then for every hang: handling (picked up,
carried, turned, hung: large irregular accelerations), the release (swing amplitude in a random
direction, a little of the body tilted against the wire, a little yaw rate), the swing, settling,
the team's averaging hold; after the last hang the object is handled back onto the table (quiet
end). The swing is swing_truth's full nonlinear rigid body on a massless inextensible wire with
viscous, mass-proportional damping (every mode decays as ``exp(-t/τ)``); it is integrated (RK4)
until its envelope ``A0·exp(-t/τ)`` falls below ``residual_deg`` (10⁻³°, far under any sensor's
noise), after which the body is exactly at rest: the wire's exit point straight above the CoG, the
specific force ``g·u`` with ``u = (p - c)/|p - c|`` in body axes. Handling is kinematic: a smooth
rotation from the previous pose to the next one with a random wobble, and random translational
accelerations (peaks: 0.5-0.75 g vertical, 0.3-0.5 g horizontal, so ``|f|`` leaves 1 g by at least
0.29 g and stays within 0.25-1.82 g); it needs no dynamics.

Faults: a *knock* during a hang's averaging (a 20 ms half-sine impulse at the sensor, then the body
swings again from rest: a rigid rotation rate about the clamp that starts a swing of about
``knock_deg``, integrated by swing_truth); a hang that *never settles* (no damping: it swings at
its release amplitude for its whole span); the handling time before each hang.

Sensor
------
The reading in g is ``(I + diag(s) + C) · M · f / g + b + n``, quantised to ``lsb_g`` and clipped
to the range, then times g in m/s²: ``f`` the specific force at the sensing point in body axes,
``M = P · R_misᵀ`` with ``P`` the signed permutation of ``axes`` (row i: the object axis along
sensor axis i) and ``R_mis`` a small rotation (angle uniform in [0, misalignment], uniform axis);
``s`` per-axis sensitivity errors, ``C`` cross-axis coupling (zero diagonal), ``b`` zero offsets,
all uniform within the figures and drawn once per test; ``n`` white noise per sample. Convention
(Android ``TYPE_ACCELEROMETER``, phyphox "Acceleration with g"): the **specific force**, i.e. at
rest +9.81 m/s² along the axis that points **up**; a phone lying face up reads ``z ≈ +9.81``.
Timing: nominal rate, each instant jittered (normal, clipped to ±0.45 period), each sample dropped
with a small probability; the reported time is the true one.

phyphox's CSV export (checked in phyphox-android ``DataExport.java``, ``CsvFormat``): the header is
the column names, each in double quotes, joined by the separator (``,``: "Comma, decimal point");
numbers unquoted, Java ``DecimalFormat("0.000000000E0")`` with Locale.ENGLISH: one integer digit,
nine decimals, exponent without "+" or padding (``9.806650000E0``; ``9.364549000E-3`` is a time in
a real export of an accelerometer set quoted in a public course report); no quotes around numbers,
``NaN`` for a missing cell; lines end in ``\\n``; the set is ``Raw Data.csv`` in the export zip.

Every random draw of a log comes from one ``numpy.random.default_rng(seed)``, in a fixed order.
Units: mm, kg, s, degrees, g in names; accelerations in the log in m/s².
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import numpy.typing as npt
from scipy.spatial.transform import Rotation

from support import swing_truth as st

FloatArray = npt.NDArray[np.float64]
G_M_S2 = st.GRAVITY_M_S2  # standard gravity; Android's SensorManager.STANDARD_GRAVITY too
_Z = np.array([0.0, 0.0, 1.0])
_KNOCK_PULSE_S = 0.02
_PHYPHOX_HEADER = ('"Time (s)","Acceleration x (m/s^2)","Acceleration y (m/s^2)",'
                   '"Acceleration z (m/s^2)","Absolute acceleration (m/s^2)"')  # fmt: skip


def axes_matrix(axes: tuple[str, ...] | list[str]) -> FloatArray:
    """Body → sensor matrix of a signed permutation: row i is the object axis that sensor axis i
    lies along (``["-y", "+x", "+z"]``: sensor x along object −y, ...). Raises ``ValueError``
    unless it is a proper rotation (det +1): a mirror such as ``["+x", "+y", "-z"]`` is refused."""
    if len(axes) != 3:
        raise ValueError(f"axes must name three object axes, got {list(axes)!r}")
    m = np.zeros((3, 3))
    for i, a in enumerate(axes):
        a = str(a).strip().lower()
        if len(a) != 2 or a[0] not in "+-" or a[1] not in "xyz":
            raise ValueError(f"sensor axis {a!r}: expected a sign and an object axis, like '-y'")
        m[i, "xyz".index(a[1])] = 1.0 if a[0] == "+" else -1.0
    if sorted(np.nonzero(m)[1].tolist()) != [0, 1, 2]:
        raise ValueError(f"axes {list(axes)!r} must use each object axis once")
    if np.linalg.det(m) < 0:
        raise ValueError(f"axes {list(axes)!r} are a mirror image (left-handed, det −1); a real "
                         "sensor's axes are right-handed: flip one more sign")  # fmt: skip
    return m


@dataclass(frozen=True)
class Body:
    """The hung object (object + sensor package), body frame: mass (kg), CoG (mm), inertia
    about the CoG (kg·mm², 3×3, off-diagonal = −products of inertia)."""

    mass_kg: float
    cog_mm: tuple[float, float, float]
    inertia_kg_mm2: tuple[tuple[float, float, float], ...]


@dataclass(frozen=True)
class Hang:
    """One hang, in order. ``point_mm``: where the wire leaves the body. Release: swing amplitude
    (deg, random horizontal direction), yaw rate uniform within ±``yaw_rate_deg_s``. The swing
    decays with ``decay_time_s``; the team starts averaging ``settle_s`` after the release and
    averages ``average_s``; ``handling_s`` is the handling *before* this hang. Faults: a knock
    ``knock_after_s`` into the averaging (swing of about ``knock_deg``); ``never_settles``."""

    point_mm: tuple[float, float, float]
    wire_length_mm: float = 300.0
    release_deg: float = 3.0
    yaw_rate_deg_s: float = 10.0
    decay_time_s: float = 4.0
    settle_s: float = 30.0
    average_s: float = 15.0
    handling_s: float = 6.0
    knock_after_s: float | None = None
    knock_deg: float = 0.3
    never_settles: bool = False


@dataclass(frozen=True)
class SensorSpec:
    """The accelerometer: position (mm, body), mounting ``axes`` (see :func:`axes_matrix`) and the
    figures of its errors (half-widths of uniform draws, once per test): ``offset_g`` (float or
    per axis), ``scale_rel``, ``cross_axis_rel``, ``misalignment_deg``; per sample: white noise
    ``noise_g`` (σ, g) or ``noise_density_ug_rthz`` × √``bandwidth_hz`` (default rate/2),
    ``nonlinearity_g`` (each axis reads ``qⱼ vⱼ²`` more, ``vⱼ`` its true reading in g and ``qⱼ``
    uniform within ±``nonlinearity_g``, drawn once per test from a stream of its own, so a test
    without it draws what it drew before), ``drift_g`` (each axis's offset drifts linearly over
    the log by ``dⱼ`` uniform within ±``drift_g``: warming up; the same stream),
    quantisation ``lsb_g`` (0: none), range ``range_g``; timing: ``rate_hz``, ``jitter_ms`` (σ),
    ``drop_prob``."""

    position_mm: tuple[float, float, float]
    axes: tuple[str, str, str] = ("+x", "+y", "+z")
    rate_hz: float = 200.0
    jitter_ms: float = 1.0
    drop_prob: float = 0.002
    offset_g: float | tuple[float, float, float] = 0.02
    scale_rel: float = 0.01
    cross_axis_rel: float = 0.0
    misalignment_deg: float = 1.0
    noise_g: float | None = 0.002
    noise_density_ug_rthz: float | None = None
    bandwidth_hz: float | None = None
    lsb_g: float = 0.0006
    range_g: float = 8.0
    nonlinearity_g: float = 0.0
    drift_g: float = 0.0

    def __post_init__(self) -> None:
        axes_matrix(self.axes)

    def ideal(self) -> SensorSpec:
        """The same sensor without any error (no offset, scale, misalignment, noise, lsb)."""
        return replace(self, offset_g=0.0, scale_rel=0.0, cross_axis_rel=0.0, misalignment_deg=0.0,
                       noise_g=0.0, noise_density_ug_rthz=None, lsb_g=0.0,
                       nonlinearity_g=0.0, drift_g=0.0)  # fmt: skip

    @property
    def sigma_g(self) -> float:
        """White noise per sample (g)."""
        if self.noise_density_ug_rthz is not None:
            bw = self.bandwidth_hz if self.bandwidth_hz is not None else self.rate_hz / 2
            return float(self.noise_density_ug_rthz * 1e-6 * math.sqrt(bw))
        return float(self.noise_g or 0.0)


@dataclass(frozen=True)
class LogSpec:
    """One whole test: the body, its hangs in order, the sensor and the timeline's ends (s).
    ``rest_tolerance_deg``: how close to ``u`` (|f/g − u|, rad → deg) the truth calls rest;
    ``residual_deg``: the swing's envelope below which the body is taken exactly at rest."""

    body: Body
    hangs: tuple[Hang, ...]
    sensor: SensorSpec
    quiet_s: float = 5.0
    end_handling_s: float = 5.0
    end_quiet_s: float = 3.0
    table_up: tuple[float, float, float] = (0.0, 0.0, 1.0)
    rest_tolerance_deg: float = 0.01
    residual_deg: float = 1e-3


@dataclass(frozen=True)
class HangTruth:
    """Truth of one hang: its point (mm), true upward vertical ``up`` (unit, body axes), release
    and end times (s), the team's averaging span, the longest span in which the body was truly at
    rest (``None`` if under 1 s) and the knock's time (s) if any."""

    point_mm: FloatArray
    up: FloatArray
    release_t_s: float
    end_t_s: float
    averaging_span_s: tuple[float, float]
    rest_span_s: tuple[float, float] | None
    knock_t_s: float | None


@dataclass(frozen=True)
class SensorTruth:
    """The drawn sensor: ``mount`` (body → sensor, 3×3), misalignment rotation vector (deg),
    offsets (g), sensitivity errors (relative), cross-axis matrix, noise σ (g), lsb (g)."""

    axes: tuple[str, str, str]
    mount: FloatArray
    misalignment_deg: FloatArray
    offset_g: FloatArray
    scale_rel: FloatArray
    cross_axis: FloatArray
    sigma_g: float
    lsb_g: float
    quadratic_g: FloatArray = field(default_factory=lambda: np.zeros(3))
    drift_g: FloatArray = field(default_factory=lambda: np.zeros(3))


@dataclass(frozen=True)
class PhoneLog:
    """A generated log: sample times (s), the sensor's reported accelerations (m/s², sensor
    axes), the noise-free specific force at the sensor (m/s², body axes), the segment of each
    sample (``-1`` table or handling, ``i`` hang i from its release) and the truth."""

    t_s: FloatArray
    accel_m_s2: FloatArray
    ideal_body_m_s2: FloatArray
    segment: npt.NDArray[np.int64]
    hangs: tuple[HangTruth, ...]
    cog_mm: FloatArray
    mass_kg: float
    sensor: SensorTruth
    seed: int
    step_s: float


@dataclass
class _Member:
    """A swing to integrate: its start state, sample times from its start, their log indices."""

    body: st.HungBody
    length_mm: float
    tau_s: float
    y0: FloatArray
    t_rel: FloatArray
    idx: npt.NDArray[np.int64]


@dataclass
class _Plan:
    t: FloatArray
    f: FloatArray
    segment: npt.NDArray[np.int64]
    members: list[_Member]
    pulses: list[tuple[npt.NDArray[np.int64], FloatArray]]
    hang_info: list[dict]
    sensor: SensorTruth
    noise: FloatArray
    spec: LogSpec


def _hung_body(spec: LogSpec, hang: Hang) -> st.HungBody:
    b = spec.body
    return st.HungBody(float(b.mass_kg), np.asarray(b.cog_mm, float),
                       np.asarray(b.inertia_kg_mm2, float), np.asarray(hang.point_mm, float),
                       np.asarray(spec.sensor.position_mm, float))  # fmt: skip


def auto_step_s(spec: LogSpec) -> float:
    """RK4 step (s) for a spec: 0.3 / (swing_truth's bound on the fastest mode), at most 10 ms."""
    w = max(st.highest_frequency_rad_s(_hung_body(spec, h), h.wire_length_mm) for h in spec.hangs)
    return float(min(0.01, 0.3 / w))


def _unit(v: npt.ArrayLike) -> FloatArray:
    v = np.asarray(v, float)
    return np.asarray(v / np.linalg.norm(v))


def _rest_rotation(up: FloatArray, yaw: float) -> Rotation:
    """Body → lab attitude with ``up`` (body) pointing to lab +Z, turned ``yaw`` about it."""
    return Rotation.from_rotvec(yaw * _Z) * Rotation.from_matrix(st.rotation_taking(up, _Z))


def _handling(t: FloatArray, dur: float, r_a: Rotation, r_b: Rotation,
              rng: np.random.Generator) -> FloatArray:  # fmt: skip
    """Specific force (m/s², body) at times ``t`` (s from the handling's start): attitude from
    ``r_a`` to ``r_b`` (quintic blend) with a random wobble, random accelerations (lab; peaks
    0.5-0.75 g vertical, 0.3-0.5 g horizontal), both vanishing at the ends. Fixed draws."""
    wf, wp, wa = rng.uniform(0.3, 1.5, 3), rng.uniform(0, 2 * np.pi, 3), rng.normal(0, 0.6, (3, 3))
    af, ap, aa = rng.uniform(0.5, 3.0, 4), rng.uniform(0, 2 * np.pi, 4), rng.normal(0, 1.0, (4, 3))
    peak = np.array([rng.uniform(0.3, 0.5)] * 2 + [rng.uniform(0.5, 0.75)]) * G_M_S2

    def accel(tt: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        s = np.clip(tt / dur, 0.0, 1.0)
        win = np.sin(np.pi * s) ** 2
        wob = win[:, None] * (np.sin(2 * np.pi * wf * tt[:, None] + wp) @ wa)
        a = win[:, None] * (np.sin(2 * np.pi * af * tt[:, None] + ap) @ aa)
        return s, wob, a

    _, _, a_grid = accel(np.linspace(0.0, dur, max(int(dur * 200), 2)))
    scale = peak / np.maximum(np.abs(a_grid).max(axis=0), 1e-12)  # per lab axis
    scale[:2] = peak[0] / max(float(np.linalg.norm(a_grid[:, :2], axis=1).max()), 1e-12)
    s, wob, a = accel(np.asarray(t, float))
    h = s**3 * (10 - 15 * s + 6 * s * s)
    turn = (r_a.inv() * r_b).as_rotvec()
    rot = r_a * Rotation.from_rotvec(h[:, None] * turn) * Rotation.from_rotvec(wob)
    return np.asarray(rot.inv().apply(a * scale + G_M_S2 * _Z))


def _draw_sensor(s: SensorSpec, rng: np.random.Generator) -> SensorTruth:
    offset = np.broadcast_to(np.asarray(s.offset_g, float), (3,)) * rng.uniform(-1, 1, 3)
    scale = s.scale_rel * rng.uniform(-1, 1, 3)
    cross = s.cross_axis_rel * rng.uniform(-1, 1, (3, 3))
    np.fill_diagonal(cross, 0.0)
    axis = _unit(rng.standard_normal(3))
    mis = axis * rng.uniform(0.0, s.misalignment_deg)
    mount = axes_matrix(s.axes) @ Rotation.from_rotvec(np.radians(mis)).as_matrix().T
    return SensorTruth(tuple(s.axes), mount, mis, offset, scale, cross, s.sigma_g, s.lsb_g)  # type: ignore[arg-type]


def _plan(spec: LogSpec, rng: np.random.Generator) -> _Plan:
    """Every draw of a log, the timeline, the static and handling samples, the swings to
    integrate. Order of draws: sensor, sample times, then per segment in time order, noise."""
    sen = spec.sensor
    if not spec.hangs:
        raise ValueError("a test needs at least one hang")
    truth = _draw_sensor(sen, rng)
    table_up = _unit(spec.table_up)
    total = spec.quiet_s + spec.end_handling_s + spec.end_quiet_s + sum(
        h.handling_s + h.settle_s + h.average_s for h in spec.hangs)  # fmt: skip
    period = 1.0 / sen.rate_hz
    n_nom = int(total * sen.rate_hz) + 1
    jit = np.clip(rng.normal(0.0, sen.jitter_ms * 1e-3, n_nom), -0.45 * period, 0.45 * period)
    keep = rng.random(n_nom) >= sen.drop_prob
    t = np.maximum(np.arange(n_nom) * period + jit, 0.0)[keep]
    f = np.full((t.size, 3), np.nan)
    seg = np.full(t.size, -1, dtype=np.int64)

    def between(a: float, b: float) -> npt.NDArray[np.int64]:
        return np.nonzero((t >= a) & (t < b))[0]

    f[between(0.0, spec.quiet_s)] = G_M_S2 * table_up
    pose = _rest_rotation(table_up, rng.uniform(0, 2 * np.pi))
    now = spec.quiet_s
    members: list[_Member] = []
    pulses: list[tuple[npt.NDArray[np.int64], FloatArray]] = []
    info: list[dict] = []
    c = np.asarray(spec.body.cog_mm, float)
    for i, h in enumerate(spec.hangs):
        if h.wire_length_mm <= 0:
            raise ValueError("swing_truth's batches need a wire (length > 0)")
        body = _hung_body(spec, h)
        p = np.asarray(h.point_mm, float)
        if np.linalg.norm(p - c) < 1e-9:
            raise ValueError(f"hang {i}: the point is the CoG (no plumb line)")
        up = _unit(p - c)
        phi, psi = rng.uniform(0, 2 * np.pi, 2)
        amp, tilt = math.radians(h.release_deg), math.radians(h.release_deg) * rng.uniform(0, 0.3)
        rel = st.Release(amp * np.array([math.cos(phi), math.sin(phi), 0.0]),
                         tilt * np.array([math.cos(psi), math.sin(psi), 0.0]), np.zeros(3),
                         np.array([0, 0, math.radians(h.yaw_rate_deg_s) * rng.uniform(-1, 1)]),
                         rng.uniform(0, 2 * np.pi))  # fmt: skip
        y0 = st.initial_state(body, h.wire_length_mm, rel)
        w, x, y, z = y0[6:10]
        release_pose = Rotation.from_quat([x, y, z, w])
        idx = between(now, now + h.handling_s)
        f[idx] = _handling(t[idx] - now, h.handling_s, pose, release_pose, rng)
        t_r = now + h.handling_s
        t_e = t_r + h.settle_s + h.average_s
        hang_idx = between(t_r, t_e)
        seg[hang_idx] = i
        f[hang_idx] = G_M_S2 * up
        tau = math.inf if h.never_settles else h.decay_time_s
        a0 = math.degrees(amp + tilt)
        span = t_e - t_r
        if math.isfinite(tau) and a0 > spec.residual_deg:
            span = min(span, tau * math.log(a0 / spec.residual_deg))
        elif a0 <= spec.residual_deg:
            span = 0.0
        knock_t = None
        if h.knock_after_s is not None:
            if not 0 <= h.knock_after_s < h.average_s:
                raise ValueError(f"hang {i}: the knock must fall inside the averaging")
            knock_t = t_r + h.settle_s + h.knock_after_s
            span = min(span, knock_t - _KNOCK_PULSE_S - t_r)  # the knock hits a body at rest
        if span > 0:
            j = between(t_r, t_r + span)
            members.append(_Member(body, h.wire_length_mm, tau, y0, t[j] - t_r, j))
        kdir, kyaw = rng.standard_normal(3), rng.uniform(0, 2 * np.pi)
        if knock_t is not None:
            d_exit = float(np.linalg.norm(p - c))
            w1 = math.sqrt(G_M_S2 / ((h.wire_length_mm + d_exit) * 1e-3))
            omega_b = math.radians(h.knock_deg) * w1 * _unit(kdir - (kdir @ up) * up)
            lab = _rest_rotation(up, kyaw).apply(omega_b)
            kick = st.Release(np.zeros(3), np.zeros(3), lab, lab, kyaw)
            arm = (np.asarray(sen.position_mm, float) - p - h.wire_length_mm * up) * 1e-3
            dv = np.cross(omega_b, arm)  # m/s, body axes: rigid rotation about the clamp
            j = between(knock_t - _KNOCK_PULSE_S, knock_t)
            shape = np.sin(np.pi * (t[j] - knock_t + _KNOCK_PULSE_S) / _KNOCK_PULSE_S)
            pulses.append((j, np.outer(shape * np.pi / (2 * _KNOCK_PULSE_S), dv)))
            k_span = min(t_e - knock_t, tau * math.log(max(h.knock_deg, 2 * spec.residual_deg)
                                                       / spec.residual_deg))  # fmt: skip
            j = between(knock_t, knock_t + k_span)
            y_k = st.initial_state(body, h.wire_length_mm, kick)
            members.append(_Member(body, h.wire_length_mm, tau, y_k, t[j] - knock_t, j))
        avg = (t_r + h.settle_s, t_e)
        info.append(dict(point=p, up=up, release=t_r, end=t_e, averaging=avg, knock=knock_t))
        pose = _rest_rotation(up, rng.uniform(0, 2 * np.pi))
        now = t_e
    idx = between(now, now + spec.end_handling_s)
    table_pose = _rest_rotation(table_up, rng.uniform(0, 2 * np.pi))
    f[idx] = _handling(t[idx] - now, spec.end_handling_s, pose, table_pose, rng)
    f[t >= now + spec.end_handling_s] = G_M_S2 * table_up
    noise = rng.standard_normal((t.size, 3)) * truth.sigma_g
    return _Plan(t, f, seg, members, pulses, info, truth, noise, spec)


def _integrate(members: list[_Member], step_s: float) -> list[FloatArray]:
    """Specific force (m/s², body) of every member at its instants: one swing_truth batch."""
    live = [m for m in members if m.t_rel.size]
    out = {id(m): np.zeros((0, 3)) for m in members}
    if not live:
        return [out[id(m)] for m in members]
    k = max(m.t_rel.size for m in live)
    times = np.array([np.pad(m.t_rel, (0, k - m.t_rel.size), mode="edge") for m in live])
    batch = st.make_batch([m.body for m in live], [m.length_mm for m in live],
                          [m.tau_s for m in live])  # fmt: skip
    y0 = np.array([m.y0 for m in live]).T
    traj = st.integrate(batch, y0, times, step_s, record_every_s=1e9)
    for j, m in enumerate(live):
        out[id(m)] = traj.force[j, : m.t_rel.size]
    return [out[id(m)] for m in members]


def _longest_run(ok: npt.NDArray[np.bool_]) -> tuple[int, int] | None:
    """First and last index of the longest run of True, or None."""
    if not ok.any():
        return None
    d = np.diff(np.concatenate([[0], ok.astype(np.int8), [0]]))
    starts, ends = np.nonzero(d == 1)[0], np.nonzero(d == -1)[0]
    j = int(np.argmax(ends - starts))
    return int(starts[j]), int(ends[j] - 1)


def _finish(plan: _Plan, forces: list[FloatArray], seed: int, step_s: float) -> PhoneLog:
    f = plan.f.copy()
    for m, fm in zip(plan.members, forces, strict=True):
        f[m.idx] = fm
    for j, extra in plan.pulses:
        f[j] += extra
    if np.isnan(f).any():
        raise RuntimeError("a sample was left without a specific force")
    tol = math.radians(plan.spec.rest_tolerance_deg)
    hangs = []
    for i, h in enumerate(plan.hang_info):
        j = np.nonzero(plan.segment == i)[0]
        dev = np.linalg.norm(f[j] / G_M_S2 - h["up"], axis=1)
        run = _longest_run(dev < tol)
        rest = None
        if run is not None and plan.t[j[run[1]]] - plan.t[j[run[0]]] >= 1.0:
            rest = (float(plan.t[j[run[0]]]), float(plan.t[j[run[1]]]))
        hangs.append(HangTruth(h["point"], h["up"], h["release"], h["end"], h["averaging"], rest,
                               h["knock"]))  # fmt: skip
    s = plan.sensor
    q = np.zeros(3)
    drift = np.zeros((len(plan.t), 3))
    spec_s = plan.spec.sensor
    if spec_s.nonlinearity_g > 0 or spec_s.drift_g > 0:
        extra = np.random.default_rng([seed, 34])
        q = spec_s.nonlinearity_g * extra.uniform(-1, 1, 3)
        d = spec_s.drift_g * extra.uniform(-1, 1, 3)
        span = max(float(plan.t[-1] - plan.t[0]), 1e-9)
        drift = ((plan.t - plan.t[0]) / span)[:, None] * d
        s = replace(s, quadratic_g=q, drift_g=d)
    seen = s.mount @ (f / G_M_S2).T
    g_units = (np.eye(3) + np.diag(s.scale_rel) + s.cross_axis) @ seen + q[:, None] * seen**2
    read = g_units.T + s.offset_g + drift + plan.noise
    if s.lsb_g > 0:
        read = np.round(read / s.lsb_g) * s.lsb_g
    read = np.clip(read, -plan.spec.sensor.range_g, plan.spec.sensor.range_g)
    b = plan.spec.body
    return PhoneLog(plan.t, read * G_M_S2, f, plan.segment, tuple(hangs),
                    np.asarray(b.cog_mm, float), float(b.mass_kg), s, seed, step_s)  # fmt: skip


def generate_many(specs: list[LogSpec], seeds: list[int], step_s: float | None = None,
                  chunk: int = 32) -> list[PhoneLog]:  # fmt: skip
    """Logs of several (spec, seed) pairs, their swings integrated ``chunk`` logs per
    swing_truth batch (a step costs about the same for 1 or 300 swings). With the same step,
    each log is the one :func:`generate` gives (the default step depends on the geometry only)."""
    step = step_s if step_s is not None else min(auto_step_s(s) for s in specs)
    logs: list[PhoneLog] = []
    for lo in range(0, len(specs), chunk):
        pairs = list(zip(specs[lo : lo + chunk], seeds[lo : lo + chunk], strict=True))
        plans = [_plan(s, np.random.default_rng(seed)) for s, seed in pairs]
        forces = _integrate([m for p in plans for m in p.members], step)
        at = 0
        for p, (_, seed) in zip(plans, pairs, strict=True):
            n = len(p.members)
            logs.append(_finish(p, forces[at : at + n], int(seed), step))
            at += n
    return logs


def generate(spec: LogSpec, seed: int, step_s: float | None = None) -> PhoneLog:
    """One log of ``spec``: every draw from ``numpy.random.default_rng(seed)``.

    Returns the times ``t_s`` (s), ``accel_m_s2`` (n, 3): what the sensor reports in its own
    axes, the specific force (+9.81 m/s² along the upward axis at rest, phyphox's "Acceleration
    with g" convention), and the truth (per hang its true vertical ``up = (p − c)/|p − c|``, rest
    span, knock; the CoG; the drawn sensor errors). ``step_s``: RK4 step (default
    :func:`auto_step_s`)."""
    return generate_many([spec], [seed], step_s)[0]


def _java_e(x: float) -> str:
    """``DecimalFormat("0.000000000E0")`` of a float (phyphox's CSV number format)."""
    mant, exp = f"{x:.9E}".split("E")
    return f"{mant}E{int(exp)}"


def write_phyphox_csv(path: str | Path, log: PhoneLog) -> None:
    """The log as phyphox's "Acceleration with g" CSV export (see the module's docstring)."""
    a = log.accel_m_s2
    absolute = np.sqrt((a * a).sum(axis=1))
    rows = [_PHYPHOX_HEADER]
    rows += [",".join(_java_e(float(v)) for v in (t, *r, m))
             for t, r, m in zip(log.t_s, a, absolute, strict=True)]  # fmt: skip
    Path(path).write_bytes(("\n".join(rows) + "\n").encode("utf-8"))


def write_plain_csv(path: str | Path, log: PhoneLog) -> None:
    """The log as ``t_s,ax,ay,az`` (s, m/s², sensor axes)."""
    rows = ["t_s,ax,ay,az"] + [f"{t:.6f},{r[0]:.7f},{r[1]:.7f},{r[2]:.7f}"
                               for t, r in zip(log.t_s, log.accel_m_s2, strict=True)]  # fmt: skip
    Path(path).write_text("\n".join(rows) + "\n", encoding="utf-8")


def truth_dict(log: PhoneLog, spec: LogSpec | None = None) -> dict:
    """The truth as plain JSON-able values (mm, kg, s, deg, g)."""
    s = log.sensor
    out = {
        "seed": log.seed, "mass_kg": log.mass_kg, "cog_mm": log.cog_mm.tolist(),
        "hangs": [{"point_mm": h.point_mm.tolist(), "up": h.up.tolist(),
                   "release_t_s": h.release_t_s, "end_t_s": h.end_t_s,
                   "averaging_span_s": list(h.averaging_span_s),
                   "rest_span_s": None if h.rest_span_s is None else list(h.rest_span_s),
                   "knock_t_s": h.knock_t_s} for h in log.hangs],
        "sensor": {"axes": list(s.axes), "mount_body_to_sensor": s.mount.tolist(),
                   "misalignment_rotvec_deg": s.misalignment_deg.tolist(),
                   "offset_g": s.offset_g.tolist(), "scale_rel": s.scale_rel.tolist(),
                   "cross_axis": s.cross_axis.tolist(), "quadratic_g": s.quadratic_g.tolist(),
                   "drift_g": s.drift_g.tolist(),
                   "noise_sigma_g": s.sigma_g,
                   "lsb_g": s.lsb_g},
        "convention": "specific force, m/s^2, sensor axes: +9.81 along the upward axis at rest",
        "rk4_step_s": log.step_s,
    }  # fmt: skip
    if spec is not None:
        out["inertia_kg_mm2"] = [list(r) for r in spec.body.inertia_kg_mm2]
        out["sensor"]["position_mm"] = list(spec.sensor.position_mm)
        out["wire_length_mm"] = [h.wire_length_mm for h in spec.hangs]
    return out
