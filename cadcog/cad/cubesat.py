"""A parametric CubeSat (structure, rails, boards, battery pack, payload) as a STEP assembly.

Frame: origin at the geometric centre of the envelope, z along the rails (CubeSat convention).
The structure is four square rails at the corners, four side panels between them and two end
plates; components are boxes or z-axis cylinders, each a named solid of one material. Validation
rejects components that overlap each other or the structure, or leave the envelope.

Deployables (``[[deployables]]``: solar arrays, antennas) are flat panels stowed against a side
face, outside it (the CDS allows 6.5 mm beyond the rails there), hinged along their edge at one
end; :func:`configurations_toml` writes the configurations file that deploys them
(:mod:`cadcog.spacecraft.configurations`): each turned about its hinge so that it stands out
from its face.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from pathlib import Path

import numpy as np
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder
from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
from OCP.TopoDS import TopoDS_Shape

from cadcog.cad.assembly import Assembly, Part, Placement
from cadcog.core.errors import ParameterFileError, quote
from cadcog.core.paramfile import TableReader, read_toml, toml_string
from cadcog.core.tolerances import MIN_SOLID_DIMENSION_MM
from cadcog.mass.materials import LIBRARY, MaterialMap

#: Rail length per unit (CDS: 1U 113.5 mm, 3U 340.5 mm).
RAIL_PER_UNIT_MM = 113.5


@dataclass(frozen=True)
class Component:
    name: str
    material: str
    center_mm: tuple[float, float, float]
    size_mm: tuple[float, float, float] | None = None  # a box
    cylinder: tuple[float, float] | None = None  # (diameter, length) along z
    mass_uncertainty: float | None = None  # 1-σ relative, for the mass budget

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        c = np.asarray(self.center_mm)
        if self.size_mm is not None:
            h = 0.5 * np.asarray(self.size_mm)
        else:
            assert self.cylinder is not None
            d, length = self.cylinder
            h = np.array([d / 2, d / 2, length / 2])
        return c - h, c + h


#: The most a stowed deployable may stand out of a side face (CDS Rev. 14.1: 6.5 mm).
MAX_PROTRUSION_MM = 6.5

#: The side faces a deployable may be stowed on: (axis, sign).
SIDE_FACES = {"+x": (0, 1.0), "-x": (0, -1.0), "+y": (1, 1.0), "-y": (1, -1.0)}


@dataclass(frozen=True)
class Deployable:
    """A flat panel stowed against a side face, hinged at one end (``hinge`` ``"-z"`` or
    ``"+z"``), deployed by ``angle_deg`` about its hinge so that it stands out of the face."""

    name: str
    material: str
    face: str
    thickness_mm: float
    width_mm: float
    length_mm: float
    hinge: str = "-z"
    angle_deg: float = 90.0
    mass_uncertainty: float | None = None

    def normal(self) -> np.ndarray:
        axis, sign = SIDE_FACES[self.face]
        n = np.zeros(3)
        n[axis] = sign
        return n

    def hinge_axis(self, half_width_mm: float) -> tuple[np.ndarray, np.ndarray]:
        """A point on the hinge line and its direction: the rotation by ``angle_deg`` about it
        turns the panel's length (from the hinge) towards the face's outward normal."""
        n = self.normal()
        end = -1.0 if self.hinge == "-z" else 1.0
        point = half_width_mm * n + np.array([0.0, 0.0, end * self.length_mm / 2])
        along = np.array([0.0, 0.0, -end])  # from the hinge along the panel
        return point, np.cross(along, n)


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
    structure_mass_uncertainty: float | None = None
    deployables: tuple[Deployable, ...] = ()

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


def _uncertainty(t: TableReader) -> float | None:
    if not t.has("mass_uncertainty"):
        return None
    value = t.number("mass_uncertainty", nonnegative=True)
    if value > 1.0:
        raise t.error("mass_uncertainty", f"expected a fraction 0 to 1 (5 % = 0.05), got {value:g}")
    return value


def load_cubesat(path: str | Path) -> CubeSatSpec:
    """Read and validate a CubeSat spec file."""
    p = Path(path)
    root = TableReader(read_toml(p), p)
    name = root.identifier("name")  # names the STEP and materials files `parts cubesat` writes
    units = root.integer("units", minimum=1)
    st = root.table("structure")
    width = st.number("width_mm", positive=True, at_least=MIN_SOLID_DIMENSION_MM)
    rail = st.number("rail_mm", positive=True, at_least=MIN_SOLID_DIMENSION_MM)
    panel = st.number("panel_mm", positive=True, at_least=MIN_SOLID_DIMENSION_MM)
    smat = _material(st, "material")
    s_sigma = _uncertainty(st)
    st.finish()
    if not rail < width / 2 or not panel < rail:
        raise st.error("rail_mm", "need panel_mm < rail_mm < width_mm / 2")
    comps = []
    tables = root.tables("components")
    for t in tables:
        cname = t.identifier("name")
        mat = _material(t, "material")
        c = t.vector("center_mm")
        center = (c[0], c[1], c[2])
        sigma = _uncertainty(t)
        if t.has("size_mm"):
            s = t.vector("size_mm", positive=True, at_least=MIN_SOLID_DIMENSION_MM)
            comps.append(Component(cname, mat, center, (s[0], s[1], s[2]), None, sigma))
        else:
            d = t.number("cylinder_diameter_mm", positive=True, at_least=MIN_SOLID_DIMENSION_MM)
            length = t.number("cylinder_length_mm", positive=True, at_least=MIN_SOLID_DIMENSION_MM)
            comps.append(Component(cname, mat, center, None, (d, length), sigma))
        t.finish()
    deploys: list[Deployable] = []
    for t in root.tables("deployables") if root.has("deployables") else []:
        d_size = t.vector("size_mm", positive=True, at_least=MIN_SOLID_DIMENSION_MM)
        deploy = Deployable(
            t.identifier("name"),
            _material(t, "material"),
            t.string("face", choices=list(SIDE_FACES)),
            d_size[0],
            d_size[1],
            d_size[2],
            t.string("hinge", choices=["-z", "+z"], default="-z"),
            t.number("angle_deg", default=90.0),
            _uncertainty(t),
        )
        if deploy.thickness_mm > MAX_PROTRUSION_MM:
            raise t.error(
                "size_mm",
                f"a stowed panel {deploy.thickness_mm:g} mm thick stands out more than the CDS's "
                f"{MAX_PROTRUSION_MM:g} mm (size_mm = [thickness, width, length])",
            )
        if deploy.width_mm > width or deploy.length_mm > units * RAIL_PER_UNIT_MM:
            raise t.error("size_mm", "the panel is wider or longer than its face")
        if any(d.face == deploy.face for d in deploys):
            raise t.error("face", f"{deploy.face} already carries a deployable")
        t.finish()
        deploys.append(deploy)
    root.finish()
    spec = CubeSatSpec(
        name, units, width, rail, panel, smat, tuple(comps), p, s_sigma, tuple(deploys)
    )
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
    names = [c.name for c in comps] + [d.name for d in deploys]
    twice = next((n for i, n in enumerate(names) if n in names[:i]), None)
    if twice is not None:
        at = [i for i, n in enumerate(names) if n == twice][:2]
        raise ParameterFileError(
            p,
            f"components[{at[1]}].name",
            f"{quote(twice)} is also the name of components[{at[0]}]; component names must be "
            "unique (they name the STEP products and the materials rules)",
        )
    return spec


def _centred_box(size: tuple[float, float, float]) -> TopoDS_Shape:
    """A box centred on the origin."""
    sx, sy, sz = size
    return BRepPrimAPI_MakeBox(gp_Pnt(-sx / 2, -sy / 2, -sz / 2), sx, sy, sz).Shape()


def _z_cylinder(diameter_mm: float, length_mm: float) -> TopoDS_Shape:
    """A cylinder along z centred on the origin."""
    base = gp_Ax2(gp_Pnt(0, 0, -length_mm / 2), gp_Dir(0, 0, 1))
    return BRepPrimAPI_MakeCylinder(base, diameter_mm / 2, length_mm).Shape()


def _turn(
    deg: float, axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
) -> tuple[tuple[tuple[float, float, float], float], ...]:
    return ((axis, deg),) if deg else ()


def build_cubesat(spec: CubeSatSpec) -> tuple[Assembly, dict[str, str]]:
    """The CubeSat as a nested, instanced assembly, and each solid's material.

    Like a real export, products are modelled once and placed many times: one rail placed four
    times (turned 90° each), one side panel four times, one end plate twice (turned over for
    −z); components are modelled about their own centre and placed inside a
    ``payload_and_bus`` sub-assembly, which is itself placed at the stack's mid-height. The
    geometry, and so the mass properties, are those of the spec. Write it with
    :func:`cadcog.cad.assembly.write_assembly`.
    """
    w = 0.5 * spec.width_mm
    r = spec.rail_mm
    t = spec.panel_mm
    h = 0.5 * spec.length_mm
    inner = w - r
    materials: dict[str, str] = {}
    structure = Assembly("structure")
    rail = Part("rail", [_centred_box((r, r, 2 * h))])
    for i, (sx, sy) in enumerate([(1, 1), (-1, 1), (-1, -1), (1, -1)]):
        at = (sx * (w - r / 2), sy * (w - r / 2), 0.0)
        structure.add(rail, Placement(at, _turn(90.0 * i)), f"rail_{i + 1}")
    # Side panels span between the rails; end plates fill the square inside the rails.
    panel = Part("panel", [_centred_box((t, 2 * inner, 2 * h))])
    for name, at, turn in [
        ("panel_+x", (w - t / 2, 0.0, 0.0), 0.0),
        ("panel_+y", (0.0, w - t / 2, 0.0), 90.0),
        ("panel_-x", (-(w - t / 2), 0.0, 0.0), 180.0),
        ("panel_-y", (0.0, -(w - t / 2), 0.0), 270.0),
    ]:
        structure.add(panel, Placement(at, _turn(turn)), name)
    plate = Part("end_plate", [_centred_box((2 * inner, 2 * inner, t))])
    structure.add(plate, Placement((0.0, 0.0, h - t / 2)), "end_plate_+z")
    structure.add(
        plate, Placement((0.0, 0.0, -(h - t / 2)), _turn(180.0, (1.0, 0.0, 0.0))), "end_plate_-z"
    )
    for _, _, name in structure.components:
        materials[name] = spec.structure_material
    mid_z = 0.0
    if spec.components:
        low = min(c.bounds()[0][2] for c in spec.components)
        high = max(c.bounds()[1][2] for c in spec.components)
        mid_z = 0.5 * (low + high)
    bus = Assembly("payload_and_bus")
    for c in spec.components:
        local = np.asarray(c.center_mm) - [0.0, 0.0, mid_z]
        if c.size_mm is not None:
            shape = _centred_box(c.size_mm)
        else:
            assert c.cylinder is not None
            shape = _z_cylinder(*c.cylinder)
        at = (float(local[0]), float(local[1]), float(local[2]))
        bus.add(Part(c.name, [shape]), Placement(at), c.name)
        materials[c.name] = c.material
    top = Assembly(spec.name)
    top.add(structure, Placement(), "structure")
    top.add(bus, Placement((0.0, 0.0, mid_z)), "payload_and_bus")
    if spec.deployables:
        arrays = Assembly("deployables")
        for d in spec.deployables:
            shape = _centred_box((d.thickness_mm, d.width_mm, d.length_mm))
            centre = d.normal() * (w + d.thickness_mm / 2)
            turn = 90.0 if SIDE_FACES[d.face][0] == 1 else 0.0  # thickness along the normal
            arrays.add(
                Part(d.name, [shape]),
                Placement((float(centre[0]), float(centre[1]), float(centre[2])), _turn(turn)),
                d.name,
            )
            materials[d.name] = d.material
        top.add(arrays, Placement(), "deployables")
    return top, materials


def configurations_toml(spec: CubeSatSpec) -> str:
    """The configurations file of a CubeSat with deployables: ``stowed`` (as built) and
    ``deployed`` (each panel turned about its hinge), for ``massprops --configurations``,
    ``check`` and ``balance``."""
    lines = [
        f"# configurations of {spec.name}, written by cadcog parts cubesat",
        "[[configurations]]",
        'name = "stowed"',
        "",
        "[[configurations]]",
        'name = "deployed"',
    ]
    for d in spec.deployables:
        point, direction = d.hinge_axis(0.5 * spec.width_mm)
        lines += [
            "",
            "[[configurations.moves]]",
            f"parts = [{toml_string(d.name)}]",
            f"axis_point_mm = [{', '.join(f'{v:.6g}' for v in point)}]",
            f"axis_direction = [{', '.join(f'{v:.6g}' for v in direction)}]",
            f"angle_deg = {d.angle_deg:.6g}",
        ]
    return "\n".join(lines) + "\n"


def material_map(spec: CubeSatSpec, materials: dict[str, str]) -> MaterialMap:
    """The materials of a built CubeSat: one rule per solid, and the spec's mass uncertainties
    (the structure as one item, each component its own)."""
    sigmas: list[tuple[str, float, str]] = []
    if spec.structure_mass_uncertainty is not None:
        sigmas.append(("structure", spec.structure_mass_uncertainty, ""))
    sigmas += [(c.name, c.mass_uncertainty, "") for c in spec.components if c.mass_uncertainty]
    sigmas += [(d.name, d.mass_uncertainty, "") for d in spec.deployables if d.mass_uncertainty]
    return MaterialMap(
        tuple(materials.items()), f"cubesat spec {spec.source}", uncertainty_rules=tuple(sigmas)
    )


def materials_toml(spec: CubeSatSpec, materials: dict[str, str]) -> str:
    """:func:`material_map` as a materials file for :func:`cadcog.mass.materials.load_materials`."""
    m = material_map(spec, materials)
    lines = ["# materials of the example CubeSat, written by cadcog parts cubesat", "[materials]"]
    lines += [f"{toml_string(name)} = {toml_string(str(mat))}" for name, mat in m.rules]
    if m.uncertainty_rules:
        lines += ["", "[mass_uncertainty]   # 1-σ relative; an assembly's bodies vary together"]
        lines += [f"{toml_string(name)} = {sigma!r}" for name, sigma, _ in m.uncertainty_rules]
    return "\n".join(lines) + "\n"
