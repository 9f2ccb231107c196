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
  ``strict`` turns every note into an error, for CI. A refusal (:class:`Refusal`) still
  carries the model counted as it is, so that a caller can show what was refused.

Bodies that are instances of one product share their placement-free integration: it is done
once and transformed (rotation and translation) for every rigid placement.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.cad.bodies import Body, ProgressFactory, integrate, invalid_solids, with_mass_factor
from cadcog.cad.massresults import (
    AllExcludedError,
    BodyResult,
    ImportAudit,
    ModelMassProperties,
    OverlapPair,
    OverlapSummary,
    Refusal,
)
from cadcog.cad.massrules import (
    assign_densities,
    item_candidates,
    item_rules,
    matches_any,
    unmatched_rules,
)
from cadcog.cad.resolve import OverlapPolicy, handle_overlaps
from cadcog.cad.stepmodel import StepModel
from cadcog.cad.stepread import length_unit_mm
from cadcog.core import tolerances
from cadcog.core.errors import CadcogError, quote
from cadcog.core.units import LENGTH_UNIT_MM, UNIT_CHOICES
from cadcog.mass.materials import MaterialMap
from cadcog.mass.properties import MassProperties, combine

__all__ = [
    "AllExcludedError",
    "BodyResult",
    "ImportAudit",
    "ModelMassProperties",
    "OverlapPair",
    "OverlapPolicy",
    "OverlapSummary",
    "ProgressFactory",
    "Refusal",
    "model_mass_properties",
]

#: A model whose largest extent (mm) falls outside this range gets a note about its units.
PLAUSIBLE_EXTENT_MM = (1.0, 10_000.0)

#: Mean densities (kg/m³) outside this range, with a weighed total mass, get a units note.
PLAUSIBLE_MEAN_DENSITY_KG_M3 = (100.0, 25_000.0)

#: Overlapping pairs named in messages and in the text report (all are in the JSON).
WORST_PAIRS_SHOWN = 10


