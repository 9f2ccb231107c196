"""Densities of common spacecraft materials, and what a materials file assigns by name pattern.

Densities are nominal room-temperature values (kg/m³) from the sources named per entry: ASM
Aerospace Specification Metals / MatWeb data sheets for metals, IPC-4101 / laminate data sheets
for FR-4, manufacturers' data sheets for plastics. Real parts vary by a few per cent (alloy
temper, resin content, porosity): weigh them and use ``--total-mass-kg`` where it matters.

A materials file (TOML) has up to five tables, each mapping glob patterns of body or assembly
names (or of a body's full path, ``sat/boards/obc/*``) to a value; in each table the first
matching pattern wins, and a pattern matches a body through its own name or any assembly's
above it::

    [materials]                  # solids: a library material, or a density in kg/m³
    "rail*" = "aluminium 6061-T6"
    "battery*" = 2100.0
    "*" = "aluminium 6061-T6"     # a default, if you want one

    [surfaces]                   # surface bodies (no volume): kg/m², or a material and thickness
    "*MLI*" = 0.45
    "*kapton*" = { material = "polyimide (Kapton)", thickness_mm = 0.025 }

    [mass_uncertainty]           # 1-σ relative mass uncertainty of the matched item
    "battery_pack" = 0.02        # an assembly: the whole pack is one item
    "*" = 0.05                   # every other body on its own

    [cog_uncertainty]            # 1-σ uncertainty of the matched item's CoG, per axis (mm)
    "battery_pack" = 2.0         # the same along x, y and z
    "camera*" = [1.0, 1.0, 5.0]  # or per model axis

    [growth_allowance]           # mass growth allowance: a fraction or a maturity level
    "payload*" = "new"
    "*" = 0.05

    [maturity_levels]            # your programme's allowance per maturity level
    new = 0.20

An uncertainty rule's *item* is the deepest node the pattern matches: a rule naming an assembly
makes its bodies one item, whose masses vary together. A CoG uncertainty applies to the item of
the body's mass uncertainty; an item no ``[cog_uncertainty]`` rule names gets the default of
:mod:`cadcog.spacecraft.items` (its mass uncertainty times the spread of its mass).
"""

from __future__ import annotations

import functools
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from cadcog.core.errors import ParameterFileError
from cadcog.core.paramfile import TableReader, read_toml


@dataclass(frozen=True)
class Material:
    name: str
    density_kg_m3: float
    source: str


_ASM = "ASM Aerospace Specification Metals / MatWeb data sheet"
LIBRARY: dict[str, Material] = {
    m.name: m
    for m in (
        Material("aluminium 6061-T6", 2700.0, _ASM),
        Material("aluminium 7075-T6", 2810.0, _ASM),
        Material("aluminium 5052-H32", 2680.0, _ASM),
        Material("aluminium 2024-T3", 2780.0, _ASM),
        Material("titanium Ti-6Al-4V", 4430.0, _ASM),
        Material("stainless steel 304", 8000.0, _ASM),
        Material("stainless steel 316", 8000.0, _ASM),
        Material("steel AISI 1018", 7870.0, _ASM),
        Material("copper C11000", 8890.0, "Copper Development Association data sheet"),
        Material("brass C36000", 8500.0, "Copper Development Association data sheet"),
        Material("invar 36", 8050.0, "MatWeb data sheet (Invar 36)"),
        Material("FR-4", 1850.0, "IPC-4101 laminate data sheets (typ. 1.80-1.90 g/cm³)"),
        Material("polyimide (Kapton)", 1420.0, "DuPont Kapton HN data sheet"),
        Material("PEEK", 1300.0, "Victrex PEEK 450G data sheet"),
        Material("POM (Delrin)", 1410.0, "DuPont Delrin 100 data sheet"),
        Material("PTFE", 2200.0, "Chemours Teflon PTFE data sheet"),
        Material("ABS", 1050.0, "typical injection-grade ABS data sheet"),
        Material("PLA", 1240.0, "NatureWorks Ingeo 4043D data sheet"),
        Material("CFRP (quasi-isotropic)", 1550.0, "typical T300/epoxy laminate, 60 % fibre"),
        Material("Li-ion cell (18650)", 2600.0, "Panasonic NCR18650B: 46.5 g in 16.5 cm³"),
    )
}


