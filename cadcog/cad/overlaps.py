"""Overlapping solids, found fast: bounding-box pruning, then a boolean only for candidates.

Two solids whose interiors share volume would have that volume counted twice. Real models are full
of contact (faces that touch, bolts in their holes modelled line-on-line) and of small
interpenetrations at the modelling tolerance; those are not overlaps. A pair counts as overlapping
only when its common volume exceeds both :data:`cadcog.core.tolerances.CONTACT_VOLUME_MM3` and
:data:`cadcog.core.tolerances.CONTACT_VOLUME_RELATIVE` times the smaller solid's volume.

Pruning: every solid's axis-aligned bounding box is computed once, and pairs whose boxes do not
overlap by more than :data:`cadcog.core.tolerances.BOX_OVERLAP_MM` on every axis are dropped with
vectorised comparisons (blocks of rows, so memory stays bounded). Only the remaining candidates
go through OCCT's boolean common (``BRepAlgoAPI_Common``), and only once per distinct
configuration: two instanced parts in the same relative placement (the pins and housing of every
copy of a connector, a bracket sub-assembly used twice) share one boolean, computed in the first
part's own frame and moved to each placement.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from OCP.Bnd import Bnd_Box
from OCP.BRepAlgoAPI import BRepAlgoAPI_Common, BRepAlgoAPI_Cut
from OCP.BRepBndLib import BRepBndLib
from OCP.collections import List_TopoDS_Shape
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS_Shape

from cadcog.cad.occt import placed, rigid_transform, volume_properties
from cadcog.core import tolerances
from cadcog.core.parallel import fork_map
from cadcog.mass.properties import MassProperties

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.intp]

#: Box pairs compared at once by :func:`candidate_pairs` (about 100 bytes each).
_BLOCK_PAIRS = 1 << 20


@dataclass(frozen=True)
class Overlap:
    """Two solids sharing volume.

    Attributes
    ----------
    a, b : int
        Indices of the two solids (``a < b``).
    common : MassProperties
        Volume, centroid and inertia of the common volume at unit density (1 kg/mm³), in the
        shapes' frame: scale by a density to get its mass properties.
    """

    a: int
    b: int
    common: MassProperties

    @property
    def volume_mm3(self) -> float:
        return self.common.volume_mm3


def bounding_boxes(shapes: Sequence[TopoDS_Shape]) -> tuple[FloatArray, FloatArray]:
    """Tight axis-aligned bounding boxes (no tolerance gap): arrays ``lo``, ``hi`` of (n, 3)."""
    lo = np.empty((len(shapes), 3))
    hi = np.empty((len(shapes), 3))
    for i, shape in enumerate(shapes):
        box = Bnd_Box()
        BRepBndLib.AddOptimal_s(shape, box, False, False)
        cmin, cmax = box.CornerMin(), box.CornerMax()
        lo[i] = (cmin.X(), cmin.Y(), cmin.Z())
        hi[i] = (cmax.X(), cmax.Y(), cmax.Z())
    return lo, hi


def candidate_pairs(
    lo: FloatArray, hi: FloatArray, depth_mm: float = tolerances.BOX_OVERLAP_MM
) -> list[tuple[int, int]]:
    """Pairs ``(i, j)``, ``i < j``, whose boxes overlap by more than ``depth_mm`` on every axis.

    A sort and sweep along the axis where boxes overlap least: only boxes whose intervals
    overlap on that axis are compared on all three, with the same test as every pair would be
    (``min(hi) - max(lo) > depth_mm``), so the pairs are the same; time and memory grow with
    the boxes and the pairs found, not with their square.

    Examples
    --------
    >>> lo = np.array([[0, 0, 0], [1, 1, 1], [5, 0, 0.0]])
    >>> hi = np.array([[2, 2, 2], [3, 3, 3], [6, 1, 1.0]])
    >>> candidate_pairs(lo, hi)
    [(0, 1)]
    """
    n = len(lo)
    if n < 2:
        return []
    best: tuple[IntArray, IntArray] | None = None
    for axis in range(3):
        order: IntArray = np.argsort(lo[:, axis], kind="stable")
        starts = lo[order, axis]
        # Boxes after k in this order that start before k ends: hi - lo > depth ≥ 0 needs lo < hi.
        ends = np.searchsorted(starts, hi[order, axis], side="left")
        counts: IntArray = np.maximum(ends - np.arange(1, n + 1), 0)
        if best is None or counts.sum() < best[1].sum():
            best = (order, counts)
    assert best is not None
    order, counts = best
    pairs: list[tuple[int, int]] = []
    first = 0
    while first < n:  # blocks of about _BLOCK_PAIRS sweep pairs: bounded memory
        total = np.cumsum(counts[first:])
        last = first + max(1, int(np.searchsorted(total, _BLOCK_PAIRS, side="right")))
        k = np.repeat(np.arange(first, last), counts[first:last])
        if len(k):
            offsets = np.arange(len(k)) - np.repeat(
                np.cumsum(counts[first:last]) - counts[first:last], counts[first:last]
            )
            i = order[k]
            j = order[k + 1 + offsets]
            depth = np.minimum(hi[i], hi[j]) - np.maximum(lo[i], lo[j])
            hit = np.all(depth > depth_mm, axis=1)
            a, b = np.minimum(i[hit], j[hit]), np.maximum(i[hit], j[hit])
            pairs.extend(zip(a.tolist(), b.tolist(), strict=True))
        first = last
    return sorted(pairs)


def common_volume(a: TopoDS_Shape, b: TopoDS_Shape) -> MassProperties | None:
    """Properties of ``a ∩ b`` at unit density, or None if the boolean fails or is empty."""
    args = List_TopoDS_Shape()
    args.Append(a)
    tools = List_TopoDS_Shape()
    tools.Append(b)
    op = BRepAlgoAPI_Common()
    op.SetArguments(args)
    op.SetTools(tools)
    op.SetRunParallel(False)
    op.SetCheckInverted(False)  # solids reach here with a positive integrated volume
    op.Build()
    if not op.IsDone():
        return None
    props = volume_properties(op.Shape())
    return props if props.volume_mm3 > 0 else None


def is_overlap(common_mm3: float, volume_a_mm3: float, volume_b_mm3: float) -> bool:
    """Whether a common volume is an overlap rather than contact (see the module docstring).

    Examples
    --------
    >>> is_overlap(0.004, 1000.0, 50.0), is_overlap(5.0, 1000.0, 50.0)
    (False, True)
    """
    floor = max(
        tolerances.CONTACT_VOLUME_MM3,
        tolerances.CONTACT_VOLUME_RELATIVE * min(volume_a_mm3, volume_b_mm3),
    )
    return common_mm3 > floor


@dataclass(frozen=True)
class Placed:
    """A solid for :func:`find_overlaps`: at its global placement, and in its own frame.

    Attributes
    ----------
    shape : TopoDS_Shape
        The solid at its global placement.
    local_shape : TopoDS_Shape
        The same solid in its product's frame (``shape = local_shape.Moved(placement)``).
    placement : TopLoc_Location
    key : str
        Identifies the geometry: solids with one key are instances of one shape.
    box_lo, box_hi : ndarray, shape (3,)
        An axis-aligned box containing the solid at its placement.
    rigid : (ndarray, ndarray) or None
        Rotation and translation of ``placement``, None if it is not rigid
        (:func:`cadcog.cad.occt.rigid_transform`, as the body already has it).
    """

    shape: TopoDS_Shape
    local_shape: TopoDS_Shape
    placement: TopLoc_Location
    key: str
    box_lo: FloatArray
    box_hi: FloatArray
    rigid: tuple[FloatArray, FloatArray] | None


def relative_key(a: Placed, b: Placed) -> tuple[str, str, tuple[float, ...]] | None:
    """Identifies the configuration of ``b`` seen from ``a``'s frame (None if not rigid)."""
    if a.rigid is None:
        return None
    rel = a.placement.Inverted().Multiplied(b.placement)
    if rigid_transform(rel) is None:
        return None
    t = rel.Transformation()
    digits = tuple(round(t.Value(i, j), 9) for i in (1, 2, 3) for j in (1, 2, 3, 4))
    return a.key, b.key, digits


