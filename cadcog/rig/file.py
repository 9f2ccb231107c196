"""Reading and validating rig parameter files (TOML).

The format is documented in ``docs/rig.md``; ``parts/paper_rig.toml`` is the reference example.
Validation is complete before anything is built or written: unknown, missing or mistyped keys,
non-positive sizes and masses, holes deeper than the part or off their face, holes that meet,
suspension points off the surface or under the measurement equipment, and ME sub-volumes that
overlap each other or the proof mass all raise :class:`~cadcog.core.errors.ParameterFileError`
naming the file and the key.
"""

from __future__ import annotations

from collections.abc import Sequence
from importlib import resources
from itertools import combinations
from pathlib import Path

import numpy as np

from cadcog.core import bounds, tolerances
from cadcog.core.errors import ParameterFileError
from cadcog.core.paramfile import TableReader, read_toml
from cadcog.core.tolerances import MIN_SOLID_DIMENSION_MM
from cadcog.core.units import density_kg_mm3_to_kg_m3
from cadcog.rig.accelerometer import axes_problem
from cadcog.rig.geometry import AXIS_NAMES, FACES, face_plane_mm
from cadcog.rig.inclinometer import DEVICES, InclinometerConfig, SensorModel
from cadcog.rig.parameters import (
    INCLINOMETER_MODELS,
    WIRE_MODELS,
    ErrorOptions,
    HoleSpec,
    MEVolume,
    ProofMass,
    Rig,
    SuspensionPoint,
    SwingOptions,
)

#: Names used for files and JSON keys: letters, digits, underscore and hyphen.
#: Body names the ground truth uses itself; ME volumes may not take them.
RESERVED_BODY_NAMES = ("proof_mass", "measurement_equipment", "assembly")


def default_rig_path() -> Path:
    """Path of the built-in paper rig (``parts/paper_rig.toml``)."""
    return Path(str(resources.files("cadcog._rigs").joinpath("paper_rig.toml")))


def load_rig(path: str | Path) -> Rig:
    """Read, type-check and geometrically validate a rig file.

    Parameters
    ----------
    path : path-like
        A TOML rig file.

    Returns
    -------
    Rig

    Raises
    ------
    cadcog.core.errors.ParameterFileError
        Naming the file and the offending key.
    """
    path = Path(path)
    data = read_toml(path)
    if "proof_mass" not in data and ("candidates" in data or "measurement_equipment" in data):
        raise ParameterFileError(
            path,
            "proof_mass",
            "missing: this is a spacecraft set-up ([candidates], [measurement_equipment]), not "
            "a rig file: give it as the set-up (--setup, or setup= from Python)",
        )
    root = TableReader(data, path)
    name = _name(root, "name")

    pm_t = root.table("proof_mass")
    size = pm_t.vector("size_mm", positive=True, at_least=MIN_SOLID_DIMENSION_MM)
    proof_mass = ProofMass(
        size_mm=(size[0], size[1], size[2]),
        mass_kg=pm_t.number("mass_kg", positive=True),
        material=pm_t.string("material"),
    )
    _check_density(pm_t, proof_mass.mass_kg, proof_mass.size_mm, solid=True)
    pm_t.finish()

    holes_t = root.table("holes")
    holes = HoleSpec(
        diameter_mm=holes_t.number("diameter_mm", positive=True, at_least=MIN_SOLID_DIMENSION_MM),
        depth_mm=holes_t.number("depth_mm", positive=True, at_least=MIN_SOLID_DIMENSION_MM),
        wire_exit_height_mm=holes_t.number("wire_exit_height_mm", nonnegative=True),
    )
    holes_t.finish()

    points = []
    point_tables = root.tables("suspension_points", min_count=2)
    for t in point_tables:
        pos = t.vector("position_mm")
        points.append(
            SuspensionPoint(
                id=_name(t, "id"),
                face=t.string("face", choices=list(FACES)),
                position_mm=(pos[0], pos[1], pos[2]),
            )
        )
        t.finish()

    me_t = root.table("measurement_equipment")
    volume_tables = me_t.tables("volumes")
    volumes = []
    for t in volume_tables:
        vsize = t.vector("size_mm", positive=True, at_least=MIN_SOLID_DIMENSION_MM)
        center = t.vector("center_mm")
        volumes.append(
            MEVolume(
                name=_name(t, "name"),
                size_mm=(vsize[0], vsize[1], vsize[2]),
                center_mm=(center[0], center[1], center[2]),
                mass_kg=t.number("mass_kg", positive=True),
                cog_uncertainty_cube_mm=t.number("cog_uncertainty_cube_mm", nonnegative=True),
            )
        )
        t.finish()
    me_t.finish()

    inclinometer = _inclinometer(root.table("inclinometer"))
    error_options = _error_options(root.table("error_model")) if root.has("error_model") else None
    swing = swing_options(root.table("swing")) if root.has("swing") else SwingOptions()
    root.finish()

    _check_unique(point_tables, [p.id for p in points], "id")
    _check_unique(volume_tables, [v.name for v in volumes], "name")
    for t, v in zip(volume_tables, volumes, strict=True):
        _check_density(t, v.mass_kg, v.size_mm, solid=False)
        if v.name in RESERVED_BODY_NAMES:
            raise t.error("name", f"{v.name!r} is reserved; choose another name")
    _check_holes(holes_t, point_tables, proof_mass, holes, points)
    _check_me(volume_tables, proof_mass, volumes)
    _check_points_clear_of_me(point_tables, holes, points, volumes)
    rig = Rig(
        name,
        path,
        proof_mass,
        holes,
        tuple(points),
        tuple(volumes),
        inclinometer,
        error_options or ErrorOptions(),
        swing,
    )
    if not rig.proof_mass_volume_mm3 > 0.0:  # pragma: no cover - excluded by the hole checks
        raise pm_t.error("size_mm", "the holes remove the whole proof mass")
    return rig


