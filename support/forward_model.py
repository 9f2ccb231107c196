"""An independent forward model of the example 3U CubeSat's suspension test.

What it simulates
-----------------
A *truth* spacecraft (the CAD's items, changed per scenario: item masses, an item's CoG, an
unmodelled mass), the measurement equipment (ME) riding on it with its real CoG, and the test the
lab runs: the assembly hung by a wire from each of the plan's points in turn, the dual-axis
inclinometer sampled ``samples_per_suspension`` times per hang and read by a 10-bit ADC, and a
weighing of the spacecraft alone. The output is the readings CSV in the documented counts format
(``docs/estimate.md``: ``point_id,x_mm,y_mm,z_mm,inc_x_counts,inc_y_counts,top_face_up``, one row
per sample, the *nominal* point in the position columns), the weighed mass, and the truth to
compare the estimates with.

Physics, written here from the documentation (``docs/method.md`` §1-4, ``docs/montecarlo.md``):

- truth spacecraft: the CAD items (bodies grouped by their uncertainty ``item``; bodies of one
  item vary together) with their masses and CoGs changed by the scenario, plus any unmodelled
  point mass;
- ME: each sub-volume's true CoG uniform in a cube of edge ``cog_uncertainty_cube_mm`` around its
  CAD CoG, one draw per campaign;
- each hang, from the candidate's nominal point ``p0`` on a face of the bounding box with outward
  normal (bolt axis) ``n``: the wire's point is ``p0`` plus the play, uniform in a ``play_mm``
  square in the face plane, plus the wire's virtual offset along ``n``: the ``paper`` model
  uniform in ``[0, wire_offset_max_mm]``, independent per hang, the ``one-wire`` model's one
  ``λ`` per campaign uniform in that range with the elastica's shape, or the ``elastica``
  ``λ/cos(θ/2)``, ``λ = √(EI/W)``, ``EI`` uniform within ``±wire_stiffness_rel_uncertainty`` of
  its nominal value once per campaign, ``W`` the true hung weight (spacecraft + ME), ``θ`` the
  angle between the bolt axis and the vertical (solved by fixed-point iteration);
- equilibrium: the upward vertical in the body frame is ``u = (p − G)/|p − G|``, ``G`` the true
  assembly CoG;
- the inclinometer: ``X = asin(u·x_b)``, ``Y = asin(u·y_b)`` (times the rig's axis signs), a
  per-hang bias uniform in ``±accuracy_deg`` per axis (``hang-bias``; per sample under
  ``paper-averaged``), Gaussian noise ``sensor_noise_deg`` per sample, then the ADC: the sensor's
  voltage ``V = angle·sensitivity + zero_v`` falls in the bin ``floor(V·2^bits/ref)``, clipped to
  ``[0, 2^bits − 1]`` (the reader takes the bin centre, ``cadcog/rig/inclinometer.py``);
  ``top_face_up`` is the sign of ``u_z``;
- weighing: the truth's mass plus ``N(0, weighing_sigma_kg²)`` (1 g).

What is independent of cadcog
-----------------------------
Everything above is computed here with numpy. From cadcog it takes only *data*: the set-up read
by :func:`cadcog.load_setup` (the CAD bodies, the ME volumes placed on the spacecraft, the
candidate points and their face normals, the rig's inclinometer parameters and ``[error_model]``
values). It calls none of cadcog's simulation code (``cadcog.validation.campaign``,
``cadcog.uncertainty``, ``cadcog.method.errormodel``, ``cadcog.bench.simulator``) nor its
estimator or its mass combination.

Frames and units
----------------
The spacecraft's CAD frame (the CubeSat convention: origin at the centre of the
100 × 100 × 340.5 mm envelope, z along the rails); lengths in mm, masses in kg, inertias in
kg·mm² about the body's own CoG, angles in degrees, weights in N, ``EI`` in N·mm².

Every random draw comes from a :class:`numpy.random.Generator`; :func:`rng_for` seeds one per
(scenario, seed).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]

STANDARD_GRAVITY = 9.80665  # m/s²: W [N] = m [kg] · g
RECOMMENDED_POINTS = ("+x_-30_-30", "-x_30_-30", "+y_30_-30", "-y_-30_-30")
CAMERA = "cubesat_3u/payload_and_bus/payload_camera"
BATTERY = "cubesat_3u/payload_and_bus/battery_pack"
UNMODELLED = "unmodelled"
NONE = "none"
HARNESS_MASS_KG = 0.040
HARNESS_POSITION_MM = (22.0, 22.0, -152.0)  # bottom bay, beside the EPS board: a harness bundle
WRONG_REGION_MM = (-45.0, -45.0, 120.0, 45.0, 45.0, 165.0)  # the top bay: not where it is
WEIGHING_SIGMA_KG = 0.001
ALL_SOURCES = frozenset({"me_cog", "play", "wire", "inclinometer", "noise", "adc", "weighing"})


# --- the CAD as data ------------------------------------------------------------------------------
@dataclass(frozen=True)
class CadItem:
    """One uncertainty item of the CAD: its bodies combined (they vary together).

    ``inertia_kg_mm2`` is about the item's own CoG; ``sigma_rel`` is None for a fixed item."""

    key: str
    mass_kg: float
    cog_mm: FloatArray
    inertia_kg_mm2: FloatArray
    sigma_rel: float | None

    @property
    def spread_mm(self) -> FloatArray:
        """Radius of gyration per axis, ``√(C_kk/m)``, ``C = tr(J)/2·I − J`` the item's second
        central moment tensor (``C_kk = ∫ x_k² dm``)."""
        j = self.inertia_kg_mm2
        c = 0.5 * np.trace(j) * np.eye(3) - j
        return np.asarray(np.sqrt(np.clip(np.diag(c), 0.0, None) / self.mass_kg))


