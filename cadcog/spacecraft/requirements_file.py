"""The requirements file (TOML; ``parts/cubesat_3u_requirements.toml`` is the example): its
reader, :func:`load_requirements`, into :class:`Requirements` (the format is described in
:mod:`cadcog.spacecraft.requirements`, which checks a model against them)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from cadcog.core.paramfile import TableReader
from cadcog.mass.inertia import Frame
from cadcog.spacecraft.baseline import Tolerances
from cadcog.spacecraft.envelope import CDS_COG_LIMITS_MM

MOMENT_NAMES = ("min", "intermediate", "max", "xx", "yy", "zz")


@dataclass(frozen=True)
class Allocation:
    node: str
    max_kg: float


@dataclass(frozen=True)
class Ratio:
    numerator: str
    denominator: str
    min: float | None
    max: float | None


@dataclass(frozen=True)
class Requirements:
    """A validated requirements file (everything but the model)."""

    name: str
    source: Path
    max_kg: float | None = None
    margin: float = 0.0
    min_kg: float | None = None
    allocations: tuple[Allocation, ...] = ()
    form_factor: str | None = None
    cog_limits_mm: tuple[float, float, float] | None = None
    cog_axes: str = "+x,+y,+z"
    cog_at_95: bool = False
    inertia_about: str | tuple[float, float, float] = "cog"
    inertia_axes: str = "+x,+y,+z"
    max_misalignment_deg: float | None = None
    distinct_moments_rel: float = 1e-6
    max_product_kg_mm2: float | None = None
    ratios: tuple[Ratio, ...] = ()
    baseline_file: Path | None = None
    tolerances: Tolerances = field(default_factory=Tolerances)
    configurations_file: Path | None = None
    cog_configurations: tuple[str, ...] = ()  # ("*",): every configuration
    inertia_configurations: tuple[str, ...] = ()


def _frame_axes(t: TableReader, key: str) -> str:
    axes = t.string(key, default="+x,+y,+z")
    try:
        Frame.parse(axes, [0.0, 0.0, 0.0])
    except ValueError as exc:
        raise t.error(key, str(exc)) from None
    return axes


def load_requirements(root: TableReader, path: Path) -> Requirements:
    """The requirement tables of a requirements file (its model keys are read elsewhere)."""
    base = path.parent
    name = root.string("name", default=path.stem)
    kw: dict[str, Any] = {}
    if root.has("mass"):
        m = root.table("mass")
        if m.has("max_kg"):
            kw["max_kg"] = m.number("max_kg", positive=True)
        kw["margin"] = m.number("margin", nonnegative=True, default=0.0)
        if kw["margin"] >= 1.0:
            raise m.error("margin", f"a fraction below 1 (10 % = 0.10), got {kw['margin']:g}")
        if m.has("min_kg"):
            kw["min_kg"] = m.number("min_kg", positive=True)
            if "max_kg" in kw and kw["min_kg"] > kw["max_kg"]:
                raise m.error(
                    "min_kg",
                    f"{kw['min_kg']:g} is above max_kg {kw['max_kg']:g}: no model can pass",
                )
        if m.has("allocation"):
            kw["allocations"] = tuple(_allocation(a) for a in m.tables("allocation"))
        m.finish()
    if root.has("cog"):
        c = root.table("cog")
        if c.has("form_factor") and c.has("limits_mm"):
            raise c.error("limits_mm", "give form_factor or limits_mm, not both")
        if c.has("form_factor"):
            kw["form_factor"] = c.string("form_factor", choices=list(CDS_COG_LIMITS_MM))
        elif c.has("limits_mm"):
            v = c.vector("limits_mm", positive=True)
            kw["cog_limits_mm"] = (v[0], v[1], v[2])
        else:
            raise c.error("form_factor", "missing: give form_factor or limits_mm")
        kw["cog_axes"] = _frame_axes(c, "axes")
        kw["cog_at_95"] = c.boolean("at_95", default=False)
        kw["cog_configurations"] = _configuration_names(c, root)
        c.finish()
    if root.has("inertia"):
        i = root.table("inertia")
        if i.has("about"):
            kw["inertia_about"] = _about(i)
        kw["inertia_axes"] = _frame_axes(i, "axes")
        if i.has("max_misalignment_deg"):
            kw["max_misalignment_deg"] = i.number("max_misalignment_deg", nonnegative=True)
        if i.has("distinct_moments_rel"):
            if not i.has("max_misalignment_deg"):
                raise i.error("distinct_moments_rel", "goes with max_misalignment_deg")
            rel = i.number("distinct_moments_rel", nonnegative=True)
            if not rel < 1:
                raise i.error("distinct_moments_rel", f"expected a fraction below 1, got {rel:g}")
            kw["distinct_moments_rel"] = rel
        if i.has("max_product_kg_mm2"):
            kw["max_product_kg_mm2"] = i.number("max_product_kg_mm2", nonnegative=True)
        if i.has("ratio"):
            kw["ratios"] = tuple(_ratio(r) for r in i.tables("ratio"))
        kw["inertia_configurations"] = _configuration_names(i, root)
        i.finish()
    if root.has("baseline"):
        b = root.table("baseline")
        kw["baseline_file"] = base / b.string("file")
        kw["tolerances"] = Tolerances(
            b.number("mass_tolerance_kg", nonnegative=True, default=Tolerances().mass_kg),
            b.number("cog_tolerance_mm", nonnegative=True, default=Tolerances().cog_mm),
        )
        b.finish()
    if root.has("configurations"):
        kw["configurations_file"] = base / root.string("configurations")
    return Requirements(name, path, **kw)


def _configuration_names(t: TableReader, root: TableReader) -> tuple[str, ...]:
    """A table's ``configurations``: ``"*"`` (every one) or a list of names; it needs the file's
    top-level ``configurations`` file."""
    if not t.has("configurations"):
        return ()
    if not root.has("configurations"):
        raise t.error(
            "configurations",
            'needs a configurations file: configurations = "FILE.toml" at the top of the file',
        )
    if t.is_string("configurations"):
        value = t.string("configurations")
        if value != "*":
            raise t.error("configurations", f'{value!r}: expected "*" or a list of names')
        return ("*",)
    return tuple(t.strings("configurations"))


def _allocation(t: TableReader) -> Allocation:
    out = Allocation(t.string("node"), t.number("max_kg", positive=True))
    t.finish()
    return out


def _about(t: TableReader) -> str | tuple[float, float, float]:
    if t.is_string("about"):
        return t.string("about", choices=("cog", "centre", "origin"))
    v = t.vector("about")
    return v[0], v[1], v[2]


def _ratio(t: TableReader) -> Ratio:
    r = Ratio(
        t.string("numerator", choices=MOMENT_NAMES),
        t.string("denominator", choices=MOMENT_NAMES),
        t.number("min", positive=True) if t.has("min") else None,
        t.number("max", positive=True) if t.has("max") else None,
    )
    if r.min is None and r.max is None:
        raise t.error("min", "give min, max or both")
    t.finish()
    return r
