"""Mass properties of any STEP model: exact integration per solid, each with its own density.

Real CAD is messy, so every solid is checked before a number comes out: shells that are not
closed solids, zero or negative volumes, solids that overlap (their common volume would be
counted twice), and a scale that looks like metres or inches. Each problem names the solid and
stops the computation with a hint (exclude it, fix the units) rather than silently producing a
number. No mesh is needed: a solid that cannot be tessellated still integrates.
"""

from __future__ import annotations

import fnmatch
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import build123d as bd
import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepAlgoAPI import BRepAlgoAPI_Common
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepGProp import BRepGProp
from OCP.GProp import GProp_GProps
from OCP.TopAbs import TopAbs_SHELL
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS

from cadcog.cad.occt import solid_properties
from cadcog.errors import CadcogError
from cadcog.massprops import MassProperties, combine
from cadcog.materials import MaterialMap
from cadcog.units import density_kg_m3_to_kg_mm3

#: Length of one model unit in mm.
UNIT_SCALE_MM = {"mm": 1.0, "m": 1000.0, "in": 25.4}

#: A model whose largest extent (in mm) falls outside this range is probably in the wrong unit.
PLAUSIBLE_EXTENT_MM = (5.0, 5000.0)

#: Mean densities outside this range (kg/m³) point at a unit error when the total mass is known.
PLAUSIBLE_MEAN_DENSITY_KG_M3 = (100.0, 25_000.0)

#: Common volume (relative to the smaller solid) above which two solids overlap.
OVERLAP_RELATIVE = 1e-6


@dataclass(frozen=True)
class SolidEntry:
    name: str
    path: tuple[str, ...]
    shape: Any  # TopoDS_Shape


@dataclass(frozen=True)
class SolidResult:
    name: str
    path: tuple[str, ...]
    material: str
    rule: str
    density_kg_m3: float
    properties: MassProperties

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "path": "/".join(self.path),
            "material": self.material,
            "rule": self.rule,
            "density_kg_m3": self.density_kg_m3,
            "volume_mm3": self.properties.volume_mm3,
            "mass_kg": self.properties.mass_kg,
            "cog_mm": self.properties.cog_mm.tolist(),
        }


@dataclass(frozen=True)
class ModelMassProperties:
    total: MassProperties
    solids: tuple[SolidResult, ...]
    excluded: tuple[str, ...] = ()
    notes: tuple[str, ...] = field(default=())

    def to_dict(self) -> dict[str, Any]:
        return {
            **self.total.to_dict(),
            "solids": [s.to_dict() for s in self.solids],
            "excluded": list(self.excluded),
            "notes": list(self.notes),
        }


def read_step_solids(path: str | Path) -> list[SolidEntry]:
    """Every solid of a STEP file with its name and assembly path (labels kept).

    Raises
    ------
    CadcogError
        If the file cannot be read, or holds shells that are not closed solids.
    """
    p = Path(path)
    if not p.is_file():
        raise CadcogError(f"{p}: file not found")
    try:
        root = bd.import_step(p)
    except Exception as exc:  # OCCT raises plain exceptions on unreadable files
        raise CadcogError(f"{p}: cannot read as STEP ({exc})") from None
    entries: list[SolidEntry] = []
    problems: list[str] = []

    def walk(node: Any, path: tuple[str, ...]) -> None:
        label = node.label or ""
        here = (*path, label) if label else path
        children = list(node.children)
        if children:
            for child in children:
                walk(child, here)
            return
        solids = node.solids()
        base = label or (path[-1] if path else p.stem)
        if not solids:
            if node.faces():
                problems.append(f"{'/'.join(here) or base}: surfaces without a closed solid")
            return
        for i, s in enumerate(solids):
            name = base if len(solids) == 1 else f"{base}#{i + 1}"
            entries.append(SolidEntry(name, here, s.wrapped))

    walk(root, ())
    if problems:
        raise CadcogError(
            f"{p}: open shells (not solids) cannot have a volume: {'; '.join(problems)}; close "
            "them in the CAD tool or leave them out of the export"
        )
    if not entries:
        raise CadcogError(f"{p}: no solids found")
    names = [e.name for e in entries]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        entries = [
            SolidEntry(f"{'/'.join(e.path)}" if e.name in dup else e.name, e.path, e.shape)
            for e in entries
        ]
    return entries


def _closed(shape: Any) -> bool:
    explorer = TopExp_Explorer(shape, TopAbs_SHELL)
    found = False
    while explorer.More():
        found = True
        if not BRep_Tool.IsClosed_s(TopoDS.Shell(explorer.Current())):
            return False
        explorer.Next()
    return found


def _common_volume(a: Any, b: Any) -> float:
    op = BRepAlgoAPI_Common(a, b)
    op.Build()
    if not op.IsDone():
        return 0.0
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(op.Shape(), props)
    return float(props.Mass())


def bounding_box_mm(shape: Any) -> tuple[np.ndarray, np.ndarray]:
    """Axis-aligned bounding box (min, max corners) of a shape, in model units."""
    b = bd.Solid(shape).bounding_box()
    return np.array([b.min.X, b.min.Y, b.min.Z]), np.array([b.max.X, b.max.Y, b.max.Z])


