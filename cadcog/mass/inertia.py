"""Inertia as engineers use it: principal axes, other points and frames, product conventions.

cadcog's inertia tensor (``MassProperties.inertia_kg_mm2``) is ``J = ∫ ρ (|r|² 𝟙 − r rᵀ) dV``:
its diagonal holds the moments ``Ixx = ∫ (y² + z²) dm``..., its off-diagonal entries are
``J_xy = −∫ x y dm``. CAD tools and mass-properties reports quote *products of inertia* in one
of two conventions, and a wrong guess flips the sign of every product:

- ``positive`` (SolidWorks, most mass-properties reports): ``Pxy = +∫ x y dm``, so the tensor
  entry is ``−Pxy``;
- ``negative`` (the tensor's own entries): ``Ixy = −∫ x y dm``.

:func:`products_of_inertia` gives either, named. A :class:`Frame` states a reference point and
axes (for example a CubeSat's geometric centre with the CubeSat Design Specification's axes, or
a separation plane); :func:`inertia_in_frame` expresses the inertia about its origin, in its
axes.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import quote
from cadcog.mass.properties import MassProperties

FloatArray = npt.NDArray[np.float64]

ProductConvention = Literal["positive", "negative"]

#: Relative difference of two principal moments below which their axes are not unique.
DEGENERATE_RELATIVE = 1e-6

#: How far a frame's axes may be from orthonormal (largest entry of ``R Rᵀ − 𝟙``).
ORTHONORMAL_TOLERANCE = 1e-6

#: Axis vectors whose pairwise cosines are below this are squared up to the nearest
#: orthonormal frame (0.057°: vectors typed to four figures); above it they are refused.
SQUARE_UP_COS = 1e-3

_AXIS_INDEX = {"x": 0, "y": 1, "z": 2}


@dataclass(frozen=True)
class PrincipalAxes:
    """Principal moments and axes of an inertia tensor.

    Attributes
    ----------
    moments_kg_mm2 : ndarray, shape (3,)
        Ascending.
    axes : ndarray, shape (3, 3)
        Row ``i`` is the unit axis of ``moments_kg_mm2[i]`` in the tensor's frame; the rows form
        a right-handed frame, each with its largest component positive (the third axis's sign
        follows from the first two).
    degenerate : bool
        Two or more moments equal (to :data:`DEGENERATE_RELATIVE`): their axes are not unique.
    """

    moments_kg_mm2: FloatArray
    axes: FloatArray
    degenerate: bool

    @property
    def n_equal(self) -> int:
        """How many moments are equal (to :data:`DEGENERATE_RELATIVE`): 0, 2 or 3.

        Examples
        --------
        >>> principal_axes(np.eye(3)).n_equal, principal_axes(np.diag([1.0, 1, 2])).n_equal
        (3, 2)
        """
        equal = int(np.count_nonzero(self._equal_neighbours()))
        return 0 if equal == 0 else equal + 1

    def _equal_neighbours(self) -> npt.NDArray[np.bool_]:
        """Whether moments 1 and 2, and 2 and 3, are equal (to :data:`DEGENERATE_RELATIVE` of
        the largest): the moments are sorted, so only neighbours can be."""
        d = np.diff(self.moments_kg_mm2)
        scale = max(float(np.max(np.abs(self.moments_kg_mm2))), np.finfo(float).tiny)
        return np.asarray(d <= DEGENERATE_RELATIVE * scale)

    def unique(self) -> tuple[bool, bool, bool]:
        """Whether each axis is determined: False for the axes of equal moments.

        Examples
        --------
        >>> principal_axes(np.diag([1.0, 1.0, 2.0])).unique(), principal_axes(np.eye(3)).unique()
        ((False, False, True), (False, False, False))
        """
        equal = self._equal_neighbours()
        out = [True, True, True]
        for k in (0, 1):
            if equal[k]:
                out[k] = out[k + 1] = False
        return out[0], out[1], out[2]

    def degeneracy_note(self) -> str:
        """What equal moments mean for the axes, or "" when all three differ."""
        if self.n_equal == 3:
            return "all three moments are equal: every axis through the CoG is principal"
        if self.n_equal == 2:
            return "two moments are equal: their axes are not unique (any pair in their plane)"
        return ""

    def angles_from_frame_deg(self) -> FloatArray:
        """Angle of each principal axis from the frame axis nearest to it (degrees).

        Examples
        --------
        >>> p = principal_axes(np.diag([1.0, 2.0, 3.0]))
        >>> p.angles_from_frame_deg().tolist()
        [0.0, 0.0, 0.0]
        """
        cos = np.clip(np.max(np.abs(self.axes), axis=1), -1.0, 1.0)
        return np.asarray(np.rad2deg(np.arccos(cos)))


def principal_axes(inertia_kg_mm2: npt.ArrayLike) -> PrincipalAxes:
    """Principal moments (ascending) and axes of a symmetric inertia tensor.

    Examples
    --------
    >>> p = principal_axes([[2.0, -1.0, 0], [-1.0, 2.0, 0], [0, 0, 5.0]])
    >>> p.moments_kg_mm2.round(12).tolist()
    [1.0, 3.0, 5.0]
    >>> p.axes.round(6).tolist()[0]
    [0.707107, 0.707107, 0.0]
    """
    j = np.asarray(inertia_kg_mm2, dtype=float)
    moments, vectors = np.linalg.eigh(0.5 * (j + j.T))
    axes = vectors.T.copy()
    for i in range(2):
        k = int(np.argmax(np.abs(axes[i])))
        if axes[i, k] < 0:
            axes[i] = -axes[i]
    axes[2] = np.cross(axes[0], axes[1])
    scale = max(float(np.max(np.abs(moments))), np.finfo(float).tiny)
    degenerate = bool(np.min(np.diff(moments)) <= DEGENERATE_RELATIVE * scale)
    return PrincipalAxes(np.asarray(moments), axes, degenerate)


def products_of_inertia(
    inertia_kg_mm2: npt.ArrayLike, convention: ProductConvention = "positive"
) -> dict[str, float]:
    """The products of inertia ``xy``, ``xz``, ``yz`` in the named sign convention.

    Examples
    --------
    >>> j = [[2.0, -1.0, 0], [-1.0, 2.0, 0], [0, 0, 5.0]]  # ∫xy dm = +1
    >>> products_of_inertia(j, "positive")["xy"], products_of_inertia(j, "negative")["xy"]
    (1.0, -1.0)
    """
    if convention not in ("positive", "negative"):
        raise ValueError(f"convention must be 'positive' or 'negative', got {convention!r}")
    j = np.asarray(inertia_kg_mm2, dtype=float)
    sign = -1.0 if convention == "positive" else 1.0
    return {"xy": sign * float(j[0, 1]), "xz": sign * float(j[0, 2]), "yz": sign * float(j[1, 2])}


#: The inertia tensor's convention, as every output that holds a tensor names it.
TENSOR_CONVENTION = "J = ∫ (|r|² 1 − r rᵀ) dm: off-diagonal entries are −∫ x·y dm"

PRODUCT_CONVENTIONS: dict[str, str] = {
    "positive": "Pxy = +∫ x·y dm (the tensor's off-diagonal entry is −Pxy)",
    "negative": "Ixy = −∫ x·y dm (the tensor's own off-diagonal entry)",
}


@dataclass(frozen=True)
class Frame:
    """A reference point and axes, in model coordinates.

    Attributes
    ----------
    origin_mm : ndarray, shape (3,)
    axes : ndarray, shape (3, 3)
        Row ``i`` is the frame's axis ``i`` in model coordinates: orthonormal, right-handed.
    label : str
        What the frame is, for reports ("model", "geometric centre, CDS axes", ...).

    Examples
    --------
    >>> f = Frame.parse("+y,-x,+z", [10.0, 0.0, 0.0])
    >>> f.point_to_frame([10.0, 5.0, 0.0]).tolist()
    [5.0, 0.0, 0.0]
    """

    origin_mm: FloatArray
    axes: FloatArray
    label: str = ""

    def __post_init__(self) -> None:
        o = np.array(self.origin_mm, dtype=float)
        r = np.array(self.axes, dtype=float)
        if o.shape != (3,) or r.shape != (3, 3) or not np.all(np.isfinite(r)):
            raise ValueError("a frame needs a 3-vector origin and 3 × 3 finite axes")
        if not np.all(np.isfinite(o)):
            raise ValueError("the frame's origin must be finite")
        if np.max(np.abs(r @ r.T - np.eye(3))) > ORTHONORMAL_TOLERANCE:
            raise ValueError("the frame's axes must be orthonormal unit vectors")
        if np.linalg.det(r) < 0:
            raise ValueError("the frame's axes must be right-handed (x × y = z)")
        o.setflags(write=False)
        r.setflags(write=False)
        object.__setattr__(self, "origin_mm", o)
        object.__setattr__(self, "axes", r)

    @classmethod
    def model(cls) -> Frame:
        return cls(np.zeros(3), np.eye(3), "model origin and axes")

    @classmethod
    def parse(cls, axes: str, origin_mm: npt.ArrayLike, label: str = "") -> Frame:
        """A frame from signed model axes or from axis vectors.

        - ``"+y,-x,+z"``: the frame's x is model +y...;
        - ``"1,1,0;-1,1,0"`` or ``"1,1,0;-1,1,0;0,0,1"``: the frame's x and y axes (and z) as
          model vectors, any length (each is normalised); without z, ``z = x × y``. The rows
          of a rotation matrix from model to frame are these vectors. Axes within
          :data:`SQUARE_UP_COS` of perpendicular (vectors typed to four figures) are squared
          up to the nearest orthonormal frame; farther, the text is refused.

        Raises
        ------
        ValueError
            If the text is neither, or its axes are not a right-handed orthogonal frame.

        Examples
        --------
        >>> f = Frame.parse("1,1,0;-1,1,0", [0, 0, 0])
        >>> f.axes.round(4).tolist()
        [[0.7071, 0.7071, 0.0], [-0.7071, 0.7071, 0.0], [0.0, 0.0, 1.0]]
        >>> Frame.parse("0.7071,0.7071,0;-0.7071,0.7071,0", [0, 0, 0]).axes[2].tolist()
        [0.0, 0.0, 1.0]
        """
        if not isinstance(axes, str):  # the API passes what the caller gave
            raise ValueError(
                f"expected three signed axes such as '+y,-x,+z' (a str), got "
                f"{type(axes).__name__} {quote(axes)}"
            )
        if ";" in axes:
            return cls(np.asarray(origin_mm, dtype=float), _vector_axes(axes), label or axes)
        parts = [p.strip().lower() for p in axes.split(",")]
        rows = []
        for part in parts:
            sign = -1.0 if part.startswith("-") else 1.0
            name = part.lstrip("+-")
            if name not in _AXIS_INDEX or len(part) - len(name) > 1:
                raise ValueError(f"expected three signed axes such as '+y,-x,+z', got {axes!r}")
            row = np.zeros(3)
            row[_AXIS_INDEX[name]] = sign
            rows.append(row)
        if len(rows) != 3:
            raise ValueError(f"expected three signed axes such as '+y,-x,+z', got {axes!r}")
        return cls(np.asarray(origin_mm, dtype=float), np.array(rows), label or axes)

    def point_to_frame(self, point_mm: npt.ArrayLike) -> FloatArray:
        """Coordinates of a model point in this frame."""
        return np.asarray(self.axes @ (np.asarray(point_mm, dtype=float) - self.origin_mm))


def _vector_axes(text: str) -> FloatArray:
    """Rows of a right-handed orthonormal frame from ``"x1,x2,x3;y1,y2,y3[;z1,z2,z3]"``."""
    expected = "expected two or three axis vectors 'X1,X2,X3;Y1,Y2,Y3[;Z1,Z2,Z3]'"
    rows = []
    for part in text.split(";"):
        try:
            v = [float(c) for c in part.split(",")]
        except ValueError:
            v = []
        if len(v) != 3 or not all(np.isfinite(v)) or np.linalg.norm(v) == 0:
            raise ValueError(f"{expected}, got {text!r}")
        rows.append(np.asarray(v) / np.linalg.norm(v))
    if len(rows) not in (2, 3):
        raise ValueError(f"{expected}, got {text!r}")
    if len(rows) == 2:
        rows.append(np.cross(rows[0], rows[1]))
    r = np.array(rows)
    gram = r @ r.T - np.eye(3)
    worst = float(np.max(np.abs(gram)))
    if worst > SQUARE_UP_COS:
        raise ValueError(
            f"axes {text!r} are {np.degrees(np.arcsin(min(worst, 1.0))):.2g}° from perpendicular "
            f"(more than {np.degrees(np.arcsin(SQUARE_UP_COS)):.2g}°): expected orthogonal axes"
        )
    if np.linalg.det(r) < 0:
        raise ValueError(f"axes {text!r} are left-handed: expected x × y = z")
    u, _, vt = np.linalg.svd(r)  # the nearest orthonormal matrix (polar decomposition)
    return np.asarray(u @ vt)


def inertia_in_frame(props: MassProperties, frame: Frame) -> FloatArray:
    """Inertia tensor about the frame's origin, in the frame's axes (kg·mm²).

    ``R · J_o · Rᵀ`` with ``J_o`` the inertia about the origin by the parallel-axis theorem.

    Examples
    --------
    >>> from cadcog.mass.properties import box_properties
    >>> box = box_properties([2.0, 2.0, 2.0], [0, 0, 0], mass_kg=3.0)
    >>> inertia_in_frame(box, Frame.parse("+x,+y,+z", [1.0, 0, 0])).diagonal().tolist()
    [2.0, 5.0, 5.0]
    """
    j = props.inertia_about(frame.origin_mm)
    return np.asarray(frame.axes @ j @ frame.axes.T)
