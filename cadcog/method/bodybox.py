"""The box a hung body's suspension points sit on: it gives each point's bolt axis."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import ReadingsError
from cadcog.method.readings import Suspension
from cadcog.rig.geometry import FloatArray, face_normal_of_point, same_point
from cadcog.rig.parameters import Rig


@dataclass(frozen=True)
class BodyBox:
    """The box whose faces the suspension points sit on (or above): it gives the bolt axes.

    The paper rig's proof mass ``[0, size]``; a spacecraft's bounding box, and the points the
    set-up lists on the model itself with their face (``known``: position and outward normal),
    which may lie anywhere inside the box.
    """

    lo_mm: FloatArray
    hi_mm: FloatArray
    source: str
    known: tuple[tuple[FloatArray, FloatArray], ...] = ()

    def normal_at(self, position_mm: npt.ArrayLike) -> FloatArray:
        """Bolt axis (outward normal, shape (3,)) at a suspension point.

        A point the set-up lists (within :data:`~cadcog.core.tolerances.SUSPENSION_ON_FACE_MM`
        on every axis) takes the face it names; any other point the box face it sits on.

        Raises
        ------
        ValueError
            If the point is neither listed nor on the box's surface.
        """
        p = np.asarray(position_mm, dtype=float)
        for q, n in self.known:
            if same_point(p, q):
                return np.array(n, dtype=float)
        return face_normal_of_point(p, self.lo_mm, self.hi_mm)

    def normals(self, suspensions: Sequence[Suspension]) -> FloatArray:
        """Bolt axis (outward face normal) of each suspension point, shape (k, 3)."""
        out = []
        for s in suspensions:
            try:
                out.append(self.normal_at(s.position_mm))
            except ValueError:
                listed = (
                    "; are these the readings of this set-up? (a point from another set-up's list)"
                    if self.known
                    else ""
                )
                raise ReadingsError(
                    f"line {s.line}: suspension {s.id} at {list(s.position_mm)} mm lies inside "
                    f"the bounding box of the body ({self.source}) and is none of its listed "
                    f"points: a suspension point must be on its surface{listed}"
                ) from None
        return np.array(out)

    def outside_by_mm(self, point_mm: npt.ArrayLike) -> FloatArray:
        """How far ``point_mm`` lies outside the box along each axis (0 inside), shape (3,).

        Examples
        --------
        >>> box = BodyBox(np.zeros(3), np.array([10.0, 10.0, 10.0]), "a cube")
        >>> box.outside_by_mm([5.0, -2.0, 13.0]).tolist()
        [0.0, 2.0, 3.0]
        """
        p = np.asarray(point_mm, dtype=float)
        return np.asarray(np.maximum(np.maximum(self.lo_mm - p, p - self.hi_mm), 0.0))

    @classmethod
    def of_rig(cls, rig: Rig) -> BodyBox:
        return cls(np.zeros(3), np.asarray(rig.proof_mass.size_mm, float), f"rig {rig.source}")
