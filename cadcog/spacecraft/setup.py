"""A spacecraft from its CAD: its set-up file, and comparison of a measured CoG with the CAD.

Test planning (which suspension points to use) is :mod:`cadcog.spacecraft.plan`.

The set-up file (``parts/cubesat_3u_setup.toml`` is the example) names the model (a STEP file
with a materials file, or a cadcog CubeSat spec), the measurement equipment (a rig's ME volumes,
placed on the spacecraft), the inclinometer and error model (the rig's), the candidate suspension
points (listed, or a grid on faces of the model's bounding box) and, optionally, the CubeSat
form factor.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from cadcog.core import bounds, tolerances
from cadcog.core.errors import CadcogError, ParameterFileError
from cadcog.core.paramfile import TableReader, read_toml
from cadcog.core.results import one_line_repr
from cadcog.mass.properties import MassProperties
from cadcog.method.cogestimate import CogEstimate
from cadcog.method.errormodel import ErrorModel
from cadcog.method.estimate import BodyBox, MEData, estimate_cog
from cadcog.method.readings import Suspension, id_problem
from cadcog.rig.file import default_rig_path, load_rig, swing_options
from cadcog.rig.geometry import (
    FACES,
    face_normal,
    face_normal_of_point,
    same_point,
)
from cadcog.rig.mounting import me_base_problem
from cadcog.rig.parameters import MEVolume, Rig, SwingOptions, me_cog_cov_mm2
from cadcog.spacecraft.compare import compare_with_cad
from cadcog.spacecraft.envelope import CDS_COG_LIMITS_MM
from cadcog.spacecraft.items import (
    DEFAULT_WEIGHING_SIGMA_KG,
    LinearPrior,
    items_from_bodies,
    linear_prior,
)
from cadcog.spacecraft.setup_draft import form_factor_mismatch
from cadcog.uncertainty.montecarlo import Scenario

if TYPE_CHECKING:
    from cadcog.spacecraft.update import UnmodelledPrior, UpdateResult

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class Candidate:
    """A candidate suspension point: its id, position (mm), outward normal (the bolt axis), and
    whether the set-up lists it (``[[candidates.points]]``) rather than gridding it on the box."""

    id: str
    position_mm: FloatArray
    normal: FloatArray
    listed: bool = False


@dataclass(frozen=True, repr=False)  # one line: its bodies and candidates by their count
class Setup:
    """A spacecraft's test set-up, read by :func:`load_setup`: its CAD mass properties and
    bounding box, the measurement equipment placed on it, the rig (inclinometer and error
    model), the candidate suspension points and the CubeSat envelope to check."""

    name: str
    source: Path
    mass: MassProperties  # the spacecraft without ME, from CAD
    bbox_mm: tuple[FloatArray, FloatArray]
    me_volumes: tuple[MEVolume, ...]
    rig: Rig  # inclinometer, error model
    candidates: tuple[Candidate, ...]
    form_factor: str | None
    cog_limits_mm: FloatArray | None
    bodies: tuple[Any, ...]  # cadcog.cad.stepmass.BodyResult: mass, CoG, uncertainty item
    swing: SwingOptions = field(default_factory=SwingOptions)  # [swing], else the rig's
    #: What the file says that its model contradicts without making it unusable (a
    #: ``form_factor`` whose envelope the model's box is not): said by every command using it.
    notes: tuple[str, ...] = ()

    def __repr__(self) -> str:
        return one_line_repr(self)

    @property
    def geometric_center_mm(self) -> FloatArray:
        """Centre of the model's bounding box (mm)."""
        lo, hi = self.bbox_mm
        return np.asarray(0.5 * (lo + hi))

    @property
    def me_mass_kg(self) -> float:
        """Mass of the measurement equipment (kg)."""
        return sum(v.mass_kg for v in self.me_volumes)

    @property
    def me_cog_mm(self) -> FloatArray:
        """CoG of the measurement equipment as placed on the spacecraft (mm)."""
        m = np.array([v.mass_kg for v in self.me_volumes])
        c = np.array([v.center_mm for v in self.me_volumes])
        return np.asarray(m @ c / m.sum())

    @property
    def me_cog_cov_mm2(self) -> FloatArray:
        """Covariance of the ME CoG from its volumes' uncertainty cubes (mm²)."""
        return me_cog_cov_mm2(self.me_volumes)

    def body(self) -> BodyBox:
        """The model's bounding box: the faces the suspension points sit on (bolt axes)."""
        lo, hi = self.bbox_mm
        known = tuple((c.position_mm, c.normal) for c in self.candidates if c.listed)
        return BodyBox(np.asarray(lo), np.asarray(hi), f"setup {self.source}", known)

    def cad_prior(self) -> LinearPrior:
        """The CAD's mass and CoG with their stated uncertainty (:mod:`.items`)."""
        items, fixed = items_from_bodies(self.bodies)
        return linear_prior(items, fixed)

    def me_data(
        self, weighed_mass_kg: float | None = None, mass_sigma_kg: float = DEFAULT_WEIGHING_SIGMA_KG
    ) -> MEData:
        """What ME compensation needs: the spacecraft's mass and the placed ME.

        The mass is the weighed one (± ``mass_sigma_kg``) when given, else the CAD's with the
        CAD's own mass uncertainty, which the compensated CoG then carries."""
        cad = MEData(
            self.mass.mass_kg,
            self.me_mass_kg,
            self.me_cog_mm,
            self.me_cog_cov_mm2,
            f"setup {self.source}",
            self.cad_prior().mass_sigma_kg,
            "CAD",
        )
        return cad if weighed_mass_kg is None else cad.weighed(weighed_mass_kg, mass_sigma_kg)

    @property
    def assembly_cog_mm(self) -> FloatArray:
        """CoG of spacecraft and ME together (mm): what the hangs measure."""
        m, me = self.mass.mass_kg, self.me_mass_kg
        return np.asarray((m * self.mass.cog_mm + me * self.me_cog_mm) / (m + me))

    def scenario(self, candidates: tuple[Candidate, ...] | None = None) -> Scenario:
        """The Monte Carlo scenario of hanging from ``candidates`` (default: all of them)."""
        cands = self.candidates if candidates is None else candidates
        return Scenario(
            tuple(c.id for c in cands),
            np.array([c.position_mm for c in cands]),
            np.array([c.normal for c in cands]),
            self.mass.cog_mm,
            self.mass.mass_kg,
            self.me_mass_kg,
            self.me_cog_mm,
        )

    def error_model(self) -> ErrorModel:
        """The rig's error model with this set-up's ME volumes."""
        model = ErrorModel.from_rig(self.rig)
        return replace(
            model,
            me_masses_kg=tuple(v.mass_kg for v in self.me_volumes),
            me_edges_mm=tuple(v.cog_uncertainty_cube_mm for v in self.me_volumes),
        )