@dataclass(frozen=True)
class Hangs:
    """The points to hang from: ids, nominal positions on the faces (mm), outward normals."""

    ids: tuple[str, ...]
    points_mm: FloatArray  # (k, 3)
    normals: FloatArray  # (k, 3)


@dataclass(frozen=True)
class Rig:
    """The rig's documented parameters the forward model needs (from ``setup.rig``)."""

    accuracy_deg: float
    sign_x: int
    sign_y: int
    adc_bits: int
    adc_reference_v: float
    sensitivity_v_per_deg: float
    zero_v: float
    samples: int
    inclinometer_model: str
    sensor_noise_deg: float
    play_mm: float
    wire_model: str
    wire_offset_max_mm: float
    wire_bending_stiffness_n_mm2: float
    wire_stiffness_rel_uncertainty: float

    @property
    def max_counts(self) -> int:
        return int(2**self.adc_bits - 1)

    def deg_to_counts(self, angle_deg: FloatArray) -> npt.NDArray[np.int64]:
        """ADC counts of a reading: the bin the sensor's voltage falls in, clipped to the ADC."""
        volts = np.asarray(angle_deg) * self.sensitivity_v_per_deg + self.zero_v
        counts = np.floor(volts * 2**self.adc_bits / self.adc_reference_v)
        return np.clip(counts, 0, self.max_counts).astype(np.int64)

    def counts_to_deg(self, counts: npt.ArrayLike) -> FloatArray:
        """The reading at the centre of the bin (the documented transfer function)."""
        volts = (np.asarray(counts, dtype=float) + 0.5) * self.adc_reference_v / 2**self.adc_bits
        return np.asarray((volts - self.zero_v) / self.sensitivity_v_per_deg)

    @property
    def lsb_deg(self) -> float:
        return self.adc_reference_v / 2**self.adc_bits / self.sensitivity_v_per_deg


