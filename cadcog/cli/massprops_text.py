"""``cadcog massprops``'s readable output: audit, budget table, totals, inertia, overlaps, envelope.

Numbers go through :mod:`cadcog.core.numformat` (significant figures, a unit that fits); the
budget table through :func:`cadcog.spacecraft.mass_budget.budget_rows` (copies grouped, heaviest
first, small siblings collapsed). Products of inertia are labelled with their convention.
"""

from __future__ import annotations

import numpy as np

from cadcog.cli._table import text_table
from cadcog.core import numformat as nf
from cadcog.core import tolerances
from cadcog.mass.inertia import products_of_inertia
from cadcog.mass.properties import radii_of_gyration_mm
from cadcog.spacecraft.mass_budget import budget_rows
from cadcog.spacecraft.mass_summary import MassReport, density_sources

#: The products' convention as one short label beside them.
PRODUCT_LABELS = {
    "positive": "products Pxy = +∫xy dm; the tensor's entry is −Pxy",
    "negative": "products Ixy = −∫xy dm, the tensor's own entries",
}

#: Longest name shown in the budget table (longer ones are cut with "…").
NAME_MAX_CHARS = 60


def _count(n: int, one: str, many: str = "") -> str:
    return f"{n} {one if n == 1 else many or one + 's'}"


def budget_table(
    report: MassReport, depth: int, collapse_below: float = 0.0, indent: int = 0
) -> str:
    """The budget as a text table: ``node``, ``n × unit``, mass, share, ±, (with MGA), (face
    area, when computed), CoG (mm)."""
    b = report.budget
    rows = budget_rows(b.root, depth, collapse_below=collapse_below)
    unit = nf.mass_unit([b.root.mass_kg])
    known = b.root.surface_area_mm2
    area = None if known is None else nf.area_unit([known])
    body = []
    for r in rows:
        name = "  " * r.level + r.label
        if len(name) > NAME_MAX_CHARS:
            name = name[: NAME_MAX_CHARS - 1] + "…"
        each = (
            f"{r.count} × {nf.in_unit(r.unit_mass_kg, unit)}"
            if r.count > 1 and r.unit_mass_kg is not None
            else ""
        )
        sigma = "" if r.mass_sigma_kg is None else nf.in_unit(r.mass_sigma_kg, unit, 2)
        row = [name, each, nf.in_unit(r.mass_kg, unit), nf.share(r.share), sigma]
        if b.growth_kg:
            row.append(nf.in_unit(r.predicted_mass_kg, unit))
        if area is not None:
            row.append("" if r.surface_area_mm2 is None else nf.in_unit(r.surface_area_mm2, area))
        body.append([*row, nf.vector(r.cog_mm, 2)])
    u = unit[0]
    headers = ["mass budget", f"n × each ({u})", f"mass ({u})", "share", f"± 1σ ({u})"]
    if b.growth_kg:
        headers.append(f"with MGA ({u})")
    if area is not None:
        headers.append(f"area ({area[0]})")
    headers.append("CoG (mm)")
    if not any(row[1] for row in body):  # no copies grouped: no "n × each" column
        headers.pop(1)
        body = [[row[0], *row[2:]] for row in body]
    return text_table(headers, body, "l" + "r" * (len(headers) - 1), indent)


def print_report(
    report: MassReport, depth: int, products: str, collapse_below: float = 0.0
) -> None:
    """Readable report: audit, budget table, totals, inertia, overlaps, envelope, notes."""
    r, a, b = report.result, report.result.audit, report.budget
    units = ", ".join(a.declared_units) or "none"
    if a.units_override:
        units += f" (overridden: {a.units_override}, lengths × {a.scale_to_mm:g})"
    print(f"{a.source}: declared unit {units}")
    print(
        f"{_count(a.n_products, 'product')}, {_count(a.n_instances, 'instance')}: "
        f"{_count(a.n_solids, 'solid')}, {_count(a.n_surfaces, 'surface body', 'surface bodies')}"
        f"; densities from {density_sources(r.bodies)}"
    )
    if a.excluded:
        print(f"excluded: {len(a.excluded)} bodies")
    print()
    print(budget_table(report, depth, collapse_below))
    if collapse_below > 0:
        print(f"(siblings each under {nf.share(collapse_below)} of the mass summed as 'N others')")
    t = r.total
    unit = nf.mass_unit([t.mass_kg])
    line = f"\ntotal {nf.mass(t.mass_kg)}"
    if b.total_given:
        line += " (the weighed mass given, every density scaled to it)"
    elif b.mass_sigma_kg is not None:
        sigma = f"{nf.in_unit(b.mass_sigma_kg, unit, 2)} {unit[0]}"
        line += f" ± {sigma} (1 σ, {b.sigma_coverage:.0%} of the mass has one)"
    print(line + f", volume {nf.sig(t.volume_mm3, 5)} mm³")
    cog = f"CoG {nf.vector(t.cog_mm)} mm"
    if b.cog_cov_mm2 is not None:
        given = ", given that total" if b.total_given else ""
        cog += f" ± {nf.vector(np.sqrt(np.diag(b.cog_cov_mm2)))} mm (1 σ{given})"
    print(cog)
    if b.growth_kg:
        print(
            f"with growth allowances: {nf.mass(b.predicted.mass_kg)} "
            f"(+{nf.in_unit(b.growth_kg, unit)} {unit[0]}, {nf.share(b.growth_kg / t.mass_kg)}), "
            f"CoG {nf.vector(b.predicted.cog_mm)} mm"
        )
    print_inertia(report, products)
    print_rest(report)