#: Coarsest ADC step (degrees) a rig's inclinometer may have: one step of 1° already moves a
#: plumb line by 17 mm per metre; the paper's 10-bit ADC has 0.146°.
MAX_ADC_STEP_DEG = 1.0


#: Keys of an ``[inclinometer]`` table that only an angle-reading device has.
_ANGLE_ONLY_KEYS = (
    "range_deg", "accuracy_deg", "sign_x", "sign_y", "adc_bits", "adc_reference_v",
    "sensitivity_v_per_deg", "zero_v", "offset_deg",
)  # fmt: skip


def _inclinometer(t: TableReader) -> InclinometerConfig:
    """The ``[inclinometer]`` table: range required, the rest defaulting to the paper's rig
    (or, with ``device = "accelerometer"``, :func:`_accelerometer`)."""
    device = t.string("device", choices=DEVICES, default="inclinometer")
    if device == "accelerometer":
        return _accelerometer(t)
    for key in ("axes", "offset_g", "accuracy_g", "cross_axis_rel"):
        if t.has(key):
            raise t.error(key, 'an accelerometer\'s figure: declare device = "accelerometer"')
    d, ds = InclinometerConfig(), SensorModel()
    range_deg = t.number("range_deg", positive=True)
    if range_deg > 90.0:
        raise t.error("range_deg", f"expected at most 90 degrees, got {range_deg}")
    config = InclinometerConfig(
        range_deg=range_deg,
        accuracy_deg=t.number("accuracy_deg", nonnegative=True, default=d.accuracy_deg),
        sign_x=t.integer("sign_x", choices=(1, -1), default=d.sign_x),
        sign_y=t.integer("sign_y", choices=(1, -1), default=d.sign_y),
        sensor=SensorModel(
            adc_bits=t.integer("adc_bits", minimum=1, default=ds.adc_bits),
            adc_reference_v=t.number("adc_reference_v", positive=True, default=ds.adc_reference_v),
            sensitivity_v_per_deg=t.number(
                "sensitivity_v_per_deg", positive=True, default=ds.sensitivity_v_per_deg
            ),
            zero_v=t.number("zero_v", default=ds.zero_v),
        ),
        offset_deg=t.number("offset_deg", nonnegative=True, default=d.offset_deg),
        scale_error_rel=t.number("scale_error_rel", nonnegative=True, default=d.scale_error_rel),
        mounting_misalignment_deg=t.number(
            "mounting_misalignment_deg", nonnegative=True, default=d.mounting_misalignment_deg
        ),
    )
    lsb = config.sensor.lsb_deg
    if lsb > MAX_ADC_STEP_DEG:
        key = "sensitivity_v_per_deg" if t.has("sensitivity_v_per_deg") else "adc_bits"
        raise t.error(
            key,
            f"the ADC step is {lsb:.3g}° (adc_reference_v / 2^adc_bits / sensitivity_v_per_deg): "
            f"expected at most {MAX_ADC_STEP_DEG:g}° for an inclinometer that can locate a CoG",
        )
    t.finish()
    return config


