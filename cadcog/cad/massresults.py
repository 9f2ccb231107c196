"""The result of :func:`cadcog.cad.stepmass.model_mass_properties`, as values: the model's
total, each body as counted, the import audit and the overlaps, with their JSON forms.

:func:`to_data` and :func:`from_data` turn a :class:`ModelMassProperties` into plain data
(numbers, strings, lists) and back, exactly (floats written with ``repr``): the form the
mass-properties cache keeps (:mod:`cadcog.cad.cache`). Nothing here imports OCP.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from cadcog.core.errors import CadcogError
from cadcog.core.results import JsonResult
from cadcog.mass.properties import MassProperties


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
    surface_area_mm2 : float or None
        Area of the body's faces (mm²): a solid's whole boundary, as modelled (before any
        overlap resolution; faces it shares with a neighbour counted in both); a surface body's
        ``area_mm2``. None unless asked for (``massprops --surface-area``).
    products : tuple of str
        The product each node of ``nodes`` places (the STEP's product names): copies of one
        part share them whatever the exporter named the instances.
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
    surface_area_mm2: float | None = None
    products: tuple[str, ...] = ()

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
        if self.surface_area_mm2 is not None:
            out["surface_area_mm2"] = self.surface_area_mm2
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
        line = (
            f"{len(self.pairs)} overlapping pair(s): {self.volume_mm3:.4g} mm³ and "
            f"{self.mass_kg * 1e3:.4g} g counted more than once ({self.mass_fraction:.3%} of the "
            f"mass), shifting the CoG by {shift:.3g} mm"
        )
        summed = sum(p.mass_kg for p in self.pairs)
        if abs(summed - self.mass_kg) > 1e-3 * max(self.mass_kg, 1e-300):
            line += (
                f" (the pairs' own shares sum to {summed * 1e3:.4g} g: where three or more "
                "solids share a region, each pair lists it, and the total counts it once for "
                "each solid beyond the first)"
            )
        return line

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
    #: The weighed total every density was scaled to (``--total-mass-kg``), or None.
    total_mass_given_kg: float | None = None

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
            "total_mass_given_kg": self.total_mass_given_kg,
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


# --- plain data, exactly ---------------------------------------------------------------------
class Refusal(CadcogError):
    """The model was refused: overlaps above the threshold under ``check``, or a note under
    ``strict``. It still carries the model counted as what was refused allows.

    Attributes
    ----------
    as_is : ModelMassProperties
        The model counted as it is and without ``strict``: under ``check`` as ``allow`` counts
        it (each solid whole, the overlaps an info line), under another policy as that policy
        does; notes not errors. What ``massprops`` writes under ``"refused"`` with ``--json``,
        ``--csv`` or ``--report``.
    """

    def __init__(self, message: str, as_is: ModelMassProperties) -> None:
        super().__init__(message)
        self.as_is = as_is

    def __reduce__(self) -> tuple[Any, ...]:
        return (Refusal, (str(self), self.as_is))


def _props_data(p: MassProperties) -> list[Any]:
    return [p.mass_kg, p.cog_mm.tolist(), p.inertia_kg_mm2.tolist(), p.volume_mm3]


def _props(d: list[Any]) -> MassProperties:
    return MassProperties(d[0], np.array(d[1]), np.array(d[2]), d[3])


def _tuple3(v: Any) -> Any:
    return None if v is None else tuple(float(x) for x in v)


def to_data(m: ModelMassProperties) -> dict[str, Any]:
    """Every field of ``m`` as JSON-ready data (numbers as Python floats, tuples as lists):
    :func:`from_data` gives back an equal result, to the last bit of every float."""

    def fields(obj: Any) -> dict[str, Any]:
        return {f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)}

    bodies = []
    for b in m.bodies:
        d = fields(b)
        d["nodes"] = list(b.nodes)
        d["products"] = list(b.products)
        d["properties"] = _props_data(b.properties)
        d["cog_sigma_mm"] = None if b.cog_sigma_mm is None else list(b.cog_sigma_mm)
        bodies.append(d)
    audit = fields(m.audit)
    audit["left_out_surfaces"] = [list(x) for x in m.audit.left_out_surfaces]
    audit["bbox_mm"] = [list(m.audit.bbox_mm[0]), list(m.audit.bbox_mm[1])]
    for key in ("declared_units", "excluded", "closed_shells_made_solid", "invalid_topology"):
        audit[key] = list(audit[key])
    audit["curve_only_parts"] = list(m.audit.curve_only_parts)
    overlaps = fields(m.overlaps)
    overlaps["pairs"] = [fields(p) for p in m.overlaps.pairs]
    overlaps["cog_shift_mm"] = list(m.overlaps.cog_shift_mm)
    return {
        "total": _props_data(m.total),
        "bodies": bodies,
        "audit": audit,
        "overlaps": overlaps,
        "notes": list(m.notes),
        "info": list(m.info),
    }


def from_data(d: dict[str, Any]) -> ModelMassProperties:
    """The :class:`ModelMassProperties` that :func:`to_data` gave ``d`` for.

    Raises
    ------
    KeyError, TypeError, ValueError, IndexError
        If ``d`` is not such data (a damaged cache entry: the caller computes afresh).
    """
    bodies = []
    for b in d["bodies"]:
        b = dict(b)
        b["nodes"] = tuple(b["nodes"])
        b["products"] = tuple(str(x) for x in b["products"])
        b["properties"] = _props(b["properties"])
        b["cog_sigma_mm"] = _tuple3(b["cog_sigma_mm"])
        bodies.append(BodyResult(**b))
    a = dict(d["audit"])
    a["left_out_surfaces"] = tuple((str(p), float(v)) for p, v in a["left_out_surfaces"])
    a["bbox_mm"] = (_tuple3(a["bbox_mm"][0]), _tuple3(a["bbox_mm"][1]))
    for key in ("declared_units", "excluded", "closed_shells_made_solid", "invalid_topology"):
        a[key] = tuple(a[key])
    a["curve_only_parts"] = tuple(a["curve_only_parts"])
    a["density_sources"] = dict(a["density_sources"])
    o = dict(d["overlaps"])
    o["pairs"] = tuple(OverlapPair(**p) for p in o["pairs"])
    o["cog_shift_mm"] = _tuple3(o["cog_shift_mm"])
    return ModelMassProperties(
        _props(d["total"]),
        tuple(bodies),
        ImportAudit(**a),
        OverlapSummary(**o),
        tuple(d["notes"]),
        tuple(d["info"]),
    )