@dataclass(frozen=True)
class Cad:
    """Everything of the set-up the forward model uses, as plain arrays."""

    items: tuple[CadItem, ...]
    me_masses_kg: FloatArray  # (v,)
    me_centers_mm: FloatArray  # (v, 3)
    me_cube_mm: FloatArray  # (v,)
    hangs: Hangs
    rig: Rig

    @property
    def mass_kg(self) -> float:
        return float(sum(i.mass_kg for i in self.items))

    @property
    def cog_mm(self) -> FloatArray:
        return np.asarray(sum(i.mass_kg * i.cog_mm for i in self.items) / self.mass_kg)

    @property
    def me_mass_kg(self) -> float:
        return float(self.me_masses_kg.sum())

    @property
    def me_cog_mm(self) -> FloatArray:
        return np.asarray(self.me_masses_kg @ self.me_centers_mm / self.me_mass_kg)

    def item(self, key: str) -> CadItem:
        for i in self.items:
            if i.key == key:
                return i
        raise KeyError(key)


def combine_bodies(
    key: str, masses: Sequence[float], cogs: FloatArray, inertias: FloatArray, sigma: float | None
) -> CadItem:
    """Bodies as one item: total mass, mass-weighted CoG, inertia about it (parallel axes)."""
    m = np.asarray(masses, dtype=float)
    c = np.asarray(cogs, dtype=float).reshape(-1, 3)
    total = float(m.sum())
    g = m @ c / total
    j = np.zeros((3, 3))
    for mk, ck, jk in zip(m, c, np.asarray(inertias, dtype=float).reshape(-1, 3, 3), strict=True):
        d = ck - g
        j += jk + mk * (float(d @ d) * np.eye(3) - np.outer(d, d))
    return CadItem(key, total, g, j, sigma)


def cad_from_setup(setup: Any, point_ids: Sequence[str] = RECOMMENDED_POINTS) -> Cad:
    """The set-up's data (``cadcog.load_setup``) as a :class:`Cad`: items, ME, hangs, rig."""
    groups: dict[str, list[Any]] = {}
    for b in setup.bodies:
        groups.setdefault(b.item, []).append(b)
    items = []
    for key, members in groups.items():
        sig = {b.sigma_rel for b in members}
        if len(sig) != 1:
            raise ValueError(f"item {key}: its bodies disagree on the mass uncertainty {sig}")
        items.append(
            combine_bodies(
                key,
                [b.properties.mass_kg for b in members],
                np.array([b.properties.cog_mm for b in members]),
                np.array([b.properties.inertia_kg_mm2 for b in members]),
                members[0].sigma_rel,
            )
        )
    by_id = {c.id: c for c in setup.candidates}
    cands = [by_id[p] for p in point_ids]
    hangs = Hangs(
        tuple(point_ids),
        np.array([c.position_mm for c in cands], dtype=float),
        np.array([c.normal for c in cands], dtype=float),
    )
    inc, eo = setup.rig.inclinometer, setup.rig.error_options
    s = inc.sensor
    rig = Rig(
        inc.accuracy_deg,
        inc.sign_x,
        inc.sign_y,
        s.adc_bits,
        s.adc_reference_v,
        s.sensitivity_v_per_deg,
        s.zero_v,
        eo.samples,
        eo.inclinometer_model,
        eo.sensor_noise_deg,
        eo.play_mm,
        eo.wire_model,
        eo.wire_offset_max_mm,
        eo.wire_bending_stiffness_n_mm2,
        eo.wire_stiffness_rel_uncertainty,
    )
    vols = setup.me_volumes
    return Cad(
        tuple(items),
        np.array([v.mass_kg for v in vols], dtype=float),
        np.array([v.center_mm for v in vols], dtype=float),
        np.array([v.cog_uncertainty_cube_mm for v in vols], dtype=float),
        hangs,
        rig,
    )


# --- truths ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Truth:
    """The real spacecraft (without the ME).

    ``changed`` is the explanation a perfect update would rank first: an item key,
    ``"unmodelled"``, ``"none"`` (identical), or None when many items change at once.
    ``region_mm`` is the region given to ``update`` for an unmodelled mass (None: none given)."""

    mass_kg: float
    cog_mm: FloatArray
    item_masses_kg: FloatArray
    item_cogs_mm: FloatArray
    unmodelled_mass_kg: float | None = None
    unmodelled_cog_mm: FloatArray | None = None
    changed: str | None = NONE
    region_mm: tuple[float, ...] | None = None


