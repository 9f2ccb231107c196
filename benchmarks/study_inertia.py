"""Bias and coverage of ``cadcog inertia`` against an independent nonlinear swing (issue 20).

The truth is :mod:`support.swing_truth` (full nonlinear rigid body on a massless
inextensible wire, large amplitude, damping, accelerometer-type inclinometer, bias, noise, the
rig's ADC with 16× oversampling, sample jitter; see :mod:`support.swing_files`). Each
campaign is written as a swing file and a readings CSV and estimated by the command's own entry
point (``cadcog.cli._main.main`` in-process, ``--json``) with a copy of the rig or set-up file
carrying the row's ``[swing]`` table; the object's inertia about its own CoG from cadcog's CAD
is the target.

Per row: each principal moment's relative bias and 95 % error, and its 95 % interval
(± 1.96 σ) coverage; the whole tensor's χ² (6 entries, the reported 6 × 6 covariance, 6 dof)
coverage at 95 %; the principal axes' angle errors (95th percentile and the share within 2°);
every rate with its Clopper-Pearson 95 % interval.

Two phases, so the slow simulation runs once:

    nice -n 5 .venv/bin/python benchmarks/study_inertia.py simulate [--seeds 200] [--rows ...]
    nice -n 5 .venv/bin/python benchmarks/study_inertia.py estimate [--rows ...] [--limit N]
    .venv/bin/python benchmarks/study_inertia.py report [--rows ...]

``modes`` prints the truth's small-oscillation frequencies of the rig's hangs (from the
simulator's own linearisation). ``simulate`` caches every row in
``build/study_inertia/ROW.npz``; ``estimate`` appends each campaign's score to
``build/study_inertia/ROW.scores.jsonl`` (resumable); ``report`` prints the markdown tables of
``docs/inertia_validation.md``. ``--placeholder`` replaces the estimator by a stand-in
(the truth plus a 1 % draw, reported σ 1 %) to exercise the statistics before it exists.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
from scipy import stats

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from study_inertia_rows import (  # noqa: E402
    CACHE,
    CHI2_6_95,
    OFF,
    RIG,
    ROWS,
    SETUP,
    Row,
)

from support import estimator_runs as er  # noqa: E402
from support import swing_files as sf  # noqa: E402


def parameter_source(row: Row) -> Path:
    """The row's rig or set-up file; with ``off``, an edited copy (``CACHE/ROW.toml``)."""
    src = RIG if row.source == "rig" else SETUP
    if not row.off:
        return src
    text = src.read_text(encoding="utf-8")
    for pattern, repl in (e for o in row.off for e in OFF[o].edits):
        text, n = re.subn(pattern, repl, text)
        if not n:
            raise ValueError(f"{src.name}: no line matches {pattern!r}")
    CACHE.mkdir(parents=True, exist_ok=True)
    out = CACHE / f"{row.name}.toml"
    out.write_text(text, encoding="utf-8")
    return out


def swing_extra(row: Row) -> str:
    """The ``[swing]`` keys a row's ``off`` adds."""
    return "".join(OFF[o].swing for o in row.off)


def truth_of(row: Row) -> sf.Truth:
    src = parameter_source(row)
    return sf.rig_truth(src) if row.source == "rig" else sf.setup_truth(src)


# --- simulate -------------------------------------------------------------------------------
def simulate(row: Row, seeds: int, batch: int) -> Path:
    """Simulate ``seeds`` campaigns of a row (seed s uses ``default_rng([20, s])``) and cache
    the recorded files' content (not the noise-free diagnostics)."""
    truth = truth_of(row)
    arrays: dict[str, list[Any]] = {k: [] for k in ("t_ms", "x", "y", "sx", "sy", "L", "tau")}
    t0 = time.time()
    for lo in range(0, seeds, batch):
        rngs = [np.random.default_rng([20, s]) for s in range(lo, min(seeds, lo + batch))]
        for camp in sf.simulate_campaigns(truth, row.points, row.config, rngs, row.hang_ids):
            arrays["t_ms"].append([h.t_ms for h in camp])
            arrays["x"].append([h.inc_x_deg for h in camp])
            arrays["y"].append([h.inc_y_deg for h in camp])
            arrays["sx"].append([h.settled_x_deg for h in camp])
            arrays["sy"].append([h.settled_y_deg for h in camp])
            arrays["L"].append([h.true_wire_length_mm for h in camp])
            arrays["tau"].append([h.decay_time_s for h in camp])
        print(
            f"  {row.name}: {min(seeds, lo + batch)}/{seeds} ({time.time() - t0:.0f} s)",
            file=sys.stderr,
        )
    CACHE.mkdir(parents=True, exist_ok=True)
    path = CACHE / f"{row.name}.npz"
    np.savez_compressed(path, **{k: np.asarray(v) for k, v in arrays.items()})
    return path