def estimate_for_setup(
    setup: Setup,
    suspensions: Sequence[Suspension],
    *,
    wire_correction: bool = True,
    self_calibrate: bool = False,
    angle_sigma_deg: float | None = None,
    point_sigma_mm: float | None = None,
    min_angle_deg: float = tolerances.MIN_PAIR_ANGLE_DEG,
    compare: bool = False,
    weighed_mass_kg: float | None = None,
    mass_sigma_kg: float = DEFAULT_WEIGHING_SIGMA_KG,
) -> CogEstimate:
    """The spacecraft's compensated CoG from its suspensions, as ``cadcog estimate --setup``
    computes it: the set-up's inclinometer, error model, bolt axes and measurement equipment.

    The ME is compensated with the weighed mass (± ``mass_sigma_kg``) when given, else with the
    CAD's mass and its uncertainty. With ``compare``, the result's ``cad`` holds
    :func:`cadcog.spacecraft.compare.compare_with_cad` of it (what the command prints after the
    estimate)."""
    estimate = estimate_cog(
        suspensions,
        setup.rig.inclinometer,
        setup.me_data(weighed_mass_kg, mass_sigma_kg),
        model=setup.error_model(),
        body=setup.body(),
        wire_correction=wire_correction,
        self_calibrate=self_calibrate,
        angle_sigma_deg=angle_sigma_deg,
        point_sigma_mm=point_sigma_mm,
        min_angle_deg=min_angle_deg,
    )
    warning = _outside_warning(setup, estimate.cog_mm, estimate.cov_mm2)
    said = (*setup.notes, warning) if warning else setup.notes
    if said:
        estimate = replace(estimate, warnings=(*estimate.warnings, *said))
    if not compare:
        return estimate
    cad = compare_with_cad(setup, estimate.cog_mm, estimate.cov_mm2, estimate.compensation)
    return replace(estimate, cad=cad)


