"""An independent generator of null campaigns on a rig, for checking `cadcog validate`'s size.

Written from the documented physics only (``parts/paper_rig.toml``, ``docs/rig.md``,
``docs/montecarlo.md``, the ADC transfer function of ``docs/rig.md``), without cadcog's campaign,
Monte Carlo or error-model code, so that a shared mistake cannot hide a wrong size:

- the rig file is read with :mod:`tomllib`; the proof mass is the box minus its drilled holes
  (cylinders of the hole diameter and depth, into the face at each point), its CoG from those
  closed forms;
- the measurement equipment (ME): each volume's real CoG uniform in its uncertainty cube, drawn
  once per campaign;
- each hang: the wire leaves the bolt ``wire_exit_height_mm`` above the hole along the face's
  outward normal; the suspension point plays in a uniform ``play_mm`` square in the face plane and
  the virtual point lies uniform ``0 … wire_offset_max_mm`` further out along the normal; the
  object hangs with its true CoG straight below that point;
- the inclinometer: readings ``X = asin(u·x)``, ``Y = asin(u·y)`` (times the axis signs), a bias
  uniform ±accuracy per axis fixed during the hang (the ``hang-bias`` model), and per sample
  Gaussian noise of ``sensor_noise_deg``; then, when quantised, the 10-bit ADC: the voltage
  ``V = angle·sensitivity + zero_v`` falls into bin ``floor(V·2^bits / V_ref)``, clipped to the
  ADC's range. The CSV holds those counts (``inc_x_counts, inc_y_counts``), or the unquantised
  angles (``inc_x_deg, inc_y_deg``, 9 decimals) for the comparison without the ADC.

What one rig shares across its hangs (issue 31), drawn once per campaign when asked for:

- the wire: ``"paper"`` (the above: an offset drawn afresh for every hang, the paper's model),
  ``"one-wire"`` (one wire of elastica length λ uniform in 0 … ``wire_offset_max_mm`` for the
  campaign, the rig file's default model), ``"flexible"`` (an ideal string: it
  turns at the exit itself, no offset on any hang) or ``"stiff"`` (a wire of bending stiffness
  EI under the hung weight W: the object hangs below the straight part's line, found here by
  integrating the elastica ``EI φ'' = W sin φ`` numerically from the clamp, where the wire leaves
  along the bolt axis, and iterating the hang to its equilibrium);
- the sensor: each channel's zero offset and sensitivity error uniform within the given figures,
  and its mounting a rotation of angle uniform in [0, figure] about a uniformly random axis
  (:class:`scipy.spatial.transform.Rotation`): the sensor sees the vertical in its own axes and
  reports ``(1 + s)·asin(v) + b`` per channel before its per-hang bias and noise.

A reversal (``reversals``): after the campaign's hangs, the object hangs again from a listed
point with the sensor turned 180° about its own z axis on its mount (the mount's tilt stays, the
sensor's x and y axes reverse: it sees ``diag(−1, −1, 1)·R·u``); a hang of its own, with its own
play, bias and noise, the same wire and the same sensor. It is written as point ``<id>~`` with
``sensor_turned`` true.

Campaign ``i`` of a seed draws from ``SeedSequence(seed, spawn_key=(i,))`` alone.
"""

from __future__ import annotations

import functools
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]

_FACE_NORMALS = {
    "+x": (1.0, 0.0, 0.0),
    "-x": (-1.0, 0.0, 0.0),
    "+y": (0.0, 1.0, 0.0),
    "-y": (0.0, -1.0, 0.0),
    "+z": (0.0, 0.0, 1.0),
    "-z": (0.0, 0.0, -1.0),
}


