"""Densities of common spacecraft materials, and material assignment by name pattern.

Densities are nominal room-temperature values (kg/m³) from the sources named per entry: ASM
Aerospace Specification Metals / MatWeb data sheets for metals, IPC-4101 / laminate data sheets
for FR-4, manufacturers' data sheets for plastics. Real parts vary by a few per cent (alloy
temper, resin content, porosity): weigh them and use ``--total-mass-kg`` where it matters.

A materials file (TOML) maps glob patterns of solid or assembly names to a material name from
:data:`LIBRARY` or to a density in kg/m³; the first matching pattern wins::

    [materials]
    "rail*" = "aluminium 6061-T6"
    "battery*" = 2100.0
    "*" = "aluminium 6061-T6"     # a default, if you want one
"""

from __future__ import annotations

import fnmatch
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from cadcog.errors import ParameterFileError
from cadcog.paramfile import TableReader, read_toml


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


@dataclass(frozen=True)
class Assignment:
    """A solid's material: its name (or 'density'), density and the rule that chose it."""

    material: str
    density_kg_m3: float
    rule: str


@dataclass(frozen=True)
class MaterialMap:
    """Ordered (pattern, material-or-density) rules; the first pattern matching a name wins."""

    rules: tuple[tuple[str, str | float], ...]
    source: str = ""

    def assign(self, names: Sequence[str]) -> Assignment | None:
        """Material of a solid known by ``names`` (its own name, then its assemblies')."""
        for pattern, value in self.rules:
            if any(fnmatch.fnmatchcase(n, pattern) for n in names):
                if isinstance(value, str):
                    m = LIBRARY[value]
                    return Assignment(m.name, m.density_kg_m3, pattern)
                return Assignment("density", value, pattern)
        return None

    @classmethod
    def uniform(cls, density_kg_m3: float) -> MaterialMap:
        return cls((("*", density_kg_m3),), "uniform density")


def load_materials(path: str | Path) -> MaterialMap:
    """Read a materials file; unknown material names and bad densities name the key."""
    p = Path(path)
    root = TableReader(read_toml(p), p)
    table = root.table("materials")
    rules: list[tuple[str, str | float]] = []
    for pattern in list(table.keys()):
        if table.is_string(pattern):
            name = table.string(pattern)
            if name not in LIBRARY:
                raise table.error(
                    pattern,
                    f"unknown material {name!r}; known: {', '.join(sorted(LIBRARY))}, "
                    "or give a density in kg/m³",
                )
            rules.append((pattern, name))
        else:
            density = table.number(pattern, positive=True)
            if not 10.0 <= density <= 25_000.0:
                raise table.error(
                    pattern,
                    f"density {density:g} kg/m³ is implausible; expected "
                    "kg/m³ between 10 and 25000 (is it in g/cm³?)",
                )
            rules.append((pattern, density))
    table.finish()
    root.finish()
    if not rules:
        raise ParameterFileError(p, "materials", "no rules: map name patterns to materials")
    return MaterialMap(tuple(rules), str(p))
