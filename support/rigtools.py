"""Helpers for tests that need modified rig files: the paper rig as a dict, and a TOML writer.

The writer covers exactly what rig files use (scalars, arrays of scalars, tables and arrays of
tables nested under tables) so tests can change one key and write the file back.
"""

from __future__ import annotations

import copy
import json
import tomllib
from pathlib import Path
from typing import Any

from cadcog.rig.file import default_rig_path


def paper_rig_dict() -> dict[str, Any]:
    with default_rig_path().open("rb") as fh:
        return copy.deepcopy(tomllib.load(fh))


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(type(v))


def _is_table_array(v: Any) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def _emit(lines: list[str], table: dict[str, Any], prefix: str) -> None:
    for k, v in table.items():
        if not isinstance(v, dict) and not _is_table_array(v):
            lines.append(f"{k} = {_value(v)}")
    for k, v in table.items():
        name = f"{prefix}.{k}" if prefix else k
        if isinstance(v, dict):
            lines.append(f"\n[{name}]")
            _emit(lines, v, name)
        elif _is_table_array(v):
            for item in v:
                lines.append(f"\n[[{name}]]")
                _emit(lines, item, name)


def to_toml(data: dict[str, Any]) -> str:
    lines: list[str] = []
    _emit(lines, data, "")
    return "\n".join(lines) + "\n"


def write_rig(path: Path, data: dict[str, Any]) -> Path:
    path.write_text(to_toml(data), encoding="utf-8")
    return path


#: The paper rig's top face (mm): a sensor package resting above it sits on a spacer.
PAPER_TOP_Z_MM = 78.0


def package_rig(
    path: Path,
    *,
    package: tuple[float, tuple[float, float, float], tuple[float, float, float]],
    volume_name: str,
    inclinometer: dict[str, Any],
    swing: dict[str, Any],
    points: tuple[int, ...] | None = None,
) -> Path:
    """The paper rig read by a sensor package laid on it, written to ``path``.

    ``package`` is the package's mass (kg), centre and size (mm); it is the rig's whole ME (one
    volume named ``volume_name``), on a 0.1 g spacer down to the top face when it does not rest
    on it. ``inclinometer`` and ``swing`` are the rig's tables of those names; ``points`` the
    indices of the suspension points kept (all six by default).
    """
    data = paper_rig_dict()
    data["inclinometer"] = dict(inclinometer)
    mass, centre, size = package
    volumes: list[dict[str, Any]] = [
        {"name": volume_name, "size_mm": list(size), "center_mm": list(centre),
         "mass_kg": mass, "cog_uncertainty_cube_mm": 5.0},
    ]  # fmt: skip
    gap = centre[2] - size[2] / 2 - PAPER_TOP_Z_MM
    if gap > 1e-6:
        volumes.append(
            {"name": "spacer", "size_mm": [10.0, 10.0, gap],
             "center_mm": [centre[0], centre[1], PAPER_TOP_Z_MM + gap / 2], "mass_kg": 1e-4,
             "cog_uncertainty_cube_mm": 1.0}
        )  # fmt: skip
    data["measurement_equipment"]["volumes"] = volumes
    if points is not None:
        data["suspension_points"] = [data["suspension_points"][i] for i in points]
    data["swing"] = dict(swing)
    return write_rig(path, data)


HEADER = "point_id,x_mm,y_mm,z_mm,inc_x_deg,inc_y_deg,top_face_up"


def ideal_rows(rig: Any, wire_offset_mm: float | None = None) -> list[str]:
    """One noise-free readings row per suspension point of ``rig`` (assembly CoG).

    The body hangs from the virtual suspension point above the wire exit along the bolt axis:
    the wire scale ``wire_offset_mm`` (default: the one the rig's error model expects, which
    ``cadcog estimate`` corrects) times the model's shape at the hang's angle (1 for the
    paper's model, ``1/cos(θ/2)`` for the elastica and one-wire models); the row gives the
    wire exit, as a lab would.
    """
    import numpy as np

    from cadcog.method.errormodel import ErrorModel
    from cadcog.method.wire import wire_shape_factor
    from cadcog.rig.geometry import ideal_reading

    model = ErrorModel.from_rig(rig)
    scale = model.wire_prior(rig.weight_n).scale_mm if wire_offset_mm is None else wire_offset_mm
    shaped = model.wire_model != "paper"
    g = rig.analytic_assembly.cog_mm
    rows = []
    for p in rig.suspension_points:
        w = rig.wire_exit_mm(p)
        offset = scale
        for _ in range(50 if shaped else 0):  # the angle depends on the offset: a fixed point
            up = (w + offset * p.normal - g) / np.linalg.norm(w + offset * p.normal - g)
            offset = scale * float(wire_shape_factor(up @ p.normal, model.wire_model))
        r = ideal_reading(w + offset * p.normal, g)
        rows.append(
            f"{p.id},{float(w[0])!r},{float(w[1])!r},{float(w[2])!r},{r.inc_x_deg!r},{r.inc_y_deg!r},"
            f"{str(r.top_face_up).lower()}"
        )
    return rows


def write_csv(path: Path, rows: list[str], header: str = HEADER) -> Path:
    path.write_text("\n".join([header, *rows]) + "\n", encoding="utf-8")
    return path