def unit_scale(model: StepModel, units: str | None) -> tuple[float, list[str], list[str]]:
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
    surface_areas: bool = False,
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
    overlaps : "check", "allow", "resolve" or "skip"
        Refuse overlaps above the threshold, count each solid as it is, cut each common volume
        out of the less dense solid, or count each solid as it is without searching (no
        summary; the fastest).
    strict : bool
        Raise on any note; also checks every solid's topology (otherwise only the solids that
        go through a boolean are checked).
    progress : ProgressFactory, optional
    workers : int
        Processes for the integrations and overlap booleans (results do not depend on it).
    surface_areas : bool
        Also each body's face area (``BodyResult.surface_area_mm2``, for insulation and
        coatings); it costs about half an integration more per distinct product.

    Raises
    ------
    Refusal
        Overlaps beyond the threshold under ``check``, or (with ``strict``) any note; its
        ``as_is`` is the model counted as it is (``check`` as ``allow``, without ``strict``),
        from the same computation.
    CadcogError
        Naming the file and the bodies: zero or negative volumes, open solids, bodies without a
        density, every body excluded.
    """
    src = model.source
    if overlaps not in ("check", "allow", "resolve", "skip"):
        raise CadcogError(
            f"overlaps: expected check, allow, resolve or skip, got {quote(overlaps)}"
        )
    if units is not None and units not in LENGTH_UNIT_MM:
        raise CadcogError(f"--units: unknown unit {units!r}; expected {', '.join(UNIT_CHOICES)}")
    scale, notes, info = unit_scale(model, units)

    kept = [b for b in model.bodies if not matches_any(exclude, b)]
    excluded = tuple(b.path for b in model.bodies if matches_any(exclude, b))
    for pattern in exclude:
        if not any(matches_any([pattern], b) for b in model.bodies):
            notes.append(f"--exclude {pattern!r} matched no body")
    if materials is not None:
        notes.extend(
            f"materials rule {rule} ({materials.source or 'materials'}) matches no body or "
            "assembly name: a typo? (the bodies it meant fall to a later rule)"
            for rule in unmatched_rules(materials, model.bodies)
        )
    if not kept:
        shown = " ".join(f"--exclude {p!r}" for p in exclude)
        raise AllExcludedError(f"{shown}: excludes every body of {src}")

    bodies, audit_bits = integrate(kept, scale, progress, workers, surface_areas)
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

    assign_densities(bodies, materials, total_mass_kg, notes, src, info)
    summary, resolved_info, in_booleans, refused = handle_overlaps(
        bodies, overlaps, scale, progress, src, workers
    )
    info.extend(resolved_info)
    invalid = invalid_solids(bodies, None if strict else in_booleans, workers)
    # what the checks find without --strict: the solids that took part in a boolean (the
    # order of the bodies kept)
    product_of = {b.step.path: b.step.product_key for b in bodies}
    invalid_as_is = [p for p in invalid if product_of[p] in in_booleans]
    parts = _Parts(
        model, bodies, materials, total_mass_kg, units, scale, excluded, audit_bits, bbox
    )
    # What a refusal carries: the model counted as it is (check as allow), without strict.
    as_is_summary = replace(summary, policy="allow") if overlaps == "check" else summary
    if refused is not None:
        raise Refusal(refused, parts.assemble(as_is_summary, notes, info, invalid_as_is))
    result = parts.assemble(summary, notes, info, invalid)
    if strict and result.notes:
        same = invalid_as_is == invalid and as_is_summary is summary
        as_is = result if same else parts.assemble(as_is_summary, notes, info, invalid_as_is)
        raise Refusal(
            f"{src}: --strict: {len(result.notes)} note(s): " + " | ".join(result.notes), as_is
        )
    return result


@dataclass(frozen=True)
class _Parts:
    """What a model's result is assembled from once its bodies are integrated, their densities
    assigned and their overlaps handled: :meth:`assemble` gives the result for a summary, notes,
    info lines and invalid solids (twice when a refusal carries the model as counted)."""

    model: StepModel
    bodies: list[Body]
    materials: MaterialMap | None
    total_mass_kg: float | None
    units: str | None
    scale: float
    excluded: tuple[str, ...]
    audit_bits: dict[str, Any]
    bbox: tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]

    def assemble(
        self,
        summary: OverlapSummary,
        notes_so_far: list[str],
        info_so_far: list[str],
        invalid: list[str],
    ) -> ModelMassProperties:
        """The result (``notes_so_far`` and ``info_so_far`` are copied, not extended).

        Raises
        ------
        CadcogError
            If no body has mass.
        """
        model, bodies, units, scale = self.model, self.bodies, self.units, self.scale
        excluded, audit_bits, src, bbox = self.excluded, self.audit_bits, model.source, self.bbox
        total_mass_kg = self.total_mass_kg
        notes, info = list(notes_so_far), list(info_so_far)
        raw = [with_mass_factor(b.props, b.density_kg_mm3) for b in bodies]
        counted = [(b, p) for b, p in zip(bodies, raw, strict=True) if p.mass_kg > 0]
        if not counted:
            raise CadcogError(f"{src}: no body has mass (only surfaces without an areal density?)")
        factor = self._weighed_factor(counted, notes, info)
        summary = _scaled_summary(summary, factor)
        _overlap_lines(summary, notes, info)
        results = [self._body_result(b, p, factor) for b, p in counted]
        left_out = tuple((b.step.path, b.props.mass_kg) for b in bodies if b.density_kg_mm3 == 0.0)
        notes += _quality_notes(left_out, audit_bits["made_solid"], invalid, model)
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
            tuple(invalid),
            model.curve_only_parts,
            sources,
            (tuple(float(v) for v in bbox[0]), tuple(float(v) for v in bbox[1])),  # type: ignore[arg-type]
            total_mass_kg,
        )
        total = combine(r.properties for r in results)
        return ModelMassProperties(total, tuple(results), audit, summary, tuple(notes), tuple(info))

    def _weighed_factor(
        self, counted: list[tuple[Body, MassProperties]], notes: list[str], info: list[str]
    ) -> float:
        """The factor that scales every density to the weighed total mass (1 without one); a
        note when the mean density it implies is implausible for the declared unit."""
        total_mass_kg = self.total_mass_kg
        if total_mass_kg is None:
            return 1.0
        factor = total_mass_kg / sum(p.mass_kg for _, p in counted)
        info.append(f"densities scaled by {factor:.6g} to match the weighed {total_mass_kg:g} kg")
        volume = sum(b.props.volume_mm3 for b, _ in counted)
        mean = total_mass_kg / volume * 1e9 if volume > 0 else float("inf")
        lo_d, hi_d = PLAUSIBLE_MEAN_DENSITY_KG_M3
        if self.units is None and not lo_d <= mean <= hi_d:
            notes.append(
                f"the weighed mass implies a mean density of {mean:.4g} kg/m³: the file's "
                f"declared unit ({self.model.declared_unit or 'none'}) may be wrong; pass --units"
            )
        return factor

    def _body_result(self, b: Body, p: MassProperties, factor: float) -> BodyResult:
        """One body's line of the result, its densities scaled by ``factor``."""
        materials = self.materials
        sigma, growth = item_rules(b.step, materials)
        return BodyResult(
            b.step.path,
            tuple(n.name for n in b.step.nodes),
            b.step.kind,
            b.material,
            b.source,
            None if b.density_kg_m3 is None else b.density_kg_m3 * factor,
            None if b.areal_density_kg_m2 is None else b.areal_density_kg_m2 * factor,
            with_mass_factor(p, factor),
            b.props.mass_kg if b.step.kind == "surface" else 0.0,
            b.removed_mm3,
            None if sigma is None else sigma.value,
            b.step.path if sigma is None else sigma.item,
            0.0 if growth is None else growth.value,
            "" if growth is None else growth.label,
            None if materials is None else materials.cog_uncertainty(item_candidates(b.step)),
            b.surface_area_mm2,
            tuple(n.product for n in b.step.nodes),
        )


