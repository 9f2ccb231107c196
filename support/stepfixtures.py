"""STEP files for tests, written through OCCT's XCAF document so that every feature of real
exports can be reproduced on purpose: products instanced many times, placements (rotation and
translation) at every level, instance names, materials with densities, surface bodies, files in
metres.

Alongside each file the builder keeps an *independent* expectation: every solid's placement is
composed with numpy (4 × 4 matrices), and boxes get closed-form mass properties, so tests compare
the reader's OCCT pipeline with arithmetic that shares none of its code.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_Transform
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder
from OCP.gp import gp_Ax1, gp_Dir, gp_Pln, gp_Pnt, gp_Trsf, gp_Vec
from OCP.STEPCAFControl import STEPCAFControl_Writer
from OCP.STEPControl import STEPControl_AsIs
from OCP.TCollection import TCollection_ExtendedString, TCollection_HAsciiString
from OCP.TDataStd import TDataStd_Name
from OCP.TDF import TDF_Label
from OCP.TDocStd import TDocStd_Document
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS_Shape
from OCP.XCAFApp import XCAFApp_Application
from OCP.XCAFDoc import XCAFDoc_DocumentTool

from cadcog.mass.properties import MassProperties, box_properties


def rotation(axis: tuple[float, float, float], deg: float) -> np.ndarray:
    """Rotation matrix about ``axis`` by ``deg`` (Rodrigues), for the numpy expectation."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    t = math.radians(deg)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(t) * k + (1 - math.cos(t)) * k @ k


@dataclass(frozen=True)
class Place:
    """A rigid placement: rotation about ``axis`` by ``deg``, then translation ``t_mm``."""

    t_mm: tuple[float, float, float] = (0.0, 0.0, 0.0)
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    deg: float = 0.0

    def matrix(self) -> np.ndarray:
        m = np.eye(4)
        m[:3, :3] = rotation(self.axis, self.deg)
        m[:3, 3] = self.t_mm
        return m

    def location(self) -> TopLoc_Location:
        r = gp_Trsf()
        r.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(*self.axis)), math.radians(self.deg))
        t = gp_Trsf()
        t.SetTranslation(gp_Vec(*self.t_mm))
        return TopLoc_Location(t.Multiplied(r))


@dataclass
class Part:
    """A product that is a part: one or more boxes (closed form) or any shapes."""

    name: str
    boxes: list[tuple[tuple[float, float, float], tuple[float, float, float]]]  # size, corner
    density_kg_m3: float | None = None  # written as an XCAF material when set
    material: str = "test material"
    shapes: list[TopoDS_Shape] = field(default_factory=list)  # extra non-box shapes


@dataclass
class Assembly:
    """A product that is an assembly of placed components (instance name optional)."""

    name: str
    components: list[tuple[Part | Assembly, Place, str]] = field(default_factory=list)

    def add(self, child: Part | Assembly, place: Place = Place(), instance: str = "") -> None:
        self.components.append((child, place, instance))


def box_shape(size: tuple[float, float, float], corner: tuple[float, float, float]) -> TopoDS_Shape:
    return BRepPrimAPI_MakeBox(gp_Pnt(*corner), *size).Shape()


def _name(label: TDF_Label, name: str) -> None:
    TDataStd_Name.Set_s(label, TCollection_ExtendedString(name))


def write_step(root: Assembly | Part, path: Path, *, metres: bool = False) -> Path:
    """Write ``root`` as a STEP file (AP214) with true instancing and materials.

    ``metres``: every length is written in metres and the file declares metres (as Onshape
    does); the geometry is the same.
    """
    app = XCAFApp_Application.GetApplication_s()
    doc = TDocStd_Document(TCollection_ExtendedString("XmlXCAF"))
    app.InitDocument(doc)
    shapes = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    materials = XCAFDoc_DocumentTool.MaterialTool_s(doc.Main())
    scale = gp_Trsf()
    scale.SetScaleFactor(1e-3 if metres else 1.0)
    labels: dict[int, TDF_Label] = {}

    def scaled(shape: TopoDS_Shape) -> TopoDS_Shape:
        if not metres:
            return shape
        return BRepBuilderAPI_Transform(shape, scale, True).Shape()

    def label_of(node: Part | Assembly) -> TDF_Label:
        if id(node) in labels:
            return labels[id(node)]
        if isinstance(node, Part):
            from OCP.BRep import BRep_Builder
            from OCP.TopoDS import TopoDS_Compound

            solids = [box_shape(s, c) for s, c in node.boxes] + list(node.shapes)
            if len(solids) == 1:
                shape = scaled(solids[0])
            else:
                b = BRep_Builder()
                comp = TopoDS_Compound()
                b.MakeCompound(comp)
                for s in solids:
                    b.Add(comp, scaled(s))
                shape = comp
            label = shapes.AddShape(shape, False)
            _name(label, node.name)
            if node.density_kg_m3 is not None:
                mat = materials.AddMaterial(
                    TCollection_HAsciiString(node.material),
                    TCollection_HAsciiString("test"),
                    node.density_kg_m3,
                    TCollection_HAsciiString("kg/m^3"),
                    TCollection_HAsciiString("POSITIVE_RATIO_MEASURE"),
                )
                materials.SetMaterial(label, mat)
        else:
            label = shapes.NewShape()
            _name(label, node.name)
            for child, place, instance in node.components:
                loc = place.location()
                if metres:
                    t = loc.Transformation()
                    v = t.TranslationPart()
                    t.SetTranslationPart(gp_Vec(v.X() * 1e-3, v.Y() * 1e-3, v.Z() * 1e-3))
                    loc = TopLoc_Location(t)
                comp = shapes.AddComponent(label, label_of(child), loc)
                if instance:
                    _name(comp, instance)
        labels[id(node)] = label
        return label

    label_of(root)
    shapes.UpdateAssemblies()
    writer = STEPCAFControl_Writer()
    writer.SetMaterialMode(True)
    writer.Transfer(doc, STEPControl_AsIs)
    writer.Write(str(path))
    if metres:
        text = path.read_text(encoding="utf-8")
        text = re.sub(r"SI_UNIT\(\.MILLI\.,\.METRE\.\)", "SI_UNIT($,.METRE.)", text)
        path.write_text(text, encoding="utf-8")
    return path


