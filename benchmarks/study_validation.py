"""Size and power of `cadcog validate`'s campaign verdict, and of the statistics it could use.

Virtual campaigns on the paper rig (:func:`cadcog.validation.campaign.simulated_readings`, read back
as `cadcog validate` reads a CSV: :func:`cadcog.validation.campaign.campaign_suspensions`) are
validated by :func:`cadcog.validation.verification.validate_campaign`, the function behind the
command, against one null distribution of simulated whole campaigns
(:func:`cadcog.validation.verification.campaign_null`, 2000 campaigns, the command's default). Three
truths:

- ``clean``: campaigns from the error model itself (the false-alarm rate);
- ``doubled``: every error's spread doubled about its mean (inclinometer accuracy and noise,
  play, ME cubes; the wire offset U(−0.5, 1.5) mm instead of U(0, 1) mm);
- ``3× bias``: the inclinometer's accuracy bias three times the model's (±0.3°).

Beside the verdict's statistic T (each hang's line against the known CoG) it measures, with
thresholds set on separate clean campaigns, the power the other candidates would have: the
Mahalanobis² of the joint estimate, the KS distance and the mean of the pair errors, and the
paper's window check (any window whose F(ε) leaves the Clopper-Pearson interval of p̂).

Run: ``.venv/bin/python benchmarks/study_validation.py [--campaigns 1000]``; the tables are in
``docs/validation.md``.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace

import numpy as np
from scipy import stats

from cadcog.method.errormodel import ErrorModel
from cadcog.method.estimate import BodyBox, MEData, estimate_cog
from cadcog.method.readings import Suspension
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.rig.parameters import Rig
from cadcog.uncertainty.montecarlo import Scenario
from cadcog.validation.campaign import campaign_suspensions, simulated_readings
from cadcog.validation.verification import campaign_null, campaign_scenario, validate_campaign


def campaigns(rig: Rig, truth: str, seeds: range) -> list[list[Suspension]]:
    """Virtual campaigns of one truth, with the positions a lab would record."""
    model = ErrorModel.from_rig(rig)
    sc = Scenario.from_rig(rig)
    if truth == "doubled":
        model = replace(
            model,
            accuracy_deg=2 * model.accuracy_deg,
            sensor_noise_deg=2 * model.sensor_noise_deg,
            play_mm=2 * model.play_mm,
            me_edges_mm=tuple(2 * e for e in model.me_edges_mm),
            wire_offset_max_mm=2 * model.wire_offset_max_mm,
        )
        # U(0, 2) above a bolt head 0.5 mm below where the lab thinks it is: U(−0.5, 1.5).
        sc = sc.with_points(sc.ids, sc.points_mm - 0.5 * sc.normals, sc.normals)
    elif truth == "3x bias":
        model = replace(model, accuracy_deg=3 * model.accuracy_deg)
    nominal = Scenario.from_rig(rig).points_mm
    out = []
    for seed in seeds:
        sus = campaign_suspensions(
            simulated_readings(sc, model, rig.inclinometer, seed), rig.inclinometer
        )
        out.append(
            [
                replace(s, position_mm=tuple(float(c) for c in p))
                for s, p in zip(sus, nominal, strict=True)
            ]  # type: ignore[misc]
        )
    return out


def statistics(rig: Rig, sus: list[Suspension], null: object) -> dict[str, float]:
    v = validate_campaign(rig, sus, null=null)  # type: ignore[arg-type]
    est = estimate_cog(
        sus,
        rig.inclinometer,
        MEData.from_rig(rig),
        model=ErrorModel.from_rig(rig),
        body=BodyBox.of_rig(rig),
    )
    e = est.cog_mm - rig.analytic_proof_mass.cog_mm
    return {
        "p": v.verdict.p_value,
        "T": v.verdict.statistic,
        "mahalanobis2": float(e @ np.linalg.solve(est.cov_mm2, e)),
        "ks": v.validation.ks_statistic,
        "mean_pair": float(np.mean(v.validation.measured_norms_mm)),
        "cp_alarm": float(not v.validation.consistent_cp),
        "window_alarm": float(not v.validation.consistent),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--campaigns", type=int, default=1000)
    args = parser.parse_args()
    n = args.campaigns
    rig = load_rig(default_rig_path())
    model = ErrorModel.from_rig(rig)
    t = time.perf_counter()
    first = campaigns(rig, "clean", range(1))[0]
    null = campaign_null(campaign_scenario(rig, first), model, 2000, seed=12345)
    print(f"null distribution: 2000 campaigns in {time.perf_counter() - t:.2f} s")
    stats_by = {}
    # Thresholds of the alternative statistics from clean campaigns of their own.
    for truth, seeds in (
        ("reference", range(10_000, 10_000 + n)),
        ("clean", range(n)),
        ("doubled", range(n)),
        ("3x bias", range(n)),
    ):
        t = time.perf_counter()
        runs = campaigns(rig, "clean" if truth == "reference" else truth, seeds)
        stats_by[truth] = {
            k: np.array(v)
            for k, v in zip(
                ("p", "T", "mahalanobis2", "ks", "mean_pair", "cp_alarm", "window_alarm"),
                zip(*[statistics(rig, s, null).values() for s in runs], strict=True),
                strict=True,
            )
        }
        print(f"{truth}: {n} campaigns in {time.perf_counter() - t:.1f} s")
    ref = stats_by["reference"]
    print(f"\n## {n} campaigns per truth; level 5 %\n")
    print(
        "| statistic | false alarms (clean) | power: doubled errors | power: 3× inclinometer bias |"
    )
    print("|---|---|---|---|")

    def rate(x: np.ndarray) -> str:
        k = int(np.sum(x))
        lo, hi = stats.binomtest(k, x.size).proportion_ci(0.95)
        return f"{k / x.size:.1%} [{lo:.1%}, {hi:.1%}]"

    print(
        "| **T, campaign verdict (p < 0.05 against the simulated null)** | "
        + " | ".join(rate(stats_by[t]["p"] < 0.05) for t in ("clean", "doubled", "3x bias"))
        + " |"
    )
    for key, name in (
        ("T", "T, threshold from clean campaigns"),
        ("mahalanobis2", "Mahalanobis² of the joint estimate"),
        ("ks", "KS distance of the pair errors"),
        ("mean_pair", "mean pair error"),
    ):
        thr = np.quantile(ref[key], 0.95)
        print(
            f"| {name} | "
            + " | ".join(rate(stats_by[t][key] > thr) for t in ("clean", "doubled", "3x bias"))
            + " |"
        )
    for key, name in (
        ("cp_alarm", "paper's window check (Clopper-Pearson, pairs as independent)"),
        ("window_alarm", "any window outside its simulated null range"),
    ):
        print(
            f"| {name} | "
            + " | ".join(rate(stats_by[t][key] > 0) for t in ("clean", "doubled", "3x bias"))
            + " |"
        )
    p = stats_by["clean"]["p"]
    print(
        f"\nclean campaigns' p-values: KS distance from uniform "
        f"{stats.kstest(p, 'uniform').statistic:.3f}"
    )


if __name__ == "__main__":
    main()