def _accelerometer(t: TableReader) -> InclinometerConfig:
    """An ``[inclinometer]`` table with ``device = "accelerometer"``: a three-axis
    accelerometer (:mod:`cadcog.rig.accelerometer`), its mounting and shared figures."""
    present = set(t.keys())  # (not t.has: an unknown key's message lists what was asked for)
    angle = [k for k in _ANGLE_ONLY_KEYS if k in present]
    if angle:
        hint = {
            "offset_deg": " (declare offset_g, in g)",
            "accuracy_deg": " (declare accuracy_g, in g)",
        }.get(angle[0], "")
        others = f" (and {', '.join(angle[1:])})" if len(angle) > 1 else ""
        raise t.error(
            angle[0],
            f"an angle-reading inclinometer's figure{others}; an accelerometer has none{hint}",
        )
    # How it sits and what it shares are what a team must think about: no silent perfect sensor.
    missing = [
        k
        for k in ("axes", "offset_g", "scale_error_rel", "mounting_misalignment_deg")
        if k not in present
    ]
    if missing:
        raise t.error(
            missing[0],
            "missing: an accelerometer declares how it sits and its shared figures "
            f"({', '.join(missing)}; 0 for a figure known to be negligible): docs/bench.md §8",
        )
    d = InclinometerConfig()
    axes = tuple(t.strings("axes"))
    problem = axes_problem(axes)
    if problem is not None:
        raise t.error("axes", problem)
    offset_g = t.number("offset_g", nonnegative=True, default=0.0)
    scale = t.number("scale_error_rel", nonnegative=True, default=d.scale_error_rel)
    mounting = t.number(
        "mounting_misalignment_deg", nonnegative=True, default=d.mounting_misalignment_deg
    )
    accuracy = t.number("accuracy_g", positive=True, default=d.accuracy_g)
    cross = t.number("cross_axis_rel", nonnegative=True, default=d.cross_axis_rel)
    config = InclinometerConfig(
        range_deg=90.0,
        accuracy_deg=0.0,
        scale_error_rel=scale,
        mounting_misalignment_deg=mounting,
        device="accelerometer",
        axes=axes,  # type: ignore[arg-type]
        offset_g=offset_g,
        accuracy_g=accuracy,
        cross_axis_rel=cross,
    )
    t.finish()
    return config


def _error_options(t: TableReader) -> ErrorOptions:
    """The optional ``[error_model]`` table; absent keys take the defaults."""
    d = ErrorOptions()
    if t.has("dither_noise_deg"):
        raise t.error(
            "dither_noise_deg",
            "renamed sensor_noise_deg (the noise of one raw sample, in every inclinometer model)",
        )
    if t.has("inclinometer_model") and t.string("inclinometer_model") in ("paper", "conservative"):
        raise t.error(
            "inclinometer_model",
            "the models are now 'hang-bias' (was 'conservative', the default) and "
            "'paper-averaged' (was 'paper')",
        )
    options = ErrorOptions(
        samples=t.integer("samples_per_suspension", minimum=1, default=d.samples),
        inclinometer_model=t.string(  # type: ignore[arg-type]
            "inclinometer_model", choices=INCLINOMETER_MODELS, default=d.inclinometer_model
        ),
        sensor_noise_deg=t.number("sensor_noise_deg", nonnegative=True, default=d.sensor_noise_deg),
        play_mm=t.number("play_mm", nonnegative=True, default=d.play_mm),
        wire_model=t.string(  # type: ignore[arg-type]
            "wire_model", choices=WIRE_MODELS, default=d.wire_model
        ),
        wire_offset_max_mm=t.number(
            "wire_offset_max_mm", nonnegative=True, default=d.wire_offset_max_mm
        ),
        wire_bending_stiffness_n_mm2=t.number(
            "wire_bending_stiffness_n_mm2", positive=True, default=d.wire_bending_stiffness_n_mm2
        ),
        wire_stiffness_rel_uncertainty=t.number(
            "wire_stiffness_rel_uncertainty",
            nonnegative=True,
            default=d.wire_stiffness_rel_uncertainty,
        ),
    )
    if options.wire_stiffness_rel_uncertainty >= 1.0:
        raise t.error("wire_stiffness_rel_uncertainty", "expected a fraction below 1")
    t.finish()
    return options


