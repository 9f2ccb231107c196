"""``cadcog massprops --csv PATH``: the mass budget and every body as one CSV table.

One header row, then one row per budget node (identical sibling copies grouped as in the text
table, heaviest first, every level; kind ``node``), then one row per body (kind ``body``), so
that the file pastes into a mass-budget spreadsheet as it is. Units are the JSON's: kg, mm,
kg·mm², full precision (``repr`` of each float). Inertia is about the row's own CoG in model
axes; the products are ``Pxy = +∫ x·y dm`` (the tensor's off-diagonal entry is ``−Pxy``: the
header says so); ``Ixx_total_cog_kg_mm2``... are the row's moments about the *total's* CoG
(its contribution to the total's moments). Bodies carry their material, density source and
density; nodes leave those cells empty. A node row's ``count`` is the number of identical copies
it stands for and ``unit_mass_kg`` the mass of one. ``area_mm2`` is a surface body's area (the
one its areal density multiplies); ``surface_area_mm2``, with ``--surface-area``, every body's
face area and each node's sum (empty without it).

Examples
--------
>>> HEADER[:6]
('kind', 'level', 'path', 'name', 'count', 'unit_mass_kg')
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any

import numpy as np

from cadcog.core.fileio import staged_file
from cadcog.mass.inertia import products_of_inertia
from cadcog.spacecraft.mass_budget import budget_rows
from cadcog.spacecraft.mass_summary import MassReport

#: The columns, in order (products in the positive convention, named in the header).
HEADER = (
    "kind",
    "level",
    "path",
    "name",
    "count",
    "unit_mass_kg",
    "mass_kg",
    "share",
    "mass_sigma_kg",
    "n_bodies",
    "cog_x_mm",
    "cog_y_mm",
    "cog_z_mm",
    "Ixx_kg_mm2",
    "Iyy_kg_mm2",
    "Izz_kg_mm2",
    "Pxy_kg_mm2 (+∫xy dm)",
    "Pxz_kg_mm2 (+∫xz dm)",
    "Pyz_kg_mm2 (+∫yz dm)",
    "kx_mm",
    "ky_mm",
    "kz_mm",
    "Ixx_total_cog_kg_mm2",
    "Iyy_total_cog_kg_mm2",
    "Izz_total_cog_kg_mm2",
    "kind_of_body",
    "material",
    "density_source",
    "density_kg_m3",
    "volume_mm3",
    "area_mm2",
    "surface_area_mm2",
)


def _f(value: float | None) -> str:
    return "" if value is None else repr(float(value) + 0.0)


def _inertia_cells(j: np.ndarray, mass_kg: float, about_total: np.ndarray) -> list[str]:
    p = products_of_inertia(j, "positive")
    k = np.sqrt(np.clip(np.diagonal(j), 0.0, None) / mass_kg) if mass_kg > 0 else np.zeros(3)
    return [
        *(_f(j[i, i]) for i in range(3)),
        _f(p["xy"]),
        _f(p["xz"]),
        _f(p["yz"]),
        *(_f(v) for v in k),
        *(_f(about_total[i, i]) for i in range(3)),
    ]


def csv_rows(report: MassReport) -> list[list[str]]:
    """The table's rows after the header (strings, as written)."""
    total = report.result.total
    rows: list[list[str]] = []
    for r in budget_rows(report.budget.root):
        about_total = r.inertia_kg_mm2 + r.mass_kg * (
            np.dot(d := total.cog_mm - r.cog_mm, d) * np.eye(3) - np.outer(d, d)
        )
        rows.append(
            [
                "node",
                str(r.level),
                r.path,
                r.label,
                str(r.count),
                _f(r.unit_mass_kg),
                _f(r.mass_kg),
                _f(r.share),
                _f(r.mass_sigma_kg),
                str(r.n_bodies),
                *(_f(v) for v in r.cog_mm),
                *_inertia_cells(r.inertia_kg_mm2, r.mass_kg, about_total),
                "",
                "",
                "",
                "",
                "",
                "",
                _f(r.surface_area_mm2),
            ]
        )
    m_total = total.mass_kg
    below_top = 1 if report.root_prefix else 0  # the root row is the one top assembly
    for b in report.result.bodies:
        p = b.properties
        info: dict[str, Any] = b.to_dict()
        rows.append(
            [
                "body",
                str(len(b.nodes) - below_top),
                b.path,
                b.name,
                "1",
                _f(p.mass_kg),
                _f(p.mass_kg),
                _f(p.mass_kg / m_total),
                _f(None if b.sigma_rel is None else b.sigma_rel * p.mass_kg),
                "1",
                *(_f(v) for v in p.cog_mm),
                *_inertia_cells(p.inertia_kg_mm2, p.mass_kg, p.inertia_about(total.cog_mm)),
                b.kind,
                b.material,
                b.density_source,
                _f(info.get("density_kg_m3")),
                _f(p.volume_mm3) if b.kind == "solid" else "",
                _f(info.get("area_mm2")) if b.kind == "surface" else "",
                _f(b.surface_area_mm2),
            ]
        )
    return rows


def write_budget_csv(report: MassReport, path: str | Path) -> Path:
    """Write the table to ``path`` whole (staged, then moved) and return it."""
    with staged_file(path) as tmp, open(tmp, "w", encoding="utf-8", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(HEADER)
        w.writerows(csv_rows(report))
    return Path(path)