def truth_from_items(
    cad: Cad,
    masses: FloatArray,
    cogs: FloatArray,
    *,
    extra_mass_kg: float | None = None,
    extra_cog_mm: Sequence[float] | None = None,
    changed: str | None = NONE,
    region_mm: tuple[float, ...] | None = None,
) -> Truth:
    """The truth's mass and CoG from its items' masses and CoGs and an optional point mass."""
    m = np.asarray(masses, dtype=float)
    c = np.asarray(cogs, dtype=float)
    total = float(m.sum())
    moment = m @ c
    extra_c = None
    if extra_mass_kg is not None:
        extra_c = np.asarray(extra_cog_mm, dtype=float)
        total += extra_mass_kg
        moment = moment + extra_mass_kg * extra_c
    return Truth(total, moment / total, m, c, extra_mass_kg, extra_c, changed, region_mm)


def _cad_arrays(cad: Cad) -> tuple[FloatArray, FloatArray]:
    return (
        np.array([i.mass_kg for i in cad.items]),
        np.array([i.cog_mm for i in cad.items]),
    )


def _prior_deltas(cad: Cad, rng: np.random.Generator) -> FloatArray:
    """Each uncertain item's relative mass change ~ N(0, sigma_rel²); fixed items 0."""
    sig = np.array([i.sigma_rel or 0.0 for i in cad.items])
    return np.asarray(rng.normal(0.0, 1.0, len(cad.items)) * sig)


def _scaled(cad: Cad, key: str, factor: float) -> FloatArray:
    m, _ = _cad_arrays(cad)
    m = m.copy()
    m[[i.key for i in cad.items].index(key)] *= factor
    return m


def identical(cad: Cad, rng: np.random.Generator) -> Truth:
    """1. The spacecraft is its CAD."""
    return truth_from_items(cad, *_cad_arrays(cad), changed=NONE)


def priors(cad: Cad, rng: np.random.Generator) -> Truth:
    """2. Item masses drawn from their own priors (bodies of one item scale together)."""
    m, c = _cad_arrays(cad)
    return truth_from_items(cad, m * (1.0 + _prior_deltas(cad, rng)), c, changed=None)


def camera_heavy(cad: Cad, rng: np.random.Generator) -> Truth:
    """3. The payload camera 15 % heavier, its CoG unchanged."""
    _, c = _cad_arrays(cad)
    return truth_from_items(cad, _scaled(cad, CAMERA, 1.15), c, changed=CAMERA)


def battery_heavy(cad: Cad, rng: np.random.Generator) -> Truth:
    """4. The battery pack 15 % heavier, its CoG unchanged."""
    _, c = _cad_arrays(cad)
    return truth_from_items(cad, _scaled(cad, BATTERY, 1.15), c, changed=BATTERY)


def harness(cad: Cad, rng: np.random.Generator) -> Truth:
    """5. A 40 g harness bundle the CAD does not have, at [22, 22, −152] mm (the bottom bay,
    beside the EPS board, inside the envelope); no region given to the update."""
    return truth_from_items(
        cad,
        *_cad_arrays(cad),
        extra_mass_kg=HARNESS_MASS_KG,
        extra_cog_mm=HARNESS_POSITION_MM,
        changed=UNMODELLED,
    )


def harness_wrong_region(cad: Cad, rng: np.random.Generator) -> Truth:
    """6. The same 40 g, but the update is told it is in the top bay (z 120..165 mm)."""
    t = harness(cad, rng)
    return Truth(
        t.mass_kg,
        t.cog_mm,
        t.item_masses_kg,
        t.item_cogs_mm,
        t.unmodelled_mass_kg,
        t.unmodelled_cog_mm,
        UNMODELLED,
        WRONG_REGION_MM,
    )


def camera_offset(cad: Cad, rng: np.random.Generator) -> Truth:
    """7. The camera's CoG 3 mm off in +x, its mass unchanged."""
    m, c = _cad_arrays(cad)
    c = c.copy()
    c[[i.key for i in cad.items].index(CAMERA)] += np.array([3.0, 0.0, 0.0])
    return truth_from_items(cad, m, c, changed=CAMERA)


