"""Triangle meshes of a model's bodies, for pictures (never for mass properties).

Each product is tessellated once, coarsely (a chordal deflection of
:data:`VIEW_DEFLECTION_RELATIVE` of its size), and its triangles are moved to every instance's
placement. Mass properties never come from these meshes: they are exact B-rep integrals.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from OCP.BRep import BRep_Tool
from OCP.BRepMesh import BRepMesh_IncrementalMesh
from OCP.TopAbs import TopAbs_FACE, TopAbs_REVERSED
from OCP.TopExp import TopExp_Explorer
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS, TopoDS_Shape

from cadcog.cad.overlaps import bounding_boxes
from cadcog.cad.stepmodel import StepBody

FloatArray = npt.NDArray[np.float64]

#: Chordal deflection of view meshes, relative to each product's bounding-box diagonal.
VIEW_DEFLECTION_RELATIVE = 0.01

#: Angular deflection of view meshes (radians).
VIEW_ANGULAR_DEFLECTION_RAD = 0.5


@dataclass(frozen=True)
class BodyMesh:
    """A body's triangles at its global placement.

    Attributes
    ----------
    path : str
    kind : "solid" or "surface"
    vertices_mm : ndarray, shape (n, 3)
    triangles : ndarray of int, shape (m, 3)
    """

    path: str
    kind: str
    vertices_mm: FloatArray
    triangles: npt.NDArray[np.int64]


def shape_mesh(shape: TopoDS_Shape) -> tuple[FloatArray, npt.NDArray[np.int64]]:
    """Vertices and outward-oriented triangles of a shape, in its own frame."""
    lo, hi = bounding_boxes([shape])
    size = float(np.linalg.norm(hi[0] - lo[0])) or 1.0
    BRepMesh_IncrementalMesh(
        shape, VIEW_DEFLECTION_RELATIVE * size, False, VIEW_ANGULAR_DEFLECTION_RAD, False
    ).Perform()
    vertices: list[FloatArray] = []
    triangles: list[npt.NDArray[np.int64]] = []
    offset = 0
    explorer = TopExp_Explorer(shape, TopAbs_FACE)
    while explorer.More():
        face = TopoDS.Face(explorer.Current())
        loc = TopLoc_Location()
        tri = BRep_Tool.Triangulation_s(face, loc)
        if tri is not None:
            trsf = loc.Transformation()
            pts = []
            for i in range(1, tri.NbNodes() + 1):
                p = tri.Node(i).Transformed(trsf)
                pts.append((p.X(), p.Y(), p.Z()))
            idx = np.array([tri.Triangle(i).Get() for i in range(1, tri.NbTriangles() + 1)]) - 1
            if face.Orientation() == TopAbs_REVERSED:
                idx = idx[:, ::-1]
            vertices.append(np.array(pts, dtype=float))
            triangles.append(idx + offset)
            offset += len(pts)
        explorer.Next()
    if not vertices:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    return np.vstack(vertices), np.vstack(triangles).astype(np.int64)


def body_meshes(bodies: Sequence[StepBody], scale: float = 1.0) -> list[BodyMesh]:
    """Meshes of ``bodies`` at their placements (one tessellation per product), times ``scale``."""
    cache: dict[str, tuple[FloatArray, npt.NDArray[np.int64]]] = {}
    out = []
    for body in bodies:
        rigid = body.rigid
        if rigid is None:
            v, t = shape_mesh(body.shape)
        else:
            if body.product_key not in cache:
                cache[body.product_key] = shape_mesh(body.local_shape)
            local, t = cache[body.product_key]
            r, shift = rigid
            v = local @ r.T + shift
        out.append(BodyMesh(body.path, body.kind, v * scale, t))
    return out
