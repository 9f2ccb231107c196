"""``cadcog massprops --report DIR``: a spacecraft model's mass properties as one HTML page.

The page holds the import audit (declared unit, products and instances, solids, surface bodies,
overlaps, invalid topology, density sources, notes), the mass budget tree, the mass properties
(inertia in both product conventions, principal moments and axes, the user's frame), three
views of the model with its CoG, principal axes and CubeSat envelope, and every body. The
figure is embedded, so ``index.html`` is self-contained; ``views.png`` and ``massprops.json``
are written beside it. Files appear whole or not at all (staged, then moved).
"""

from __future__ import annotations

import html
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from cadcog.core import numformat as nf
from cadcog.core.fileio import staged_output_dir
from cadcog.core.jsontext import dumps_json
from cadcog.core.numformat import signed
from cadcog.core.version import __version__
from cadcog.mass.inertia import PRODUCT_CONVENTIONS, TENSOR_CONVENTION, products_of_inertia
from cadcog.mass.properties import radii_of_gyration_mm
from cadcog.reports.html import CSS, img_tag, table, vec
from cadcog.spacecraft.mass_budget import budget_rows
from cadcog.spacecraft.mass_summary import MassReport, density_sources

if TYPE_CHECKING:
    from cadcog.cad.stepmodel import StepModel

REPORT_FILE = "index.html"

#: Budget tree levels shown on the page (the JSON beside it has every level).
PAGE_TREE_DEPTH = 4

#: On the page, siblings each under this share of the mass are summed into one row (the JSON
#: and ``--csv`` have every body).
PAGE_COLLAPSE_BELOW = 0.001


def envelope_corners(report: MassReport) -> np.ndarray | None:
    """The CoG envelope box's 8 corners in model coordinates, or None without an envelope."""
    env = report.envelope
    if env is None:
        return None
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    return np.asarray(env.geometric_center_mm + (signs * env.limits_mm) @ report.frame.axes)


#: Parts named on the views: the heaviest few.
VIEW_LABELS = 6


def view_labels(report: MassReport) -> list[tuple[str, np.ndarray]]:
    """(name, CoG) of the parts to name on the views, heaviest first: the budget's rows two
    levels down that show no children (copies grouped); names cut to 24 characters. Each view
    names the first :data:`VIEW_LABELS` of them that do not crowd one another."""
    rows = budget_rows(report.budget.root, 2)
    leaves = [
        r
        for k, r in enumerate(rows)
        if r.level > 0 and not r.collapsed and (k + 1 == len(rows) or rows[k + 1].level <= r.level)
    ]
    leaves.sort(key=lambda r: -r.mass_kg)
    return [(r.label[:24], r.cog_mm) for r in leaves]


def write_mass_report(
    report: MassReport,
    model: StepModel | Callable[[], StepModel],
    out_dir: str | Path,
    *,
    refusal: str | None = None,
    cache_files: Sequence[Path] = (),
) -> Path:
    """Write ``out_dir/index.html`` (with ``views.png`` and ``massprops.json``); its path.

    With ``refusal`` (the error the command exits 2 with), the page opens with it and shows
    ``report`` as the count that was refused; the JSON beside it holds ``"refused"``.
    ``model`` is the model or a function that reads it: with ``cache_files`` (the model's
    files) the views are kept in the cache under their content and everything the picture
    shows, so an unchanged model's page needs no CAD (``model`` is then not read).
    """
    import base64

    title = f"{Path(report.result.audit.source).name}: CoG (+), principal axes"
    corners = envelope_corners(report)
    labels = view_labels(report)

    def render() -> bytes:
        from cadcog.cad.tessellate import body_meshes
        from cadcog.reports import plots

        step = model() if callable(model) else model
        kept = {b.path for b in report.result.bodies}
        meshes = body_meshes(
            [b for b in step.bodies if b.path in kept], scale=report.result.audit.scale_to_mm
        )
        with tempfile.TemporaryDirectory() as tmp:
            png = Path(tmp) / "views.png"
            plots.model_views(
                [(m.vertices_mm, m.triangles, m.kind) for m in meshes],
                report.result.total.cog_mm,
                report.principal.axes,
                png,
                envelope_corners_mm=corners,
                labels=labels,
                title=title,
            )
            return png.read_bytes()

    if cache_files:
        from cadcog.cad import cache

        settings = {
            "kind": "massprops views",
            "bodies": sorted(b.path for b in report.result.bodies),
            "scale_to_mm": report.result.audit.scale_to_mm,
            "cog_mm": report.result.total.cog_mm.tolist(),
            "axes": report.principal.axes.tolist(),
            "envelope": None if corners is None else np.asarray(corners).tolist(),
            "labels": [[name, np.asarray(c).tolist()] for name, c in labels],
            "title": title,
        }
        data, _ = cache.cached_data(
            settings,
            list(cache_files),
            lambda: {"png": base64.b64encode(render()).decode("ascii")},
            code=("cad", "core", "mass", "reports", "spacecraft"),
        )
        png_bytes = base64.b64decode(data["png"])
    else:
        png_bytes = render()
    out = Path(out_dir)
    with staged_output_dir(out) as stage:
        views = stage / "views.png"
        views.write_bytes(png_bytes)
        data = report.to_dict()
        if refusal is not None:
            data = {"refused": {"error": refusal, "exit_status": 2}, **data}
        (stage / "massprops.json").write_text(dumps_json(data), encoding="utf-8")
        (stage / REPORT_FILE).write_text(render_html(report, views, refusal), encoding="utf-8")
    return out / REPORT_FILE


