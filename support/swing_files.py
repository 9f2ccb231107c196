"""Simulated swing campaigns (the truth of ``swing_truth``) and the files the estimator reads.

Inputs come through cadcog's own readers only (a rig file's closed-form mass properties, a
set-up's CAD mass properties and placed measurement equipment, the inclinometer's ADC model);
the physics is :mod:`support.swing_truth`'s. One *campaign* is a set of hangs of one
hung body, each released, recorded and let settle:

- **release** (lab frame): the rest pose rotated about the clamp by a horizontal angle
  ``U(0.5, 1)·amplitude_deg`` at a random azimuth, the body tilted further about its wire exit by
  ``U(0, 0.2)·amplitude_deg`` (the second, fast mode), the wire given a horizontal angular rate
  of ``U(0, 1)·amplitude·ω₁`` at another random azimuth (ω₁ = √(g/(L + d)), so both horizontal
  directions swing with random phases) and the body a yaw rate ``U(−1, 1)·yaw_rate_deg_s``;
- **wire**: per hang the true free length is ``N(L, σ_L)`` (the estimator is told ``L ± σ_L``);
  the amplitude decay time is ``U(decay_time_range_s)`` per hang; with ``hinge_errors`` the
  wire's hinge on the body is not the nominal exit but lies, per hang, uniformly in a
  ``play_mm`` square in the face plane around it and ``U(0, wire_offset_max_mm)`` out along the
  bolt axis (the rig's error model: bolt play, and the paper's wire model of the bending
  stiffness as an outward hinge offset); the files give the nominal exit. With ``one_wire``
  ``"flexible"`` or ``"stiff"`` (issue 31: one wire hangs every hang) the campaign has **one**
  wire: one free length ``N(L, σ_L)`` for all its hangs, and its hinge on the body at the exit
  itself (an ideal string turns there) or, for a stiff wire of ``bending_stiffness_n_mm2``
  under the hung weight, where its straight part's line meets the bolt axis, found by
  integrating the elastica numerically (:func:`support.rig_campaigns.
  elastica_virtual_offset_mm`, written without cadcog's wire model); the play stays per hang;
- **measurement equipment** (with ``me_errors``, once per campaign: one ME is mounted for the
  whole test): each ME volume's centre of mass moved uniformly within its
  ``cog_uncertainty_cube_mm`` cube, and its own inertia scaled by ``1 + U(±√3·me_inertia_rel)``
  (the spread the rig or set-up declares); the object itself is exact;
- **air** (with ``drag_area_m2`` > 0): quadratic drag ``−½ρ C_dA |v| v`` at the object's
  centroid (its CoG: the proof mass and the CubeSat are near-uniform), not at the hung
  assembly's CoG, so it turns the body too (:mod:`support.swing_truth`);
- **sensor** (the rig's ``[inclinometer]`` and ``[error_model]``): the true angle
  ``asin(f_x/|f|)`` (:func:`swing_truth.inclinations_deg`), saturated at ±``range_deg``, plus a
  bias per hang and axis ``U(±accuracy_deg)``, plus white noise ``N(0, sensor_noise_deg)`` per
  ADC conversion, quantised by the rig's ADC (``SensorModel``: bin = ⌊counts + ½⌋, clipped to
  the ADC's range), ``oversample`` conversions averaged per sample, then the device's signs;
- **timing**: sample *k* is taken at ``k/rate + U(±jitter_ms)`` after release, and stamped with
  the device clock in whole milliseconds (``⌊(t₀ + t)(1 + clock_ppm·10⁻⁶)·1000⌋``, t₀ the hang's
  start on that clock, hangs 2-5 minutes apart);
- **settled readings** (the readings CSV): ``settled_samples`` samples of the rest pose with the
  same bias, noise and ADC (what ``cadcog estimate`` and ``cadcog inertia`` expect).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import numpy.typing as npt

from support import swing_truth as st

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class SwingConfig:
    """Parameters of a simulated campaign (defaults documented in the module docstring)."""

    wire_length_mm: float = 300.0
    wire_length_sigma_mm: float = 2.0
    amplitude_deg: float = 10.0
    yaw_rate_deg_s: float = 5.0
    decay_time_range_s: tuple[float, float] = (5.0, 30.0)
    duration_s: float = 60.0
    sample_rate_hz: float = 50.0
    jitter_ms: float = 3.0
    clock_ppm: float = 0.0
    oversample: int = 16
    settled_samples: int = 15
    dt_s: float | None = None  # RK4 step; None: min(4 ms, 0.15/ω_max)
    hinge_errors: bool = True  # the rig error model's play and wire offset move the hinge
    one_wire: str = ""  # "", "flexible" or "stiff": one wire per campaign (module docstring)
    bending_stiffness_n_mm2: float = 30.0  # the stiff wire's EI
    me_errors: bool = False  # the ME's CoG and own inertia drawn once per campaign
    me_inertia_rel: float = 0.3  # their spread (1 σ), as the parameter file's [swing] declares
    drag_area_m2: float = 0.0  # the air's drag on the body, C_d·A (0: none; module docstring)


@dataclass(frozen=True)
class Sensor:
    """The inclinometer as the rig file defines it (cadcog's ``InclinometerConfig``), with the
    error model's per-conversion noise."""

    config: object  # cadcog.rig.inclinometer.InclinometerConfig
    noise_deg: float

    def read(
        self, true_deg: FloatArray, bias_deg: FloatArray, oversample: int, rng: np.random.Generator
    ) -> FloatArray:
        """Device readings (degrees, device signs) of true angles ``(..., )`` with per-hang bias
        broadcast against them."""
        cfg = self.config
        sensor = cfg.sensor  # type: ignore[attr-defined]
        x = np.clip(true_deg, -cfg.range_deg, cfg.range_deg) + bias_deg  # type: ignore[attr-defined]
        conv = x[..., None] + rng.normal(0.0, self.noise_deg, (*x.shape, oversample))
        counts = np.clip(np.floor(sensor.deg_to_counts(conv) + 0.5), 0, sensor.max_counts)
        return np.asarray(sensor.counts_to_deg(counts.mean(axis=-1)))


@dataclass(frozen=True)
class Truth:
    """What hangs, and what the estimator must recover.

    Attributes
    ----------
    body : swing_truth.HungBody
        Object + measurement equipment (``wire_exit_mm`` unused: per hang).
    object_mass_kg : float
    object_cog_mm : ndarray, shape (3,)
    object_inertia_kg_mm2 : ndarray, shape (3, 3)
        The object's inertia about its own CoG, model axes: the target.
    hangs : tuple of (str, ndarray (3,))
        Available hang points: id and wire exit (mm).
    sensor : Sensor
    normals : tuple of ndarray (3,)
        Each hang point's bolt axis (outward face normal), as ``hangs``.
    play_mm, wire_offset_max_mm : float
        The rig's error model: the wire's hinge lies uniformly in a ``play_mm`` square in the
        face plane around the exit, and ``U(0, wire_offset_max_mm)`` out along the bolt axis
        (the paper's wire model: its bending stiffness moves the effective hinge outwards).
    me_volumes : tuple of (mass_kg, center_mm (3,), size_mm (3,), cog_uncertainty_cube_mm)
        The ME's homogeneous boxes, as the parameter file places them (``body`` holds them at
        their nominal places).
    """

    body: st.HungBody
    object_mass_kg: float
    object_cog_mm: FloatArray
    object_inertia_kg_mm2: FloatArray
    hangs: tuple[tuple[str, FloatArray], ...]
    sensor: Sensor
    normals: tuple[FloatArray, ...]
    play_mm: float
    wire_offset_max_mm: float
    me_volumes: tuple[tuple[float, FloatArray, FloatArray, float], ...] = ()

    def with_me_drawn(self, rng: np.random.Generator, inertia_rel: float) -> Truth:
        """The same object under an ME as mounted on one test: each volume's centre of mass
        uniform within its uncertainty cube, its own inertia scaled by ``1 + U(±√3·rel)``."""
        from cadcog.mass.properties import MassProperties, box_properties, combine

        # the volume only weighs a compound's volume, which nothing here reads
        parts = [
            MassProperties(self.object_mass_kg, self.object_cog_mm, self.object_inertia_kg_mm2, 0.0)
        ]
        for mass, center, size, cube in self.me_volumes:
            box = box_properties(size, center, mass_kg=mass)
            moved = np.asarray(center, float) + rng.uniform(-0.5, 0.5, 3) * cube
            scale = 1.0 + rng.uniform(-1.0, 1.0) * np.sqrt(3.0) * inertia_rel
            parts.append(MassProperties(mass, moved, box.inertia_kg_mm2 * scale, box.volume_mm3))
        asm = combine(parts)
        body = replace(
            self.body, mass_kg=asm.mass_kg, cog_mm=asm.cog_mm, inertia_kg_mm2=asm.inertia_kg_mm2
        )
        return replace(self, body=body)

    def exit_of(self, point_id: str) -> FloatArray:
        return self.hangs[self._index(point_id)][1]

    def hung_from(self, hinge_mm: npt.ArrayLike) -> st.HungBody:
        """The body as it hangs with the wire leaving it at ``hinge_mm``."""
        return replace(self.body, wire_exit_mm=np.asarray(hinge_mm, dtype=float))

    def released(
        self,
        hinge_mm: npt.ArrayLike,
        releases: Sequence[st.Release],
        length_mm: float,
        decay_time_s: float,
        t_s: FloatArray,
    ) -> tuple[FloatArray, FloatArray]:
        """The noise-free readings (device-free angles, degrees, each ``(len(releases),
        len(t_s))``: x, y) of the body hung from ``hinge_mm`` on a wire of ``length_mm``,
        released each way, every hang damped with ``decay_time_s``."""
        body = self.hung_from(hinge_mm)
        n = len(releases)
        y0 = np.array([st.initial_state(body, length_mm, r) for r in releases]).T
        batch = st.make_batch([body] * n, [length_mm] * n, [decay_time_s] * n)
        dt = min(4e-3, 0.15 / st.highest_frequency_rad_s(body, length_mm))
        traj = st.integrate(batch, y0, np.tile(t_s, (n, 1)), dt, 10.0)
        tx, ty = st.inclinations_deg(traj.force)
        return np.asarray(tx), np.asarray(ty)

    def normal_of(self, point_id: str) -> FloatArray:
        return self.normals[self._index(point_id)]

    def _index(self, point_id: str) -> int:
        for i, (pid, _) in enumerate(self.hangs):
            if pid == point_id:
                return i
        raise KeyError(point_id)


def _inclinometer_centre(volumes: Sequence[object]) -> FloatArray:
    for v in volumes:
        if "inclinometer" in v.name:  # type: ignore[attr-defined]
            return np.asarray(v.center_mm, float)  # type: ignore[attr-defined]
    raise ValueError("no measurement-equipment volume has 'inclinometer' in its name")


def _me_volume(v: object) -> tuple[float, FloatArray, FloatArray, float]:
    """An ME volume of a rig or set-up file as (mass, centre, size, CoG uncertainty cube)."""
    return (
        float(v.mass_kg),  # type: ignore[attr-defined]
        np.asarray(v.center_mm, float),  # type: ignore[attr-defined]
        np.asarray(v.size_mm, float),  # type: ignore[attr-defined]
        float(v.cog_uncertainty_cube_mm),  # type: ignore[attr-defined]
    )


def rig_truth(rig_path: str | Path, sensor_mm: npt.ArrayLike | None = None) -> Truth:
    """The paper-style rig as cadcog's closed-form CAD says: proof mass (the object) + ME."""
    from cadcog.rig.file import load_rig

    rig = load_rig(rig_path)
    asm, pm = rig.analytic_assembly, rig.analytic_proof_mass
    sensor = _inclinometer_centre(rig.me_volumes) if sensor_mm is None else sensor_mm
    body = st.HungBody(asm.mass_kg, asm.cog_mm, asm.inertia_kg_mm2, asm.cog_mm, np.asarray(sensor))
    hangs = tuple((p.id, np.asarray(rig.wire_exit_mm(p), float)) for p in rig.suspension_points)
    e = rig.error_options
    normals = tuple(np.asarray(p.normal, float) for p in rig.suspension_points)
    sensor_ = Sensor(rig.inclinometer, e.sensor_noise_deg)
    me = tuple(_me_volume(v) for v in rig.me_volumes)
    return Truth(
        body, pm.mass_kg, pm.cog_mm, pm.inertia_kg_mm2, hangs, sensor_, normals, e.play_mm,
        e.wire_offset_max_mm, me,
    )  # fmt: skip


def setup_truth(setup_path: str | Path, sensor_mm: npt.ArrayLike | None = None) -> Truth:
    """A spacecraft set-up as its CAD says: the spacecraft (the object) + the placed ME boxes."""
    from cadcog.mass.properties import box_properties, combine
    from cadcog.spacecraft.setup import load_setup

    s = load_setup(setup_path)
    me = combine(box_properties(v.size_mm, v.center_mm, mass_kg=v.mass_kg) for v in s.me_volumes)
    asm = combine([s.mass, me])
    sensor = _inclinometer_centre(s.me_volumes) if sensor_mm is None else sensor_mm
    body = st.HungBody(asm.mass_kg, asm.cog_mm, asm.inertia_kg_mm2, asm.cog_mm, np.asarray(sensor))
    hangs = tuple((c.id, np.asarray(c.position_mm, float)) for c in s.candidates)
    e = s.rig.error_options
    normals = tuple(np.asarray(c.normal, float) for c in s.candidates)
    sensor_ = Sensor(s.rig.inclinometer, e.sensor_noise_deg)
    me_boxes = tuple(_me_volume(v) for v in s.me_volumes)
    return Truth(
        body, s.mass.mass_kg, s.mass.cog_mm, s.mass.inertia_kg_mm2, hangs, sensor_, normals,
        e.play_mm, e.wire_offset_max_mm, me_boxes,
    )  # fmt: skip


@dataclass(frozen=True)
class HangRecord:
    """One simulated hang as recorded.

    Attributes
    ----------
    point_id : str
    wire_exit_mm : ndarray, shape (3,)
    top_face_up : bool
    t_ms : ndarray of int, shape (k,)
        Device timestamps (ms).
    inc_x_deg, inc_y_deg : ndarray, shape (k,)
        Swing readings (device degrees).
    settled_x_deg, settled_y_deg : ndarray, shape (s,)
        Settled readings.
    true_wire_length_mm, decay_time_s : float
    true_x_deg, true_y_deg : ndarray, shape (k,)
        Noise-free angles at the true sampling instants (diagnostics).
    """

    point_id: str
    wire_exit_mm: FloatArray
    top_face_up: bool
    t_ms: npt.NDArray[np.int64]
    inc_x_deg: FloatArray
    inc_y_deg: FloatArray
    settled_x_deg: FloatArray
    settled_y_deg: FloatArray
    true_wire_length_mm: float
    decay_time_s: float
    true_x_deg: FloatArray = field(repr=False)
    true_y_deg: FloatArray = field(repr=False)


def _release(
    body: st.HungBody, length_mm: float, cfg: SwingConfig, rng: np.random.Generator
) -> st.Release:
    amp = np.radians(cfg.amplitude_deg)
    d_m = float(np.linalg.norm(np.subtract(body.wire_exit_mm, body.cog_mm))) * 1e-3
    w1 = np.sqrt(st.GRAVITY_M_S2 / (length_mm * 1e-3 + d_m))

    def horizontal(magnitude: float) -> FloatArray:
        a = rng.uniform(0, 2 * np.pi)
        return np.array([np.cos(a), np.sin(a), 0.0]) * magnitude

    wire_rate = horizontal(rng.uniform(0, 1) * amp * w1)
    yaw = np.radians(cfg.yaw_rate_deg_s) * rng.uniform(-1, 1)
    return st.Release(
        horizontal(rng.uniform(0.5, 1) * amp),
        horizontal(rng.uniform(0, 0.2) * amp),
        wire_rate,
        wire_rate + np.array([0.0, 0.0, yaw]),
        float(rng.uniform(0, 2 * np.pi)),
    )


def simulate_campaigns(
    truth: Truth,
    point_ids: Sequence[str],
    cfg: SwingConfig,
    rngs: Sequence[np.random.Generator],
    hang_ids: Sequence[str] | None = None,
) -> list[list[HangRecord]]:
    """Simulate one campaign per generator, all hangs of all campaigns in one batch.

    Parameters
    ----------
    truth : Truth
    point_ids : sequence of str
        The points hung, in order (a point may repeat: a re-hang).
    cfg : SwingConfig
    rngs : sequence of numpy.random.Generator
        One per campaign (its every draw comes from it).
    hang_ids : sequence of str, optional
        The ``point_id`` each hang gets in the files (default ``point_ids``; give distinct ids
        to re-hangs of one point).

    Returns
    -------
    list (per campaign) of list (per hang) of HangRecord
    """
    ids = list(point_ids if hang_ids is None else hang_ids)
    n_s = round(cfg.duration_s * cfg.sample_rate_hz)
    bodies, lengths, taus, y0, t_true, t0s = [], [], [], [], [], []
    if cfg.one_wire not in ("", "flexible", "stiff"):
        raise ValueError(f"one_wire must be '', 'flexible' or 'stiff', got {cfg.one_wire!r}")
    for rng in rngs:
        start_s = rng.uniform(5, 60)
        campaign_length = max(rng.normal(cfg.wire_length_mm, cfg.wire_length_sigma_mm), 1.0)
        # the ME mounted for this test (with me_errors), drawn once for all its hangs
        camp_truth = truth.with_me_drawn(rng, cfg.me_inertia_rel) if cfg.me_errors else truth
        for pid in point_ids:
            hinge = camp_truth.exit_of(pid)
            if cfg.hinge_errors:
                n = truth.normal_of(pid)
                t1 = np.cross(n, [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0])
                t1 /= np.linalg.norm(t1)
                t2 = np.cross(n, t1)
                a, b = rng.uniform(-0.5, 0.5, 2) * truth.play_mm
                hinge = hinge + a * t1 + b * t2
                if not cfg.one_wire:
                    hinge = hinge + rng.uniform(0, truth.wire_offset_max_mm) * n
                elif cfg.one_wire == "stiff":
                    hinge = hinge + _stiff_offset_mm(camp_truth, hinge, n, cfg) * n
            body = camp_truth.hung_from(hinge)
            if cfg.wire_length_mm == 0:
                length = 0.0
            elif cfg.one_wire:
                length = campaign_length
            else:
                length = max(rng.normal(cfg.wire_length_mm, cfg.wire_length_sigma_mm), 1.0)
            bodies.append(body)
            lengths.append(length)
            taus.append(rng.uniform(*cfg.decay_time_range_s))
            y0.append(st.initial_state(body, length, _release(body, length, cfg, rng)))
            k = np.arange(1, n_s + 1) / cfg.sample_rate_hz
            t_true.append(np.maximum(k + rng.uniform(-1, 1, n_s) * cfg.jitter_ms * 1e-3, 0.0))
            t0s.append(start_s)
            start_s += cfg.duration_s + rng.uniform(120, 300)
    omega = max(st.highest_frequency_rad_s(b, ln) for b, ln in zip(bodies, lengths, strict=True))
    dt = cfg.dt_s if cfg.dt_s is not None else min(4e-3, 0.15 / omega)
    # the air pushes on the object's shape: its centre of pressure at the object's centroid
    batch = st.make_batch(
        bodies, lengths, taus, cfg.drag_area_m2, np.tile(truth.object_cog_mm, (len(bodies), 1))
    )
    traj = st.integrate(batch, np.array(y0).T, np.array(t_true), dt, 10.0)
    true_x, true_y = st.inclinations_deg(traj.force)
    out: list[list[HangRecord]] = []
    h = 0
    for rng in rngs:
        campaign = []
        for pid, hid in zip(point_ids, ids, strict=True):
            body = bodies[h]
            u = body.plumb_up
            rest_x, rest_y = np.degrees(np.arcsin(u[0])), np.degrees(np.arcsin(u[1]))
            acc = truth.sensor.config.accuracy_deg  # type: ignore[attr-defined]
            bias = rng.uniform(-acc, acc, 2)
            sens = truth.sensor
            sx = truth.sensor.config.sign_x  # type: ignore[attr-defined]
            sy = truth.sensor.config.sign_y  # type: ignore[attr-defined]
            clock = (t0s[h] + t_true[h]) * (1 + cfg.clock_ppm * 1e-6)
            n_set = cfg.settled_samples
            campaign.append(
                HangRecord(
                    hid,
                    truth.exit_of(pid),
                    bool(u[2] > 0),
                    np.floor(clock * 1000).astype(np.int64),
                    sx * sens.read(true_x[h], bias[0], cfg.oversample, rng),
                    sy * sens.read(true_y[h], bias[1], cfg.oversample, rng),
                    sx * sens.read(np.full(n_set, rest_x), bias[0], cfg.oversample, rng),
                    sy * sens.read(np.full(n_set, rest_y), bias[1], cfg.oversample, rng),
                    float(lengths[h]),
                    float(taus[h]),
                    true_x[h],
                    true_y[h],
                )
            )
            h += 1
        out.append(campaign)
    return out


def swing_text(campaign: Sequence[HangRecord]) -> str:
    """The swing file: ``point_id,t_s,inc_x_deg,inc_y_deg``, each hang's rows contiguous."""
    lines = [
        "# simulated swing (support/swing_truth.py): device clock in s, device degrees",
        "point_id,t_s,inc_x_deg,inc_y_deg",
    ]
    for h in campaign:
        for t, x, y in zip(h.t_ms, h.inc_x_deg, h.inc_y_deg, strict=True):
            lines.append(f"{h.point_id},{t / 1000:.3f},{x:.5f},{y:.5f}")
    return "\n".join(lines) + "\n"


def readings_text(campaign: Sequence[HangRecord]) -> str:
    """The readings CSV of the same hangs (``docs/estimate.md``), settled samples, degrees."""
    lines = ["point_id,x_mm,y_mm,z_mm,inc_x_deg,inc_y_deg,top_face_up"]
    for h in campaign:
        x, y, z = (f"{c:.4f}" for c in h.wire_exit_mm)
        face = "true" if h.top_face_up else "false"
        for a, b in zip(h.settled_x_deg, h.settled_y_deg, strict=True):
            lines.append(f"{h.point_id},{x},{y},{z},{a:.5f},{b:.5f},{face}")
    return "\n".join(lines) + "\n"


def write_campaign(campaign: Sequence[HangRecord], swings: Path, readings: Path) -> None:
    """Write a campaign's swing file and readings CSV."""
    swings.write_text(swing_text(campaign), encoding="utf-8")
    readings.write_text(readings_text(campaign), encoding="utf-8")


def _stiff_offset_mm(truth: Truth, exit_mm: FloatArray, n: FloatArray, cfg: SwingConfig) -> float:
    """How far out along the bolt axis a stiff wire's straight part meets it: the elastica of
    EI under the hung weight, integrated numerically, at this hang's equilibrium angle."""
    import math

    from support.rig_campaigns import elastica_virtual_offset_mm

    g = truth.body.cog_mm
    lam = math.sqrt(cfg.bending_stiffness_n_mm2 / (truth.body.mass_kg * 9.80665))
    q = np.asarray(exit_mm, dtype=float)
    off = 0.0
    for _ in range(50):  # the hang's equilibrium: the angle and the offset agree
        up = (q - g) / np.linalg.norm(q - g)
        theta = math.acos(float(np.clip(up @ n, -1.0, 1.0)))
        new = elastica_virtual_offset_mm(theta, lam)
        if abs(new - off) < 1e-12:
            break
        off = new
        q = np.asarray(exit_mm, dtype=float) + off * n
    return off
