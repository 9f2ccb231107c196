"""Body-frame geometry shared by the rig model and the estimator.

Body frame (docs/method.md §1): origin at a vertex of the proof mass, x along its longest edge, y
along its shortest, z completing a right-handed frame; the proof mass occupies ``[0, size]`` on each
axis. Faces are named by their outward normal: ``+x``, ``-x``, ``+y``, ``-y``, ``+z``, ``-z``.

The inclinometer frame is a pure translation of the body frame. Readings follow the project's
sign convention: ``sin X = u·x_b`` and ``sin Y = u·y_b`` where ``u`` is the *upward* vertical in
body components, so X is positive when the body's +x axis points upward.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from cadcog.core import tolerances
from cadcog.core.units import rad_to_deg
from cadcog.rig.inclinometer import readings_from_verticals

FloatArray = npt.NDArray[np.float64]

#: Face name → (axis index, sign of the outward normal).
FACES: dict[str, tuple[int, int]] = {
    "+x": (0, 1),
    "-x": (0, -1),
    "+y": (1, 1),
    "-y": (1, -1),
    "+z": (2, 1),
    "-z": (2, -1),
}

AXIS_NAMES = "xyz"


def face_normal(face: str) -> FloatArray:
    """Outward unit normal of a face of the proof mass.

    Examples
    --------
    >>> face_normal("-y").tolist()
    [0.0, -1.0, 0.0]
    """
    axis, sign = FACES[face]
    n = np.zeros(3)
    n[axis] = float(sign)
    return n


def face_plane_mm(face: str, size_mm: npt.ArrayLike) -> float:
    """Coordinate of a face's plane along its axis, for a box occupying ``[0, size_mm]``.

    Examples
    --------
    >>> face_plane_mm("+z", [200, 75, 78]), face_plane_mm("-z", [200, 75, 78])
    (78.0, 0.0)
    """
    axis, sign = FACES[face]
    return float(np.asarray(size_mm, dtype=float)[axis]) if sign > 0 else 0.0


def same_point(
    a_mm: npt.ArrayLike, b_mm: npt.ArrayLike, tolerance_mm: float = tolerances.SUSPENSION_ON_FACE_MM
) -> bool:
    """Whether two suspension points are one: within ``tolerance_mm`` on every axis (a file's
    rounding to 1e-3 mm never separates a point from itself).

    Examples
    --------
    >>> same_point([38.5254, 0, 1], [38.525, 0, 1]), same_point([38.5, 0, 1], [38.52, 0, 1])
    (True, False)
    """
    d = np.asarray(a_mm, dtype=float) - np.asarray(b_mm, dtype=float)
    return bool(np.max(np.abs(d)) <= tolerance_mm)


def face_normal_of_point(
    point_mm: npt.ArrayLike,
    lo_mm: npt.ArrayLike,
    hi_mm: npt.ArrayLike,
    tolerance_mm: float = tolerances.SUSPENSION_ON_FACE_MM,
) -> FloatArray:
    """Outward normal of the face of the box ``[lo, hi]`` a point sits on or above.

    The face is the one the point lies furthest outside of; a point less than ``tolerance_mm``
    inside a face still sits on it (:data:`cadcog.core.tolerances.SUSPENSION_ON_FACE_MM`).

    Raises
    ------
    ValueError
        If the point is deeper inside the box than ``tolerance_mm``.

    Examples
    --------
    >>> face_normal_of_point([45, 20, 82], [0, 0, 0], [200, 75, 78]).tolist()
    [0.0, 0.0, 1.0]
    >>> face_normal_of_point([45, 20, 77.9995], [0, 0, 0], [200, 75, 78]).tolist()  # rounded
    [0.0, 0.0, 1.0]
    """
    p = np.asarray(point_mm, dtype=float)
    outside = np.concatenate([p - np.asarray(hi_mm, float), np.asarray(lo_mm, float) - p])
    i = int(np.argmax(outside))
    if not outside[i] >= -tolerance_mm:
        raise ValueError(f"point {p.tolist()} lies inside the body, not on a face")
    n = np.zeros(3)
    n[i % 3] = 1.0 if i < 3 else -1.0
    return n


@dataclass(frozen=True)
class IdealReading:
    """What a perfect inclinometer reads when the body hangs from a point.

    Attributes
    ----------
    inc_x_deg, inc_y_deg : float
        Readings about the inclinometer's x and y axes (degrees, project sign convention).
    top_face_up : bool
        Whether the inclinometer's top face (+z) points upward.
    vertical : ndarray, shape (3,)
        Upward unit vertical in body components.
    """

    inc_x_deg: float
    inc_y_deg: float
    top_face_up: bool
    vertical: FloatArray

    def in_range(self, range_deg: float) -> bool:
        """True if both axes read within ``±range_deg``."""
        return not axes_beyond_range(self.inc_x_deg, self.inc_y_deg, range_deg)


def axes_beyond_range(inc_x_deg: float, inc_y_deg: float, range_deg: float) -> list[str]:
    """The axes reading beyond ``±range_deg``, as ``"X = 62.00°"`` strings (empty: in range).

    Examples
    --------
    >>> axes_beyond_range(62.0, -10.0, 60.0)
    ['X = 62.00°']
    """
    return [
        f"{axis} = {value:.2f}°"
        for axis, value in (("X", inc_x_deg), ("Y", inc_y_deg))
        if abs(value) > range_deg
    ]


def upward_vertical(suspension_mm: npt.ArrayLike, cog_mm: npt.ArrayLike) -> FloatArray:
    """Upward vertical, in body components, of a body hanging from ``suspension_mm``.

    At rest the CoG lies straight below the suspension point, so the upward vertical is the unit
    vector from the CoG to the suspension point.

    Raises
    ------
    ValueError
        If the suspension point coincides with the CoG (no defined vertical).

    Examples
    --------
    >>> upward_vertical([0, 0, 10], [0, 0, 0]).tolist()
    [0.0, 0.0, 1.0]
    """
    d = np.asarray(suspension_mm, dtype=float) - np.asarray(cog_mm, dtype=float)
    norm = float(np.linalg.norm(d))
    if norm == 0.0:
        raise ValueError("suspension point coincides with the CoG: the vertical is undefined")
    return d / norm


def ideal_reading(suspension_mm: npt.ArrayLike, cog_mm: npt.ArrayLike) -> IdealReading:
    """Noise-free inclinometer reading when hanging from ``suspension_mm`` (forward model).

    Examples
    --------
    >>> r = ideal_reading([1.0, 0.0, 1.0], [0.0, 0.0, 0.0])
    >>> round(r.inc_x_deg, 9), r.inc_y_deg, r.top_face_up
    (45.0, 0.0, True)
    """
    u = upward_vertical(suspension_mm, cog_mm)
    x_deg, y_deg, up = readings_from_verticals(u)  # the project convention: no sign flips
    return IdealReading(float(x_deg[0]), float(y_deg[0]), bool(up[0]), u)


def angle_between_lines_deg(u1: npt.ArrayLike, u2: npt.ArrayLike) -> float:
    """Acute angle between two lines with directions ``u1`` and ``u2`` (degrees, 0 to 90).

    Examples
    --------
    >>> round(angle_between_lines_deg([1, 0, 0], [-1, 1, 0]), 9)
    45.0
    """
    a = np.asarray(u1, dtype=float)
    b = np.asarray(u2, dtype=float)
    a = a / np.linalg.norm(a)
    b = b / np.linalg.norm(b)
    # atan2 of |cross| and |dot| is accurate at both ends, unlike acos or asin alone.
    return float(rad_to_deg(np.arctan2(np.linalg.norm(np.cross(a, b)), abs(np.dot(a, b)))))
