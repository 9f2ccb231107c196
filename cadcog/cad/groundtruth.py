"""Ground truth of a rig from its CAD: exact, density-weighted mass properties of every body.

The result is a plain-JSON dictionary (schema in ``docs/rig.md``), written as
``ground_truth.json`` by ``cadcog parts build``. It depends only on the rig file and the
geometry kernel, so rebuilding gives byte-identical output.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from cadcog.cad.occt import solid_properties
from cadcog.cad.rigsolids import RigModel
from cadcog.core import tolerances
from cadcog.core.units import density_kg_mm3_to_kg_m3
from cadcog.core.version import __version__
from cadcog.mass.properties import MassProperties, combine
from cadcog.rig.parameters import Rig

FORMAT = "cadcog-ground-truth/1"

FRAME = (
    "body frame: origin at a vertex of the proof mass, which occupies [0, size_mm]; x along its "
    "longest edge, y along its shortest, z completing a right-handed frame"
)


def _body(props: MassProperties, **extra: Any) -> dict[str, Any]:
    return {**props.to_dict(), **extra}


def ground_truth(rig: Rig, model: RigModel) -> dict[str, Any]:
    """Compute the ground-truth dictionary of ``rig`` from its built ``model``.

    Every solid is integrated on its own with its own density; the measurement equipment and the
    assembly are combined by mass.
    """
    integrated = {
        s.label: solid_properties(s.wrapped, model.densities_kg_mm3[s.label], name=s.label)
        for s in model.bodies
    }
    props = {name: ip.properties for name, ip in integrated.items()}
    pm = props["proof_mass"]
    me = combine(props[v.name] for v in rig.me_volumes)
    assembly = combine([pm, me])

    bodies: dict[str, Any] = {
        "proof_mass": _body(
            pm,
            material=rig.proof_mass.material,
            density_kg_m3=density_kg_mm3_to_kg_m3(model.densities_kg_mm3["proof_mass"]),
        ),
        "measurement_equipment": _body(me),
    }
    for v in rig.me_volumes:
        bodies[v.name] = _body(
            props[v.name], density_kg_m3=density_kg_mm3_to_kg_m3(model.densities_kg_mm3[v.name])
        )

    size = np.asarray(rig.proof_mass.size_mm)
    # Shift of the proof-mass CoG from the box centre caused by the holes; differences below
    # round-off of the coordinates themselves are written as 0.
    hole_shift = pm.cog_mm - 0.5 * size
    hole_shift[np.abs(hole_shift) < tolerances.ROUNDOFF_RELATIVE * float(size.max())] = 0.0
    readings = rig.ideal_readings(assembly.cog_mm)
    points = []
    for p in rig.suspension_points:
        r = readings[p.id]
        points.append(
            {
                "id": p.id,
                "face": p.face,
                "position_mm": list(p.position_mm),
                "normal": p.normal.tolist(),
                "wire_exit_mm": rig.wire_exit_mm(p).tolist(),
                "ideal_reading_deg": [r.inc_x_deg, r.inc_y_deg],
                "top_face_up": r.top_face_up,
                "in_range": r.in_range(rig.inclinometer_range_deg),
            }
        )

    worst_error = max(ip.relative_error for ip in integrated.values())
    return {
        "format": FORMAT,
        "cadcog_version": __version__,
        "rig": rig.name,
        "frame": FRAME,
        "bodies": bodies,
        "assembly": _body(assembly),
        "hole_cog_shift_mm": hole_shift.tolist(),
        "suspension_points": points,
        "inclinometer_range_deg": rig.inclinometer_range_deg,
        "me_cog_uncertainty_boxes": [
            {
                "name": v.name,
                "mass_kg": v.mass_kg,
                "center_mm": props[v.name].cog_mm.tolist(),
                "edge_mm": v.cog_uncertainty_cube_mm,
            }
            for v in rig.me_volumes
        ],
        "integration": {
            "method": "OCCT BRepGProp adaptive Gauss volume integration per solid, "
            "weighted by each solid's density",
            "requested_relative_error": tolerances.OCCT_INTEGRATION_EPS,
            # Two significant digits: the estimate is itself noise at the 1e-16 level.
            "estimated_relative_error": float(f"{worst_error:.2g}"),
        },
    }