def expected_boxes(
    root: Assembly | Part, placement: np.ndarray | None = None, default_density: float = 1000.0
) -> list[MassProperties]:
    """Closed-form mass properties of every box of ``root`` at its composed placement (numpy).

    Densities: the part's ``density_kg_m3`` or ``default_density`` (kg/m³).
    """
    m = np.eye(4) if placement is None else placement
    out: list[MassProperties] = []
    if isinstance(root, Part):
        rho = (root.density_kg_m3 or default_density) * 1e-9
        for size, corner in root.boxes:
            s = np.asarray(size, dtype=float)
            local = box_properties(s, np.asarray(corner) + s / 2, mass_kg=rho * float(np.prod(s)))
            r, t = m[:3, :3], m[:3, 3]
            out.append(
                MassProperties(
                    local.mass_kg,
                    r @ local.cog_mm + t,
                    r @ local.inertia_kg_mm2 @ r.T,
                    local.volume_mm3,
                )
            )
        return out
    for child, place, _ in root.components:
        out.extend(expected_boxes(child, m @ place.matrix(), default_density))
    return out


# --- ready-made models ----------------------------------------------------------------------
def nested_three_levels() -> Assembly:
    """sat → board (rotated) → bracket sub-assembly ×2 (rotated) → plates ×2 (rotated);
    the bracket product and the plate product are each instanced several times."""
    plate = Part("plate", [((10.0, 5.0, 2.0), (0.0, 0.0, 0.0))])
    bracket = Assembly("bracket")
    bracket.add(plate, Place((20.0, 0.0, 0.0), (0, 0, 1), 90.0))
    bracket.add(plate, Place((0.0, 30.0, 0.0), (1, 0, 0), 30.0))
    board = Assembly("board")
    board.add(bracket, Place((100.0, 0.0, 0.0), (0, 1, 0), 45.0))
    board.add(bracket, Place((0.0, 100.0, 5.0), (0, 0, 1), 180.0))
    base = Part("base", [((60.0, 40.0, 3.0), (-30.0, -20.0, -3.0))])
    sat = Assembly("sat")
    sat.add(board, Place((0.0, 0.0, 50.0), (1, 1, 0), 20.0))
    sat.add(base, Place((5.0, -5.0, 0.0), (0, 0, 1), 10.0))
    return sat


def kicad_like_board(n_components: int = 20, pin_depth_mm: float = 0.5) -> Assembly:
    """A board with components as KiCad exports them: every component product is named
    ``COMPOUND``, holds a body and two pins, and is placed rotated (0°, 90°, 45°, ...) on the
    board; the pins sink ``pin_depth_mm`` into the board (a small real overlap)."""
    board = Part("PCB", [((100.0, 80.0, 1.6), (0.0, 0.0, 0.0))], density_kg_m3=1850.0)
    comp = Part(
        "COMPOUND",
        [
            ((4.0, 2.0, 1.0), (-2.0, -1.0, 0.5)),
            ((0.6, 0.6, 0.5 + pin_depth_mm), (-1.8, -0.3, -pin_depth_mm)),
            ((0.6, 0.6, 0.5 + pin_depth_mm), (1.2, -0.3, -pin_depth_mm)),
        ],
        density_kg_m3=3000.0,
    )
    top = Assembly("board_top")
    top.add(board)
    angles = (0.0, 90.0, 45.0, 180.0, 30.0)
    for k in range(n_components):
        x = 8.0 + (k % 8) * 11.0
        y = 8.0 + (k // 8) * 12.0
        top.add(comp, Place((x, y, 1.6), (0, 0, 1), angles[k % len(angles)]))
    return top


def square_face(size_mm: float, z_mm: float) -> TopoDS_Shape:
    """A square sheet (no volume) of side ``size_mm`` at height ``z_mm``, centred on the z axis."""
    h = size_mm / 2
    pln = gp_Pln(gp_Pnt(0, 0, z_mm), gp_Dir(0, 0, 1))
    return BRepBuilderAPI_MakeFace(pln, -h, h, -h, h).Face()


def cylinder(radius_mm: float, height_mm: float) -> TopoDS_Shape:
    return BRepPrimAPI_MakeCylinder(radius_mm, height_mm).Shape()
