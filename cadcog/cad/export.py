"""STEP and STL export with controlled, absolute tessellation."""

from __future__ import annotations

from pathlib import Path

import build123d as bd
from OCP.BRepMesh import BRepMesh_IncrementalMesh
from OCP.StlAPI import StlAPI_Writer

from cadcog.cad.assembly import step_timestamp
from cadcog.core import tolerances
from cadcog.core.errors import CadcogError
from cadcog.core.fileio import silent_write_failure
from cadcog.core.units import deg_to_rad


def write_step(assembly: bd.Compound, path: Path) -> None:
    """Write a labelled assembly to STEP (AP214, mm); the labels become product names."""
    try:
        written = bd.export_step(assembly, path, timestamp=step_timestamp())
    except RuntimeError:  # build123d raises where OCCT's writer returns a failure
        written = False
    if not written:
        raise CadcogError(f"{path}: STEP export failed ({silent_write_failure()})")


def write_stl(
    solid: bd.Shape,
    path: Path,
    deflection_mm: float = tolerances.STL_DEFLECTION_MM,
    angular_deflection_deg: float = tolerances.STL_ANGULAR_DEFLECTION_DEG,
) -> None:
    """Write a binary STL tessellated with an *absolute* chordal deflection.

    build123d's ``export_stl`` passes its tolerance to OCCT as a relative deflection, which is
    only ~0.1 % accurate on curved parts; here the deflection is in mm, so the volume error of the
    mesh is bounded by ``deflection_mm`` times the curved area.
    """
    mesh = BRepMesh_IncrementalMesh(
        solid.wrapped, deflection_mm, False, float(deg_to_rad(angular_deflection_deg)), True
    )
    mesh.Perform()
    writer = StlAPI_Writer()
    writer.ASCIIMode = False
    if not writer.Write(solid.wrapped, str(path)):
        raise CadcogError(f"{path}: STL export failed ({silent_write_failure()})")