def campaigns(row: Row) -> tuple[sf.Truth, list[list[sf.HangRecord]]]:
    """The cached campaigns of a row, as records."""
    truth = truth_of(row)
    with np.load(CACHE / f"{row.name}.npz") as z:
        d = {k: z[k] for k in z.files}  # an NpzFile decompresses the array at every access
    ids = row.hang_ids or row.points
    out = []
    for c in range(d["x"].shape[0]):
        camp = []
        for h, (pid, hid) in enumerate(zip(row.points, ids, strict=True)):
            u = truth.hung_from(truth.exit_of(pid)).plumb_up
            camp.append(
                sf.HangRecord(
                    hid,
                    truth.exit_of(pid),
                    bool(u[2] > 0),
                    d["t_ms"][c, h],
                    d["x"][c, h],
                    d["y"][c, h],
                    d["sx"][c, h],
                    d["sy"][c, h],
                    float(d["L"][c, h]),
                    float(d["tau"][c, h]),
                    np.empty(0),
                    np.empty(0),
                )
            )
        out.append(camp)
    return truth, out


# --- estimate -------------------------------------------------------------------------------
def scores_path(row: Row, tag: str = "scores") -> Path:
    return CACHE / f"{row.name}.{tag}.jsonl"


def estimate_row(row: Row, use_placeholder: bool, limit: int | None) -> None:
    """Estimate a row's cached campaigns, appending one JSON line per campaign (its score, or
    the estimator's error) to ``build/study_inertia/ROW.scores.jsonl``; campaigns already
    there are skipped, so an interrupted run resumes."""
    truth, camps = campaigns(row)
    camps = camps[:limit] if limit else camps
    out = scores_path(row)
    done = {json.loads(x)["seed"] for x in out.read_text().splitlines()} if out.exists() else set()
    rng = np.random.default_rng(0)
    with tempfile.TemporaryDirectory() as tmp, out.open("a", encoding="utf-8") as log:
        d = Path(tmp)
        src = parameter_source(row)
        params = er.parameter_file(src, row.source, row.config, truth, d, swing_extra(row))
        for seed, camp in enumerate(camps):
            if seed in done:
                continue
            sw, rd = d / "swings.csv", d / "readings.csv"
            sf.write_campaign(camp, sw, rd)
            t0 = time.time()
            try:
                if use_placeholder:
                    res = er.placeholder(truth, rng)
                else:
                    extra: tuple[str, ...] = ()
                    if row.weighed:  # a scale of 1 g: the true mass plus its error
                        scale_rng = np.random.default_rng([7, seed])  # the same on a resume
                        mass = truth.object_mass_kg + scale_rng.normal(0.0, 0.001)
                        extra = ("--weighed-mass-kg", f"{mass:.6f}", "--mass-sigma-kg", "0.001")
                    res = er.run_estimator(sw, rd, params, row.source, extra)
                entry: dict[str, Any] = {"seed": seed, **er.score(res, truth)}
            except (RuntimeError, SystemExit, ValueError) as exc:
                entry = {"seed": seed, "error": str(exc) or type(exc).__name__}
            entry["seconds"] = round(time.time() - t0, 1)
            log.write(json.dumps(entry) + "\n")
            log.flush()


def load_scores(row: Row, tag: str) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """A row's scored campaigns and its failed ones (``ROW.TAG.jsonl``)."""
    p = scores_path(row, tag)
    entries = [json.loads(x) for x in p.read_text().splitlines()] if p.exists() else []
    return [e for e in entries if "error" not in e], [e for e in entries if "error" in e]


def rate(k: int, n: int) -> str:
    lo, hi = stats.binomtest(k, n).proportion_ci(0.95)  # Clopper-Pearson
    return f"{k / n:.1%} [{lo:.1%}, {hi:.1%}]"


