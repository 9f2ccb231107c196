"""Mass properties of a STEP model: every body at its global placement, with its own density.

The model comes from :func:`cadcog.cad.stepread.read_step` (bodies at their composed global
placements, unique path names). Each solid is integrated exactly (OCCT, no mesh) with its own
density; bodies are combined by mass, never by volume. Real CAD is messy, so the computation
reports what it found and what it did:

- **units**: the length unit the file declares is reported and trusted (OCCT's reader already
  converted it to mm); ``units`` overrides a wrong declaration and says so, never scaling twice;
  a model whose extent looks implausible gets a note, not a refusal;
- **exclusion** (glob patterns on names and paths) applies before every check;
- **densities** come from the materials file, else from a material the STEP file carries (XCAF),
  else from one uniform density; each body's source is reported;
- **surface bodies** (no volume) are left out with their area in a note, or given an areal
  density (kg/m²) by the materials file;
- **overlaps** (shared volume, counted more than once) are found fast
  (:mod:`cadcog.cad.overlaps`) and summarised; the computation refuses only when the mass
  counted more than once exceeds :data:`cadcog.core.tolerances.OVERLAP_REFUSE_MASS_FRACTION` of the
  total, unless the caller chose to
  ``allow`` them (each solid counted as it is) or ``resolve`` them (the denser solid of each pair
  keeps the common volume);
- **notes** (things a user should look at) are separate from **info** (what was done as asked);
  ``strict`` turns every note into an error, for CI.

Bodies that are instances of one product share their placement-free integration: it is done
once and transformed (rotation and translation) for every rigid placement.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.TopAbs import TopAbs_SHELL
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS, TopoDS_Shape

from cadcog.cad.occt import placed, rigid_transform, surface_properties, volume_properties
from cadcog.cad.overlaps import Overlap, Placed, bounding_boxes, cut_by, find_overlaps
from cadcog.cad.stepread import StepBody, StepModel, length_unit_mm
from cadcog.core import tolerances
from cadcog.core.errors import CadcogError, quote
from cadcog.core.parallel import fork_map
from cadcog.core.results import JsonResult
from cadcog.core.units import (
    LENGTH_UNIT_MM,
    UNIT_CHOICES,
    areal_density_kg_m2_to_kg_mm2,
    density_kg_m3_to_kg_mm3,
)
from cadcog.mass.materials import DENSITY_RANGE_KG_M3, ItemRule, MaterialMap, glob_match
from cadcog.mass.properties import MassProperties, combine

OverlapPolicy = Literal["check", "allow", "resolve"]

#: A model whose largest extent (mm) falls outside this range gets a note about its units.
PLAUSIBLE_EXTENT_MM = (1.0, 10_000.0)

#: Mean densities (kg/m³) outside this range, with a weighed total mass, get a units note.
PLAUSIBLE_MEAN_DENSITY_KG_M3 = (100.0, 25_000.0)

#: Overlapping pairs named in messages and in the text report (all are in the JSON).
WORST_PAIRS_SHOWN = 10

#: ``progress(description, total)`` returns a function called with the number of steps done.
ProgressFactory = Callable[[str, int], Callable[[int], None]]


class AllExcludedError(CadcogError):
    """The exclusion patterns leave no body to integrate."""


@dataclass(frozen=True)
class BodyResult(JsonResult):
    """One body as counted.

    Attributes
    ----------
    path : str
        Unique path name.
    nodes : tuple of str
        The unique names from the root to the body (the path, split).
    kind : "solid" or "surface"
    material : str
        Material name, 'density' for a bare density, or the surface label.
    density_source : str
        Where the density came from, e.g. ``materials rule 'rail*'`` or ``STEP material 'Al'``.
    density_kg_m3 : float or None
        Solids: the density used (after any scaling to a weighed total mass).
    areal_density_kg_m2 : float or None
        Surfaces: the areal density used.
    properties : MassProperties
        Mass properties as counted (after overlap resolution, if any).
    area_mm2 : float
        Surface area (surfaces only; 0 for solids).
    removed_mm3 : float
        Volume removed by overlap resolution (the denser neighbour kept it).
    sigma_rel : float or None
        1-σ relative mass uncertainty from the materials file, if any.
    item : str
        The uncertainty item the body belongs to (its own path, or an assembly's).
    growth : float
        Mass growth allowance (fraction); ``growth_label`` names its maturity level.
    cog_sigma_mm : (float, float, float) or None
        1-σ uncertainty of its item's CoG per axis (mm) from the materials file's
        ``[cog_uncertainty]``; None: the default of :mod:`cadcog.spacecraft.items`.
    """

    path: str
    nodes: tuple[str, ...]
    kind: str
    material: str
    density_source: str
    density_kg_m3: float | None
    areal_density_kg_m2: float | None
    properties: MassProperties
    area_mm2: float = 0.0
    removed_mm3: float = 0.0
    sigma_rel: float | None = None
    item: str = ""
    growth: float = 0.0
    growth_label: str = ""
    cog_sigma_mm: tuple[float, float, float] | None = None

    @property
    def name(self) -> str:
        return self.nodes[-1]

    def to_dict(self) -> dict[str, Any]:
        p = self.properties
        out: dict[str, Any] = {
            "path": self.path,
            "kind": self.kind,
            "material": self.material,
            "density_source": self.density_source,
        }
        if self.kind == "solid":
            out["density_kg_m3"] = self.density_kg_m3
            out["volume_mm3"] = p.volume_mm3
        else:
            out["areal_density_kg_m2"] = self.areal_density_kg_m2
            out["area_mm2"] = self.area_mm2
        out["mass_kg"] = p.mass_kg
        out["cog_mm"] = p.cog_mm.tolist()
        if self.removed_mm3:
            out["overlap_removed_mm3"] = self.removed_mm3
        if self.sigma_rel is not None:
            out["mass_sigma_rel"] = self.sigma_rel
            out["uncertainty_item"] = self.item
            if self.cog_sigma_mm is not None:
                out["cog_sigma_mm"] = list(self.cog_sigma_mm)
        if self.growth or self.growth_label:
            out["growth_allowance"] = self.growth
            if self.growth_label:
                out["maturity"] = self.growth_label
        return out


@dataclass(frozen=True)
class OverlapPair(JsonResult):
    """An overlapping pair: its common volume, the mass that volume counts twice (at the less
    dense solid's density), and the denser solid (which keeps the volume when resolving)."""

    a: str
    b: str
    volume_mm3: float
    mass_kg: float
    kept_by: str

    def to_dict(self) -> dict[str, Any]:
        return {
            "a": self.a,
            "b": self.b,
            "volume_mm3": self.volume_mm3,
            "double_counted_mass_kg": self.mass_kg,
            "denser": self.kept_by,
        }

    def describe(self, root: str = "") -> str:
        """``a & b (volume, mass)``, paths shown below ``root`` (a common top assembly)."""
        a, b = (p[len(root) :] if root and p.startswith(root) else p for p in (self.a, self.b))
        return f"{a} & {b} ({self.volume_mm3:.4g} mm³, {self.mass_kg * 1e3:.4g} g)"


@dataclass(frozen=True)
class OverlapSummary(JsonResult):
    """Overlaps found, and what they do to the totals.

    ``volume_mm3`` and ``mass_kg`` are what counting each solid as it is adds to the truth: the
    volume (and mass, at the less dense solid's density) counted more than once, exactly, also
    where three or more solids share a region (each less dense solid is cut by its denser
    partners). ``cog_shift_mm`` is the CoG counting each solid as it is minus the CoG with every
    region counted once. The pairs list each pair's own common volume, largest mass first.
    """

    policy: str
    pairs: tuple[OverlapPair, ...] = ()
    volume_mm3: float = 0.0
    mass_kg: float = 0.0
    mass_fraction: float = 0.0
    cog_shift_mm: tuple[float, float, float] = (0.0, 0.0, 0.0)
    n_candidates: int = 0
    n_contact: int = 0

    def headline(self) -> str:
        """One line: count, double-counted volume and mass, its share and the CoG shift."""
        shift = float(np.linalg.norm(self.cog_shift_mm))
        return (
            f"{len(self.pairs)} overlapping pair(s): {self.volume_mm3:.4g} mm³ and "
            f"{self.mass_kg * 1e3:.4g} g counted more than once ({self.mass_fraction:.3%} of the "
            f"mass), shifting the CoG by {shift:.3g} mm"
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "policy": self.policy,
            "n_pairs": len(self.pairs),
            "volume_mm3": self.volume_mm3,
            "excess_mass_kg": self.mass_kg,
            "mass_fraction": self.mass_fraction,
            "cog_shift_mm": list(self.cog_shift_mm),
            "n_candidate_pairs": self.n_candidates,
            "n_contact_pairs": self.n_contact,
            "pairs": [p.to_dict() for p in self.pairs],
        }


@dataclass(frozen=True)
class ImportAudit(JsonResult):
    """What was found in the file and how it was read."""

    source: str
    declared_units: tuple[str, ...]
    units_override: str | None
    scale_to_mm: float
    n_products: int
    n_instances: int
    n_solids: int
    n_surfaces: int
    excluded: tuple[str, ...]
    left_out_surfaces: tuple[tuple[str, float], ...]
    closed_shells_made_solid: tuple[str, ...]
    invalid_topology: tuple[str, ...]
    curve_only_parts: tuple[str, ...]
    density_sources: dict[str, int]
    bbox_mm: tuple[tuple[float, float, float], tuple[float, float, float]]

    @property
    def extent_mm(self) -> np.ndarray:
        return np.asarray(self.bbox_mm[1]) - np.asarray(self.bbox_mm[0])

    def to_dict(self) -> dict[str, Any]:
        return {
            "source": self.source,
            "declared_units": list(self.declared_units),
            "units_override": self.units_override,
            "scale_to_mm": self.scale_to_mm,
            "n_products": self.n_products,
            "n_instances": self.n_instances,
            "n_solids": self.n_solids,
            "n_surfaces": self.n_surfaces,
            "excluded": list(self.excluded),
            "left_out_surfaces": [{"path": p, "area_mm2": a} for p, a in self.left_out_surfaces],
            "closed_shells_made_solid": list(self.closed_shells_made_solid),
            "invalid_topology": list(self.invalid_topology),
            "curve_only_parts": list(self.curve_only_parts),
            "density_sources": dict(self.density_sources),
            "bbox_mm": [list(self.bbox_mm[0]), list(self.bbox_mm[1])],
        }


@dataclass(frozen=True, repr=False)  # JsonResult's one-line repr
class ModelMassProperties(JsonResult):
    """Mass properties of a model, its bodies, the import audit, overlaps, notes and info."""

    total: MassProperties
    bodies: tuple[BodyResult, ...]
    audit: ImportAudit
    overlaps: OverlapSummary
    notes: tuple[str, ...] = field(default=())
    info: tuple[str, ...] = field(default=())

    @property
    def solids(self) -> tuple[BodyResult, ...]:
        """The bodies with a volume (surface bodies aside)."""
        return tuple(b for b in self.bodies if b.kind == "solid")

    @property
    def bbox_mm(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper corners of the model's bounding box (mm), after exclusions."""
        return np.asarray(self.audit.bbox_mm[0]), np.asarray(self.audit.bbox_mm[1])

    def to_dict(self) -> dict[str, Any]:
        return {
            **self.total.to_dict(),
            "bodies": [b.to_dict() for b in self.bodies],
            "audit": self.audit.to_dict(),
            "overlaps": self.overlaps.to_dict(),
            "notes": list(self.notes),
            "info": list(self.info),
        }


# --- helpers ---------------------------------------------------------------------------------
def _closed(shape: TopoDS_Shape) -> bool:
    explorer = TopExp_Explorer(shape, TopAbs_SHELL)
    found = False
    while explorer.More():
        found = True
        if not BRep_Tool.IsClosed_s(TopoDS.Shell(explorer.Current())):
            return False
        explorer.Next()
    return found


def _scaled_lengths(p: MassProperties, scale: float, dimension: int) -> MassProperties:
    """Properties of a body ``scale`` times larger (``dimension`` 3 for volumes, 2 areas)."""
    if scale == 1.0:
        return p
    k = scale**dimension
    return MassProperties(
        p.mass_kg * k, p.cog_mm * scale, p.inertia_kg_mm2 * k * scale**2, p.volume_mm3 * scale**3
    )


def _with_mass_factor(p: MassProperties, factor: float) -> MassProperties:
    """The same geometry with its mass (and inertia) multiplied by ``factor``: a density."""
    return MassProperties(p.mass_kg * factor, p.cog_mm, p.inertia_kg_mm2 * factor, p.volume_mm3)


def _rule_names(body: StepBody) -> tuple[str, ...]:
    """Names a materials rule may match: the body's own, then its assemblies' (deepest first),
    as full paths and as paths below the common top assembly."""
    root = f"{body.root}/" if body.root else ""
    above = tuple(reversed(body.assembly_paths))
    below = tuple(a[len(root) :] for a in above if root and a.startswith(root))
    return (*body.match_names(), *above, *below)


def _common_root(paths: Sequence[str]) -> str:
    """``"top/"`` when every path lies below one top assembly, else ``""``."""
    firsts = {p.split("/", 1)[0] for p in paths}
    if len(firsts) == 1 and all("/" in p for p in paths):
        return f"{firsts.pop()}/"
    return ""


def _matches_any(patterns: Sequence[str], body: StepBody) -> bool:
    root = f"{body.root}/" if body.root else ""
    below = tuple(a[len(root) :] for a in body.assembly_paths if root and a.startswith(root))
    names = (*body.match_names(), *body.assembly_paths, *below)
    return any(glob_match(n, pat) for pat in patterns for n in names)


def _unit_scale(model: StepModel, units: str | None) -> tuple[float, list[str], list[str]]:
    """mm per file unit on top of the reader's conversion, with notes and info."""
    notes: list[str] = []
    info: list[str] = []
    declared = model.declared_unit
    if units is None:
        if declared is None and model.declared_units:
            notes.append(
                f"the file declares several length units ({', '.join(model.declared_units)}); "
                "OCCT converted each part's own"
            )
        elif declared is None:
            notes.append("the file declares no length unit; read as mm")
        elif length_unit_mm(declared) is None:
            notes.append(f"the file declares an unknown length unit {declared!r}; read as mm")
        return 1.0, notes, info
    true_mm = LENGTH_UNIT_MM[units]
    declared_mm = length_unit_mm(declared) if declared is not None else None
    if declared is None or declared_mm is None:
        what = (
            f"several length units ({', '.join(model.declared_units)})"
            if model.declared_units
            else "no length unit"
        )
        if declared is not None:
            what = f"the unknown length unit {declared!r}"
        raise CadcogError(
            f"{model.source}: --units {units} overrides the file's declared unit, but the file "
            f"declares {what}: cannot tell by how much to scale"
        )
    scale = true_mm / declared_mm
    if scale == 1.0:
        info.append(f"--units {units}: the file already declares {declared}; nothing scaled")
    else:
        info.append(
            f"--units {units}: the file declares {declared} but is taken to be in {units}; "
            f"lengths scaled by {scale:g}"
        )
    return scale, notes, info


# --- the computation -------------------------------------------------------------------------
@dataclass
class _Body:
    """Working state of one kept body."""

    step: StepBody
    props: MassProperties  # unit density (kg/mm³) or unit areal density (kg/mm²), mm
    box_lo: np.ndarray = field(default_factory=lambda: np.zeros(3))  # file frame and unit
    box_hi: np.ndarray = field(default_factory=lambda: np.zeros(3))
    material: str = ""
    source: str = ""
    density_kg_m3: float | None = None
    areal_density_kg_m2: float | None = None
    removed_mm3: float = 0.0

    @property
    def density_kg_mm3(self) -> float:
        if self.step.kind == "solid":
            return density_kg_m3_to_kg_mm3(self.density_kg_m3 or 0.0)
        return areal_density_kg_m2_to_kg_mm2(self.areal_density_kg_m2 or 0.0)


def model_mass_properties(
    model: StepModel,
    materials: MaterialMap | None,
    *,
    total_mass_kg: float | None = None,
    units: str | None = None,
    exclude: Sequence[str] = (),
    overlaps: OverlapPolicy = "check",
    strict: bool = False,
    progress: ProgressFactory | None = None,
    workers: int = 1,
) -> ModelMassProperties:
    """Exact, density-weighted mass properties of the bodies of a STEP model.

    Parameters
    ----------
    model : StepModel
    materials : MaterialMap or None
        Densities by name pattern. None: the STEP file's own materials (XCAF) where present;
        with ``total_mass_kg`` and no body carrying a material, one uniform density.
    total_mass_kg : float, optional
        Scale every density so the total equals this weighed mass.
    units : str, optional
        The file's true length unit (from :data:`UNIT_CHOICES`) when its declaration is wrong.
    exclude : sequence of str
        Glob patterns of bodies or assemblies to leave out, before any check.
    overlaps : "check", "allow" or "resolve"
    strict : bool
        Raise on any note.
    progress : ProgressFactory, optional
    workers : int
        Processes for the integrations and overlap booleans (results do not depend on it).

    Raises
    ------
    CadcogError
        Naming the file and the bodies: zero or negative volumes, open solids, bodies without a
        density, overlaps beyond the threshold under ``check``, every body excluded, and (with
        ``strict``) any note.
    """
    src = model.source
    if overlaps not in ("check", "allow", "resolve"):
        raise CadcogError(f"overlaps: expected check, allow or resolve, got {quote(overlaps)}")
    if units is not None and units not in LENGTH_UNIT_MM:
        raise CadcogError(f"--units: unknown unit {units!r}; expected {', '.join(UNIT_CHOICES)}")
    scale, notes, info = _unit_scale(model, units)

    kept = [b for b in model.bodies if not _matches_any(exclude, b)]
    excluded = tuple(b.path for b in model.bodies if _matches_any(exclude, b))
    for pattern in exclude:
        if not any(_matches_any([pattern], b) for b in model.bodies):
            notes.append(f"--exclude {pattern!r} matched no body")
    if materials is not None:
        notes.extend(
            f"materials rule {rule} ({materials.source or 'materials'}) matches no body or "
            "assembly name: a typo? (the bodies it meant fall to a later rule)"
            for rule in _unmatched_rules(materials, model.bodies)
        )
    if not kept:
        shown = " ".join(f"--exclude {p!r}" for p in exclude)
        raise AllExcludedError(f"{shown}: excludes every body of {src}")

    bodies, audit_bits = _integrate(kept, scale, progress, workers)
    problems = audit_bits.pop("problems")
    if problems:
        raise CadcogError(f"{src}: {'; '.join(problems)}")

    bbox = (
        np.min([b.box_lo for b in bodies], axis=0) * scale,
        np.max([b.box_hi for b in bodies], axis=0) * scale,
    )
    extent = float(np.max(bbox[1] - bbox[0]))
    if units is None and not PLAUSIBLE_EXTENT_MM[0] <= extent <= PLAUSIBLE_EXTENT_MM[1]:
        notes.append(
            f"the model spans {extent:.4g} mm in the file's declared unit "
            f"({model.declared_unit or 'none'}); if that is wrong, pass --units"
        )

    _assign_densities(bodies, materials, total_mass_kg, notes, src)
    summary, resolved_info = _handle_overlaps(bodies, overlaps, scale, progress, src, workers)
    info.extend(resolved_info)

    raw = [_with_mass_factor(b.props, b.density_kg_mm3) for b in bodies]
    counted = [(b, p) for b, p in zip(bodies, raw, strict=True) if p.mass_kg > 0]
    if not counted:
        raise CadcogError(f"{src}: no body has mass (only surfaces without an areal density?)")
    factor = 1.0
    if total_mass_kg is not None:
        factor = total_mass_kg / sum(p.mass_kg for _, p in counted)
        info.append(f"densities scaled by {factor:.6g} to match the weighed {total_mass_kg:g} kg")
        volume = sum(b.props.volume_mm3 for b, _ in counted)
        mean = total_mass_kg / volume * 1e9 if volume > 0 else float("inf")
        lo_d, hi_d = PLAUSIBLE_MEAN_DENSITY_KG_M3
        if units is None and not lo_d <= mean <= hi_d:
            notes.append(
                f"the weighed mass implies a mean density of {mean:.4g} kg/m³: the file's "
                f"declared unit ({model.declared_unit or 'none'}) may be wrong; pass --units"
            )
    if factor != 1.0 and summary.pairs:
        summary = replace(
            summary,
            mass_kg=summary.mass_kg * factor,
            pairs=tuple(replace(p, mass_kg=p.mass_kg * factor) for p in summary.pairs),
        )
    if summary.pairs and overlaps == "check":
        notes.append(
            f"{summary.headline()}; under the refusal threshold of "
            f"{tolerances.OVERLAP_REFUSE_MASS_FRACTION:.1%}: each solid counted as it is"
        )
    elif summary.pairs and overlaps == "allow":  # the user chose: info, not a note
        info.append(f"{summary.headline()}; --allow-overlap: each solid counted as it is")
    results = []
    for b, p in counted:
        sigma, growth = _item_rules(b.step, materials)
        results.append(
            BodyResult(
                b.step.path,
                tuple(n.name for n in b.step.nodes),
                b.step.kind,
                b.material,
                b.source,
                None if b.density_kg_m3 is None else b.density_kg_m3 * factor,
                None if b.areal_density_kg_m2 is None else b.areal_density_kg_m2 * factor,
                _with_mass_factor(p, factor),
                b.props.mass_kg if b.step.kind == "surface" else 0.0,
                b.removed_mm3,
                None if sigma is None else sigma.value,
                b.step.path if sigma is None else sigma.item,
                0.0 if growth is None else growth.value,
                "" if growth is None else growth.label,
                None if materials is None else materials.cog_uncertainty(_item_candidates(b.step)),
            )
        )
    left_out = tuple((b.step.path, b.props.mass_kg) for b in bodies if b.density_kg_mm3 == 0.0)
    if left_out:
        area = sum(a for _, a in left_out)
        shown = ", ".join(f"{p} ({a:.4g} mm²)" for p, a in left_out[:WORST_PAIRS_SHOWN])
        more = f" and {len(left_out) - WORST_PAIRS_SHOWN} more" if len(left_out) > 10 else ""
        notes.append(
            f"{len(left_out)} surface bod{'y' if len(left_out) == 1 else 'ies'} "
            f"({area:.4g} mm² in all) have no volume and are left out: {shown}{more}; give "
            "them an areal density in the materials file's [surfaces] table"
        )
    if audit_bits["made_solid"]:
        notes.append(
            f"closed shells made into solids: {', '.join(audit_bits['made_solid'][:10])}"
            + (" ..." if len(audit_bits["made_solid"]) > 10 else "")
        )
    if audit_bits["invalid"]:
        notes.append(
            f"OCCT reports invalid topology in {len(audit_bits['invalid'])} solid(s) "
            f"({', '.join(audit_bits['invalid'][:10])}); integrated anyway"
        )
    if model.curve_only_parts:
        notes.append(
            f"{len(model.curve_only_parts)} part(s) hold only curves or points, no mass: "
            + ", ".join(model.curve_only_parts[:10])
        )
    sources: dict[str, int] = {}
    for r in results:
        kind = r.density_source.split(" ", 1)[0]
        sources[kind] = sources.get(kind, 0) + 1
    audit = ImportAudit(
        str(src),
        model.declared_units,
        units,
        scale,
        model.n_products,
        model.n_instances,
        sum(1 for b in bodies if b.step.kind == "solid"),
        sum(1 for b in bodies if b.step.kind == "surface"),
        excluded,
        left_out,
        tuple(audit_bits["made_solid"]),
        tuple(audit_bits["invalid"]),
        model.curve_only_parts,
        sources,
        (tuple(float(v) for v in bbox[0]), tuple(float(v) for v in bbox[1])),  # type: ignore[arg-type]
    )
    if strict and notes:
        raise CadcogError(f"{src}: --strict: {len(notes)} note(s): " + " | ".join(notes))
    total = combine(r.properties for r in results)
    return ModelMassProperties(total, tuple(results), audit, summary, tuple(notes), tuple(info))


@dataclass(frozen=True)
class _ProductCheck:
    """Placement-free results for one product's body, computed once for all its instances."""

    props: MassProperties  # unit density, the product's frame
    closed: bool
    valid: bool
    box_lo: np.ndarray
    box_hi: np.ndarray


def _check_product(body: StepBody) -> _ProductCheck:
    shape = body.local_shape
    if body.kind == "solid":
        props = volume_properties(shape)
        closed = _closed(shape)
        valid = bool(BRepCheck_Analyzer(shape).IsValid())
    else:
        props, closed, valid = surface_properties(shape), True, True
    lo, hi = bounding_boxes([shape])
    return _ProductCheck(props, closed, valid, lo[0], hi[0])


def _global_box(check: _ProductCheck, body: StepBody) -> tuple[np.ndarray, np.ndarray]:
    """The body's axis-aligned box: its product's box moved, exact for axis-aligned rotations
    (any multiple of 90°); other rotations are boxed afresh, since a moved box is looser."""
    rigid = rigid_transform(body.placement)
    if rigid is not None:
        r, t = rigid
        if np.all(np.isclose(np.abs(r), np.round(np.abs(r)), atol=1e-12)):
            corners = np.array(
                [
                    [(check.box_lo, check.box_hi)[k][i] for i, k in enumerate(bits)]
                    for bits in np.ndindex(2, 2, 2)
                ]
            )
            moved = corners @ r.T + t
            return moved.min(axis=0), moved.max(axis=0)
    lo, hi = bounding_boxes([body.shape])
    return lo[0], hi[0]


def _item_rules(
    body: StepBody, materials: MaterialMap | None
) -> tuple[ItemRule | None, ItemRule | None]:
    """The body's mass uncertainty and growth allowance rules (item = deepest matched node)."""
    if materials is None:
        return None, None
    return materials.uncertainty(_item_candidates(body)), materials.growth(_item_candidates(body))


def _item_candidates(body: StepBody) -> list[tuple[str, tuple[str, ...]]]:
    """(node path, names a rule may match), the body first, then its assemblies deepest first;
    paths both full and below the common top assembly."""
    root = f"{body.root}/" if body.root else ""

    def below(path: str) -> str:
        return path[len(root) :] if root and path.startswith(root) else ""

    own = body.nodes[-1]
    own_names = (body.path, below(body.path), own.name, own.instance, own.product)
    candidates = [(body.path, tuple(dict.fromkeys(v for v in own_names if v)))]
    for k in range(len(body.nodes) - 1, 0, -1):
        node = body.nodes[k - 1]
        prefix = "/".join(n.name for n in body.nodes[:k])
        names = (prefix, below(prefix), node.name, node.instance, node.product)
        candidates.append((prefix, tuple(dict.fromkeys(v for v in names if v))))
    return candidates


def _unmatched_rules(materials: MaterialMap, bodies: Sequence[StepBody]) -> list[str]:
    """``"[table] pattern"`` of every rule that matches no name of any body or assembly: most
    often a typo, whose bodies then fall to a later rule (a default) without a word."""
    names: set[str] = set()
    for b in bodies:
        names.update(_rule_names(b))
        for _, n in _item_candidates(b):
            names.update(n)
    tables = {
        "materials": [p for p, _ in materials.rules],
        "surfaces": [p for p, _, _ in materials.surface_rules],
        "mass_uncertainty": [p for p, _, _ in materials.uncertainty_rules],
        "growth_allowance": [p for p, _, _ in materials.growth_rules],
        "cog_uncertainty": [p for p, _ in materials.cog_rules],
    }
    return [
        f"[{table}] {pattern!r}"
        for table, patterns in tables.items()
        for pattern in dict.fromkeys(patterns)
        if not any(glob_match(n, pattern) for n in names)
    ]


def _integrate(
    kept: Sequence[StepBody], scale: float, progress: ProgressFactory | None, workers: int
) -> tuple[list[_Body], dict[str, Any]]:
    """Unit-density properties of every body (shared between instances), and the audit."""
    firsts: dict[str, StepBody] = {}
    for body in kept:
        firsts.setdefault(body.product_key, body)
    tick = progress("integrating bodies", len(firsts)) if progress else None
    checks = dict(
        zip(
            firsts,
            fork_map(_check_product, list(firsts.values()), workers=workers, progress=tick),
            strict=True,
        )
    )
    problems: list[str] = []
    empty: list[str] = []
    open_solids: list[str] = []
    invalid: list[str] = []
    made_solid: list[str] = []
    out: list[_Body] = []
    for body in kept:
        check = checks[body.product_key]
        rigid = rigid_transform(body.placement)
        if rigid is not None:
            placed_props = placed(check.props, *rigid)
        elif body.kind == "solid":
            placed_props = volume_properties(body.shape)
        else:
            placed_props = surface_properties(body.shape)
        props = _scaled_lengths(placed_props, scale, 3 if body.kind == "solid" else 2)
        if body.kind == "solid":
            if not check.closed:
                open_solids.append(body.path)
            elif not props.volume_mm3 > 1e-9:
                empty.append(body.path)
            if not check.valid:
                invalid.append(body.path)
            if body.made_from_shell:
                made_solid.append(body.path)
        lo, hi = _global_box(check, body)
        out.append(_Body(body, props, box_lo=lo, box_hi=hi))
    if open_solids:
        problems.append(
            f"solids whose shells are not closed: {', '.join(open_solids[:10])}"
            f"{' ...' if len(open_solids) > 10 else ''}; fix them or --exclude them"
        )
    if empty:
        problems.append(
            f"zero or negative volume: {', '.join(empty[:10])}"
            f"{' ...' if len(empty) > 10 else ''} (degenerate or inside-out solids); --exclude "
            "them or fix the model"
        )
    return out, {"problems": problems, "invalid": invalid, "made_solid": made_solid}


def _assign_densities(
    bodies: list[_Body],
    materials: MaterialMap | None,
    total_mass_kg: float | None,
    notes: list[str],
    src: Any,
) -> None:
    """Fill each body's material, density and its source; raise for solids without one."""
    solids = [b for b in bodies if b.step.kind == "solid"]
    xcaf_usable = [b for b in solids if b.step.material and b.step.material.density_kg_m3]
    uniform = materials is None and total_mass_kg is not None and not xcaf_usable
    origin = (materials.source if materials is not None else "") or "materials"
    bad_xcaf: set[str] = set()
    missing: list[str] = []
    lo_d, hi_d = DENSITY_RANGE_KG_M3
    for b in bodies:
        names = _rule_names(b.step)
        if b.step.kind == "surface":
            found_s = materials.assign_surface(names) if materials is not None else None
            if found_s is None:
                b.material, b.source = "none", "left out (no areal density)"
                b.areal_density_kg_m2 = 0.0
            else:
                b.material = found_s.material
                b.source = f"materials rule {found_s.rule!r} ({origin})"
                b.areal_density_kg_m2 = found_s.areal_density_kg_m2
            continue
        found = materials.assign(names) if materials is not None else None
        xm = b.step.material
        if found is not None:
            b.material, b.density_kg_m3 = found.material, found.density_kg_m3
            b.source = f"materials rule {found.rule!r} ({origin})"
        elif uniform:
            b.material, b.density_kg_m3 = "uniform", 1000.0
            b.source = "uniform (scaled to --total-mass-kg)"
        elif xm is not None and xm.density_kg_m3 and lo_d <= xm.density_kg_m3 <= hi_d:
            b.material, b.density_kg_m3 = xm.name, xm.density_kg_m3
            b.source = f"STEP material {xm.name!r} ({xm.raw})"
        else:
            if xm is not None:
                bad_xcaf.add(f"{xm.name} ({xm.raw or 'no density'})")
            missing.append(b.step.path)
    from_file = [b for b in solids if b.source.startswith("STEP material")]
    if len(from_file) >= 2 and len({(b.material, b.density_kg_m3) for b in from_file}) == 1:
        b0 = from_file[0]
        notes.append(
            f"all {len(from_file)} solids without a materials rule carry the same STEP material "
            f"{b0.material!r} ({b0.density_kg_m3:g} kg/m³): exporters stamp a default material "
            "on every body (Fusion 360 writes 'Steel' on boards and plastics alike); check it, "
            "or give a materials file"
        )
    if bad_xcaf:
        notes.append(
            "STEP materials without a usable density (kg/m³ between "
            f"{lo_d:g} and {hi_d:g}): {', '.join(sorted(bad_xcaf))}"
        )
    if missing:
        shown = ", ".join(missing[:10]) + (
            f" and {len(missing) - 10} more" if len(missing) > 10 else ""
        )
        raise CadcogError(
            f"{src}: no density for {len(missing)} solid(s): {shown}; give a materials file "
            '(--materials; a catch-all "*" rule gives a default) or --density-kg-m3'
        )


def _handle_overlaps(
    bodies: list[_Body],
    policy: OverlapPolicy,
    scale: float,
    progress: ProgressFactory | None,
    src: Any,
    workers: int,
) -> tuple[OverlapSummary, list[str]]:
    """Find overlaps among solids, summarise them, refuse or resolve them per ``policy``."""
    solids = [b for b in bodies if b.step.kind == "solid"]
    if len(solids) < 2:
        return OverlapSummary(policy), []
    placed_solids = [
        Placed(b.step.shape, b.step.local_shape, b.step.placement, b.step.product_key, lo, hi)
        for b, lo, hi in ((b, b.box_lo, b.box_hi) for b in solids)
    ]
    volumes = [b.props.volume_mm3 for b in solids]
    found, n_candidates, n_contact = find_overlaps(
        placed_solids, volumes, scale=scale, progress=progress, workers=workers
    )
    if not found:
        return OverlapSummary(policy, n_candidates=n_candidates, n_contact=n_contact), []

    def lighter(o: Overlap) -> tuple[int, int]:
        """(less dense, denser): the later solid in file order loses a tie."""
        da, db = solids[o.a].density_kg_mm3, solids[o.b].density_kg_mm3
        return (o.b, o.a) if db <= da else (o.a, o.b)

    pairs = []
    partners: dict[int, list[int]] = {}
    for o in found:
        lose, keep = lighter(o)
        partners.setdefault(lose, []).append(keep)
        common = _scaled_lengths(o.common, scale, 3)
        pairs.append(
            OverlapPair(
                solids[o.a].step.path,
                solids[o.b].step.path,
                common.volume_mm3,
                common.mass_kg * solids[lose].density_kg_mm3,
                solids[keep].step.path,
            )
        )
    # Exact totals, also where three or more solids share a region: each less dense solid is cut
    # by its denser partners; what it loses is what was counted more than once.
    losers = list(partners)
    jobs = [(solids[i].step.shape, [solids[k].step.shape for k in partners[i]]) for i in losers]
    tick = progress("resolving overlaps", len(jobs)) if progress else None
    cuts = fork_map(_cut_properties, jobs, workers=workers, progress=tick)
    failed = [solids[i].step.path for i, c in zip(losers, cuts, strict=True) if c is None]
    if failed:
        raise CadcogError(
            f"{src}: OCCT could not cut the overlaps out of {', '.join(failed[:10])}; "
            "--exclude them or fix the model"
        )
    removed = []
    after: dict[int, MassProperties] = {}
    for i, cut in zip(losers, cuts, strict=True):
        assert cut is not None
        after[i] = _scaled_lengths(cut, scale, 3)
        lost = solids[i].props.volume_mm3 - after[i].volume_mm3
        if lost > 0:
            region = combine([solids[i].props, after[i].scaled(-1.0)])
            removed.append(_with_mass_factor(region, solids[i].density_kg_mm3))
    as_is = [_with_mass_factor(b.props, b.density_kg_mm3) for b in bodies if b.density_kg_mm3 > 0]
    total_as_is = combine(as_is)
    double_mass = sum(r.mass_kg for r in removed)
    single = combine([*as_is, *(r.scaled(-1.0) for r in removed)]) if removed else total_as_is
    fraction = double_mass / total_as_is.mass_kg
    shift = total_as_is.cog_mm - single.cog_mm
    ranked = tuple(sorted(pairs, key=lambda p: -p.mass_kg))
    summary = OverlapSummary(
        policy,
        ranked,
        sum(r.volume_mm3 for r in removed),
        double_mass,
        fraction,
        (float(shift[0]), float(shift[1]), float(shift[2])),
        n_candidates,
        n_contact,
    )
    if policy == "check" and fraction > tolerances.OVERLAP_REFUSE_MASS_FRACTION:
        root = _common_root([b.step.path for b in bodies])
        worst = "; ".join(p.describe(root) for p in ranked[:3])
        raise CadcogError(
            f"{src}: {summary.headline()}, above the "
            f"{tolerances.OVERLAP_REFUSE_MASS_FRACTION:.1%} threshold; worst: {worst}. Fix the "
            "model, --exclude one of each pair, --resolve-overlaps (the denser solid keeps the "
            "common volume) or --allow-overlap (count each solid as it is); --json lists every "
            "pair"
        )
    if policy != "resolve":
        return summary, []
    for i, props in after.items():
        solids[i].removed_mm3 = solids[i].props.volume_mm3 - props.volume_mm3
        solids[i].props = props
    info = [
        f"--resolve-overlaps: {len(found)} overlapping pair(s) resolved, the denser solid of "
        f"each keeping the common volume ({double_mass * 1e3:.4g} g no longer counted more than "
        "once)"
    ]
    return summary, info


def _cut_properties(job: tuple[TopoDS_Shape, list[TopoDS_Shape]]) -> MassProperties | None:
    """Unit-density properties of a solid minus its tools (None if OCCT fails)."""
    cut = cut_by(*job)
    return None if cut is None else volume_properties(cut)
