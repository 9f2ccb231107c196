"""``cadcog acquire --report DIR``: the record of a test run, as one HTML page.

What a test engineer files after a suspension test: which rig or spacecraft, the readings file,
the device and its link (lines rejected, samples lost), every attempt at every hang (its
outcome, mean angles, settle time, swing period and decay, how far its line passed from the
others), and the result: the compensated CoG with its uncertainty, its difference from the CAD
and the CubeSat envelope for a spacecraft, the error against the simulated truth for a dry run,
and a figure of the CoG's 95 % ellipsoid. ``acquire.json`` beside the page holds what
``cadcog acquire --json`` prints; files appear whole or not at all (staged, then moved).
"""

from __future__ import annotations

import html
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from cadcog.core.fileio import staged_output_dir
from cadcog.core.jsontext import dumps_json
from cadcog.core.numformat import signed
from cadcog.core.version import __version__
from cadcog.reports.html import CSS, img_tag, num, table, vec

if TYPE_CHECKING:
    from cadcog.bench.session import SessionResult
    from cadcog.bench.target import BenchTarget

REPORT_FILE = "index.html"


def write_run_report(
    result: SessionResult,
    target: BenchTarget,
    summary: dict[str, Any],
    out_dir: str | Path,
) -> Path:
    """Write ``out_dir/index.html`` (with ``cog.png`` and ``acquire.json``); its path.

    ``summary`` is the run's JSON form (``cadcog acquire --json``: the session, and ``cad``
    and ``simulated_truth`` when known). Needs an estimate (two hangs or more).
    """
    from cadcog.reports import plots

    est = result.estimate
    if est is None:
        raise ValueError("no estimate: fewer than two hangs recorded")
    out = Path(out_dir)
    with staged_output_dir(out) as stage:
        figure = stage / "cog.png"
        entries = [("measured", est.cog_mm, est.cov_mm2)]
        cad = summary.get("cad")
        if cad is not None:
            entries.append(("CAD", np.asarray(cad["cad_cog_mm"]), np.zeros((3, 3))))
        truth = summary.get("simulated_truth")
        if truth is not None:
            entries.append(
                ("simulated truth", np.asarray(truth["object_cog_mm"]), np.zeros((3, 3)))
            )
        plots.cog_ellipses(entries, figure, title=f"{target.name}: compensated CoG, 95 % ellipsoid")
        (stage / "acquire.json").write_text(dumps_json(summary), encoding="utf-8")
        page = render_html(result, target, summary, figure)
        (stage / REPORT_FILE).write_text(page, encoding="utf-8")
    return out / REPORT_FILE


def _f(value: float | None, digits: int = 2) -> str:
    return "" if value is None else num(value, digits)