def _common_of(job: tuple[TopoDS_Shape, TopoDS_Shape]) -> MassProperties | None:
    return common_volume(*job)


def find_overlaps(
    solids: Sequence[Placed],
    volumes_mm3: Sequence[float],
    *,
    scale: float = 1.0,
    progress: Callable[[str, int], Callable[[int], None]] | None = None,
    workers: int = 1,
) -> tuple[list[Overlap], list[tuple[int, int]], int]:
    """Every overlapping pair of solids.

    Parameters
    ----------
    solids : sequence of Placed
        In the file's (converted) length unit.
    volumes_mm3 : sequence of float
        Their volumes in mm³ (after ``scale``).
    scale : float
        mm per file unit, when the file's declared unit is overridden (volumes scale by its cube).
    progress : callable, optional
        ``progress(description, total)`` returns a function called with 1 after each boolean.
    workers : int
        Processes for the booleans (the result does not depend on it).

    Returns
    -------
    overlaps : list of Overlap
        Common volumes in the file's frame and unit (not scaled).
    candidates : list of (int, int)
        Pairs whose boxes overlapped (each got a boolean, or shared one).
    n_contact : int
        Candidates whose common volume was contact, not overlap.
    """
    lo = np.array([s.box_lo for s in solids])
    hi = np.array([s.box_hi for s in solids])
    pairs = candidate_pairs(lo, hi, tolerances.BOX_OVERLAP_MM / scale)
    # One boolean per distinct configuration: instances in the same relative placement share.
    jobs: list[tuple[TopoDS_Shape, TopoDS_Shape]] = []
    job_of: dict[object, int] = {}
    pair_job: list[tuple[int, bool]] = []  # (job index, computed in the first solid's frame)
    for i, j in pairs:
        a, b = solids[i], solids[j]
        key = relative_key(a, b)
        if key is None:
            pair_job.append((len(jobs), False))
            jobs.append((a.shape, b.shape))
            continue
        if key not in job_of:
            rel = a.placement.Inverted().Multiplied(b.placement)
            job_of[key] = len(jobs)
            jobs.append((a.local_shape, b.local_shape.Moved(rel)))
        pair_job.append((job_of[key], True))
    tick = progress("checking overlaps", len(jobs)) if progress and jobs else None
    commons = fork_map(_common_of, jobs, workers=workers, progress=tick)
    overlaps = []
    contact = 0
    for (i, j), (k, local) in zip(pairs, pair_job, strict=True):
        common = commons[k]
        if common is not None and local:
            rigid = solids[i].rigid
            common = None if rigid is None else placed(common, *rigid)
        if common is not None and is_overlap(
            common.volume_mm3 * scale**3, volumes_mm3[i], volumes_mm3[j]
        ):
            overlaps.append(Overlap(i, j, common))
        else:
            contact += 1
    return overlaps, pairs, contact


def cut_by(shape: TopoDS_Shape, tools: Sequence[TopoDS_Shape]) -> TopoDS_Shape | None:
    """``shape`` minus every tool (one boolean), or None if OCCT fails."""
    args = List_TopoDS_Shape()
    args.Append(shape)
    cutters = List_TopoDS_Shape()
    for t in tools:
        cutters.Append(t)
    op = BRepAlgoAPI_Cut()
    op.SetArguments(args)
    op.SetTools(cutters)
    op.SetRunParallel(False)
    op.Build()
    return op.Shape() if op.IsDone() else None
