"""``cadcog report``: the whole chain on a rig, and a self-contained HTML page to read.

Chain: CAD parts and ground truth → error budget → Monte Carlo → campaign (given, or a virtual
one) → validation → compensated estimate. Figures are PNGs embedded as data URIs, so the page is
one file that opens anywhere; the PNGs and the JSON of every step are written beside it.
"""

from __future__ import annotations

import base64
import html
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core import numformat as nf
from cadcog.core.errors import ReadingsError, named_by
from cadcog.core.fileio import staged_output_dir
from cadcog.core.jsontext import dumps_json
from cadcog.core.numformat import signed
from cadcog.core.version import __version__
from cadcog.method.bodybox import BodyBox
from cadcog.method.cogestimate import CogEstimate
from cadcog.method.errormodel import ErrorModel
from cadcog.method.estimate import estimate_for_rig
from cadcog.method.foreignhangs import refuse_foreign_hangs
from cadcog.method.readings import Suspension, read_readings
from cadcog.reports.html import CSS, img_tag, table, vec
from cadcog.rig.inclinometer import require_angle_sensor
from cadcog.rig.parameters import Rig
from cadcog.uncertainty.error_budget import Budget, error_budget
from cadcog.uncertainty.montecarlo import Scenario
from cadcog.uncertainty.random_points import SimulationReport, SimulationSettings, run_simulation
from cadcog.validation.campaign import VIRTUAL_CAMPAIGN, virtual_campaign, write_campaign
from cadcog.validation.verification import CampaignValidation, validate_campaign

FloatArray = npt.NDArray[np.float64]

REPORT_FILE = "index.html"
PARTS_DIR = "parts"

#: The sub-packages whose code makes a rig's parts (hashed into the cache key).
_PARTS_CODE = ("cad", "mass", "core", "rig")


@dataclass(frozen=True)
class ReportResult:
    out_dir: Path
    report: Path
    ground_truth: dict[str, Any]
    budget: Budget
    simulation: SimulationReport
    validation: CampaignValidation
    estimate: CogEstimate
    campaign_is_virtual: bool


def _measured(rig: Rig, campaign_csv: Path) -> list[Suspension]:
    """A measured campaign's hangs, checked on the rig's body before any long step runs."""
    suspensions = read_readings(campaign_csv, rig.inclinometer)
    try:
        BodyBox.of_rig(rig).normals(suspensions)
    except ReadingsError as exc:
        raise ReadingsError(
            f"{campaign_csv}: {exc}; `cadcog report` runs a rig's chain (its --rig, the "
            "paper's by default): a spacecraft's readings go to `cadcog estimate --setup`"
        ) from None
    refuse_foreign_hangs(rig, suspensions, campaign_csv)  # compared with this rig's truth
    return suspensions