def cog_priors(cad: Cad, rng: np.random.Generator) -> Truth:
    """8. Scenario 2's mass draws, and every uncertain item's CoG shifted per axis by
    ``N(0, (sigma_rel · spread_k)²)``, ``spread_k = √(C_kk/m)`` (:attr:`CadItem.spread_mm`)."""
    m, c = _cad_arrays(cad)
    masses = m * (1.0 + _prior_deltas(cad, rng))
    shift = np.array([(i.sigma_rel or 0.0) * i.spread_mm for i in cad.items])
    cogs = c + rng.normal(0.0, 1.0, c.shape) * shift
    return truth_from_items(cad, masses, cogs, changed=None)


ScenarioFn = Callable[[Cad, np.random.Generator], Truth]
SCENARIOS: dict[str, ScenarioFn] = {
    "identical": identical,
    "priors": priors,
    "camera +15 %": camera_heavy,
    "battery +15 %": battery_heavy,
    "40 g unmodelled": harness,
    "40 g, wrong region": harness_wrong_region,
    "camera CoG +3 mm x": camera_offset,
    "item CoG priors": cog_priors,
}
SCENARIO_NUMBER = {name: k + 1 for k, name in enumerate(SCENARIOS)}


def rng_for(scenario: str, seed: int) -> np.random.Generator:
    """The generator of one (scenario, seed): independent streams for every pair."""
    return np.random.default_rng([SCENARIO_NUMBER[scenario], seed])


# --- the test -------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Campaign:
    """One simulated test: the truth, what happened in each hang, and what was recorded."""

    truth: Truth
    me_cog_mm: FloatArray  # true ME CoG
    assembly_cog_mm: FloatArray  # true CoG of spacecraft + ME
    wire_points_mm: FloatArray  # (k, 3): the true virtual suspension points
    verticals: FloatArray  # (k, 3): the true upward verticals in the body frame
    readings_deg: FloatArray  # (k, n, 2): what the device output before the ADC (device signs)
    counts: npt.NDArray[np.int64]  # (k, n, 2)
    weighed_mass_kg: float
    hangs: Hangs
    sources: frozenset[str] = field(default=ALL_SOURCES)

    def csv_text(self) -> str:
        """The readings CSV (counts columns), one row per sample."""
        lines = ["point_id,x_mm,y_mm,z_mm,inc_x_counts,inc_y_counts,top_face_up"]
        for j, pid in enumerate(self.hangs.ids):
            x, y, z = self.hangs.points_mm[j]
            up = "true" if self.verticals[j, 2] > 0 else "false"
            for cx, cy in self.counts[j]:
                lines.append(f"{pid},{x:.3f},{y:.3f},{z:.3f},{int(cx)},{int(cy)},{up}")
        return "\n".join(lines) + "\n"

    def write_csv(self, path: str | Path) -> Path:
        p = Path(path)
        p.write_text(self.csv_text(), encoding="utf-8")
        return p


def _face_tangents(normal: FloatArray) -> FloatArray:
    """Two unit vectors spanning the plane ⊥ ``normal`` (axis-aligned faces: the other axes)."""
    a = np.eye(3)[int(np.argmin(np.abs(normal)))]
    t1 = np.cross(normal, a)
    t1 /= np.linalg.norm(t1)
    return np.array([t1, np.cross(normal, t1)])


def hang_verticals(points_mm: FloatArray, assembly_cog_mm: FloatArray) -> FloatArray:
    """Upward verticals at equilibrium: the CoG hangs straight below the suspension point."""
    d = np.asarray(points_mm) - np.asarray(assembly_cog_mm)
    return np.asarray(d / np.linalg.norm(d, axis=-1, keepdims=True))