def swing_options(t: TableReader) -> SwingOptions:
    """The ``[swing]`` table (every key optional; defaults :class:`SwingOptions`')."""
    d = SwingOptions()
    sensor = t.vector("sensor_position_mm") if t.has("sensor_position_mm") else None
    out = SwingOptions(
        wire_length_mm=t.number("wire_length_mm", nonnegative=True, default=d.wire_length_mm),
        wire_length_sigma_mm=t.number(
            "wire_length_sigma_mm", nonnegative=True, default=d.wire_length_sigma_mm
        ),
        sensor_position_mm=None if sensor is None else (sensor[0], sensor[1], sensor[2]),
        sensor_position_sigma_mm=t.number(
            "sensor_position_sigma_mm", nonnegative=True, default=d.sensor_position_sigma_mm
        ),
        frequency_model_rel=(
            t.number("frequency_model_rel", nonnegative=True)
            if t.has("frequency_model_rel")
            else d.frequency_model_rel
        ),
        me_inertia_rel=t.number("me_inertia_rel", nonnegative=True, default=d.me_inertia_rel),
    )
    if out.wire_length_sigma_mm > out.wire_length_mm / 4 and out.wire_length_mm > 0:
        raise t.error(
            "wire_length_sigma_mm",
            f"expected at most a quarter of wire_length_mm ({out.wire_length_mm:g} mm): a 1 σ "
            f"of {out.wire_length_sigma_mm:g} mm is not a measured length",
        )
    t.finish()
    return out


def _name(t: TableReader, key: str) -> str:
    return t.identifier(key)


def _check_unique(tables: list[TableReader], values: list[str], key: str) -> None:
    seen: set[str] = set()
    for t, v in zip(tables, values, strict=True):
        if v in seen:
            raise t.error(key, f"duplicate {key} {v!r}")
        seen.add(v)


def _hole_box(point: SuspensionPoint, holes: HoleSpec) -> tuple[np.ndarray, np.ndarray]:
    """Axis-aligned bounding box of a hole's cylinder."""
    axis, sign = FACES[point.face]
    r = 0.5 * holes.diameter_mm
    p = np.asarray(point.position_mm)
    lo, hi = p - r, p + r
    lo[axis], hi[axis] = sorted((p[axis], p[axis] - sign * holes.depth_mm))
    return lo, hi


def _overlap_depth(lo1: np.ndarray, hi1: np.ndarray, lo2: np.ndarray, hi2: np.ndarray) -> float:
    """Smallest per-axis overlap of two boxes: > 0 means their interiors intersect."""
    return float(np.min(np.minimum(hi1, hi2) - np.maximum(lo1, lo2)))


#: A box denser than this many times the densest solid has a length in metres, not mm.
METRES_DENSITY_FACTOR = 1000.0


def _check_density(
    table: TableReader, mass_kg: float, size_mm: Sequence[float], *, solid: bool
) -> None:
    """A box's mass over its volume is a density: the proof mass's (a homogeneous block) within
    the ``_kg_m3`` bound (0.1 g in the paper's block is 0.09 kg/m³, a unit slip that would put
    the CoG metres away); an ME volume's (a part's envelope, mostly air) at most the densest
    solid's (25 g typed as 25 kg made a 450 000 kg/m³ Arduino and an ME 150× the object)."""
    density = density_kg_mm3_to_kg_m3(mass_kg / float(np.prod(size_mm)))
    bound = bounds.bound_for("density_kg_m3")
    assert bound is not None
    problem = bounds.check("density_kg_m3", density) if solid else None
    if density > bound.hi:
        unit = (
            "are its size_mm in metres?"
            if density > METRES_DENSITY_FACTOR * bound.hi
            else "is its mass_kg in grams?"
        )
        problem = f"denser than any solid ({bound.hi:g} kg/m³): {unit}"
    if problem is not None:
        raise table.error(
            "mass_kg",
            f"{mass_kg:g} kg in a {' × '.join(f'{v:g}' for v in size_mm)} mm box is "
            f"{density:.3g} kg/m³: {problem}",
        )


