"""Exact mass properties of B-rep solids by OCCT's volume integration.

Each solid is integrated on its own (``BRepGProp.VolumeProperties_s`` with a requested relative
error) and given its own density; assemblies are combined by mass with
:func:`cadcog.massprops.combine`. Never use ``center(CenterOf.MASS)`` of a compound for this: it
weights solids by volume, not by mass.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from OCP.BRepGProp import BRepGProp
from OCP.GProp import GProp_GProps
from OCP.TopoDS import TopoDS_Shape

from cadcog import tolerances
from cadcog.errors import CadcogError
from cadcog.massprops import MassProperties


@dataclass(frozen=True)
class IntegratedProperties:
    """Mass properties of one solid, with OCCT's estimate of its relative integration error."""

    properties: MassProperties
    relative_error: float


def solid_properties(
    shape: TopoDS_Shape, density_kg_mm3: float, *, name: str = "solid"
) -> IntegratedProperties:
    """Mass properties of one closed solid of uniform density, by exact B-rep integration.

    Parameters
    ----------
    shape : OCP TopoDS_Shape
        A closed solid (``build123d.Solid.wrapped``).
    density_kg_mm3 : float
    name : str
        Used in error messages.

    Raises
    ------
    CadcogError
        If the solid has no positive volume (open shell or inverted orientation).
    """
    props = GProp_GProps()
    error = BRepGProp.VolumeProperties_s(shape, props, tolerances.OCCT_INTEGRATION_EPS, True)
    volume = props.Mass()
    if not volume > 0.0:
        raise CadcogError(f"{name}: integrated volume is {volume} mm³; expected a closed solid")
    c = props.CentreOfMass()
    m = props.MatrixOfInertia()
    inertia = np.array([[m.Value(i, j) for j in (1, 2, 3)] for i in (1, 2, 3)])
    mp = MassProperties(
        mass_kg=density_kg_mm3 * volume,
        cog_mm=np.array([c.X(), c.Y(), c.Z()]),
        inertia_kg_mm2=density_kg_mm3 * inertia,
        volume_mm3=volume,
    )
    return IntegratedProperties(mp, float(error))
