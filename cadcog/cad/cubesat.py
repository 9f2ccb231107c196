"""A parametric CubeSat (structure, rails, boards, battery pack, payload) in build123d.

Frame: origin at the geometric centre of the envelope, z along the rails (CubeSat convention).
The structure is four square rails at the corners, four side panels between them and two end
plates; components are boxes or z-axis cylinders, each a named solid of one material. Validation
rejects components that overlap each other or the structure, or leave the envelope.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from pathlib import Path

import build123d as bd
import numpy as np

from cadcog.errors import ParameterFileError
from cadcog.materials import LIBRARY
from cadcog.paramfile import TableReader, read_toml

#: Rail length per unit (CDS: 1U 113.5 mm, 3U 340.5 mm).
RAIL_PER_UNIT_MM = 113.5


@dataclass(frozen=True)
class Component:
    name: str
    material: str
    center_mm: tuple[float, float, float]
    size_mm: tuple[float, float, float] | None = None  # a box
    cylinder: tuple[float, float] | None = None  # (diameter, length) along z

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        c = np.asarray(self.center_mm)
        if self.size_mm is not None:
            h = 0.5 * np.asarray(self.size_mm)
        else:
            assert self.cylinder is not None
            d, length = self.cylinder
            h = np.array([d / 2, d / 2, length / 2])
        return c - h, c + h


@dataclass(frozen=True)
class CubeSatSpec:
    name: str
    units: int
    width_mm: float
    rail_mm: float
    panel_mm: float
    structure_material: str
    components: tuple[Component, ...]
    source: Path

    @property
    def length_mm(self) -> float:
        return self.units * RAIL_PER_UNIT_MM

    @property
    def inner_half_mm(self) -> np.ndarray:
        """Half-extent of the free volume: inside the rails' square and the end plates."""
        w = 0.5 * self.width_mm - self.rail_mm
        return np.array([w, w, 0.5 * self.length_mm - self.panel_mm])


def _material(t: TableReader, key: str) -> str:
    name = t.string(key)
    if name not in LIBRARY:
        raise t.error(key, f"unknown material {name!r}; known: {', '.join(sorted(LIBRARY))}")
    return name


def load_cubesat(path: str | Path) -> CubeSatSpec:
    """Read and validate a CubeSat spec file."""
    p = Path(path)
    root = TableReader(read_toml(p), p)
    name = root.string("name")
    units = root.integer("units", minimum=1)
    st = root.table("structure")
    width = st.number("width_mm", positive=True)
    rail = st.number("rail_mm", positive=True)
    panel = st.number("panel_mm", positive=True)
    smat = _material(st, "material")
    st.finish()
    if not rail < width / 2 or not panel < rail:
        raise st.error("rail_mm", "need panel_mm < rail_mm < width_mm / 2")
    comps = []
    tables = root.tables("components")
    for t in tables:
        cname = t.string("name")
        mat = _material(t, "material")
        c = t.vector("center_mm")
        center = (c[0], c[1], c[2])
        if t.has("size_mm"):
            s = t.vector("size_mm", positive=True)
            comps.append(Component(cname, mat, center, size_mm=(s[0], s[1], s[2])))
        else:
            d = t.number("cylinder_diameter_mm", positive=True)
            length = t.number("cylinder_length_mm", positive=True)
            comps.append(Component(cname, mat, center, cylinder=(d, length)))
        t.finish()
    root.finish()
    spec = CubeSatSpec(name, units, width, rail, panel, smat, tuple(comps), p)
    inner = spec.inner_half_mm
    for t, comp in zip(tables, comps, strict=True):
        lo, hi = comp.bounds()
        if np.any(lo < -inner) or np.any(hi > inner):
            lim = ", ".join(f"±{v:g}" for v in inner)
            raise t.error(
                "center_mm",
                f"{comp.name} leaves the free volume inside the rails and end plates "
                f"(x, y, z within {lim} mm)",
            )
    for (t1, a), (_, b) in combinations(zip(tables, comps, strict=True), 2):
        (alo, ahi), (blo, bhi) = a.bounds(), b.bounds()
        if np.all(np.minimum(ahi, bhi) - np.maximum(alo, blo) > 1e-9):
            raise t1.error("center_mm", f"components {a.name} and {b.name} overlap")
    names = [c.name for c in comps]
    if len(set(names)) != len(names):
        raise ParameterFileError(p, "components", "component names must be unique")
    return spec


def _box(name: str, lo: np.ndarray, hi: np.ndarray) -> bd.Solid:
    dx, dy, dz = (float(v) for v in hi - lo)
    s = bd.Solid.make_box(dx, dy, dz, bd.Plane(origin=tuple(lo)))
    s.label = name
    return s


def build_cubesat(spec: CubeSatSpec) -> tuple[bd.Compound, dict[str, str]]:
    """The CubeSat as a labelled assembly, and each solid's material."""
    w = 0.5 * spec.width_mm
    r = spec.rail_mm
    t = spec.panel_mm
    h = 0.5 * spec.length_mm
    materials: dict[str, str] = {}
    structure = []
    for i, (sx, sy) in enumerate([(1, 1), (-1, 1), (-1, -1), (1, -1)]):
        rail_lo = np.array([min(sx * w, sx * (w - r)), min(sy * w, sy * (w - r)), -h])
        rail_hi = np.array([max(sx * w, sx * (w - r)), max(sy * w, sy * (w - r)), h])
        structure.append(_box(f"rail_{i + 1}", rail_lo, rail_hi))
    inner = w - r
    # Side panels span between the rails; end plates fill the square inside the rails.
    for name, plo, phi in [
        ("panel_+x", [w - t, -inner, -h], [w, inner, h]),
        ("panel_-x", [-w, -inner, -h], [-w + t, inner, h]),
        ("panel_+y", [-inner, w - t, -h], [inner, w, h]),
        ("panel_-y", [-inner, -w, -h], [inner, -w + t, h]),
        ("end_plate_+z", [-inner, -inner, h - t], [inner, inner, h]),
        ("end_plate_-z", [-inner, -inner, -h], [inner, inner, -h + t]),
    ]:
        structure.append(_box(name, np.array(plo, float), np.array(phi, float)))
    for s in structure:
        materials[s.label] = spec.structure_material
    parts = []
    for c in spec.components:
        if c.size_mm is not None:
            lo, hi = c.bounds()
            solid = _box(c.name, lo, hi)
        else:
            assert c.cylinder is not None
            d, length = c.cylinder
            base = np.asarray(c.center_mm) - [0, 0, length / 2]
            solid = bd.Solid.make_cylinder(d / 2, length, bd.Plane(origin=tuple(base)))
            solid.label = c.name
        parts.append(solid)
        materials[c.name] = c.material
    asm = bd.Compound(
        children=[
            bd.Compound(children=structure, label="structure"),
            bd.Compound(children=parts, label="payload_and_bus"),
        ],
        label=spec.name,
    )
    return asm, materials


def materials_toml(materials: dict[str, str]) -> str:
    """A materials file for :func:`cadcog.materials.load_materials`, one rule per solid."""
    lines = ["# materials of the example CubeSat, written by cadcog parts cubesat", "[materials]"]
    lines += [f'"{name}" = "{mat}"' for name, mat in materials.items()]
    return "\n".join(lines) + "\n"