#: Plausible volume densities (kg/m³): outside, a value is probably in another unit.
DENSITY_RANGE_KG_M3 = (10.0, 25_000.0)

#: Plausible areal densities of surface bodies (kg/m²): Kapton film to thick cover glass.
AREAL_DENSITY_RANGE_KG_M2 = (1e-4, 100.0)


@dataclass(frozen=True)
class Assignment:
    """A solid's material: its name (or 'density'), density and the rule that chose it."""

    material: str
    density_kg_m3: float
    rule: str


@dataclass(frozen=True)
class SurfaceAssignment:
    """A surface body's areal density and the rule that chose it."""

    material: str
    areal_density_kg_m2: float
    rule: str


@dataclass(frozen=True)
class ItemRule:
    """An uncertainty or growth rule that matched: the item's key, the value and the pattern.

    ``label`` names the maturity level for growth allowances given by level ('' otherwise).
    """

    item: str
    value: float
    rule: str
    label: str = ""


@functools.lru_cache(maxsize=1024)
def _glob_regex(pattern: str) -> re.Pattern[str]:
    parts = (".*" if c == "*" else "." if c == "?" else re.escape(c) for c in pattern)
    return re.compile("".join(parts), re.DOTALL)


def glob_match(name: str, pattern: str) -> bool:
    """Whether ``name`` matches ``pattern``: ``*`` any text, ``?`` one character, and every
    other character itself (``[`` and ``]`` too: they appear in instance names, ``screw[3]``).

    Examples
    --------
    >>> glob_match("sat/bracket[2]/plate", "*/bracket[2]/*"), glob_match("bracket2", "bracket[2]")
    (True, False)
    """
    return _glob_regex(pattern).fullmatch(name) is not None


def _matches(pattern: str, names: Sequence[str]) -> bool:
    return any(glob_match(n, pattern) for n in names)


def _first_item(
    rules: Sequence[tuple[str, float, str]], candidates: Sequence[tuple[str, Sequence[str]]]
) -> ItemRule | None:
    """First rule (in order) matching a candidate; within a rule, the first (deepest) one."""
    for pattern, value, label in rules:
        for key, names in candidates:
            if _matches(pattern, names):
                return ItemRule(key, value, pattern, label)
    return None


#: Names exporters give a body that has no material of its own (case-insensitive): Inventor's
#: "Generic" (1 g/cm³), SolidWorks', Onshape's and FreeCAD's defaults. A STEP material by one
#: of these names is a placeholder, not the part's material.
PLACEHOLDER_MATERIAL_NAMES = frozenset(
    {
        "generic",
        "default",
        "default material",
        "no material",
        "none",
        "not specified",
        "<not specified>",
        "material",
        "unnamed material",
    }
)


def is_placeholder_material(name: str) -> bool:
    """Whether a STEP material's name is an exporter's placeholder.

    Examples
    --------
    >>> is_placeholder_material("Generic"), is_placeholder_material("Aluminum 6061")
    (True, False)
    """
    return name.strip().lower() in PLACEHOLDER_MATERIAL_NAMES


