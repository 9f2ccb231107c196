"""Which solid of a model, if any, holds a point (OCCT's exact solid classifier).

A ballast location must be where ballast can sit: on a face or in free space, not inside a
solid. A point within ``tolerance_mm`` of a solid's boundary counts as on it (files round
positions to 0.001 mm).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt
from OCP.BRepClass3d import BRepClass3d_SolidClassifier
from OCP.gp import gp_Pnt
from OCP.TopAbs import TopAbs_IN
from OCP.TopoDS import TopoDS_Shape

from cadcog.cad.overlaps import bounding_boxes
from cadcog.core import tolerances


def solids_holding(
    solids: Sequence[tuple[str, TopoDS_Shape]],
    points_mm: npt.ArrayLike,
    *,
    scale_to_mm: float = 1.0,
    tolerance_mm: float = tolerances.SUSPENSION_ON_FACE_MM,
) -> list[str | None]:
    """For each point, the name of the first solid holding it (deeper than ``tolerance_mm``
    inside), or None.

    Parameters
    ----------
    solids : sequence of (str, TopoDS_Shape)
        Named solids at their global placement, in the file's units.
    points_mm : array_like, shape (n, 3)
        Points in mm (the model's mm: file units × ``scale_to_mm``).
    scale_to_mm : float
        mm per file unit on top of the reader's conversion (a ``units`` override).
    tolerance_mm : float
        Points this close to a boundary are on it (mm).
    """
    pts = np.asarray(points_mm, dtype=float).reshape(-1, 3) / scale_to_mm
    tol = tolerance_mm / scale_to_mm
    lo, hi = bounding_boxes([shape for _, shape in solids])
    out: list[str | None] = []
    for p in pts:
        found = None
        for (name, shape), a, b in zip(solids, lo, hi, strict=True):
            if np.any(p < a - tol) or np.any(p > b + tol):
                continue
            cls = BRepClass3d_SolidClassifier(shape, gp_Pnt(*p.tolist()), tol)
            if cls.State() == TopAbs_IN:
                found = name
                break
        out.append(found)
    return out