def model_mass_properties(
    entries: Sequence[SolidEntry],
    materials: MaterialMap | None,
    *,
    total_mass_kg: float | None = None,
    units: str | None = None,
    exclude: Sequence[str] = (),
    allow_overlap: bool = False,
) -> ModelMassProperties:
    """Exact, density-weighted mass properties of the solids of a model.

    Parameters
    ----------
    entries : sequence of SolidEntry
    materials : MaterialMap or None
        None with ``total_mass_kg``: one uniform density giving that mass.
    total_mass_kg : float, optional
        Scale every density so the total equals this weighed mass.
    units : "mm", "m", "in" or None
        Length unit of the model; None means mm, after a plausibility check.
    exclude : sequence of str
        Glob patterns of solids to leave out.
    allow_overlap : bool
        Accept overlapping solids (their common volume counts twice).
    """
    scale = UNIT_SCALE_MM[units or "mm"]
    kept = [
        e
        for e in entries
        if not any(fnmatch.fnmatchcase(n, pat) for pat in exclude for n in (e.name, *e.path))
    ]
    excluded = tuple(e.name for e in entries if e not in kept)
    if not kept:
        raise CadcogError("every solid is excluded")
    # Geometry checks, in model units.
    bad = [e.name for e in kept if not _closed(e.shape)]
    if bad:
        raise CadcogError(
            f"open shells, not closed solids: {', '.join(bad)}; fix them or --exclude them"
        )
    invalid = [e.name for e in kept if not BRepCheck_Analyzer(e.shape).IsValid()]
    volumes = {}
    for e in kept:
        props = GProp_GProps()
        BRepGProp.VolumeProperties_s(e.shape, props)
        volumes[e.name] = props.Mass() * scale**3
    empty = [n for n, v in volumes.items() if not v > 1e-9]
    if empty:
        raise CadcogError(
            f"zero or negative volume: {', '.join(empty)} "
            "(degenerate or inside-out solids); --exclude them or fix the model"
        )
    boxes = {e.name: bounding_box_mm(e.shape) for e in kept}
    lo = np.min([b[0] for b in boxes.values()], axis=0) * scale
    hi = np.max([b[1] for b in boxes.values()], axis=0) * scale
    extent = float(np.max(hi - lo))
    if units is None and not PLAUSIBLE_EXTENT_MM[0] <= extent <= PLAUSIBLE_EXTENT_MM[1]:
        guess = "metres (--units m)" if extent < PLAUSIBLE_EXTENT_MM[0] else "a smaller unit"
        raise CadcogError(
            f"the model spans {extent:g} mm if its unit is mm; is it in {guess}? Pass --units "
            "mm, m or in to say which"
        )
    if not allow_overlap:
        overlaps = []
        for i, a in enumerate(kept):
            for b in kept[i + 1 :]:
                (alo, ahi), (blo, bhi) = boxes[a.name], boxes[b.name]
                if np.any(np.minimum(ahi, bhi) <= np.maximum(alo, blo)):
                    continue
                common = _common_volume(a.shape, b.shape) * scale**3
                if common > OVERLAP_RELATIVE * min(volumes[a.name], volumes[b.name]):
                    overlaps.append(f"{a.name} & {b.name} ({common:.4g} mm³)")
        if overlaps:
            raise CadcogError(
                "solids overlap, so their common volume would count twice: "
                + "; ".join(overlaps)
                + ". Fix the model, --exclude one of each pair, or "
                "--allow-overlap"
            )
    # Densities.
    assigned: dict[str, tuple[str, str, float]] = {}
    missing: list[str] = []
    for entry in kept:
        if materials is None:
            assigned[entry.name] = ("uniform", "total mass", 1.0)
            continue
        found = materials.assign([entry.name, *reversed(entry.path)])
        if found is None:
            missing.append(entry.name)
        else:
            assigned[entry.name] = (found.material, found.rule, found.density_kg_m3)
    if missing:
        raise CadcogError(
            f"no material for {len(missing)} solid(s): {', '.join(missing)}; add patterns to the "
            'materials file, or a catch-all "*" rule for a default density'
        )
    factor = 1.0
    notes = []
    if total_mass_kg is not None:
        raw = sum(density_kg_m3_to_kg_mm3(assigned[n][2]) * volumes[n] for n in assigned)
        factor = total_mass_kg / raw
        notes.append(f"densities scaled by {factor:.6g} to match the weighed {total_mass_kg:g} kg")
        mean_density = total_mass_kg / sum(volumes.values()) * 1e9
        lo_d, hi_d = PLAUSIBLE_MEAN_DENSITY_KG_M3
        if units is None and not lo_d <= mean_density <= hi_d:
            raise CadcogError(
                f"the weighed mass implies a mean density of {mean_density:.4g} kg/m³: the model's "
                "unit is probably not mm; pass --units m or --units in (or --units mm to accept)"
            )
    if invalid:
        notes.append(f"OCCT reports invalid topology in {', '.join(invalid)}; integrated anyway")
    results = []
    for e in kept:
        material, rule, density = assigned[e.name]
        density *= factor
        ip = solid_properties(e.shape, density_kg_m3_to_kg_mm3(density) * scale**3, name=e.name)
        p = ip.properties
        props = MassProperties(
            p.mass_kg, p.cog_mm * scale, p.inertia_kg_mm2 * scale**2, p.volume_mm3 * scale**3
        )
        results.append(SolidResult(e.name, e.path, material, rule, density, props))
    total = combine(r.properties for r in results)
    return ModelMassProperties(total, tuple(results), excluded, tuple(notes))