@dataclass(frozen=True)
class MaterialMap:
    """What a materials file says, as ordered (pattern, value) rules per table.

    Attributes
    ----------
    rules : tuple of (str, str or float)
        Solids: pattern → library material name or density (kg/m³).
    source : str
        Where the rules came from (a file, an option), for messages and reports.
    surface_rules : tuple of (str, str, float)
        Surface bodies: pattern → (material label, areal density in kg/m²).
    uncertainty_rules : tuple of (str, float, str)
        Pattern → 1-σ relative mass uncertainty ('' label).
    growth_rules : tuple of (str, float, str)
        Pattern → mass growth allowance fraction, and the maturity level it came from.
    cog_rules : tuple of (str, (float, float, float))
        Pattern → 1-σ CoG uncertainty of the item along x, y, z (mm).
    step_first : bool
        A catch-all rule ``"*"`` gives a default only to solids whose STEP file carries no
        usable material (True, a materials file); False: it overrides them too (one density for
        every solid, ``--density-kg-m3``). Named rules always override the STEP's material.
    """

    rules: tuple[tuple[str, str | float], ...]
    source: str = ""
    surface_rules: tuple[tuple[str, str, float], ...] = ()
    uncertainty_rules: tuple[tuple[str, float, str], ...] = ()
    growth_rules: tuple[tuple[str, float, str], ...] = ()
    cog_rules: tuple[tuple[str, tuple[float, float, float]], ...] = ()
    step_first: bool = True

    def assign(self, names: Sequence[str]) -> Assignment | None:
        """Material of a solid known by ``names`` (its own name, then its assemblies')."""
        for pattern, value in self.rules:
            if _matches(pattern, names):
                if isinstance(value, str):
                    m = LIBRARY[value]
                    return Assignment(m.name, m.density_kg_m3, pattern)
                return Assignment("density", value, pattern)
        return None

    def assign_surface(self, names: Sequence[str]) -> SurfaceAssignment | None:
        """Areal density of a surface body known by ``names``."""
        for pattern, label, areal in self.surface_rules:
            if _matches(pattern, names):
                return SurfaceAssignment(label, areal, pattern)
        return None

    def uncertainty(self, candidates: Sequence[tuple[str, Sequence[str]]]) -> ItemRule | None:
        """Mass uncertainty of a body: ``candidates`` are (node path, names), deepest first.

        The rule's item is the deepest node it matches (an assembly makes one item).
        """
        return _first_item(self.uncertainty_rules, candidates)

    def cog_uncertainty(
        self, candidates: Sequence[tuple[str, Sequence[str]]]
    ) -> tuple[float, float, float] | None:
        """CoG uncertainty (mm, per axis) of a body's item: the first rule matching the body or
        an assembly above it (``candidates`` as for :meth:`uncertainty`)."""
        for pattern, sigma in self.cog_rules:
            if any(_matches(pattern, names) for _, names in candidates):
                return sigma
        return None

    def growth(self, candidates: Sequence[tuple[str, Sequence[str]]]) -> ItemRule | None:
        """Mass growth allowance of a body (same matching as :meth:`uncertainty`)."""
        return _first_item(self.growth_rules, candidates)

    @classmethod
    def uniform(cls, density_kg_m3: float) -> MaterialMap:
        return cls((("*", density_kg_m3),), "uniform density", step_first=False)


def _density(t: TableReader, key: str) -> float:
    density = t.number(key, positive=True)
    lo, hi = DENSITY_RANGE_KG_M3
    if not lo <= density <= hi:
        raise t.error(
            key,
            f"density {density:g} kg/m³ is implausible; expected kg/m³ between {lo:g} and "
            f"{hi:g} (is it in g/cm³?)",
        )
    return density


def _library_name(t: TableReader, key: str) -> str:
    name = t.string(key)
    if name not in LIBRARY:
        try:
            number: float | None = float(name)
        except ValueError:
            number = None
        if number is not None:
            raise t.error(
                key,
                f"{name!r} is a number written as text: write {number:g} without quotes for a "
                "density in kg/m³",
            )
        raise t.error(
            key,
            f"unknown material {name!r}; known: {', '.join(sorted(LIBRARY))}, or give a "
            "density in kg/m³",
        )
    return name


def _fraction(t: TableReader, key: str, what: str, upper: float) -> float:
    value = t.number(key, nonnegative=True)
    if value > upper:
        raise t.error(key, f"{what} {value:g} is a fraction: expected 0 to {upper:g} (5 % = 0.05)")
    return value


#: The largest CoG uncertainty accepted (mm): beyond, the value is probably in another unit.
MAX_COG_SIGMA_MM = 1000.0


def _cog_sigma(t: TableReader, key: str) -> tuple[float, float, float]:
    if t.is_array(key):
        values = list(t.vector(key))
        if any(not v >= 0 for v in values):
            raise t.error(key, f"CoG uncertainty {values} must be ≥ 0 mm on every axis")
    else:
        values = [t.number(key, nonnegative=True)] * 3
    if max(values) > MAX_COG_SIGMA_MM:
        raise t.error(
            key,
            f"CoG uncertainty {max(values):g} mm is implausible; expected 1-σ in mm, at most "
            f"{MAX_COG_SIGMA_MM:g}",
        )
    return values[0], values[1], values[2]