def _ok(flag: bool | None, yes: str = "yes", no: str = "no") -> str:
    if flag is None:
        return "n/a"
    return f'<span class="ok">{yes}</span>' if flag else f'<span class="bad">{no}</span>'


def _audit_rows(report: MassReport) -> list[list[str]]:
    esc = html.escape
    r, a = report.result, report.result.audit
    ov = r.overlaps
    units = ", ".join(a.declared_units) or "none declared"
    if a.units_override:
        units += f"; overridden to {a.units_override} (lengths × {a.scale_to_mm:g})"
    surfaces = f"{a.n_surfaces}"
    if a.left_out_surfaces:
        area = sum(x for _, x in a.left_out_surfaces)
        surfaces += f" ({len(a.left_out_surfaces)} left out: {area:.4g} mm², no areal density)"
    sources = esc(density_sources(r.bodies))
    rows = [
        ["declared length unit", esc(units)],
        ["products / instances", f"{a.n_products} / {a.n_instances}"],
        ["solids", str(a.n_solids)],
        ["surface bodies", esc(surfaces)],
        ["excluded bodies", str(len(a.excluded))],
        [
            "overlaps",
            esc(ov.headline()) + f" (policy: {esc(ov.policy)})" if ov.pairs else "none",
        ],
        [
            "contact pairs (ignored)",
            f"{ov.n_contact} of {ov.n_candidates} candidate pairs",
        ],
        ["invalid topology (OCCT)", esc(", ".join(a.invalid_topology[:20])) or "none"],
        ["closed shells made solid", esc(", ".join(a.closed_shells_made_solid[:20])) or "none"],
        ["curve-only parts", esc(", ".join(a.curve_only_parts[:20])) or "none"],
        ["density sources", sources],
    ]
    return rows


def _budget_table(report: MassReport) -> str:
    """The budget as on the text output: copies grouped, heaviest first, one mass unit."""
    esc = html.escape
    b = report.budget
    unit = nf.mass_unit([b.root.mass_kg])
    rows = []
    for r in budget_rows(b.root, PAGE_TREE_DEPTH, collapse_below=PAGE_COLLAPSE_BELOW):
        k = r.radii_of_gyration_mm
        rows.append(
            [
                "&nbsp;" * 4 * r.level + esc(r.label),
                nf.in_unit(r.unit_mass_kg, unit) if r.count > 1 and r.unit_mass_kg else "",
                nf.in_unit(r.mass_kg, unit),
                f'<span class="v">{nf.share(r.share)}</span>',
                "" if r.mass_sigma_kg is None else nf.in_unit(r.mass_sigma_kg, unit, 2),
                nf.in_unit(r.predicted_mass_kg, unit),
                f'<span class="v">{vec(r.cog_mm, 2)}</span>',
                f'<span class="v">{", ".join(nf.sig(v, 3) for v in k)}</span>',
                str(r.n_bodies),
            ]
        )
    u = unit[0]
    header = [
        "node",
        f"each ({u})",
        f"mass ({u})",
        "share",
        f"± 1σ ({u})",
        f"with MGA ({u})",
        "CoG (mm)",
        "kx, ky, kz (mm)",
        "bodies",
    ]
    return table(header, rows)


def _inertia_rows(j: np.ndarray, unit: tuple[str, float]) -> list[list[str]]:
    return [[f"{'xyz'[i]}", *[nf.in_unit(v, unit) for v in j[i]]] for i in range(3)]