def build_report(
    rig: Rig,
    out_dir: str | Path,
    campaign_csv: Path | None = None,
    *,
    seed: int = 0,
    log: Callable[[str], None] = lambda _m: None,
) -> ReportResult:
    """Run the chain on ``rig`` and write ``out_dir/index.html`` with its figures and data."""
    from cadcog.reports import plots

    out = Path(out_dir)
    # its Monte Carlo and validation model an inclinometer: said before any CAD is built
    require_angle_sensor(rig.inclinometer.device, "cadcog report")
    measured = None if campaign_csv is None else _measured(rig, campaign_csv)
    with staged_output_dir(out) as stage:
        truth = rig_parts(rig, stage / PARTS_DIR, log)
        log("error budget")
        budget = error_budget(Scenario.from_rig(rig), ErrorModel.from_rig(rig))
        log("Monte Carlo (25 random points, 300 pairs, 1000 trials each)")
        sim = run_simulation(rig, SimulationSettings(seed=seed))
        virtual = measured is None
        if measured is None:
            campaign_csv = stage / "campaign.csv"
            log("virtual test campaign")
            write_campaign(
                campaign_csv,
                virtual_campaign(rig, seed),
                f"{VIRTUAL_CAMPAIGN}, rig {rig.name}, seed {seed}",
            )
            measured = read_readings(campaign_csv, rig.inclinometer)
        suspensions = measured
        with named_by(None if virtual else campaign_csv):  # refusals name the user's file
            log("validation against simulated campaigns")
            validation = validate_campaign(rig, suspensions, seed=seed)
            log("compensated estimate")
            estimate = estimate_for_rig(rig, suspensions)
        figures = {
            "rig": stage / "rig.png",
            "histogram": stage / "histogram.png",
            "validation": stage / "validation.png",
            "estimate": stage / "estimate.png",
        }
        plots.rig_view(rig, np.array(truth["assembly"]["cog_mm"]), figures["rig"])
        plots.error_histogram(
            sim.result.histogram,
            sim.fits,
            figures["histogram"],
            f"{rig.name}: {sim.fits.n} simulated trials",
        )
        plots.validation_plot(
            validation.simulated_norms_mm, validation.validation, figures["validation"]
        )
        truth_cog = np.array(truth["bodies"]["proof_mass"]["cog_mm"])
        plots.ellipse_plot(estimate.cog_mm, estimate.cov_mm2, truth_cog, figures["estimate"])
        for name, data in (
            ("budget.json", budget.to_dict()),
            ("simulation.json", sim.to_dict()),
            ("validation.json", validation.to_dict()),
            ("estimate.json", estimate.to_dict()),
        ):
            (stage / name).write_text(dumps_json(data), encoding="utf-8")
        page = render_html(
            rig,
            truth,
            budget,
            sim,
            validation,
            estimate,
            figures,
            virtual,
            campaign_csv if not virtual else None,
        )
        (stage / REPORT_FILE).write_text(page, encoding="utf-8")
    return ReportResult(out, out / REPORT_FILE, truth, budget, sim, validation, estimate, virtual)


def parts_cache_key(rig: Rig) -> str:
    """The cache key of ``rig``'s parts: a SHA-256 of every field of the rig (``repr`` of its
    frozen dataclasses: exact floats), the STEP timestamp's ``SOURCE_DATE_EPOCH``, and (as
    every key) the geometry kernel's versions and the sources of cadcog's ``cad``, ``mass``,
    ``core`` and ``rig``."""
    from cadcog.cad import cache

    settings = {
        "kind": "rig parts",
        "rig": repr(rig),
        "SOURCE_DATE_EPOCH": os.environ.get("SOURCE_DATE_EPOCH", ""),
    }
    return cache.key(settings, [], code=_PARTS_CODE)


def rig_parts(
    rig: Rig, parts_dir: Path, log: Callable[[str], None] = lambda _m: None
) -> dict[str, Any]:
    """Write ``rig``'s parts into the new folder ``parts_dir`` as ``cadcog parts build`` does
    (STEP, one STL per body, ``ground_truth.json``) and return the ground truth.

    The parts are byte-for-byte reproducible, so they are kept in the cache
    (:mod:`cadcog.cad.cache`, plain JSON: the ground truth as data, the files' bytes in
    base64) under :func:`parts_cache_key`: a second run on an unchanged rig writes the same
    bytes and returns the same ground truth, to the last bit, without importing build123d.
    """
    from cadcog.cad import cachestore

    entry = parts_cache_key(rig)
    hit = _parts_entry(cachestore.load_data(entry))
    if hit is not None:
        log("CAD parts and their ground truth (from the cache: unchanged rig)")
        truth, files = hit
        for name, data in files.items():
            path = parts_dir / name
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(data)
        return truth
    from cadcog.cad.build import build_parts

    log("building the CAD parts and their ground truth")
    built = build_parts(rig, parts_dir)
    stored = {
        "ground_truth": built.ground_truth,
        "files": {
            p.relative_to(parts_dir).as_posix(): base64.b64encode(p.read_bytes()).decode("ascii")
            for p in built.files
        },
    }
    cachestore.store_data(entry, stored)
    return built.ground_truth


