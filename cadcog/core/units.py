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

#: Square millimetres in one square metre.
MM2_PER_M2 = 1.0e6

#: Millimetres in one metre.
MM_PER_M = 1.0e3

#: kg·mm² in one kg·m² (inertia).
KG_MM2_PER_KG_M2 = 1.0e6


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


#: Millimetres per length unit, by the names STEP files (and OCCT's reader) use for them.
LENGTH_UNIT_MM: dict[str, float] = {
    "millimetre": 1.0,
    "millimeter": 1.0,
    "mm": 1.0,
    "micrometre": 1e-3,
    "micrometer": 1e-3,
    "centimetre": 10.0,
    "centimeter": 10.0,
    "cm": 10.0,
    "decimetre": 100.0,
    "metre": 1000.0,
    "meter": 1000.0,
    "m": 1000.0,
    "kilometre": 1e6,
    "inch": 25.4,
    "in": 25.4,
    "foot": 304.8,
    "ft": 304.8,
    "mil": 0.0254,
}

#: Length units a user may name for a model (``--units``, set-up ``units``): keys of
#: :data:`LENGTH_UNIT_MM`.
UNIT_CHOICES = ("mm", "cm", "m", "in", "ft")

#: kg/m³ per unit of density, by the unit names material data in STEP files use.
_DENSITY_KG_M3 = {
    "kg/m^3": 1.0,
    "kg/m3": 1.0,
    "g/cm^3": 1000.0,
    "g/cm3": 1000.0,
    "g/cc": 1000.0,
    "kg/mm^3": 1e9,
    "kg/mm3": 1e9,
    "g/mm^3": 1e6,
    "g/mm3": 1e6,
    "lb/in^3": 27679.9047,
    "lb/in3": 27679.9047,
}


def density_kg_m3_from_named_unit(value: float, unit: str) -> float | None:
    """A density given with a unit name, in kg/m³; None if the unit is not recognised.

    Examples
    --------
    >>> density_kg_m3_from_named_unit(7.85, "g/cm^3")
    7850.0
    >>> density_kg_m3_from_named_unit(2700.0, "kg/m^3"), density_kg_m3_from_named_unit(1, "?")
    (2700.0, None)
    """
    factor = _DENSITY_KG_M3.get(unit.strip().lower().replace(" ", ""))
    return None if factor is None else value * factor


def density_kg_m3_from_step(
    value: float, unit: str, plausible_kg_m3: tuple[float, float] = (10.0, 25_000.0)
) -> float | None:
    """A material density as OCCT's STEP reader reports it, in kg/m³; None if unknown.

    The reader passes on the value of the file's density measure and the measure's *name*:
    when the name is a unit (``kg/m^3``, ``g/cm^3``, ...) it is used. Otherwise (Fusion 360
    writes ``density measure``) the unit depends on how the file declared it: OCCT converts a
    kg·m⁻³ declaration to g/mm³ (7850 kg/m³ arrives as 0.00785) but passes a g·cm⁻³ one
    unchanged (2.7). Both readings are tried; the one inside ``plausible_kg_m3`` is taken. They
    differ by 1000, so at most one fits, except for values between 10 and 25 kg/m³ against
    10 000 and 25 000 kg/m³, which are left unknown.

    Examples
    --------
    >>> density_kg_m3_from_step(0.00785, "density measure"), density_kg_m3_from_step(2.7, "")
    (7850.0, 2700.0)
    >>> density_kg_m3_from_step(2700.0, "kg/m^3"), density_kg_m3_from_step(0.015, "?")
    (2700.0, None)
    """
    named = density_kg_m3_from_named_unit(value, unit)
    if named is not None or not value > 0:
        return named
    lo, hi = plausible_kg_m3
    fits = [d for d in (value * 1e3, value * 1e6) if lo <= d <= hi]  # g/cm³, g/mm³
    return float(f"{fits[0]:.12g}") if len(fits) == 1 else None  # no 7849.999999999999


def areal_density_kg_m2_to_kg_mm2(areal_density_kg_m2: float) -> float:
    """Convert an areal density from kg/m² to kg/mm².

    Examples
    --------
    >>> areal_density_kg_m2_to_kg_mm2(0.5)
    5e-07
    """
    return areal_density_kg_m2 / MM2_PER_M2


#: Standard gravity (m/s²), to turn masses into the wire tension W.
STANDARD_GRAVITY_M_S2 = 9.80665

#: Density of dry air at 20 °C and 101.325 kPa (kg/m³): what a swinging body carries with it.
AIR_DENSITY_KG_M3 = 1.204
