"""Parametric build123d models of a rig.

Coordinate frame: the body frame of :mod:`cadcog.rig.geometry` (origin at a proof-mass vertex, the
proof mass in ``[0, size_mm]``). Every solid carries a label, which the STEP assembly keeps.
"""

from __future__ import annotations

from dataclasses import dataclass

import build123d as bd

from cadcog.core.errors import CadcogError
from cadcog.rig.parameters import MEVolume, Rig


@dataclass(frozen=True)
class RigModel:
    """The solids of a rig, each labelled, and the density each is made of.

    Attributes
    ----------
    proof_mass : build123d.Solid
        The box with one hole per suspension point.
    me_volumes : tuple of build123d.Solid
        One box per ME sub-volume, in the rig file's order.
    densities_kg_mm3 : dict
        Label → density (kg/mm³).
    """

    proof_mass: bd.Solid
    me_volumes: tuple[bd.Solid, ...]
    densities_kg_mm3: dict[str, float]

    @property
    def bodies(self) -> tuple[bd.Solid, ...]:
        """Every solid, proof mass first."""
        return (self.proof_mass, *self.me_volumes)

    def assembly(self, name: str) -> bd.Compound:
        """A named assembly: ``name`` → (proof_mass, measurement_equipment → volumes)."""
        me = bd.Compound(children=list(self.me_volumes), label="measurement_equipment")
        return bd.Compound(children=[self.proof_mass, me], label=name)


def build_proof_mass(rig: Rig) -> bd.Solid:
    """The proof mass: a box in ``[0, size_mm]`` with a flat-bottomed hole per suspension point.

    Raises
    ------
    CadcogError
        If the boolean cut does not leave exactly one solid.
    """
    sx, sy, sz = rig.proof_mass.size_mm
    body = bd.Solid.make_box(sx, sy, sz)
    cutters = [
        bd.Solid.make_cylinder(
            rig.hole_radius_mm,
            rig.holes.depth_mm,
            bd.Plane(origin=p.position_mm, z_dir=tuple(-p.normal)),
        )
        for p in rig.suspension_points
    ]
    solids = body.cut(*cutters).solids()
    if len(solids) != 1:
        raise CadcogError(f"cutting the holes left {len(solids)} solids, expected one")
    solid = solids[0]
    solid.label = "proof_mass"
    return solid


def build_me_volume(volume: MEVolume) -> bd.Solid:
    """One ME sub-volume as an axis-aligned box centred on ``center_mm``."""
    sx, sy, sz = volume.size_mm
    solid = bd.Solid.make_box(sx, sy, sz, bd.Plane(origin=tuple(volume.min_mm)))
    solid.label = volume.name
    return solid


def build_rig(rig: Rig) -> RigModel:
    """Build every solid of ``rig``."""
    densities = {"proof_mass": rig.proof_mass_density_kg_mm3}
    for v in rig.me_volumes:
        densities[v.name] = v.mass_kg / (v.size_mm[0] * v.size_mm[1] * v.size_mm[2])
    return RigModel(
        proof_mass=build_proof_mass(rig),
        me_volumes=tuple(build_me_volume(v) for v in rig.me_volumes),
        densities_kg_mm3=densities,
    )