def _parts_entry(data: Any) -> tuple[dict[str, Any], dict[str, bytes]] | None:
    """The ground truth and the files (relative path → bytes) of a parts entry, or None if
    ``data`` is not one (no entry, or a damaged one: the parts are then built again)."""
    if data is None:
        return None
    try:
        truth = data["ground_truth"]
        files = {
            name: base64.b64decode(text, validate=True) for name, text in data["files"].items()
        }
    except (KeyError, TypeError, AttributeError, ValueError):
        return None
    names_ok = all(
        isinstance(n, str) and n and not Path(n).is_absolute() and ".." not in Path(n).parts
        for n in files
    )
    if not isinstance(truth, dict) or not files or not names_ok:
        return None
    return truth, files


# --- HTML ----------------------------------------------------------------------------------------
def render_html(
    rig: Rig,
    truth: dict[str, Any],
    budget: Budget,
    sim: SimulationReport,
    validation: CampaignValidation,
    estimate: CogEstimate,
    figures: dict[str, Path],
    virtual: bool,
    campaign_path: Path | None,
) -> str:
    """The report's page: a summary line, then one section per step of the chain."""
    esc = html.escape
    pm_truth = np.array(truth["bodies"]["proof_mass"]["cog_mm"])
    sections = [
        _summary(estimate, pm_truth, sim),
        _rig_section(rig, truth, figures["rig"]),
        _truth_section(truth),
        _budget_section(budget),
        _mc_section(sim, figures["histogram"]),
        _validation_section(validation, figures["validation"], virtual, campaign_path),
        _estimate_section(estimate, pm_truth, figures["estimate"]),
    ]
    body = "\n\n".join(sections)
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>cadcog report: {esc(rig.name)}</title><style>{CSS}</style></head>
<body>
<h1>Centre of gravity report: {esc(rig.name)}</h1>
<p class="sub">cadcog {esc(__version__)} · rig file <code>{esc(str(rig.source))}</code></p>
<nav><a href="#rig">Rig</a><a href="#truth">Ground truth</a><a href="#budget">Error budget</a>
<a href="#mc">Monte Carlo</a><a href="#validation">Validation</a>
<a href="#estimate">Estimate</a></nav>

{body}
</body></html>
"""


def _yes_no(ok: bool) -> str:
    return '<span class="ok">yes</span>' if ok else '<span class="bad">no</span>'


def _summary(estimate: CogEstimate, pm_truth: FloatArray, sim: SimulationReport) -> str:
    error = estimate.cog_mm - pm_truth
    sigma = np.sqrt(np.diag(estimate.cov_mm2))
    q95, sc = sim.fits.q95_mm, sim.screened
    cog = vec(estimate.cog_mm)
    return f"""<p class="big">Compensated CoG: <b>{cog} mm</b> ± {vec(sigma)} mm (1 σ);
CAD truth {vec(pm_truth)} mm; error {np.linalg.norm(error):.3f} mm.
Simulated 95 % error of one pair: {q95:.2f} mm ({sc.get("q95_mm", float("nan")):.2f} mm
over the pairs whose lines meet at {sc["min_angle_deg"]:g}° or more).</p>"""


def _rig_section(rig: Rig, truth: dict[str, Any], figure: Path) -> str:
    esc = html.escape
    points = [
        [
            esc(p["id"]),
            esc(p["face"]),
            vec(p["wire_exit_mm"], 1),
            f"{p['ideal_reading_deg'][0]:.1f}",
            f"{p['ideal_reading_deg'][1]:.1f}",
            "yes" if p["top_face_up"] else "no",
            _yes_no(p["in_range"]),
        ]
        for p in truth["suspension_points"]
    ]
    head = ["point", "face", "wire exit (mm)", "X (deg)", "Y (deg)", "top face up", "in range"]
    size = rig.proof_mass.size_mm
    return f"""<h2 id="rig">The rig</h2>