def _surface(t: TableReader, key: str) -> tuple[str, float]:
    if t.is_table(key):
        sub = t.table(key)
        name = _library_name(sub, "material")
        thickness_mm = sub.number("thickness_mm", positive=True)
        sub.finish()
        areal = LIBRARY[name].density_kg_m3 * thickness_mm * 1e-3
        label = f"{name}, {thickness_mm:g} mm"
    else:
        areal = t.number(key, positive=True)
        label = "areal density"
    lo, hi = AREAL_DENSITY_RANGE_KG_M2
    if not lo <= areal <= hi:
        raise t.error(
            key,
            f"areal density {areal:g} kg/m² is implausible; expected kg/m² between {lo:g} and "
            f"{hi:g}",
        )
    return label, areal


#: The tables a materials file may hold.
MATERIALS_TABLES = (
    "materials",
    "surfaces",
    "mass_uncertainty",
    "cog_uncertainty",
    "maturity_levels",
    "growth_allowance",
)


def load_materials(path: str | Path) -> MaterialMap:
    """Read a materials file; unknown material names and bad values name the key."""
    p = Path(path)
    root = TableReader(read_toml(p), p)
    for name in (
        "materials",
        "surfaces",
        "mass_uncertainty",
        "cog_uncertainty",
        "growth_allowance",
    ):
        if root.is_table(name):
            for pattern in root.table(name).keys():
                if any(ord(ch) < 32 or ord(ch) == 127 for ch in pattern):
                    raise root.error(
                        name, f"pattern {pattern!r} holds a control character: no name does"
                    )
    rules: list[tuple[str, str | float]] = []
    if root.has("materials"):
        table = root.table("materials")
        for pattern in table.keys():
            if table.is_string(pattern):
                rules.append((pattern, _library_name(table, pattern)))
            else:
                rules.append((pattern, _density(table, pattern)))
        table.finish()
    surfaces: list[tuple[str, str, float]] = []
    if root.has("surfaces"):
        table = root.table("surfaces")
        for pattern in table.keys():
            surfaces.append((pattern, *_surface(table, pattern)))
        table.finish()
    sigmas: list[tuple[str, float, str]] = []
    if root.has("mass_uncertainty"):
        table = root.table("mass_uncertainty")
        for pattern in table.keys():
            sigmas.append((pattern, _fraction(table, pattern, "mass uncertainty", 1.0), ""))
        table.finish()
    cogs: list[tuple[str, tuple[float, float, float]]] = []
    if root.has("cog_uncertainty"):
        table = root.table("cog_uncertainty")
        for pattern in table.keys():
            cogs.append((pattern, _cog_sigma(table, pattern)))
        table.finish()
    levels: dict[str, float] = {}
    if root.has("maturity_levels"):
        table = root.table("maturity_levels")
        for level in table.keys():
            levels[level] = _fraction(table, level, "growth allowance", 2.0)
        table.finish()
    growth: list[tuple[str, float, str]] = []
    if root.has("growth_allowance"):
        table = root.table("growth_allowance")
        for pattern in table.keys():
            if table.is_string(pattern):
                level = table.string(pattern)
                if level not in levels:
                    known = ", ".join(levels) or "none defined"
                    raise table.error(
                        pattern,
                        f"unknown maturity level {level!r}; define it in [maturity_levels] "
                        f"(defined: {known})",
                    )
                growth.append((pattern, levels[level], level))
            else:
                growth.append((pattern, _fraction(table, pattern, "growth allowance", 2.0), ""))
        table.finish()
    root.finish(expected=MATERIALS_TABLES)
    if not (rules or surfaces or sigmas or growth or cogs):
        raise ParameterFileError(
            p,
            "materials",
            "no rules: map name patterns to materials ([materials]), areal densities "
            "([surfaces]), mass uncertainties or growth allowances",
        )
    return MaterialMap(
        tuple(rules), str(p), tuple(surfaces), tuple(sigmas), tuple(growth), tuple(cogs)
    )