def render_html(
    result: SessionResult, target: BenchTarget, summary: dict[str, Any], figure: Path
) -> str:
    esc = html.escape
    est = result.estimate
    assert est is not None
    hang_rows = [
        [
            esc(h.id),
            str(h.attempt),
            f"<span class='{'ok' if h.outcome == 'recorded' else 'bad'}'>{esc(h.outcome)}</span>",
            "" if h.mean_deg is None else f"{h.mean_deg[0]:.3f}, {h.mean_deg[1]:.3f}",
            str(h.samples or ""),
            _f(h.settled_after_s, 1),
            _f(h.period_s, 3),
            _f(h.decay_time_s, 1),
            _f(h.sigma, 1),
            esc(h.reason),
        ]
        for h in result.hangs
    ]
    resumed = (
        f"<p>Resumed: {esc(', '.join(result.resumed))} were already in the file.</p>"
        if result.resumed
        else ""
    )
    sigma = np.sqrt(np.diag(est.cov_mm2))
    cog_rows = [["xyz"[k], num(est.cog_mm[k], 3), f"{sigma[k]:.3f}"] for k in range(3)]
    comparison = ""
    cad = summary.get("cad")
    if cad is not None:
        comparison += (
            f"<p>Measured − CAD: {vec(cad['difference_mm'], 3)} mm = "
            f"{vec(cad['difference_sigma'], 1)} σ (Mahalanobis distance "
            f"{cad['mahalanobis']:.2f}).</p>"
        )
        env = cad.get("cubesat")
        if env is not None:
            comparison += (
                f"<p>{esc(str(env.get('form_factor') or 'custom'))} CoG envelope: offset "
                f"{vec(env['offset_mm'], 2)} mm from the geometric centre, limits "
                f"±{vec(env['limits_mm'], 1)} mm: <b>{'within' if env['within'] else 'OUTSIDE'}"
                f"</b>; at the 95 % edge of the uncertainty: "
                f"{'within' if env.get('within_at_95') else 'not within'}.</p>"
            )
    truth = summary.get("simulated_truth")
    if truth is not None:
        comparison += (
            f"<p>Dry run: error against the simulated truth {vec(truth['error_mm'], 3)} mm, "
            f"Mahalanobis distance {truth['mahalanobis']:.2f}.</p>"
        )
    warnings = "".join(f"<li>{esc(w)}</li>" for w in est.warnings) or "<li>none</li>"
    inertia = _inertia_section(result)
    kind = "spacecraft set-up" if target.setup is not None else "rig"
    return f"""<!doctype html>
<html lang="en"><head><meta charset="utf-8">
<title>cadcog test record: {esc(target.name)}</title><style>{CSS}</style></head><body>
<h1>Test record: {esc(target.name)}</h1>
<p class="sub">cadcog {esc(__version__)} · {kind} <code>{esc(target.source.name)}</code>
· readings <code>{esc(result.path.name)}</code> · device {esc(result.device)}</p>
<p>Link: {esc(result.link)}. Malformed lines repaired in the file: {result.repaired_lines}.</p>
{resumed}

<h2>Hangs</h2>
<div class="wide">
{
        table(
            [
                "point",
                "attempt",
                "outcome",
                "mean X, Y (°)",
                "samples",
                "settled after (s)",
                "period (s)",
                "decay (s)",
                "line (σ)",
                "reason",
            ],
            hang_rows,
        )
    }
</div>
<p class="note">Line (σ): how far the hang's plumb line passed from the estimate of the hangs
before it, in its standard deviations; a hang far from the others is offered for a redo at once.
Redone and refused attempts are in the readings file as comments only.</p>

<h2>Compensated CoG</h2>
{table(["axis", "CoG (mm)", "1 σ (mm)"], cog_rows)}
{comparison}
{img_tag(figure, "compensated CoG with its 95 % ellipsoid")}

{inertia}
<h2>Estimator warnings</h2>
<ul>{warnings}</ul>
</body></html>
"""


def _inertia_section(result: SessionResult) -> str:
    """The inertia tensor from the swings (``cadcog inertia``), or why there is none."""
    esc = html.escape
    r = result.inertia
    if r is None:
        return f"<h2>Inertia from the swings</h2>\n<p>Not estimated: {esc(result.inertia_note)}</p>"
    pr = r.principal
    rel = 100 * pr.moments_sigma_kg_mm2 / pr.moments_kg_mm2
    rows = [
        [
            f"I{k + 1}",
            num(pr.moments_kg_mm2[k], 1),
            f"{pr.moments_sigma_kg_mm2[k]:.3g} ({rel[k]:.2f} %)",
            ", ".join(signed(a, 4) for a in pr.axes[k]),
            f"{pr.axes_sigma_deg[k]:.2g}" if pr.axes_sigma_deg[k] < 90 else "undetermined",
        ]
        for k in range(3)
    ]
    cad = r.cad
    versus = (
        ""
        if cad is None
        else f"<p>Against the CAD's tensor: joint χ² {cad['chi2']:.2f} with {cad['dof']} dof "
        f"(p = {cad['p']:.3f}).</p>"
    )
    fit = (
        f"the swings' fit χ² {r.chi2:.2f} with {r.dof} dof (p = {r.consistency_p:.3f})"
        if r.dof > 0
        else "no degree of freedom left to check the swings' fit (as many frequencies as unknowns)"
    )
    warned = (
        "<p>Warnings:</p><ul>" + "".join(f"<li>{esc(w)}</li>" for w in r.warnings) + "</ul>"
        if r.warnings
        else ""
    )
    return (
        "<h2>Inertia from the swings</h2>\n"
        + table(["", "moment (kg·mm²)", "1 σ", "axis (model frame)", "axis 1 σ (°)"], rows)
        + f"\n<p>About the object's CoG, the ME removed; {fit}. Details: "
        "<code>cadcog inertia</code>.</p>" + warned + versus
    )