<p>A {size[0]:g} × {size[1]:g} ×
{size[2]:g} mm {esc(rig.proof_mass.material)} proof mass of
{rig.proof_mass.mass_kg:g} kg with {len(rig.suspension_points)} drilled suspension points, and the
measurement equipment on its +z face. Each plumb line runs from a suspension point through the
assembly's CoG.</p>
{img_tag(figure, "rig with suspension points and plumb lines")}
{table(head, points, 2)}"""


def _truth_section(truth: dict[str, Any]) -> str:
    esc = html.escape
    listed = [*truth["bodies"].items(), ("assembly", truth["assembly"])]
    mass_unit = nf.mass_unit(b["mass_kg"] for _, b in listed)  # one unit for the column
    bodies = [
        [esc(name), nf.in_unit(b["mass_kg"], mass_unit), vec(b["cog_mm"]), nf.sig(b["volume_mm3"])]
        for name, b in listed
    ]
    error = truth["integration"]["estimated_relative_error"]
    return f"""<h2 id="truth">Ground truth from CAD</h2>
<p>Exact B-rep integration per solid with its own density (OCCT); estimated relative integration
error {error:.1g}. The holes shift the proof-mass CoG
by {vec(truth["hole_cog_shift_mm"], 4)} mm.</p>
{table(["body", f"mass ({mass_unit[0]})", "CoG (mm)", "volume (mm³)"], bodies)}"""


def _budget_section(budget: Budget) -> str:
    esc = html.escape
    sources = [
        [
            esc(s.source),
            esc(s.distribution),
            f"{s.sigma:.4f} {esc(s.unit)}",
            f"{s.cog_sigma_mm:.3f}",
            f"{s.share:.1%}",
        ]
        for s in budget.sources
    ]
    pair = f"{esc(budget.pair[0])}-{esc(budget.pair[1])}"
    return f"""<h2 id="budget">Error budget</h2>