def _check_holes(
    holes_t: TableReader,
    tables: list[TableReader],
    pm: ProofMass,
    holes: HoleSpec,
    points: list[SuspensionPoint],
) -> None:
    size = np.asarray(pm.size_mm)
    r = 0.5 * holes.diameter_mm
    for t, p in zip(tables, points, strict=True):
        axis, _ = FACES[p.face]
        plane = face_plane_mm(p.face, size)
        pos = np.asarray(p.position_mm)
        off = abs(pos[axis] - plane)
        if off > tolerances.ON_SURFACE_MM:
            raise t.error(
                "position_mm",
                f"point {p.id} is not on face {p.face} ({AXIS_NAMES[axis]} = {plane:g} mm): "
                f"it is {off:g} mm away from the surface",
            )
        for j in range(3):
            if j != axis and not (r <= pos[j] <= size[j] - r):
                raise t.error(
                    "position_mm",
                    f"the hole of point {p.id} (radius {r:g} mm) is off face {p.face}: "
                    f"{AXIS_NAMES[j]} must lie in [{r:g}, {size[j] - r:g}] mm, got {pos[j]:g}",
                )
        if not holes.depth_mm < size[axis]:
            raise holes_t.error(
                "depth_mm",
                f"hole depth {holes.depth_mm:g} mm is not less than the part's "
                f"{size[axis]:g} mm extent along {AXIS_NAMES[axis]} (point {p.id})",
            )
    for (t1, p1), (_, p2) in combinations(zip(tables, points, strict=True), 2):
        if _overlap_depth(*_hole_box(p1, holes), *_hole_box(p2, holes)) > -tolerances.CONTACT_MM:
            raise t1.error(
                "position_mm",
                f"the holes of points {p1.id} and {p2.id} meet: keep their drilled cylinders apart",
            )


def _check_me(tables: list[TableReader], pm: ProofMass, volumes: list[MEVolume]) -> None:
    size = np.asarray(pm.size_mm)
    top = size[2]
    for t, v in zip(tables, volumes, strict=True):
        if _overlap_depth(v.min_mm, v.max_mm, np.zeros(3), size) > tolerances.CONTACT_MM:
            raise t.error("center_mm", f"ME volume {v.name!r} overlaps the proof mass")
        if v.min_mm[2] < top - tolerances.CONTACT_MM:
            raise t.error(
                "center_mm",
                f"ME volume {v.name!r} must sit on the +z side of the proof mass "
                f"(bottom at z >= {top:g} mm), its bottom is at z = {v.min_mm[2]:g} mm",
            )
    for (t1, v1), (_, v2) in combinations(zip(tables, volumes, strict=True), 2):
        if _overlap_depth(v1.min_mm, v1.max_mm, v2.min_mm, v2.max_mm) > tolerances.CONTACT_MM:
            raise t1.error("center_mm", f"ME volumes {v1.name!r} and {v2.name!r} overlap")
    touching = [
        v
        for v in volumes
        if abs(v.min_mm[2] - top) <= tolerances.CONTACT_MM
        and _overlap_depth(v.min_mm[:2], v.max_mm[:2], np.zeros(2), size[:2])
        > tolerances.CONTACT_MM
    ]
    if not touching:
        raise tables[0].error(
            "center_mm", f"no ME volume rests on the +z face of the proof mass (z = {top:g} mm)"
        )


def _check_points_clear_of_me(
    tables: list[TableReader],
    holes: HoleSpec,
    points: list[SuspensionPoint],
    volumes: list[MEVolume],
) -> None:
    r = 0.5 * holes.diameter_mm
    for t, p in zip(tables, points, strict=True):
        if p.face != "+z":
            continue
        lo = np.asarray(p.position_mm[:2]) - r
        hi = np.asarray(p.position_mm[:2]) + r
        for v in volumes:
            if _overlap_depth(lo, hi, v.min_mm[:2], v.max_mm[:2]) > -tolerances.CONTACT_MM:
                raise t.error(
                    "position_mm",
                    f"point {p.id} lies under ME volume {v.name!r}: the wire cannot reach it",
                )