def _outside_warning(setup: Setup, cog_mm: FloatArray, cov_mm2: FloatArray) -> str:
    """A warning when the CoG lies outside the model's bounding box: by more than 3 σ on an
    axis, the test did not locate it (too heavy a measurement equipment, hangs too close to
    parallel, or readings from another object); within its noise, the test cannot place the
    CoG within the object along that axis (its σ is wider than the object there)."""
    sigma = np.sqrt(np.maximum(np.diag(cov_mm2), 0.0))
    outside = setup.body().outside_by_mm(cog_mm)
    beyond = outside > 3 * sigma
    out = [axis for axis, b in zip("xyz", beyond, strict=True) if b]
    cog = ", ".join(f"{v:.1f}" for v in cog_mm)
    where = f"the CoG [{cog}] mm lies outside the model's bounding box"
    if not out:
        noisy = [
            f"{axis} by {d:.2g} mm ({d / s:.2g} σ)"
            for axis, d, s in zip("xyz", outside, sigma, strict=True)
            if d > 0
        ]
        if not noisy:
            return ""
        return (
            f"{where} along {', '.join(noisy)}: within its noise, so this test cannot place the "
            "CoG within the object along that axis (`cadcog plan` predicts the test's error)"
        )
    ratio = setup.me_mass_kg / setup.mass.mass_kg
    return (
        f"{where} along {', '.join(out)} by more than 3 σ: the test did not locate it (the "
        f"measurement equipment weighs {ratio:.2g} × the spacecraft; check the hangs, the "
        "readings and the set-up)"
    )


def update_for_setup(
    setup: Setup,
    suspensions: Sequence[Suspension],
    weighed_mass_kg: float,
    *,
    mass_sigma_kg: float = DEFAULT_WEIGHING_SIGMA_KG,
    unmodelled: UnmodelledPrior | None = None,
    inertia: tuple[FloatArray, FloatArray] | None = None,
) -> tuple[UpdateResult, CogEstimate]:
    """What the test and the weighing say about the CAD, as ``cadcog update`` computes it.

    The assembly CoG from :func:`estimate_for_setup` (the ME's weight from the weighing), then
    :func:`cadcog.spacecraft.update.update_budget` over the set-up's items, with an unmodelled
    mass anywhere in the model's bounding box as one of the explanations weighed. ``inertia``:
    the tensor measured from the swings (its six entries ``[xx, yy, zz, xy, xz, yz]`` and their
    covariance, ``cadcog inertia``), observed with the mass and the CoG.

    Returns
    -------
    (UpdateResult, CogEstimate)
        The update, and the estimate it started from (for its warnings and the report).
    """
    from cadcog.spacecraft.update import Measurement, update_budget

    if unmodelled is not None:
        lo, hi = setup.bbox_mm
        if np.any(unmodelled.hi_mm < lo) or np.any(unmodelled.lo_mm > hi):
            raise CadcogError(
                f"the unmodelled mass region {unmodelled.lo_mm.tolist()}-"
                f"{unmodelled.hi_mm.tolist()} mm does not meet the model's bounding box "
                f"{np.asarray(lo).round(2).tolist()}-{np.asarray(hi).round(2).tolist()} mm "
                f"({setup.source}): give a region inside the spacecraft"
            )
    estimate = estimate_for_setup(
        setup, suspensions, weighed_mass_kg=weighed_mass_kg, mass_sigma_kg=mass_sigma_kg
    )
    items, fixed = items_from_bodies(setup.bodies)
    measurement = Measurement(
        estimate.assembly_cog_mm,
        estimate.joint.cov_mm2,
        weighed_mass_kg,
        mass_sigma_kg,
        setup.me_mass_kg,
        setup.me_cog_mm,
        setup.me_cog_cov_mm2,
        None if inertia is None else np.asarray(inertia[0], dtype=float),
        None if inertia is None else np.asarray(inertia[1], dtype=float),
    )
    result = update_budget(
        items, fixed, measurement, unmodelled=unmodelled, envelope_mm=setup.bbox_mm
    )
    return result, estimate