def table(rows: list[tuple[Row, list[dict[str, Any]], int]]) -> str:
    out = [
        "| row | n | moment | bias | 95 % abs. error | error/σ: mean, sd | in ±1.96 σ [CP 95 %] "
        "| same, σ before the χ² scale | axis error 95 % | axis ≤ 2° |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    chi = [
        "| row | n | tensor χ² ≤ χ²₆(95 %) [CP 95 %] | same, before the χ² scale "
        "| median χ² (6 expected: 5.35) | σ scaled (median scale) | campaigns refused [CP 95 %] "
        "| frequencies' χ²: median |",
        "|---|---|---|---|---|---|---|---|",
    ]
    along = [
        "| row | n | moment about the true axis | bias | 95 % abs. error | error/σ: mean, sd "
        "| in ±1.96 σ [CP 95 %] |",
        "|---|---|---|---|---|---|---|",
    ]
    for row, sc, refused in rows:
        n = len(sc)
        if n == 0:
            continue
        if all("rel_true_axes" in s for s in sc):
            ra = np.array([s["rel_true_axes"] for s in sc])
            za = np.array([s["z_true_axes"] for s in sc])
            for i, name in enumerate(("I₁ (smallest)", "I₂", "I₃ (largest)")):
                zsd = za[:, i].std(ddof=1) if n > 1 else 0.0
                along.append(
                    f"| {row.label} | {n} | {name} | {100 * ra[:, i].mean():+.2f} % | "
                    f"{100 * np.quantile(np.abs(ra[:, i]), 0.95):.2f} % | "
                    f"{za[:, i].mean():+.2f}, {zsd:.2f} | "
                    f"{rate(int(np.sum(np.abs(za[:, i]) <= 1.96)), n)} |"
                )
        rel = np.array([s["rel"] for s in sc])
        z = np.array([s["z"] for s in sc])
        ax = np.array([s["axis_deg"] for s in sc])
        scale = np.array([s.get("sigma_scale", 1.0) for s in sc])
        for i, name in enumerate(("I₁ (smallest)", "I₂", "I₃ (largest)")):
            cover = int(np.sum(np.abs(z[:, i]) <= 1.96))
            raw = int(np.sum(np.abs(z[:, i] * scale) <= 1.96))
            within = int(np.sum(ax[:, i] <= 2.0))
            zsd = z[:, i].std(ddof=1) if n > 1 else 0.0
            out.append(
                f"| {row.label} | {n} | {name} | {100 * rel[:, i].mean():+.2f} % | "
                f"{100 * np.quantile(np.abs(rel[:, i]), 0.95):.2f} % | "
                f"{z[:, i].mean():+.2f}, {zsd:.2f} | {rate(cover, n)} | {rate(raw, n)} | "
                f"{np.quantile(ax[:, i], 0.95):.2f}° | {rate(within, n)} |"
            )
        c2 = np.array([s["chi2"] for s in sc])
        c2_raw = c2 * scale**2
        scaled = scale > 1.0
        median_scale = f"{np.median(scale[scaled]):.2f}" if scaled.any() else "-"
        chi.append(
            f"| {row.label} | {n} | {rate(int(np.sum(c2 <= CHI2_6_95)), n)} | "
            f"{rate(int(np.sum(c2_raw <= CHI2_6_95)), n)} | {np.median(c2):.2f} | "
            f"{rate(int(scaled.sum()), n)} ({median_scale}) "
            f"| {refused}/{n + refused} = {rate(refused, n + refused)} | {freq_chi2(sc)} |"
        )
    tables = [out, chi] + ([along] if len(along) > 2 else [])
    return "\n\n".join("\n".join(t) for t in tables) + "\n"


def freq_chi2(scores: list[dict[str, Any]]) -> str:
    """The median of the frequencies' own χ² (their consistency, ``cadcog inertia``'s
    ``consistency.chi2``; "-" for scores from before it was kept)."""
    v = np.array([s.get("freq_chi2", np.nan) for s in scores], float)
    return f"{np.nanmedian(v):.2f}" if np.isfinite(v).any() else "-"


def modes_table() -> str:
    """The truth's small-oscillation frequencies of every paper-rig hang at each wire length."""
    truth = sf.rig_truth(RIG)
    out = ["| L (mm) | hang | modes (Hz) |", "|---|---|---|"]
    for length in (0.0, 100.0, 300.0, 1000.0):
        for pid, exit_mm in truth.hangs:
            f = sf.st.linear_modes_hz(truth.hung_from(exit_mm), length)
            out.append(f"| {length:g} | {pid} | {', '.join(f'{v:.4f}' for v in f)} |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("phase", choices=("simulate", "estimate", "report", "modes"))
    ap.add_argument("--rows", nargs="*", default=list(ROWS), choices=list(ROWS))
    ap.add_argument("--seeds", type=int, default=200)
    ap.add_argument("--batch", type=int, default=100, help="campaigns integrated together")
    ap.add_argument("--limit", type=int, default=None, help="estimate the first N campaigns")
    ap.add_argument("--placeholder", action="store_true")
    ap.add_argument("--tag", default="scores", help="report ROW.TAG.jsonl (an older run kept)")
    args = ap.parse_args(argv)
    if args.phase == "modes":
        print(modes_table())
        return
    if args.phase == "simulate":
        for name in args.rows:
            print(f"{name}: {simulate(ROWS[name], args.seeds, args.batch)}", file=sys.stderr)
        return
    if args.phase == "estimate":
        for name in args.rows:
            t0 = time.time()
            estimate_row(ROWS[name], args.placeholder, args.limit)
            print(f"  {name}: {time.time() - t0:.0f} s", file=sys.stderr)
        return
    results, failed = [], []
    for name in args.rows:
        ok, bad = load_scores(ROWS[name], args.tag)
        results.append((ROWS[name], ok, len(bad)))
        failed += [f"- {ROWS[name].label}, seed {e['seed']}: {e['error']}" for e in bad]
    print(time.strftime("%Y-%m-%d"))
    print(table(results))
    print("estimator failures:" if failed else "no estimator failure")
    print("\n".join(failed))


if __name__ == "__main__":
    main()
