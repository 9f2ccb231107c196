"""Mass properties as values: a small immutable result object and closed forms.

This module is the functional numeric core used by both the CAD layer (which fills
:class:`MassProperties` from exact B-rep integration) and the analytic cross-checks (boxes and
cylinders in closed form). It never imports build123d.

Conventions
-----------
- ``inertia_kg_mm2`` is the inertia tensor about the body's own centre of gravity, in the axes of
  the body frame: ``I = ∫ ρ (|r|² 𝟙 - r rᵀ) dV`` with ``r`` measured from the CoG, so the
  off-diagonal entries are the *negated* products of inertia.
- A mass property set with negative mass describes removed material (a drilled hole) and is only
  meaningful inside :func:`combine`.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from cadcog.core import tolerances
from cadcog.core.results import JsonResult

FloatArray = npt.NDArray[np.float64]


def _vec3(value: npt.ArrayLike, name: str) -> FloatArray:
    arr = np.array(value, dtype=float)
    if arr.shape != (3,):
        raise ValueError(f"{name} must have shape (3,), got {arr.shape}")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class MassProperties(JsonResult):
    """Mass, centre of gravity, central inertia and volume of a rigid body.

    Parameters
    ----------
    mass_kg : float
        Mass in kg (negative only for removed material, see :func:`combine`).
    cog_mm : array_like, shape (3,)
        Centre of gravity in mm, body frame.
    inertia_kg_mm2 : array_like, shape (3, 3)
        Inertia tensor about the CoG in kg·mm², body-frame axes.
    volume_mm3 : float
        Volume in mm³.

    Examples
    --------
    >>> p = box_properties([10.0, 20.0, 30.0], [0.0, 0.0, 0.0], mass_kg=6.0)
    >>> float(p.inertia_kg_mm2[0, 0])  # m (b² + c²) / 12
    650.0
    >>> p.density_kg_mm3  # 6 kg in 6000 mm³
    0.001
    """

    mass_kg: float
    cog_mm: FloatArray
    inertia_kg_mm2: FloatArray
    volume_mm3: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass_kg", float(self.mass_kg))
        object.__setattr__(self, "volume_mm3", float(self.volume_mm3))
        object.__setattr__(self, "cog_mm", _vec3(self.cog_mm, "cog_mm"))
        inertia = np.array(self.inertia_kg_mm2, dtype=float)
        if inertia.shape != (3, 3):
            raise ValueError(f"inertia_kg_mm2 must have shape (3, 3), got {inertia.shape}")
        inertia.setflags(write=False)
        object.__setattr__(self, "inertia_kg_mm2", inertia)

    @property
    def density_kg_mm3(self) -> float:
        """Mean density, mass / volume (kg/mm³)."""
        return self.mass_kg / self.volume_mm3

    def inertia_about(self, point_mm: npt.ArrayLike) -> FloatArray:
        """Inertia tensor about ``point_mm`` (parallel-axis theorem), body-frame axes.

        Parameters
        ----------
        point_mm : array_like, shape (3,)

        Returns
        -------
        ndarray, shape (3, 3)
            kg·mm².
        """
        d = np.asarray(point_mm, dtype=float) - self.cog_mm
        if d.shape != (3,):
            raise ValueError(f"point_mm must have shape (3,), got {d.shape}")
        shift = parallel_axis_kg_mm2(np.array([self.mass_kg]), d[None, :])[0]
        return np.asarray(self.inertia_kg_mm2 + shift)

    def scaled(self, factor: float) -> MassProperties:
        """The same body with mass multiplied by ``factor`` (``-1`` marks removed material)."""
        return MassProperties(
            self.mass_kg * factor,
            self.cog_mm,
            self.inertia_kg_mm2 * factor,
            self.volume_mm3 * factor,
        )

    def to_dict(self) -> dict[str, object]:
        """Plain-JSON representation with unit-suffixed keys (inertia round-off snapped to 0)."""
        return {
            "mass_kg": self.mass_kg,
            "cog_mm": self.cog_mm.tolist(),
            "inertia_kg_mm2": snap_roundoff(self.inertia_kg_mm2).tolist(),
            "volume_mm3": self.volume_mm3,
        }


def snap_roundoff(values: npt.ArrayLike, relative: float | None = None) -> FloatArray:
    """Set entries below ``relative`` × the largest magnitude to exactly zero.

    The default threshold is :data:`cadcog.core.tolerances.ROUNDOFF_RELATIVE`.

    Examples
    --------
    >>> snap_roundoff([1.0, 1e-14, -2.0]).tolist()
    [1.0, 0.0, -2.0]
    """
    arr = np.array(values, dtype=float)
    rel = tolerances.ROUNDOFF_RELATIVE if relative is None else relative
    scale = float(np.max(np.abs(arr))) if arr.size else 0.0
    arr[np.abs(arr) < rel * scale] = 0.0
    return arr


def parallel_axis_kg_mm2(masses_kg: FloatArray, offsets_mm: FloatArray) -> FloatArray:
    """What moving the inertia of point masses adds, for many at once: ``mᵢ (|dᵢ|² 1 − dᵢ dᵢᵀ)``.

    The one place the parallel-axis term is computed (:meth:`MassProperties.inertia_about` calls
    it for one mass), element-wise in numpy (no BLAS dot, whose summation order depends on the
    machine), vectorised over the first axis.

    Parameters
    ----------
    masses_kg : ndarray, shape (n,)
    offsets_mm : ndarray, shape (n, 3)
        From each body's CoG to the new reference point.

    Returns
    -------
    ndarray, shape (n, 3, 3)
        kg·mm².

    Examples
    --------
    >>> parallel_axis_kg_mm2(np.array([2.0]), np.array([[0.0, 0.0, 3.0]]))[0].tolist()
    [[18.0, 0.0, 0.0], [0.0, 18.0, 0.0], [0.0, 0.0, 0.0]]
    """
    d = offsets_mm
    shift = (d * d).sum(axis=1)[:, None, None] * np.eye(3) - d[:, :, None] * d[:, None, :]
    return np.asarray(masses_kg[:, None, None] * shift)


def radii_of_gyration_mm(mass_kg: float, inertia_kg_mm2: npt.ArrayLike) -> FloatArray:
    """``k = √(I / m)`` of each diagonal moment (mm), shape (3,): the one place it is computed
    (a negative round-off moment reads 0; a massless body has none, zeros).

    Examples
    --------
    >>> radii_of_gyration_mm(2.0, np.diag([50.0, 18.0, 0.0])).tolist()
    [5.0, 3.0, 0.0]
    """
    d = np.clip(np.diagonal(np.asarray(inertia_kg_mm2, dtype=float)), 0.0, None)
    return np.asarray(np.sqrt(d / mass_kg)) if mass_kg > 0 else np.zeros(3)


def combine(parts: Iterable[MassProperties]) -> MassProperties:
    """Mass properties of a union of bodies: masses add, the CoG is mass-weighted.

    Parts with negative mass subtract (material removed from a body that contains it).

    Raises
    ------
    ValueError
        If there are no parts or the total mass is not positive.

    Examples
    --------
    >>> a = box_properties([1, 1, 1], [0, 0, 0], mass_kg=1.0)
    >>> b = box_properties([1, 1, 1], [3, 0, 0], mass_kg=3.0)
    >>> combine([a, b]).cog_mm.tolist()
    [2.25, 0.0, 0.0]
    """
    items = list(parts)
    if not items:
        raise ValueError("combine() needs at least one part")
    mass_kg = sum(p.mass_kg for p in items)
    if not mass_kg > 0.0:
        raise ValueError(f"combined mass must be positive, got {mass_kg} kg")
    # Vectorised over the parts with :meth:`MassProperties.inertia_about`'s kernel; equal to the
    # part-by-part sum within the floating-point bound of the sums (property-tested), not
    # promised to the bit: numpy may order a reduction differently on another machine.
    masses = np.array([p.mass_kg for p in items])
    cogs = np.array([p.cog_mm for p in items])
    cog_mm = np.sum(masses[:, None] * cogs, axis=0) / mass_kg
    inertia = np.sum(
        np.array([p.inertia_kg_mm2 for p in items]) + parallel_axis_kg_mm2(masses, cog_mm - cogs),
        axis=0,
    )
    volume_mm3 = sum(p.volume_mm3 for p in items)
    return MassProperties(mass_kg, cog_mm, inertia, volume_mm3)


def box_properties(
    size_mm: npt.ArrayLike, center_mm: npt.ArrayLike, *, mass_kg: float
) -> MassProperties:
    """Closed-form mass properties of a homogeneous, axis-aligned box.

    Parameters
    ----------
    size_mm : array_like, shape (3,)
        Edge lengths along x, y, z (mm).
    center_mm : array_like, shape (3,)
        Centre (mm).
    mass_kg : float

    Examples
    --------
    >>> box_properties([2, 2, 2], [1, 1, 1], mass_kg=1.0).volume_mm3
    8.0
    """
    a, b, c = _vec3(size_mm, "size_mm")
    inertia = mass_kg / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    return MassProperties(mass_kg, np.asarray(center_mm, dtype=float), inertia, a * b * c)


def cylinder_properties(
    base_center_mm: npt.ArrayLike,
    axis: npt.ArrayLike,
    radius_mm: float,
    height_mm: float,
    *,
    density_kg_mm3: float,
) -> MassProperties:
    """Closed-form mass properties of a homogeneous right circular cylinder.

    Parameters
    ----------
    base_center_mm : array_like, shape (3,)
        Centre of one end face (mm).
    axis : array_like, shape (3,)
        Direction from that end face to the other (normalised here).
    radius_mm, height_mm : float
    density_kg_mm3 : float

    Examples
    --------
    >>> p = cylinder_properties([0, 0, 0], [0, 0, 2], 1.0, 4.0, density_kg_mm3=1.0)
    >>> p.cog_mm.tolist()
    [0.0, 0.0, 2.0]
    >>> round(float(p.inertia_kg_mm2[2, 2]) / p.mass_kg, 12)  # r² / 2
    0.5
    """
    a = _vec3(axis, "axis")
    a = a / np.linalg.norm(a)
    volume = np.pi * radius_mm**2 * height_mm
    mass = density_kg_mm3 * volume
    axial = 0.5 * mass * radius_mm**2
    transverse = mass * (3.0 * radius_mm**2 + height_mm**2) / 12.0
    aa = np.outer(a, a)
    inertia = axial * aa + transverse * (np.eye(3) - aa)
    cog = _vec3(base_center_mm, "base_center_mm") + 0.5 * height_mm * a
    return MassProperties(mass, cog, inertia, volume)
