"""Do `cadcog estimate`'s uncertainties cover, and does `cadcog plan` predict what it gets?

Virtual campaigns (:func:`cadcog.validation.campaign.simulated_readings`: raw ADC counts with noise,
a bias per hang, play per hang, one wire and one ME error per campaign) are read back as `cadcog
estimate` reads them (:func:`cadcog.validation.campaign.campaign_suspensions`, equal to the CSV
path: ``tests/uncertainty/test_calibration.py``) and estimated by
:func:`cadcog.method.estimate.estimate_cog`, the function behind the command. For each set of hangs
it reports how often the reported 68 % and 95 % ellipsoids (Mahalanobis² ≤ χ²₃) contain the true
CoG, how often a clean line is flagged inconsistent, the self-calibrated wire scale's z-score
coverage, and the realised 95 % error.

Run: ``.venv/bin/python benchmarks/study_calibration.py [--campaigns 2000]``; it prints the
tables of ``docs/estimate.md`` (calibration) and ``docs/spacecraft.md`` (plan) and writes
``docs/calibration.png``.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from scipy import stats

from cadcog.method.errormodel import ErrorModel
from cadcog.method.estimate import BodyBox, MEData, estimate_cog
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.rig.inclinometer import InclinometerConfig
from cadcog.uncertainty.montecarlo import Scenario
from cadcog.validation.campaign import campaign_suspensions, simulated_readings

DOCS = Path(__file__).resolve().parents[1] / "docs"


@dataclass
class Outcome:
    name: str
    d2: np.ndarray  # Mahalanobis² of the compensated CoG error
    norms: np.ndarray  # |e| (mm)
    flagged: int  # lines flagged inconsistent
    lines: int
    z_scale: np.ndarray  # (λ̂ − λ_true)/σ_λ, self-calibrated runs

    def row(self) -> str:
        n = self.d2.size
        c95 = np.mean(self.d2 <= stats.chi2.ppf(0.95, 3))
        c68 = np.mean(self.d2 <= stats.chi2.ppf(0.68, 3))
        z = f"{np.mean(np.abs(self.z_scale) <= 1.96):.1%}" if self.z_scale.size else "-"
        return (
            f"| {self.name} | {n} | {c95:.1%} | {c68:.1%} | {self.flagged / self.lines:.2%} | "
            f"{z} | {np.quantile(self.norms, 0.95):.3f} |"
        )


def run_set(
    name: str,
    scenario: Scenario,
    model: ErrorModel,
    config: InclinometerConfig,
    me: MEData,
    body: BodyBox,
    truth_mm: np.ndarray,
    campaigns: int,
    *,
    self_calibrate: bool = False,
    truth_model: ErrorModel | None = None,
    true_scale_mm: float | None = None,
    seed0: int = 0,
) -> Outcome:
    d2, norms, zs = [], [], []
    flagged = lines = 0
    for seed in range(seed0, seed0 + campaigns):
        rows = simulated_readings(scenario, truth_model or model, config, seed)
        sus = campaign_suspensions(rows, config)
        est = estimate_cog(sus, config, me, model=model, body=body, self_calibrate=self_calibrate)
        e = est.cog_mm - truth_mm
        d2.append(float(e @ np.linalg.solve(est.cov_mm2, e)))
        norms.append(float(np.linalg.norm(e)))
        flagged += sum(r.inconsistent for r in est.joint.residuals)
        lines += len(est.joint.residuals)
        if self_calibrate and true_scale_mm is not None and est.joint.wire is not None:
            w = est.joint.wire
            zs.append((w.scale_mm - true_scale_mm) / w.sigma_mm)
    return Outcome(name, np.array(d2), np.array(norms), flagged, lines, np.array(zs))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--campaigns", type=int, default=2000)
    parser.add_argument("--no-cubesat", action="store_true", help="skip the CAD-based set-up")
    parser.add_argument(
        "--only", help="run the paper-rig row of this name only (e.g. S1+S2), no CubeSat"
    )
    args = parser.parse_args()
    n = args.campaigns
    t0 = time.perf_counter()
    rig = load_rig(default_rig_path())
    model = ErrorModel.from_rig(rig)
    me = MEData.from_rig(rig)
    body = BodyBox.of_rig(rig)
    full = Scenario.from_rig(rig)
    truth = rig.analytic_proof_mass.cog_mm
    ids = list(full.ids)

    def subset(names: list[str]) -> Scenario:
        idx = [ids.index(i) for i in names]
        return full.with_points(names, full.points_mm[idx], full.normals[idx])

    outcomes = []
    for name, names in (
        ("paper rig, S1-S6", ids),
        ("S1+S3+S5", ["S1", "S3", "S5"]),
        ("S1+S2", ["S1", "S2"]),
    ):
        if args.only is None or args.only == name:
            outcomes.append(
                run_set(name, subset(names), model, rig.inclinometer, me, body, truth, n)
            )
    if args.only is not None:
        for o in outcomes:
            print(o.row())
        return
    elastica = replace(model, wire_model="elastica")
    outcomes.append(
        run_set("S1-S6, elastica wire", full, elastica, rig.inclinometer, me, body, truth, n)
    )
    # Self-calibration: the true wire is twice as stiff as the rig file says (EI 60, not 30
    # N·mm²), known exactly in the truth; the estimator starts from the file's value.
    stiff = replace(elastica, wire_bending_stiffness_n_mm2=60.0, wire_stiffness_rel_uncertainty=0.0)
    lam_true = stiff.wire_length_mm(full.weight_n)
    outcomes.append(
        run_set(
            f"S1-S6, self-calibrated λ (true {lam_true:.3f} mm)",
            full,
            elastica,
            rig.inclinometer,
            me,
            body,
            truth,
            n,
            self_calibrate=True,
            truth_model=stiff,
            true_scale_mm=lam_true,
        )
    )
    paper_wire = replace(model, wire_model="paper")
    outcomes.append(
        run_set(
            "S1-S6, paper wire (per hang)", full, paper_wire, rig.inclinometer, me, body, truth, n
        )
    )
    outcomes.append(
        run_set(
            "S1-S6, paper wire, self-calibrated λ (true 0.5 mm)",
            full,
            paper_wire,
            rig.inclinometer,
            me,
            body,
            truth,
            n,
            self_calibrate=True,
            true_scale_mm=0.5,
        )
    )
    plan_rows = []
    if not args.no_cubesat:
        from cadcog.spacecraft.plan import plan_test
        from cadcog.spacecraft.setup import load_setup

        setup = load_setup(default_rig_path().parent / "cubesat_3u_setup.toml")
        t = time.perf_counter()
        plan = plan_test(setup)
        plan_s = time.perf_counter() - t
        assert plan.recommended is not None
        by_id = {c.id: c for c in setup.candidates}
        lo, hi = setup.bbox_mm
        sbody = BodyBox(lo, hi, "setup")
        for s in plan.best_sets:
            sc = setup.scenario(tuple(by_id[i] for i in s["points"]))
            out = run_set(
                f"3U CubeSat, {len(s['points'])} hangs: {', '.join(s['points'])}",
                sc,
                setup.error_model(),
                setup.rig.inclinometer,
                setup.me_data(),
                sbody,
                setup.mass.cog_mm,
                n,
            )
            outcomes.append(out)
            realised = float(np.quantile(out.norms, 0.95))
            # Binomial 95 % interval of the realised quantile (order statistics).
            k_lo, k_hi = stats.binom.ppf([0.025, 0.975], n, 0.95).astype(int)
            srt = np.sort(out.norms)
            plan_rows.append(
                f"| {', '.join(s['points'])} | {s['q95_mm']:.3f} | {s['linearised_q95_mm']:.3f} | "
                f"{realised:.3f} [{srt[k_lo - 1]:.3f}, {srt[min(k_hi, n - 1)]:.3f}] | "
                f"{s['q95_mm'] / realised - 1:+.1%} |"
            )
        print(f"plan_test on the 3U example: {plan_s:.2f} s (library call, set-up loaded)")

    print(f"\n## Calibration, {n} virtual campaigns per row\n")
    print(
        "| hangs | campaigns | inside 95 % ellipsoid | inside 68 % ellipsoid | lines flagged "
        "(nominal 0.30 %) | λ within ±1.96 σ | realised 95 % error (mm) |"
    )
    print("|---|---|---|---|---|---|---|")
    for o in outcomes:
        print(o.row())
    lo95, hi95 = stats.binom.ppf([0.005, 0.995], n, 0.95) / n
    lo68, hi68 = stats.binom.ppf([0.005, 0.995], n, 0.68) / n
    print(
        f"\n99 % binomial range for a calibrated ellipsoid with {n} campaigns: 95 %: "
        f"{lo95:.1%}-{hi95:.1%}, 68 %: {lo68:.1%}-{hi68:.1%}"
    )
    if plan_rows:
        print("\n## `cadcog plan` on the 3U example: predicted against realised\n")
        print(
            "| set | plan's simulated 95 % (mm) | linearised (mm) | realised by campaign + "
            "estimate (mm) [95 % CI] | plan vs realised |"
        )
        print("|---|---|---|---|---|")
        print("\n".join(plan_rows))
    _figure(outcomes, DOCS / "calibration.png")
    print(f"\n{time.perf_counter() - t0:.0f} s")


def _figure(outcomes: list[Outcome], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.2), dpi=120)
    x = np.linspace(0, 16, 400)
    ax.plot(x, stats.chi2.cdf(x, 3), "k", lw=2.5, alpha=0.4, label="χ²₃ (calibrated)")
    for o in outcomes:
        d = np.sort(o.d2)
        ax.step(d, np.arange(1, d.size + 1) / d.size, where="post", lw=1, label=o.name)
    for q in (0.68, 0.95):
        ax.axhline(q, color="grey", lw=0.6, ls=":")
    ax.set_xlim(0, 16)
    ax.set_xlabel("Mahalanobis² of the estimate's error (reported covariance)")
    ax.set_ylabel("fraction of campaigns")
    ax.set_title("Calibration of cadcog estimate's covariance, virtual campaigns", fontsize=10)
    ax.legend(fontsize=6.5, loc="lower right")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


if __name__ == "__main__":
    main()