def _configurations_html(report: MassReport) -> str:
    """Each configuration (``--configurations``): mass, CoG ± 1 σ, principal moments, envelope,
    and the parts it moves that would overlap others."""
    if not report.configurations:
        return ""
    rows = []
    for c in report.configurations:
        sd = c.cog_sigma_mm
        moments = c.principal_moments_kg_mm2
        rows.append(
            [
                html.escape(c.name),
                nf.mass(c.total.mass_kg),
                f"{vec(c.total.cog_mm, 2)} ± {vec(sd, 2)}",
                " ".join(nf.sig(m, 4) for m in moments),
                "" if c.envelope is None else html.escape(c.envelope.verdict()),
                str(len(c.moved)),
            ]
        )
    notes = "".join(f"<li>{html.escape(n)}</li>" for c in report.configurations for n in c.overlaps)
    return (
        '<h2 id="configurations">Configurations</h2>'
        + table(
            [
                "configuration",
                "mass",
                "CoG ± 1 σ (mm)",
                "principal moments (kg·mm²)",
                "envelope",
                "bodies changed",
            ],
            rows,
        )
        + (f"<ul>{notes}</ul>" if notes else "")
    )


def render_html(report: MassReport, views: Path, refusal: str | None = None) -> str:
    """The page: the refusal (if any), the summary line, then one section per view of the
    count (import audit, budget, inertia, views, envelope, bodies)."""
    esc = html.escape
    r = report.result
    name = Path(r.audit.source).name
    refusal_html = (
        f'<p class="big"><span class="bad">Refused (exit 2):</span> {esc(refusal)}</p>'
        "<p>What follows is the model counted as it is, so that the refusal can be read.</p>"
        if refusal
        else ""
    )
    sections = "\n\n".join(
        [
            _audit_section(report),
            _budget_section(report),
            _inertia_section(report),
            f"""<h2 id="views">Views</h2>
{img_tag(views, "three views of the model with its CoG and principal axes")}""",
            _envelope_section(report),
            _bodies_section(report),
        ]
    )
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>cadcog mass properties: {esc(name)}</title><style>{CSS}</style></head>
<body>
<h1>Mass properties: {esc(name)}</h1>
<p class="sub">cadcog {esc(__version__)} · <code>{esc(r.audit.source)}</code></p>
<nav><a href="#audit">Import audit</a><a href="#budget">Mass budget</a>
<a href="#inertia">Inertia</a><a href="#views">Views</a><a href="#envelope">Envelope</a>
<a href="#bodies">Bodies</a></nav>

{refusal_html}
{_summary(report)}