@dataclass(frozen=True)
class RigPhysics:
    """What the generator needs from a rig file, in plain arrays (mm, kg, degrees, volts).

    Attributes
    ----------
    ids : tuple of str
    exits_mm : ndarray, shape (k, 3)
        Where the wire leaves each bolt (the point a lab records).
    normals : ndarray, shape (k, 3)
    pm_mass_kg : float
    pm_cog_mm : ndarray, shape (3,)
        Proof-mass CoG, box minus holes.
    me_masses_kg : ndarray, shape (m,)
    me_centers_mm : ndarray, shape (m, 3)
    me_cube_mm : ndarray, shape (m,)
    """

    ids: tuple[str, ...]
    exits_mm: FloatArray
    normals: FloatArray
    pm_mass_kg: float
    pm_cog_mm: FloatArray
    me_masses_kg: FloatArray
    me_centers_mm: FloatArray
    me_cube_mm: FloatArray
    accuracy_deg: float
    sign_x: int
    sign_y: int
    adc_bits: int
    adc_reference_v: float
    sensitivity_v_per_deg: float
    zero_v: float
    samples: int
    noise_deg: float
    play_mm: float
    wire_offset_max_mm: float
    wire_model: str = "one-wire"

    @classmethod
    def from_file(cls, path: str | Path) -> RigPhysics:
        """Read a rig TOML (the paper wire model and the hang-bias inclinometer only)."""
        with Path(path).open("rb") as fh:
            d = tomllib.load(fh)
        em = d.get("error_model", {})
        if em.get("wire_model", "one-wire") not in ("paper", "one-wire"):
            raise ValueError("the independent generator models the paper and one-wire offsets")
        if em.get("inclinometer_model", "hang-bias") != "hang-bias":
            raise ValueError("the independent generator models the hang-bias inclinometer only")
        size = np.array(d["proof_mass"]["size_mm"], dtype=float)
        r = 0.5 * d["holes"]["diameter_mm"]
        depth = d["holes"]["depth_mm"]
        pts = d["suspension_points"]
        normals = np.array([_FACE_NORMALS[p["face"]] for p in pts])
        pos = np.array([p["position_mm"] for p in pts], dtype=float)
        # Box minus cylinders: each hole's centroid is half its depth inside the face.
        v_box = float(np.prod(size))
        v_hole = math.pi * r * r * depth
        hole_c = pos - 0.5 * depth * normals
        v = v_box - len(pts) * v_hole
        pm_cog = (v_box * 0.5 * size - v_hole * hole_c.sum(axis=0)) / v
        vols = d["measurement_equipment"]["volumes"]
        inc = d["inclinometer"]
        return cls(
            ids=tuple(p["id"] for p in pts),
            exits_mm=pos + d["holes"]["wire_exit_height_mm"] * normals,
            normals=normals,
            pm_mass_kg=float(d["proof_mass"]["mass_kg"]),
            pm_cog_mm=pm_cog,
            me_masses_kg=np.array([w["mass_kg"] for w in vols], dtype=float),
            me_centers_mm=np.array([w["center_mm"] for w in vols], dtype=float),
            me_cube_mm=np.array([w["cog_uncertainty_cube_mm"] for w in vols], dtype=float),
            accuracy_deg=float(inc.get("accuracy_deg", 0.1)),
            sign_x=int(inc.get("sign_x", 1)),
            sign_y=int(inc.get("sign_y", 1)),
            adc_bits=int(inc.get("adc_bits", 10)),
            adc_reference_v=float(inc.get("adc_reference_v", 5.0)),
            sensitivity_v_per_deg=float(inc.get("sensitivity_v_per_deg", 1.0 / 30.0)),
            zero_v=float(inc.get("zero_v", 2.5)),
            samples=int(em.get("samples_per_suspension", 10)),
            noise_deg=float(em.get("sensor_noise_deg", 0.05)),
            play_mm=float(em.get("play_mm", 1.0)),
            wire_offset_max_mm=float(em.get("wire_offset_max_mm", 1.0)),
            wire_model=str(em.get("wire_model", "one-wire")),
        )

    @property
    def lsb_deg(self) -> float:
        return self.adc_reference_v / 2**self.adc_bits / self.sensitivity_v_per_deg

    @property
    def assembly_cog_mm(self) -> FloatArray:
        """CoG of proof mass + ME at the ME's CAD centres."""
        m = self.me_masses_kg
        total = self.pm_mass_kg + m.sum()
        return np.asarray((self.pm_mass_kg * self.pm_cog_mm + m @ self.me_centers_mm) / total)

    def counts(self, angle_deg: FloatArray, rounding: str = "floor") -> npt.NDArray[np.int64]:
        """The ADC's bin of each angle (the transfer function of docs/rig.md).

        ``rounding="floor"``: the bin the voltage falls in, as an ADC reports it and as cadcog
        reads it back (bin centre). ``"nearest"``: ``round(V·2^bits/V_ref)``, a generator that
        mistakes the convention (half an LSB too high once read back): a negative control.
        """
        volts = angle_deg * self.sensitivity_v_per_deg + self.zero_v
        x = volts * 2**self.adc_bits / self.adc_reference_v
        if rounding not in ("floor", "nearest"):
            raise ValueError(f"rounding must be 'floor' or 'nearest', got {rounding!r}")
        c = np.floor(x) if rounding == "floor" else np.floor(x + 0.5)
        return np.clip(c, 0, 2**self.adc_bits - 1).astype(np.int64)