<p>Shares of the CoG error variance for pair {pair} (plumb
lines at {budget.pair_angle_deg:.1f}°, the median pair of the rig), by linear propagation.</p>
{table(["source", "distribution", "σ", "CoG σ (mm)", "share"], sources, 2)}
<p>Bias with every source at its mean: {vec(budget.bias_mm)} mm (the wire offset's mean).</p>"""


def _mc_section(sim: SimulationReport, figure: Path) -> str:
    esc = html.escape
    f, sc = sim.fits, sim.screened
    fits: list[tuple[str, str, float]] = [
        ("Rayleigh, maximum likelihood", f"σ = {f.rayleigh_sigma_mm:.3f}", f.ks_rayleigh),
        ("Maxwell, maximum likelihood", f"a = {f.maxwell_a_mm:.3f}", f.ks_maxwell),
        ("Rayleigh, median-matched", f"σ = {f.rayleigh_sigma_median_mm:.3f}", f.ks_rayleigh_median),
        ("Maxwell, median-matched", f"a = {f.maxwell_a_median_mm:.3f}", f.ks_maxwell_median),
    ]
    quantiles = [
        ["all", f"{f.q50_mm:.3f}", f"{f.q95_mm:.3f}", f"{sim.q99_mm:.3f}"],
        [
            f"lines at ≥ {sc['min_angle_deg']:g}° ({sc['n_groups']})",
            *(f"{sc.get(q, float('nan')):.3f}" for q in ("q50_mm", "q95_mm", "q99_mm")),
        ],
    ]
    fit_rows = [[name, scale, "", "", f"{ks:.3f}"] for name, scale, ks in fits]
    return f"""<h2 id="mc">Monte Carlo</h2>
<p>{f.n} trials: {len(sim.groups)} pairs of {len(sim.scenario.ids)} random suspension points,
{sim.settings.trials_per_group} trials each (seed {sim.settings.seed}): each simulated campaign
hangs the object once from every point and estimates every pair from those hangs, as
<code>cadcog estimate</code> does. Error model: {esc(sim.model.summary())}.</p>
{table(["pairs", "median (mm)", "95 % (mm)", "99 % (mm)"], quantiles)}
{img_tag(figure, "histogram of simulated error norms with fits")}
<p>Moment fits, shown with their KS distance as their quality (not the result):</p>
{table(["fit", "scale (mm)", "", "", "KS"], fit_rows)}
<p class="note">Maximum-likelihood fits are dragged by the few near-collinear pairs in the tail;
the median-matched fits describe the body of the distribution; the empirical quantiles are the
figures to quote.</p>"""


def _validation_section(
    validation: CampaignValidation, figure: Path, virtual: bool, campaign_path: Path | None
) -> str:
    esc = html.escape
    v, c = validation.validation, validation.verdict
    windows = [
        [
            f"{w.eps_mm:g}",
            f"{w.F:.3f}",
            str(w.k),
            str(w.n),
            f"{w.p_hat:.3f}",
            f"[{w.ci_low:.3f}, {w.ci_high:.3f}]",
            f"{w.null_k_low}-{w.null_k_high}",
            _yes_no(w.consistent),
        ]
        for w in v.windows
    ]
    pair_rows = [
        [f"{a}-{b}", f"{e:.3f}"] for (a, b), e in zip(v.pairs, v.measured_norms_mm, strict=True)
    ]
    campaign_note = (
        "This is a <b>virtual</b> campaign simulated by <code>cadcog campaign</code> (one hang per "
        "suspension point, raw ADC counts with noise, per-hang bias, play and wire offset): it "
        "shows the check working, it is not a measurement."
        if virtual
        else f"Campaign: <code>{esc(str(campaign_path))}</code>."
    )
    verdict = (
        '<span class="ok">consistent with the error model</span>'
        if c.consistent
        else '<span class="bad">not consistent with the error model</span>'
    )
    head = ["ε (mm)", "F(ε)", "k", "n", "p̂", "95 % CI (indep.)", "null k", "consistent"]
    return f"""<h2 id="validation">Validation (eqs. 14-15)</h2>
<p>{campaign_note}</p>
<p>Each of the {len(v.pairs)} pairs gives a compensated CoG; success is |e| &lt; ε. The
simulated F(ε) and the null range of k come from {validation.null.n_campaigns} whole campaigns
simulated on the campaign's own points (pairs share hangs, as in the lab). Campaign test (each
hang's line against the known CoG): T = {c.statistic:.2f}, p = {c.p_value:.3f} at level
{c.level:g}. Verdict: {verdict}.</p>
{img_tag(figure, "measured and simulated error CDFs")}
{table(head, windows, 0)}
<p class="note">The Clopper-Pearson intervals treat the pairs as independent, as the paper does;
they are not, since pairs share hangs. The null range of k and the campaign test simulate that
sharing and hold their stated level. KS of the pair errors (independent pairs assumed):
D = {v.ks_statistic:.3f}, p = {v.ks_p_value:.3f}.</p>
<details><summary>error of every pair</summary>{table(["pair", "|e| (mm)"], pair_rows)}</details>"""


def _estimate_section(estimate: CogEstimate, pm_truth: FloatArray, figure: Path) -> str:
    esc = html.escape
    error = estimate.cog_mm - pm_truth
    sigma = np.sqrt(np.diag(estimate.cov_mm2))
    rows = [
        ["assembly (object + ME)", *[f"{c:.3f}" for c in estimate.assembly_cog_mm]],
        ["object (ME removed)", *[f"{c:.3f}" for c in estimate.cog_mm]],
        ["1 σ", *[f"{c:.3f}" for c in sigma]],
        ["CAD truth", *[f"{c:.3f}" for c in pm_truth]],
        ["estimate − truth", *[signed(c, 3) for c in error]],
    ]
    warnings = "".join(f"<li>{esc(w)}</li>" for w in estimate.warnings) or "<li>none</li>"
    return f"""<h2 id="estimate">Compensated estimate</h2>
<p>Generalised least-squares point of all {len(estimate.suspensions)} plumb lines (each
weighted by its covariance from the error model), each suspension point corrected for the wire
offset the rig's error model expects, ME removed (eq. 10) with its uncertainty propagated
(eq. 16).</p>
{table(["", "x (mm)", "y (mm)", "z (mm)"], rows)}
{img_tag(figure, "uncertainty ellipses of the estimate")}
<p>Warnings:</p><ul>{warnings}</ul>
<p class="sub">Data of every step: budget.json, simulation.json, validation.json,
estimate.json, parts/ground_truth.json beside this page.</p>"""