def load_setup(path: str | Path) -> Setup:
    """Read a set-up file, compute the model's mass properties and the candidates."""
    p = Path(path)
    base = p.parent
    data = read_toml(p)
    if "name" not in data and ("materials" in data or "mass_uncertainty" in data):
        raise CadcogError(
            f"{p}: a materials file ([materials]), not a set-up: give the set-up file that "
            "names it (cadcog setup init drafts both)"
        )
    root = TableReader(data, p)
    name = root.identifier("name")
    from cadcog.cad.modelfile import load_model

    massprops = load_model(root, base)
    form = None
    if root.has("form_factor"):
        form = root.string("form_factor", choices=list(CDS_COG_LIMITS_MM))
    limits = None
    if root.has("cog_limits_mm"):
        limits = np.array(root.vector("cog_limits_mm", positive=True))
    elif form is not None:
        limits = np.array(CDS_COG_LIMITS_MM[form])
    lo, hi = massprops.bbox_mm
    mismatch = form_factor_mismatch(form, hi - lo)  # the set-up's axes are the model's
    notes = () if mismatch is None else (f"{p}: key 'form_factor': {mismatch}",)

    rig, volumes, me_base = _measurement_equipment(
        root.table("measurement_equipment"), base, lo, hi
    )
    cands = _candidates(root.table("candidates"), lo, hi)
    swing = swing_options(root.table("swing")) if root.has("swing") else rig.swing
    if swing.sensor_position_mm is not None:
        problem = _sensor_problem(np.asarray(swing.sensor_position_mm), lo, hi, volumes)
        if problem is not None:
            raise ParameterFileError(p, "swing.sensor_position_mm", problem)
    root.finish()
    if len(cands) < 2:
        raise CadcogError(f"{p}: fewer than two candidate suspension points")
    _refuse_points_in_solids(p, cands, me_base, lo, hi)
    return Setup(
        name,
        p,
        massprops.total,
        (lo, hi),
        volumes,
        rig,
        tuple(cands),
        form,
        limits,
        tuple(massprops.bodies),
        swing,
        notes,
    )


def _measurement_equipment(
    me_t: TableReader, base: Path, lo: FloatArray, hi: FloatArray
) -> tuple[Rig, tuple[MEVolume, ...], FloatArray]:
    """``[measurement_equipment]``: the rig whose ME carries the spacecraft (the paper's by
    default), its volumes moved so that its base centre is at ``base_center_mm``, and that
    base centre."""
    rig = load_rig(base / me_t.string("rig")) if me_t.has("rig") else load_rig(default_rig_path())
    target = np.array(me_t.vector("base_center_mm"))
    if (problem := me_base_problem(target, lo, hi)) is not None:
        raise me_t.error("base_center_mm", problem)
    me_t.finish()
    rig_base = np.array([*rig.analytic_me.cog_mm[:2], rig.proof_mass.size_mm[2]])
    shift = target - rig_base
    volumes = tuple(
        replace(v, center_mm=_triple(np.asarray(v.center_mm) + shift)) for v in rig.me_volumes
    )
    return rig, volumes, target