@dataclass(frozen=True)
class Campaign:
    """One generated campaign: per hang the true vertical and the raw samples.

    Attributes
    ----------
    u_true : ndarray, shape (k, 3)
        True upward verticals (body frame).
    samples_deg : ndarray, shape (k, n, 2)
        Raw samples X, Y before the ADC (bias and noise included), in the device's signs.
    """

    u_true: FloatArray
    samples_deg: FloatArray
    ids: tuple[str, ...] = ()
    turned: tuple[bool, ...] = ()
    exits_mm: FloatArray | None = None


def _tangents(normal: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Two body axes spanning an axis-aligned face."""
    axes = [np.eye(3)[i] for i in range(3) if abs(normal[i]) < 0.5]
    return axes[0], axes[1]


#: Standard gravity (m/s²), for the hung weight.
G0_M_S2 = 9.80665


@functools.lru_cache(maxsize=1)
def _offset_ratio_table() -> tuple[FloatArray, FloatArray]:
    """``Δ/λ`` of :func:`elastica_virtual_offset_mm` on a grid of θ (it depends on θ alone: the
    elastica scales with λ), each value integrated numerically once."""
    from scipy.integrate import solve_ivp

    def rhs(s: float, y: FloatArray) -> list[float]:
        return [-2.0 * math.sin(0.5 * y[0]), math.sin(y[0])]

    thetas = np.linspace(1e-4, 3.0, 601)
    ratios = np.empty_like(thetas)
    for i, theta in enumerate(thetas):
        sol = solve_ivp(rhs, (0.0, 60.0), [theta, 0.0], rtol=1e-11, atol=1e-13)
        ratios[i] = sol.y[1, -1] / math.sin(theta)
    return thetas, ratios


def elastica_virtual_offset_mm(theta_rad: float, lam_mm: float) -> float:
    """How far along the bolt axis above the clamp the straight part's line meets it, for a wire
    that leaves the clamp at ``theta_rad`` from the upward vertical: the elastica integrated
    numerically (tangent angle ``φ(s)``, ``φ(0) = θ``, ``λ² φ'' = sin φ``, the branch that
    straightens: ``φ' = −(2/λ) sin(φ/2)``), its lateral drift ``h = ∫ sin φ ds`` taken to where
    the wire is straight, then ``h / sin θ`` (tabulated in θ once, interpolated: 10⁻⁵ relative)."""
    thetas, ratios = _offset_ratio_table()
    return float(lam_mm * np.interp(theta_rad, thetas, ratios))


def generate(
    rig: RigPhysics,
    seed: int,
    index: int,
    *,
    noise_deg: float | None = None,
    samples: int | None = None,
    wire: str | None = None,
    bending_stiffness_n_mm2: float = 30.0,
    sensor_offset_deg: float = 0.0,
    sensor_scale_rel: float = 0.0,
    mounting_deg: float = 0.0,
    reversals: tuple[str, ...] = (),
) -> Campaign:
    """Campaign ``index`` of ``seed``: one hang per suspension point.

    Parameters
    ----------
    rig : RigPhysics
    seed, index : int
        The draws come from ``SeedSequence(seed, spawn_key=(index,))``.
    noise_deg, samples : optional
        Override the rig's per-sample noise and sample count.
    wire : "paper", "one-wire", "flexible" or "stiff", optional
        See the module's docstring; ``bending_stiffness_n_mm2`` is the stiff wire's EI.
        ``"one-wire"``: a wire whose elastica length λ is uniform in 0 … the rig's
        ``wire_offset_max_mm``, once per campaign. Default: the rig file's ``wire_model``.
    sensor_offset_deg, sensor_scale_rel, mounting_deg : float
        The sensor's shared errors' figures (0: none).
    reversals : tuple of str
        Points hung once more at the end with the sensor turned on its mount.
    """
    wire = rig.wire_model if wire is None else wire
    if wire not in ("paper", "one-wire", "flexible", "stiff"):
        raise ValueError(f"wire must be 'paper', 'one-wire', 'flexible' or 'stiff', got {wire!r}")
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index,)))
    noise = rig.noise_deg if noise_deg is None else noise_deg
    n = rig.samples if samples is None else samples
    # The ME: each volume's real CoG in its cube, once for the campaign.
    me_true = (
        rig.me_centers_mm + (rng.random((len(rig.me_cube_mm), 3)) - 0.5) * rig.me_cube_mm[:, None]
    )
    m = rig.me_masses_kg
    mass = rig.pm_mass_kg + m.sum()
    g = (rig.pm_mass_kg * rig.pm_cog_mm + m @ me_true) / mass
    # One sensor for the campaign.
    offset = scale = np.zeros(2)
    mount = np.eye(3)
    if sensor_offset_deg or sensor_scale_rel or mounting_deg:
        from scipy.spatial.transform import Rotation

        offset = rng.uniform(-sensor_offset_deg, sensor_offset_deg, 2)
        scale = rng.uniform(-sensor_scale_rel, sensor_scale_rel, 2)
        axis = rng.standard_normal(3)
        axis /= np.linalg.norm(axis)
        angle = np.radians(rng.uniform(0.0, mounting_deg))
        mount = Rotation.from_rotvec(axis * angle).as_matrix()
    lam = 0.0
    if wire == "stiff":
        lam = math.sqrt(bending_stiffness_n_mm2 / (mass * G0_M_S2))
    elif wire == "one-wire":
        lam = rng.random() * rig.wire_offset_max_mm
    order = [*range(len(rig.ids)), *(rig.ids.index(r) for r in reversals)]
    turned = [False] * len(rig.ids) + [True] * len(reversals)
    k = len(order)
    u = np.empty((k, 3))
    out = np.empty((k, n, 2))
    for at, j in enumerate(order):
        nrm = rig.normals[j]
        t1, t2 = _tangents(nrm)
        play = (rng.random(2) - 0.5) * rig.play_mm
        exit_mm = rig.exits_mm[j] + play[0] * t1 + play[1] * t2
        if wire == "paper":
            q = exit_mm + rng.random() * rig.wire_offset_max_mm * nrm
        else:
            q = exit_mm
            for _ in range(50):  # the hang's equilibrium: θ and the offset agree
                up = (q - g) / np.linalg.norm(q - g)
                theta = math.acos(float(np.clip(up @ nrm, -1.0, 1.0)))
                q_new = exit_mm + elastica_virtual_offset_mm(theta, lam) * nrm
                if np.linalg.norm(q_new - q) < 1e-12:
                    break
                q = q_new
        d = q - g
        u[at] = d / np.linalg.norm(d)
        seen = mount @ u[at]
        if turned[at]:
            seen = np.array([-seen[0], -seen[1], seen[2]])
        ideal = (1.0 + scale) * np.degrees(np.arcsin(seen[:2])) * (rig.sign_x, rig.sign_y)
        bias = (rng.random(2) - 0.5) * 2.0 * rig.accuracy_deg
        out[at] = ideal + offset + bias + rng.normal(0.0, 1.0, (n, 2)) * noise
    ids = tuple(rig.ids[j] + ("~" if t else "") for j, t in zip(order, turned, strict=True))
    return Campaign(u, out, ids, tuple(turned), rig.exits_mm[order])


def write_csv(
    rig: RigPhysics,
    campaign: Campaign,
    path: str | Path,
    *,
    quantise: bool,
    rounding: str = "floor",
) -> None:
    """The campaign as a readings CSV: ADC counts when ``quantise``, else degrees."""
    cols = "inc_x_counts,inc_y_counts" if quantise else "inc_x_deg,inc_y_deg"
    ids = campaign.ids or rig.ids
    exits = rig.exits_mm if campaign.exits_mm is None else campaign.exits_mm
    extra = any(campaign.turned)
    lines = [f"point_id,x_mm,y_mm,z_mm,{cols},top_face_up" + (",sensor_turned" if extra else "")]
    for j, pid in enumerate(ids):
        x, y, z = exits[j]
        head = f"{pid},{x:.3f},{y:.3f},{z:.3f}"
        up = "true" if campaign.u_true[j, 2] > 0 else "false"
        if extra:
            up += ",true" if campaign.turned[j] else ",false"
        s = campaign.samples_deg[j]
        if quantise:
            c = rig.counts(s, rounding)
            lines += [f"{head},{cx},{cy},{up}" for cx, cy in c]
        else:
            lines += [f"{head},{sx:.9f},{sy:.9f},{up}" for sx, sy in s]
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")