def print_inertia(report: MassReport, products: str) -> None:
    """Moments and labelled products about the CoG, radii of gyration, principal axes, frame."""
    t = report.result.total
    j = t.inertia_kg_mm2
    unit = nf.inertia_unit(j.ravel())
    p = products_of_inertia(j, products)  # type: ignore[arg-type]
    print(f"\ninertia about the CoG, model axes ({unit[0]}):")
    print(
        f"  Ixx {nf.in_unit(j[0, 0], unit)}  Iyy {nf.in_unit(j[1, 1], unit)}  "
        f"Izz {nf.in_unit(j[2, 2], unit)}"
    )
    symbol = "P" if products == "positive" else "I"
    # a product below the integration's round-off of the tensor is 0 (a symmetric body's
    # printed as 7.858e-17; the JSON keeps every digit)
    floor = tolerances.ROUNDOFF_RELATIVE * float(np.max(np.abs(j)))
    q = {k: 0.0 if abs(v) < floor else v for k, v in p.items() if k in ("xy", "xz", "yz")}
    print(
        f"  {symbol}xy {nf.in_unit(q['xy'], unit)}  {symbol}xz {nf.in_unit(q['xz'], unit)}  "
        f"{symbol}yz {nf.in_unit(q['yz'], unit)}  ({PRODUCT_LABELS[products]}; --products)"
    )
    k = radii_of_gyration_mm(t.mass_kg, j)
    print(f"  radii of gyration kx {nf.sig(k[0])}  ky {nf.sig(k[1])}  kz {nf.sig(k[2])} mm")
    pa = report.principal
    print(f"principal moments ({unit[0]}) and axes (model components):")
    angles = pa.angles_from_frame_deg()
    for i, unique in enumerate(pa.unique()):
        where = f"{angles[i]:.1f}° from a model axis" if unique else "not unique: see below"
        print(
            f"  {nf.in_unit(pa.moments_kg_mm2[i], unit):>10}  {nf.vector(pa.axes[i], 4)}  ({where})"
        )
    if pa.degeneracy_note():
        print(f"  ({pa.degeneracy_note()})")
    f = report.frame
    if f.label != "cog, axes +x,+y,+z":
        jf = report.frame_inertia_kg_mm2
        fu = nf.inertia_unit(jf.ravel())
        print(
            f"\nin the frame at {f.label} (origin {nf.vector(f.origin_mm)} mm in model "
            "coordinates):"
        )
        print(f"  CoG {nf.vector(f.point_to_frame(t.cog_mm))} mm")
        print(f"  inertia tensor about the origin, frame axes ({fu[0]}; off-diagonal −∫x·y dm):")
        cells = [[nf.in_unit(v, fu) for v in row] for row in jf]
        print(text_table(["", "", ""], cells, "rrr", 2).split("\n", 1)[1])


def print_rest(report: MassReport) -> None:
    """Overlaps, the CoG envelope, info and notes."""
    r = report.result
    ov = r.overlaps
    if ov.pairs:
        print(f"\noverlaps ({ov.policy}): {ov.headline()}")
        for pair in ov.pairs[:10]:
            print(
                f"  {report.short(pair.a)} & {report.short(pair.b)}: "
                f"{nf.sig(pair.volume_mm3)} mm³, {nf.mass(pair.mass_kg)} "
                f"({'kept by' if ov.policy == 'resolve' else 'denser:'} "
                f"{report.short(pair.kept_by)})"
            )
        if len(ov.pairs) > 10:
            print(f"  ... {len(ov.pairs) - 10} more in --json and --csv")
    env = report.envelope
    if env is not None:
        label = env.form_factor or "custom"
        print(
            f"\n{label} CoG offset from the geometric centre {nf.vector(env.offset_mm, 2)} mm, "
            f"limits ±{nf.vector(env.limits_mm, 1)} mm: {env.verdict()} ({env.source})"
        )
    for n in r.info:
        print(f"info: {n}")
    for n in r.notes:
        print(f"note: {n}")


def print_configurations(report: MassReport) -> None:
    """One row per configuration: mass, CoG ± 1 σ, principal moments, envelope verdict."""
    if not report.configurations:
        return
    rows = []
    for c in report.configurations:
        sd = c.cog_sigma_mm
        moments = c.principal_moments_kg_mm2
        rows.append(
            [
                c.name,
                nf.mass(c.total.mass_kg),
                f"{nf.vector(c.total.cog_mm)} ± {nf.vector(sd)}",
                " ".join(nf.sig(m, 4) for m in moments),
                "" if c.envelope is None else c.envelope.verdict(),
                str(len(c.moved)),
            ]
        )
    print("\nconfigurations (the CoG ± 1 σ in mm; principal moments in kg·mm²):")
    print(
        text_table(
            ["configuration", "mass", "CoG (mm)", "principal moments", "envelope", "changed"],
            rows,
            "lrllll",
        )
    )
    for c in report.configurations:
        for note in c.overlaps:
            print(f"note: {note}")