def _scaled_summary(summary: OverlapSummary, factor: float) -> OverlapSummary:
    """The overlaps' masses scaled with the densities."""
    if factor == 1.0 or not summary.pairs:
        return summary
    return replace(
        summary,
        mass_kg=summary.mass_kg * factor,
        pairs=tuple(replace(p, mass_kg=p.mass_kg * factor) for p in summary.pairs),
    )


def _overlap_lines(summary: OverlapSummary, notes: list[str], info: list[str]) -> None:
    """The overlaps counted as they are: a note under ``check``, an info line under ``allow``
    (the user chose it)."""
    if summary.pairs and summary.policy == "check":
        notes.append(
            f"{summary.headline()}; under the refusal threshold of "
            f"{tolerances.OVERLAP_REFUSE_MASS_FRACTION:.1%}: each solid counted as it is"
        )
    elif summary.pairs and summary.policy == "allow":
        info.append(f"{summary.headline()}; --allow-overlap: each solid counted as it is")


def _quality_notes(
    left_out: tuple[tuple[str, float], ...],
    made_solid: list[str],
    invalid: list[str],
    model: StepModel,
) -> list[str]:
    """What the model's geometry made cadcog do: surfaces without volume left out (``left_out``:
    path and area), shells made solid, invalid solids integrated, parts with no mass."""
    notes = []
    if left_out:
        area = sum(a for _, a in left_out)
        shown = ", ".join(f"{p} ({a:.4g} mm²)" for p, a in left_out[:WORST_PAIRS_SHOWN])
        more = (
            f" and {len(left_out) - WORST_PAIRS_SHOWN} more"
            if len(left_out) > WORST_PAIRS_SHOWN
            else ""
        )
        notes.append(
            f"{len(left_out)} surface bod{'y' if len(left_out) == 1 else 'ies'} "
            f"({area:.4g} mm² in all) have no volume and are left out: {shown}{more}; give "
            "them an areal density in the materials file's [surfaces] table"
        )
    if made_solid:
        notes.append(
            f"closed shells made into solids: {', '.join(made_solid[:10])}"
            + (" ..." if len(made_solid) > 10 else "")
        )
    if invalid:
        notes.append(
            f"OCCT reports invalid topology in {len(invalid)} solid(s) "
            f"({', '.join(invalid[:10])}); integrated anyway"
        )
    if model.curve_only_parts:
        notes.append(
            f"{len(model.curve_only_parts)} part(s) hold only curves or points, no mass: "
            + ", ".join(model.curve_only_parts[:10])
        )
    return notes
