"""Solids that a move makes overlap: a deployed panel through a rail, an antenna into a wall.

A configuration moves some solids rigidly (:mod:`cadcog.spacecraft.configurations`); a moved
solid that then shares volume with one that did not move with it would be counted twice. The
search is :mod:`cadcog.cad.overlaps`'s: bounding boxes pruned, then OCCT's boolean common for
the candidates, contact (a hinge's faces touching) not counted
(:func:`cadcog.cad.overlaps.is_overlap`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import numpy.typing as npt
from OCP.gp import gp_Trsf
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS_Shape

from cadcog.cad.occt import volume_properties
from cadcog.cad.overlaps import bounding_boxes, candidate_pairs, common_volume, is_overlap

FloatArray = npt.NDArray[np.float64]


def _moved(shape: TopoDS_Shape, rotation: FloatArray, translation_file: FloatArray) -> TopoDS_Shape:
    t = gp_Trsf()
    r = rotation
    t.SetValues(
        r[0, 0], r[0, 1], r[0, 2], translation_file[0],
        r[1, 0], r[1, 1], r[1, 2], translation_file[1],
        r[2, 0], r[2, 1], r[2, 2], translation_file[2],
    )  # fmt: skip
    return shape.Moved(TopLoc_Location(t))


def moved_overlaps(
    solids: Sequence[tuple[str, TopoDS_Shape]],
    placements: Mapping[str, tuple[FloatArray, FloatArray]],
    *,
    scale_to_mm: float = 1.0,
) -> list[tuple[str, str, float]]:
    """Pairs a configuration makes overlap: (moved solid, other solid, common volume mm³).

    Parameters
    ----------
    solids : sequence of (str, TopoDS_Shape)
        Named solids at their global placement, in the file's units.
    placements : mapping of str to (rotation (3, 3), translation_mm (3,))
        The moved solids' moves, ``x → R x + t`` in mm; a solid not named did not move.
    scale_to_mm : float
        mm per file unit (a ``units`` override).

    Returns
    -------
    list of (str, str, float)
        Each pair whose solids did not move together and now overlap, in name order.
    """
    names = [n for n, _ in solids]
    shapes = []
    for name, shape in solids:
        if name in placements:
            rot, t_mm = placements[name]
            shape = _moved(shape, np.asarray(rot, float), np.asarray(t_mm, float) / scale_to_mm)
        shapes.append(shape)
    lo, hi = bounding_boxes(shapes)
    volumes: dict[int, float] = {}
    out = []
    for i, j in candidate_pairs(lo, hi):
        pi, pj = placements.get(names[i]), placements.get(names[j])
        if pi is None and pj is None:
            continue  # neither moved: the model's own overlap check says
        if (
            pi is not None
            and pj is not None
            and np.allclose(pi[0], pj[0], atol=1e-12)
            and (np.allclose(pi[1], pj[1], atol=1e-9))
        ):
            continue  # moved together
        common = common_volume(shapes[i], shapes[j])
        if common is None:
            continue
        cube = scale_to_mm**3  # the shapes are in file units; contact is judged in mm³
        for k in (i, j):
            if k not in volumes:
                volumes[k] = volume_properties(shapes[k]).volume_mm3 * cube
        if is_overlap(common.volume_mm3 * cube, volumes[i], volumes[j]):
            a, b = (i, j) if pi is not None else (j, i)
            out.append((names[a], names[b], common.volume_mm3 * cube))
    return sorted(out)