def _candidates(cand_t: TableReader, lo: FloatArray, hi: FloatArray) -> list[Candidate]:
    """``[candidates]``: a grid on named faces of the model's box, then the listed points."""
    cands: list[Candidate] = []
    if cand_t.has("faces"):
        faces_value = cand_t.strings("faces", choices=list(FACES))
        spacing = cand_t.number("spacing_mm", positive=True)
        margin = cand_t.number("margin_mm", nonnegative=True)
        count = sum(_grid_size(f, lo, hi, spacing, margin) for f in faces_value)
        if count > bounds.MAX_CANDIDATES:
            raise cand_t.error(
                "spacing_mm",
                f"{spacing:g} mm gives {count} candidate points on {', '.join(faces_value)}; "
                f"at most {bounds.MAX_CANDIDATES} (every pair is screened): use a wider spacing",
            )
        for f in faces_value:
            cands.extend(_grid(f, lo, hi, spacing, margin))
    if cand_t.has("points"):
        for t in cand_t.tables("points"):
            cands.append(_listed_point(t, lo, hi, cands))
            t.finish()
    cand_t.finish()
    return cands


def _listed_point(
    t: TableReader, lo: FloatArray, hi: FloatArray, cands: Sequence[Candidate]
) -> Candidate:
    """One ``[[candidates.points]]``: on the model's box (on a named face, or its face found
    from where it lies), its id valid and new, not the point of another listed candidate."""
    pos = np.array(t.vector("position_mm"))
    if t.has("face"):  # a point on the model itself, anywhere within its box
        normal = face_normal(t.string("face", choices=list(FACES)))
        tol = tolerances.SUSPENSION_ON_FACE_MM
        if np.any(pos < lo - tol) or np.any(pos > hi + tol):
            raise t.error(
                "position_mm",
                f"{pos.tolist()} lies outside the model's bounding box "
                f"{np.round(lo, 3).tolist()}..{np.round(hi, 3).tolist()} mm: a point "
                "with a face must sit on the model",
            )
    else:
        try:
            normal = face_normal_of_point(pos, lo, hi)
        except ValueError:
            raise t.error(
                "position_mm",
                f"{pos.tolist()} is inside the model's bounding box: a suspension "
                'point must be on its surface (name its face, face = "+x", for a point '
                "on the model inside its box)",
            ) from None
    pid = t.string("id")
    problem = id_problem(pid)
    if problem is not None:
        raise t.error("id", f"{pid!r}: {problem}")
    if any(c.id == pid for c in cands):
        raise t.error("id", f"duplicate candidate id {pid!r}")
    twin = next((c for c in cands if c.listed and same_point(c.position_mm, pos)), None)
    if twin is not None:
        raise t.error("position_mm", f"{pid!r} is the point of candidate {twin.id!r}")
    return Candidate(pid, pos, normal, listed=True)


def _refuse_points_in_solids(
    path: Path, cands: Sequence[Candidate], me_base: FloatArray, lo: FloatArray, hi: FloatArray
) -> None:
    """A listed point inside the model's box (a ``face`` given), and the ME's base, must not be
    inside one of its solids: a wire is fixed on a face, the ME sits on one (the model read
    once, then kept in the cache; a set-up whose points all lie on its box reads no CAD here).

    Raises
    ------
    ParameterFileError
        Naming the key, the point and the solid.
    """
    tol = tolerances.SUSPENSION_ON_FACE_MM

    def inner(x: FloatArray) -> bool:
        return bool(np.all(x > lo + tol) and np.all(x < hi - tol))

    listed = [c for c in cands if c.listed]
    point_why = "a suspension point is on a face of the model, where a wire can be fixed"
    keyed = [
        (f"candidates.points[{i}].position_mm", f"{c.id!r} at", c.position_mm, point_why)
        for i, c in enumerate(listed)
        if inner(c.position_mm)
    ]
    if inner(me_base):
        base_why = "the measurement equipment sits on a face of the model (mm, model axes)"
        keyed.append(("measurement_equipment.base_center_mm", "the base", me_base, base_why))
    if not keyed:
        return
    from cadcog.cad.modelfile import solids_holding_points

    holders = solids_holding_points(
        [x.tolist() for _, _, x, _ in keyed], kind="suspension points", setup=path
    )
    for (key, what, x, why), solid in zip(keyed, holders, strict=True):
        if solid is not None:
            raise ParameterFileError(
                path, key, f"{what} {x.tolist()} mm lies inside the solid {solid!r}: {why}"
            )


