"""Assemblies of placed products, written to STEP through OCCT's XCAF document.

A real CAD export is a tree of *products* (parts and sub-assemblies), each modelled once in its
own frame and placed by *instances*, with names and, sometimes, materials. This module writes
such a tree with nothing but OCP: a :class:`Part` holds shapes and an optional material, an
:class:`Assembly` holds placed components, and :func:`write_assembly` creates one product per node
(a node placed twice is one product instanced twice) and writes AP214 in mm. It is what
``cadcog parts cubesat`` exports, and, being build123d-free, it keeps commands that only need
an assembly of primitives (``plan`` on a CubeSat spec) from importing build123d.

Placements are rotations (about axes through the origin, applied in order) then a translation,
in the parent's frame.
"""

from __future__ import annotations

import datetime as dt
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import numpy.typing as npt
from OCP.APIHeaderSection import APIHeaderSection_MakeHeader
from OCP.BRep import BRep_Builder
from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt, gp_Trsf, gp_Vec
from OCP.IFSelect import IFSelect_ReturnStatus
from OCP.Message import Message, Message_Gravity
from OCP.STEPCAFControl import STEPCAFControl_Writer
from OCP.STEPControl import STEPControl_AsIs
from OCP.TCollection import TCollection_ExtendedString, TCollection_HAsciiString
from OCP.TDataStd import TDataStd_Name
from OCP.TDF import TDF_Label
from OCP.TDocStd import TDocStd_Document
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS_Compound, TopoDS_Shape
from OCP.XCAFApp import XCAFApp_Application
from OCP.XCAFDoc import XCAFDoc_DocumentTool

from cadcog.core.errors import CadcogError
from cadcog.core.fileio import silent_write_failure

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class Placement:
    """Rotations about axes through the origin (applied in order), then a translation.

    Examples
    --------
    >>> p = Placement((10.0, 0.0, 0.0), (((0.0, 0.0, 1.0), 90.0),))
    >>> np.round(p.matrix() @ [1.0, 0.0, 0.0, 1.0], 12).tolist()
    [10.0, 1.0, 0.0, 1.0]
    """

    translation_mm: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotations: tuple[tuple[tuple[float, float, float], float], ...] = ()

    def trsf(self) -> gp_Trsf:
        total = gp_Trsf()
        for axis, deg in self.rotations:
            r = gp_Trsf()
            r.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(*axis)), math.radians(deg))
            total = r.Multiplied(total)
        t = gp_Trsf()
        t.SetTranslation(gp_Vec(*self.translation_mm))
        return t.Multiplied(total)

    def location(self) -> TopLoc_Location:
        return TopLoc_Location(self.trsf())

    def matrix(self) -> FloatArray:
        """The placement as a 4 × 4 homogeneous matrix."""
        t = self.trsf()
        m = np.eye(4)
        for i in range(3):
            for j in range(4):
                m[i, j] = t.Value(i + 1, j + 1)
        return m


@dataclass
class Part:
    """A product that is a part: shapes in its own frame, an optional (name, kg/m³) material."""

    name: str
    shapes: list[TopoDS_Shape]
    material: tuple[str, float] | None = None


@dataclass
class Assembly:
    """A product that is an assembly of placed components (an instance name is optional)."""

    name: str
    components: list[tuple[Part | Assembly, Placement, str]] = field(default_factory=list)

    def add(
        self, child: Part | Assembly, placement: Placement | None = None, instance: str = ""
    ) -> None:
        self.components.append((child, placement or Placement(), instance))


def step_timestamp() -> str:
    """STEP header time: ``SOURCE_DATE_EPOCH`` if set (reproducible builds), else the epoch."""
    seconds = int(os.environ.get("SOURCE_DATE_EPOCH", "0"))
    return dt.datetime.fromtimestamp(seconds, tz=dt.UTC).replace(tzinfo=None).isoformat()


def _name(label: TDF_Label, name: str) -> None:
    TDataStd_Name.Set_s(label, TCollection_ExtendedString(name))


def write_assembly(root: Assembly | Part, path: str | Path) -> None:
    """Write ``root`` as a STEP file (AP214, mm), one product per node, instances placed.

    Raises
    ------
    CadcogError
        If OCCT cannot write the file.
    """
    app = XCAFApp_Application.GetApplication_s()
    doc = TDocStd_Document(TCollection_ExtendedString("XmlXCAF"))
    app.InitDocument(doc)
    shapes = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    materials = XCAFDoc_DocumentTool.MaterialTool_s(doc.Main())
    labels: dict[int, TDF_Label] = {}

    def label_of(node: Part | Assembly) -> TDF_Label:
        if id(node) in labels:
            return labels[id(node)]
        if isinstance(node, Part):
            if len(node.shapes) == 1:
                shape = node.shapes[0]
            else:
                builder = BRep_Builder()
                compound = TopoDS_Compound()
                builder.MakeCompound(compound)
                for s in node.shapes:
                    builder.Add(compound, s)
                shape = compound
            label = shapes.AddShape(shape, False)
            _name(label, node.name)
            if node.material is not None:
                name, density = node.material
                mat = materials.AddMaterial(
                    TCollection_HAsciiString(name),
                    TCollection_HAsciiString(""),
                    density,
                    TCollection_HAsciiString("kg/m^3"),
                    TCollection_HAsciiString("POSITIVE_RATIO_MEASURE"),
                )
                materials.SetMaterial(label, mat)
        else:
            label = shapes.NewShape()
            _name(label, node.name)
            for child, placement, instance in node.components:
                component = shapes.AddComponent(label, label_of(child), placement.location())
                if instance:
                    _name(component, instance)
        labels[id(node)] = label
        return label

    label_of(root)
    shapes.UpdateAssemblies()
    for printer in Message.DefaultMessenger_s().Printers():  # no transfer statistics on stdout
        printer.SetTraceLevel(Message_Gravity.Message_Fail)
    writer = STEPCAFControl_Writer()
    writer.SetNameMode(True)
    writer.SetMaterialMode(True)
    header = APIHeaderSection_MakeHeader(writer.Writer().Model())
    if not header.IsDone():
        header = APIHeaderSection_MakeHeader(0)
        header.Apply(writer.Writer().Model())
    header.SetName(TCollection_HAsciiString(root.name))
    header.SetTimeStamp(TCollection_HAsciiString(step_timestamp()))
    header.SetOriginatingSystem(TCollection_HAsciiString("cadcog"))
    if not writer.Transfer(doc, STEPControl_AsIs):
        raise CadcogError(f"{path}: STEP export failed (transfer)")
    if writer.Write(str(path)) != IFSelect_ReturnStatus.IFSelect_RetDone:
        raise CadcogError(f"{path}: STEP export failed ({silent_write_failure()})")


def placed_parts(
    root: Assembly | Part, placement: FloatArray | None = None
) -> Sequence[tuple[Part, FloatArray]]:
    """Every part instance with its global 4 × 4 placement (numpy composition)."""
    m = np.eye(4) if placement is None else placement
    if isinstance(root, Part):
        return [(root, m)]
    out: list[tuple[Part, FloatArray]] = []
    for child, p, _ in root.components:
        out.extend(placed_parts(child, m @ p.matrix()))
    return out
