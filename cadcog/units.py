"""The one place where units are converted.

Every public boundary of cadcog uses millimetres, kilograms and degrees, with the unit in the
name (``_mm``, ``_kg``, ``_deg``, ``_kg_mm2``, ``_mm3``). Densities are quoted in kg/m³ in
parameter files and documents, because that is how material data sheets give them; internally
they are kg/mm³. Radians exist only inside numerical kernels and are produced here.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

#: Cubic millimetres in one cubic metre.
MM3_PER_M3 = 1.0e9


def density_kg_m3_to_kg_mm3(density_kg_m3: float) -> float:
    """Convert a density from kg/m³ to kg/mm³.

    Examples
    --------
    >>> density_kg_m3_to_kg_mm3(7850.0)
    7.85e-06
    """
    return density_kg_m3 / MM3_PER_M3


def density_kg_mm3_to_kg_m3(density_kg_mm3: float) -> float:
    """Convert a density from kg/mm³ to kg/m³.

    Examples
    --------
    >>> round(density_kg_mm3_to_kg_m3(7.85e-06), 6)
    7850.0
    """
    return density_kg_mm3 * MM3_PER_M3


def deg_to_rad(angle_deg: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """Degrees to radians (array-friendly)."""
    return np.deg2rad(np.asarray(angle_deg, dtype=float))


def rad_to_deg(angle_rad: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """Radians to degrees (array-friendly)."""
    return np.rad2deg(np.asarray(angle_rad, dtype=float))