{sections}
<p class="sub">Every figure on this page is in massprops.json beside it.</p>
</body></html>
"""


def _summary(report: MassReport) -> str:
    """The mass and the CoG with their σ (the materials file's), and the growth allowances'."""
    b, t = report.budget, report.result.total
    sigma_txt = ""
    if b.mass_sigma_kg is not None:
        u = nf.mass_unit([t.mass_kg])
        sigma = f"{nf.in_unit(b.mass_sigma_kg, u, 2)} {u[0]}"
        sigma_txt = f" ± {sigma} (1 σ, {b.sigma_coverage:.0%} of the mass)"
    cog_sigma = ""
    if b.cog_cov_mm2 is not None:
        cog_sigma = f" ± {vec(np.sqrt(np.diag(b.cog_cov_mm2)))} mm (1 σ)"
    growth = f" With growth allowances: {nf.mass(b.predicted.mass_kg)}." if b.growth_kg else ""
    mass, cog = nf.mass(t.mass_kg), vec(t.cog_mm)
    return f"""<p class="big">Mass <b>{mass}</b>{sigma_txt}; CoG <b>{cog} mm</b>{cog_sigma}
(model frame).{growth}</p>"""


def _audit_section(report: MassReport) -> str:
    esc = html.escape
    r = report.result
    pair_rows = [
        [
            esc(report.short(p.a)),
            esc(report.short(p.b)),
            nf.sig(p.volume_mm3),
            nf.sig(p.mass_kg * 1e3),
            esc(report.short(p.kept_by)),
        ]
        for p in r.overlaps.pairs[:10]
    ]
    overlaps_html = (
        '<div class="wide">'
        + table(["a", "b", "common volume (mm³)", "counted twice (g)", "denser"], pair_rows, 2)
        + "</div>"
        if pair_rows
        else ""
    )
    notes = "".join(f"<li>{esc(n)}</li>" for n in r.notes) or "<li>none</li>"
    info = "".join(f"<li>{esc(n)}</li>" for n in r.info) or "<li>none</li>"
    return f"""<h2 id="audit">Import audit</h2>
{table(["what was read", "found"], _audit_rows(report), 2)}
{overlaps_html}
<p>Notes (things to look at):</p><ul>{notes}</ul>
<p>Done as asked:</p><ul>{info}</ul>"""


def _budget_section(report: MassReport) -> str:
    return f"""<h2 id="budget">Mass budget</h2>
<p>By assembly node, heaviest first; identical copies of a part are one row (<i>name ×n</i>,
with the mass of each). Current best estimate; ± is 1 σ from the materials file's mass
uncertainties, whose items vary independently; k is the radius of gyration about the node's
own CoG (model axes). "With MGA" is the predicted mass with the materials file's mass growth
allowances (AIAA S-120A's current best estimate plus growth). Siblings each under 0.1 % of the
mass are summed as "N others" (every body is in massprops.json and in <code>--csv</code>).</p>
{_budget_table(report)}"""


def _inertia_section(report: MassReport) -> str:
    esc = html.escape
    t = report.result.total
    j = t.inertia_kg_mm2
    unit = nf.inertia_unit(j.ravel())
    product_rows = [
        [
            esc(PRODUCT_CONVENTIONS[c]),
            *[nf.in_unit(v, unit) for v in products_of_inertia(j, c).values()],
        ]
        for c in ("positive", "negative")
    ]
    pa = report.principal
    principal_rows = [
        [
            f"{k + 1}",
            nf.in_unit(pa.moments_kg_mm2[k], unit),
            vec(pa.axes[k], 4),
            f"{pa.angles_from_frame_deg()[k]:.2f}",
        ]
        for k in range(3)
    ]
    f = report.frame
    jf = report.frame_inertia_kg_mm2
    frame_unit = nf.inertia_unit(jf.ravel())
    degenerate = f" ({esc(pa.degeneracy_note())})" if pa.degeneracy_note() else ""
    radii = radii_of_gyration_mm(t.mass_kg, j)
    principal_header = ["axis", f"moment ({unit[0]})", "direction", "angle from nearest axis (°)"]
    return f"""<h2 id="inertia">Inertia</h2>
<p>About the CoG, model axes ({unit[0]}). Tensor: {esc(TENSOR_CONVENTION)}.</p>
{table(["tensor", "x", "y", "z"], _inertia_rows(j, unit))}
{table(["products of inertia", "xy", "xz", "yz"], product_rows)}
<p>Radii of gyration about the CoG: kx {nf.sig(radii[0])}, ky {nf.sig(radii[1])},
kz {nf.sig(radii[2])} mm.</p>
<p>Principal moments and axes (model components; each axis's largest component is positive,
the third is the cross product of the first two){degenerate}:</p>
{table(principal_header, principal_rows)}
<p>In the frame at {esc(f.label)} (origin {vec(f.origin_mm)} mm): CoG
{vec(f.point_to_frame(t.cog_mm))} mm; inertia tensor about the origin ({frame_unit[0]};
off-diagonal −∫ x·y dm):</p>
{table(["tensor", "x", "y", "z"], _inertia_rows(jf, frame_unit))}"""


def _envelope_section(report: MassReport) -> str:
    esc = html.escape
    env = report.envelope
    envelope_html = "<p>No form factor or limits given (<code>--form-factor</code>).</p>"
    if env is not None:
        envelope_html = table(
            ["axis", "offset (mm)", "limit (mm)", "margin (mm)", "1 σ (mm)"],
            [
                [
                    "xyz"[i],
                    signed(env.offset_mm[i], 2),
                    f"±{env.limits_mm[i]:g}",
                    f"{env.margin_mm[i]:.2f}",
                    "" if env.sigma_mm is None else f"{env.sigma_mm[i]:.2f}",
                ]
                for i in range(3)
            ],
        ) + (
            f"<p>{esc(env.form_factor or 'custom')} envelope around the geometric centre "
            f"{vec(env.geometric_center_mm, 2)} mm: <b>{esc(env.verdict())}</b>; at the 95 % "
            f"edge of the CAD uncertainty: {_ok(env.within_at_95)}. "
            f"<span class='sub'>{esc(env.source)}</span></p>"
        )
    return f"""<h2 id="envelope">CoG envelope</h2>
{envelope_html}
{_configurations_html(report)}"""


def _bodies_section(report: MassReport) -> str:
    esc = html.escape
    r = report.result
    body_unit = nf.mass_unit(x.properties.mass_kg for x in r.bodies)
    body_rows = [
        [
            esc(report.short(x.path)),
            esc(x.kind),
            esc(x.material),
            esc(x.density_source),
            nf.in_unit(x.properties.mass_kg, body_unit),
            vec(x.properties.cog_mm, 2),
        ]
        for x in r.bodies
    ]
    body_header = [
        "path",
        "kind",
        "material",
        "density source",
        f"mass ({body_unit[0]})",
        "CoG (mm)",
    ]
    return f"""<h2 id="bodies">Bodies</h2>
<details><summary>{len(r.bodies)} bodies</summary>
<div class="wide">{table(body_header, body_rows, 4)}</div>
</details>"""
