"""``cadcog update --report DIR``: what the measurement says about the CAD, as one HTML page.

The page holds the verdict (is the gap between CAD and measurement within their
uncertainties?), the CAD, measured and updated mass and CoG side by side, a figure of the three
CoG estimates with their 95 % ellipsoids, the items ranked by how far the data moved them, the
unmodelled mass if one was allowed, and the updated inertia. ``update.json`` (the same numbers
as ``cadcog update --json``) and ``cog.png`` are written beside ``index.html``; files appear
whole or not at all (staged, then moved).
"""

from __future__ import annotations

import html
from pathlib import Path
from typing import TYPE_CHECKING

from cadcog.core.fileio import staged_output_dir
from cadcog.core.jsontext import dumps_json
from cadcog.core.version import __version__
from cadcog.mass.inertia import PRODUCT_CONVENTIONS, TENSOR_CONVENTION
from cadcog.reports.html import CSS, img_tag, table
from cadcog.spacecraft import update_text as ut
from cadcog.spacecraft.update import INCONSISTENT_NOTE, REJECTED_NOTE, UpdateResult

if TYPE_CHECKING:
    from cadcog.method.cogestimate import CogEstimate
    from cadcog.spacecraft.setup import Setup

REPORT_FILE = "index.html"

#: Items (and explanations) listed on the page (the JSON beside it has them all).
PAGE_ITEMS = 25

#: Explanations below this posterior probability are left to update.json.
PAGE_MIN_PROBABILITY = 0.01


def write_update_report(
    result: UpdateResult, setup: Setup, estimate: CogEstimate, readings: Path, out_dir: str | Path
) -> Path:
    """Write ``out_dir/index.html`` (with ``cog.png`` and ``update.json``); its path."""
    from cadcog.reports import plots

    out = Path(out_dir)
    with staged_output_dir(out) as stage:
        figure = stage / "cog.png"
        plots.cog_ellipses(
            [
                ("CAD", result.cad.cog_mm, result.cad_cog_cov_mm2),
                ("measured", result.measured_cog_mm, result.measured_cog_cov_mm2),
                ("updated", result.posterior.cog_mm, result.posterior_cog_cov_mm2),
            ],
            figure,
            title=f"{setup.name}: spacecraft CoG, 95 % ellipsoids (projections)",
        )
        (stage / "update.json").write_text(dumps_json(result.to_dict()), encoding="utf-8")
        page = render_html(result, setup, estimate, readings, figure)
        (stage / REPORT_FILE).write_text(page, encoding="utf-8")
    return out / REPORT_FILE


def _cell(text: str) -> str:
    """A numeric cell that never breaks inside a number and its σ (a vector may break
    between its components)."""
    return ", ".join(f'<span class="v">{html.escape(p)}</span>' for p in text.split(", "))


def render_html(
    r: UpdateResult, setup: Setup, estimate: CogEstimate, readings: Path, figure: Path
) -> str:
    esc = html.escape
    verdict_cls = "bad" if r.model_rejected or not r.consistent else "ok"
    verdict = "<br>".join(esc(line) for line in r.verdict_lines())
    rows = [[esc(row[0]), *map(_cell, row[1:])] for row in ut.mass_cog_rows(r)]
    ranked = r.ranked_items()
    item_header, item_cells = ut.item_table(ranked[:PAGE_ITEMS], prior=True)
    item_rows = [[esc(row[0]), *map(_cell, row[1:])] for row in item_cells]
    more = (
        f"<p class='sub'>{len(ranked) - PAGE_ITEMS} more items in <code>update.json</code>.</p>"
        if len(ranked) > PAGE_ITEMS
        else ""
    )
    unmodelled = "<p>No unmodelled mass allowed (<code>--unmodelled-region-mm</code>).</p>"
    if r.unmodelled_mass_kg is not None:
        unmodelled = f"<p class='big'>{esc(ut.unmodelled_summary(r))}</p>"
    caveat = ""
    if r.model_rejected:
        caveat = f"<p class='note bad'>{esc(REJECTED_NOTE)}</p>"
    elif not r.consistent:
        caveat = f"<p class='note bad'>{esc(INCONSISTENT_NOTE)}</p>"
    shown = [e for e in r.explanations if e.probability >= PAGE_MIN_PROBABILITY][:PAGE_ITEMS]
    explanation_rows = [
        [esc(e.label), f"{e.probability:.1%}", f"{e.prior_probability:.2g}", esc(e.description)]
        for e in shown or r.explanations[:1]
    ]
    if len(r.explanations) > len(explanation_rows):
        rest = len(r.explanations) - len(explanation_rows)
        explanation_rows.append(["", "", "", f"{rest} less probable explanations in update.json"])
    product_rows = [
        [esc(PRODUCT_CONVENTIONS[c]), *map(_cell, ut.product_cells(r, c))]
        for c in ("positive", "negative")
    ]
    tensor_rows = [[row[0], *map(_cell, row[1:])] for row in ut.tensor_rows(r)]
    warnings = "".join(f"<li>{esc(w)}</li>" for w in estimate.warnings) or "<li>none</li>"
    return f"""<!doctype html>
<html lang="en"><head><meta charset="utf-8">
<title>cadcog update: {esc(setup.name)}</title><style>{CSS}</style></head><body>
<h1>{esc(setup.name)}: CAD against measurement</h1>
<p class="sub">cadcog {esc(__version__)} · set-up <code>{esc(setup.source.name)}</code>
· readings <code>{esc(readings.name)}</code> · {len(estimate.suspensions)} suspensions</p>
<p class="big"><span class="{verdict_cls}">{verdict}</span></p>

{caveat}
<h2>Mass and CoG</h2>
{table(["", "CAD (prior)", "measured", "updated (posterior)"], rows)}
<p class="note">± is 1 σ. The CAD's σ comes from the materials file's item mass and CoG
uncertainties; the measured CoG is the suspension estimate compensated for the measurement
equipment with the weighed mass; the updated values combine both over the explanations below,
each weighed by its probability (or are the measurement's when no explanation fits). Model
coordinates.</p>
{img_tag(figure, "CAD, measured and updated CoG with 95 % ellipsoids")}

<h2>What explains the gap</h2>
{table(["explanation", "probability", "prior", "what it says"], explanation_rows)}
<p class="note">Each explanation is a hypothesis about the CAD: every item within its stated σ
("none"), one item off by much more, or an unmodelled mass. Its probability is how well it
explains the measurement, weighed by its prior; rates over many simulated tests are in
docs/spacecraft.md.</p>

<h2>Items</h2>
{table(item_header, item_rows)}
{more}
<p class="note">A CoG and a mass give four numbers, so many items cannot all be told apart:
an item whose change is small against its ± is not resolved by this measurement.</p>

<h2>Unmodelled mass</h2>
{unmodelled}

<h2>Updated inertia about the CoG</h2>
<p>Model axes ({ut.inertia_unit(r)[0]}), ± 1 σ. Tensor: {esc(TENSOR_CONVENTION)}.</p>
{table(["tensor", "x", "y", "z"], tensor_rows)}
{table(["products of inertia", "xy", "xz", "yz"], product_rows)}

<h2>Estimator warnings</h2>
<ul>{warnings}</ul>
</body></html>
"""