def simulate(
    cad: Cad,
    truth: Truth,
    rng: np.random.Generator,
    *,
    sources: frozenset[str] = ALL_SOURCES,
    weighing_sigma_kg: float = WEIGHING_SIGMA_KG,
) -> Campaign:
    """Hang ``truth`` with the ME from every point of ``cad.hangs``, read the inclinometer and
    weigh the spacecraft; ``sources`` lists the error sources on (all by default)."""
    rig = cad.rig
    # the ME's real CoG: one draw per campaign
    me_off = np.zeros_like(cad.me_centers_mm)
    if "me_cog" in sources:
        half = 0.5 * cad.me_cube_mm[:, None]
        me_off = rng.uniform(-1.0, 1.0, cad.me_centers_mm.shape) * half
    me_cog = (cad.me_masses_kg @ (cad.me_centers_mm + me_off)) / cad.me_mass_kg
    m_all = truth.mass_kg + cad.me_mass_kg
    g = (truth.mass_kg * truth.cog_mm + cad.me_mass_kg * me_cog) / m_all

    h = cad.hangs
    k = len(h.ids)
    points = h.points_mm.copy()
    if "play" in sources:
        for j in range(k):
            t = _face_tangents(h.normals[j])
            points[j] += rng.uniform(-0.5, 0.5, 2) * rig.play_mm @ t
    offset = np.zeros(k)
    if "wire" in sources:
        if rig.wire_model == "paper":
            offset = rng.uniform(0.0, rig.wire_offset_max_mm, k)
        elif rig.wire_model in ("elastica", "one-wire"):
            if rig.wire_model == "one-wire":  # one wire: one λ for the campaign, 0 … the bound
                lam = rng.uniform(0.0, rig.wire_offset_max_mm)
            else:
                ei = rig.wire_bending_stiffness_n_mm2 * (
                    1.0 + rig.wire_stiffness_rel_uncertainty * rng.uniform(-1.0, 1.0)
                )
                lam = math.sqrt(ei / (m_all * STANDARD_GRAVITY))
            offset = np.full(k, lam)
            for _ in range(50):  # θ depends on the vertical, which depends on the offset
                u = hang_verticals(points + offset[:, None] * h.normals, g)
                cos_t = np.clip(np.sum(u * h.normals, axis=1), -1.0, 1.0)
                new = lam / np.cos(0.5 * np.arccos(cos_t))
                if np.max(np.abs(new - offset)) < 1e-12:
                    break
                offset = new
        else:
            raise ValueError(f"unknown wire model {rig.wire_model!r}")
    wire = points + offset[:, None] * h.normals
    u = hang_verticals(wire, g)

    n = rig.samples
    signs = np.array([rig.sign_x, rig.sign_y], dtype=float)
    true_deg = np.degrees(np.arcsin(np.clip(u[:, :2], -1.0, 1.0))) * signs  # (k, 2)
    readings = np.repeat(true_deg[:, None, :], n, axis=1)
    if "inclinometer" in sources:
        a = rig.accuracy_deg
        if rig.inclinometer_model == "paper-averaged":
            readings = readings + rng.uniform(-a, a, (k, n, 2))
        else:
            readings = readings + rng.uniform(-a, a, (k, 1, 2))
    if "noise" in sources:
        readings = readings + rng.normal(0.0, rig.sensor_noise_deg, (k, n, 2))
    if "adc" in sources:
        counts = rig.deg_to_counts(readings)
    else:  # no quantisation: the real-valued counts, rounded only for the CSV
        volts = readings * rig.sensitivity_v_per_deg + rig.zero_v
        counts = np.rint(volts * 2**rig.adc_bits / rig.adc_reference_v - 0.5).astype(np.int64)
    weighed = truth.mass_kg
    if "weighing" in sources:
        weighed += float(rng.normal(0.0, weighing_sigma_kg))
    return Campaign(truth, me_cog, g, wire, u, readings, counts, weighed, h, sources)


def campaign(cad: Cad, scenario: str, seed: int, **kwargs: Any) -> Campaign:
    """The truth of ``scenario`` and its simulated test, all from :func:`rng_for`."""
    rng = rng_for(scenario, seed)
    truth = SCENARIOS[scenario](cad, rng)
    return simulate(cad, truth, rng, **kwargs)
