"""Suspension points on the model itself: a grid on a face of the bounding box, cast onto the
solids along the face's inward normal (``cadcog setup init``).

A point of the bounding box is usually in the air: a board's face is recessed behind its
connectors, a structure's side is mostly rail and cut-out. The wire must leave the model along
the bolt axis with nothing in its way, so each grid point is moved along the face's inward
normal to the first solid it meets (OCCT's exact line/face intersection, no tessellation);
a grid point whose ray meets no solid, or meets it deeper than ``max_depth_mm``, is dropped.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from OCP.BRep import BRep_Builder
from OCP.gp import gp_Dir, gp_Lin, gp_Pnt
from OCP.IntCurvesFace import IntCurvesFace_ShapeIntersector
from OCP.TopoDS import TopoDS_Compound, TopoDS_Shape

from cadcog.rig.geometry import FACES

FloatArray = npt.NDArray[np.float64]

#: OCCT's tolerance for the line/face intersection (file mm).
_INTERSECT_TOLERANCE_MM = 1e-7


@dataclass(frozen=True)
class SurfacePoint:
    """A grid point of a box face moved onto the model.

    Attributes
    ----------
    face : str
        The box face (``"+x"`` ...): the point's bolt axis is its outward normal.
    position_mm : ndarray, shape (3,)
        Where the ray from the box face first meets a solid (mm).
    depth_mm : float
        How far inside the box face that is (mm, >= 0).
    """

    face: str
    position_mm: FloatArray
    depth_mm: float


def _compound(shapes: Sequence[TopoDS_Shape]) -> TopoDS_Compound:
    comp = TopoDS_Compound()
    builder = BRep_Builder()
    builder.MakeCompound(comp)
    for s in shapes:
        builder.Add(comp, s)
    return comp


def project_grid(
    shapes: Sequence[TopoDS_Shape],
    face: str,
    grid_mm: npt.ArrayLike,
    bbox_lo_mm: npt.ArrayLike,
    bbox_hi_mm: npt.ArrayLike,
    *,
    scale_to_mm: float = 1.0,
    max_depth_mm: float | None = None,
) -> list[SurfacePoint]:
    """Cast grid points of a box face onto the solids, along the face's inward normal.

    Parameters
    ----------
    shapes : sequence of TopoDS_Shape
        The model's solids at their global placement, in the file's mm.
    face : str
        The box face the grid lies on.
    grid_mm : array_like, shape (m, 3) or (m, k, 3)
        The grid points (mm, on the face's plane); with ``k`` alternatives each (rows across a
        thin extent), the alternative that meets a solid nearest the box face is kept (the
        first of equals): a board's edge, not a part behind it.
    bbox_lo_mm, bbox_hi_mm : array_like, shape (3,)
        The model's bounding box (mm).
    scale_to_mm : float
        The model's length scale (a ``--units`` override): file mm × scale = mm.
    max_depth_mm : float, optional
        Drop points deeper than this inside the face (default: half the box along the axis).

    Returns
    -------
    list of SurfacePoint
        One per grid point whose ray (one of its alternatives') meets a solid within the
        depth, in grid order.
    """
    axis, sign = FACES[face]
    lo = np.asarray(bbox_lo_mm, dtype=float)
    hi = np.asarray(bbox_hi_mm, dtype=float)
    span = float(hi[axis] - lo[axis])
    depth_max = 0.5 * span if max_depth_mm is None else float(max_depth_mm)
    inward = np.zeros(3)
    inward[axis] = -float(sign)
    inter = IntCurvesFace_ShapeIntersector()
    inter.Load(_compound(shapes), _INTERSECT_TOLERANCE_MM)

    def depth(g: FloatArray) -> float | None:
        start = (g - inward * 1.0) / scale_to_mm  # 1 mm outside the box: no hit is missed
        line = gp_Lin(gp_Pnt(*start.tolist()), gp_Dir(*inward.tolist()))
        inter.PerformNearest(line, 0.0, (span + 2.0) / scale_to_mm)
        if not inter.IsDone() or inter.NbPnt() < 1:
            return None
        w = max(float(inter.WParameter(1)) * scale_to_mm - 1.0, 0.0)  # depth inside the box
        return w if w <= depth_max else None

    grid = np.asarray(grid_mm, dtype=float)
    groups = grid.reshape(-1, 1, 3) if grid.ndim == 2 else grid.reshape(len(grid), -1, 3)
    out = []
    for alternatives in groups:
        best: tuple[float, FloatArray] | None = None
        for g in alternatives:
            w = depth(g)
            if w is not None and (best is None or w < best[0] - 1e-6):
                best = (w, g)
        if best is not None:
            out.append(SurfacePoint(face, best[1] + inward * best[0], best[0]))
    return out


#: Rays cast down across the +z face (per side) for the ME's base when the face's centre
#: meets no solid.
ME_BASE_GRID = 9


def top_surface_point(
    shapes: Sequence[TopoDS_Shape],
    bbox_lo_mm: npt.ArrayLike,
    bbox_hi_mm: npt.ArrayLike,
    *,
    scale_to_mm: float = 1.0,
) -> list[float] | None:
    """Where something can sit on top of the model (the measurement equipment's base): the
    first surface a ray straight down through the +z face's centre meets, else, of a grid of
    such rays, the one meeting the model highest (the nearest the centre among equals); None
    when no ray meets it.
    """
    lo = np.asarray(bbox_lo_mm, dtype=float)
    hi = np.asarray(bbox_hi_mm, dtype=float)
    scale = scale_to_mm
    span = float(hi[2] - lo[2])
    centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), float(hi[2])]
    hits = project_grid(shapes, "+z", [centre], lo, hi, scale_to_mm=scale, max_depth_mm=span)
    if not hits:
        u = (np.arange(ME_BASE_GRID) + 0.5) / ME_BASE_GRID
        grid = [
            [lo[0] + a * (hi[0] - lo[0]), lo[1] + b * (hi[1] - lo[1]), float(hi[2])]
            for a in u
            for b in u
        ]
        hits = project_grid(shapes, "+z", grid, lo, hi, scale_to_mm=scale, max_depth_mm=span)
        c = np.asarray(centre[:2])
        hits = sorted(
            hits,
            key=lambda h: (round(h.depth_mm, 6), float(np.linalg.norm(h.position_mm[:2] - c))),
        )
    return None if not hits else [float(v) for v in hits[0].position_mm]