def _sensor_problem(
    sensor_mm: FloatArray, lo: FloatArray, hi: FloatArray, volumes: Sequence[MEVolume]
) -> str | None:
    """Why the inclinometer cannot sense at ``sensor_mm``: it sits on the object or its ME,
    so it lies within their boxes (to :data:`~cadcog.core.tolerances.ME_BASE_MAX_GAP_MM`)."""
    boxes_lo = [lo, *(np.asarray(v.center_mm) - np.asarray(v.size_mm) / 2 for v in volumes)]
    boxes_hi = [hi, *(np.asarray(v.center_mm) + np.asarray(v.size_mm) / 2 for v in volumes)]
    a, b = np.min(boxes_lo, axis=0), np.max(boxes_hi, axis=0)
    gap = float(np.linalg.norm(np.maximum(0.0, np.maximum(a - sensor_mm, sensor_mm - b))))
    if gap <= tolerances.ME_BASE_MAX_GAP_MM:
        return None
    return (
        f"{sensor_mm.tolist()} mm is {gap:.4g} mm from the object and its measurement "
        f"equipment (expected within {tolerances.ME_BASE_MAX_GAP_MM:g} mm of them: the "
        "inclinometer sits on the ME; a length in m or in.?)"
    )


def _triple(v: FloatArray) -> tuple[float, float, float]:
    return float(v[0]), float(v[1]), float(v[2])


def _grid_counts(
    face: str, lo: FloatArray, hi: FloatArray, spacing: float, margin: float
) -> list[int]:
    axis, _ = FACES[face]
    return [max(int((hi[j] - lo[j] - 2 * margin) // spacing) + 1, 1) for j in range(3) if j != axis]


def _grid_size(face: str, lo: FloatArray, hi: FloatArray, spacing: float, margin: float) -> int:
    a, b = _grid_counts(face, lo, hi, spacing, margin)
    return a * b


def _grid(
    face: str, lo: FloatArray, hi: FloatArray, spacing: float, margin: float
) -> list[Candidate]:
    axis, sign = FACES[face]
    others = [j for j in range(3) if j != axis]
    axes = []
    for j, n in zip(others, _grid_counts(face, lo, hi, spacing, margin), strict=True):
        span = (n - 1) * spacing
        mid = 0.5 * (lo[j] + hi[j])
        axes.append(mid - span / 2 + spacing * np.arange(n))
    out = []
    for a in axes[0]:
        for b in axes[1]:
            pos = np.zeros(3)
            pos[axis] = hi[axis] if sign > 0 else lo[axis]
            pos[others[0]], pos[others[1]] = a, b
            out.append(Candidate(f"{face}_{_label(a)}_{_label(b)}", pos, face_normal(face)))
    return out


def _label(v: float) -> str:
    """A grid coordinate as an id writes it: to 0.001 mm (as the files write positions), no
    exponent, no negative zero; the position itself stays exact. Ids a grid of round
    coordinates gave before are unchanged.

    Examples
    --------
    >>> _label(-5.68434e-14), _label(10.7874), _label(-30.0), _label(12.25), _label(1234.5678)
    ('0', '10.787', '-30', '12.25', '1234.568')
    """
    return f"{round(float(v), 3) + 0.0:.3f}".rstrip("0").rstrip(".")
