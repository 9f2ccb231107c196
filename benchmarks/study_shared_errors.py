"""What a rig shares across its hangs (issue 31): the CoG estimate's coverage and the consistency
check's alarms on campaigns from an independent generator that draws the wire and the sensor's
errors once per test.

The campaigns come from :mod:`support.rig_campaigns` (written from the documented
physics, without cadcog's campaign, Monte Carlo or error-model code): the paper rig, the ME's
real CoG in its cubes, play per hang, the wire one of

- ``flexible``: an ideal string, no offset on any hang;
- ``stiff``: EI 30 N·mm² under the hung weight, its straight part's line found by integrating
  the elastica numerically (λ = 0.57 mm on the paper rig);

and one sensor per campaign: zero offsets uniform ±0.3° per channel, sensitivities ±1 %, its
axes within 0.5° of the object's (uniform in angle about a random axis), plus the per-hang bias
(±0.1°), the noise (0.05° per sample) and the 10-bit ADC. Each campaign is written as a readings
CSV of counts, read back by :func:`cadcog.method.readings.read_readings` and estimated by the
function behind ``cadcog estimate --rig``, with the rig file's error model and the sensor's
figures declared (``offset_deg = 0.3``, ``scale_error_rel = 0.01``,
``mounting_misalignment_deg = 0.5``) or not (the estimator then knows only per-hang errors).

Printed per scenario: the fraction of campaigns whose true proof-mass CoG lies inside the
estimate's 95 % ellipsoid (with its 95 % binomial interval), the mean squared Mahalanobis
distance (3 when calibrated), the fraction of campaigns with a line flagged inconsistent, the
mean error per axis (bias), the observed 95th percentile of the error's norm (with its
distribution-free 95 % interval from the order statistics) and what the Monte Carlo of
``cadcog simulate``/``plan`` predicts for that set of hangs on that rig (20 000 campaigns, one
sensor each, drawn from cadcog's own error model), and the mean stated σ (√trace of the
estimate's covariance). A set ``+ S3~`` has S3 hung again with the sensor turned 180° on its
mount (a reversal: a re-hang with its own play, bias and noise; the Monte Carlo has no reversal,
so its column reads n/a there).

Run: ``.venv/bin/python benchmarks/study_shared_errors.py [--campaigns 200] [--seed 31]``; the
table is in ``docs/estimate.md``.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from scipy import stats

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from cadcog.method.errormodel import ErrorModel
from cadcog.method.estimate import estimate_for_rig
from cadcog.method.readings import read_readings
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.uncertainty.montecarlo import Scenario, simulate
from support.rig_campaigns import RigPhysics, generate, write_csv

FIGURES = (0.3, 0.01, 0.5)  # offset °, scale, mounting °
SETS = {
    "S1-S6": ("S1", "S2", "S3", "S4", "S5", "S6"),
    "S1-S6 + S3~": ("S1", "S2", "S3", "S4", "S5", "S6", "S3~"),
    "S1,S3,S5": ("S1", "S3", "S5"),
    "S1,S3,S5 + S3~": ("S1", "S3", "S5", "S3~"),
    "S1,S2": ("S1", "S2"),
}
#: ``X~``: X hung again with the sensor turned 180° on its mount (a reversal, its own re-hang).


def rate(k: int, n: int) -> str:
    lo, hi = stats.binomtest(k, n).proportion_ci(0.95)
    return f"{k / n:.1%} [{lo:.0%}, {hi:.0%}]"


def quantile_interval(values: list[float], q: float = 0.95) -> str:
    """The sample's ``q`` quantile and its distribution-free 95 % interval (order statistics)."""
    x = np.sort(np.asarray(values))
    n = len(x)
    lo = int(stats.binom.ppf(0.025, n, q)) - 1
    hi = int(stats.binom.ppf(0.975, n, q))
    return f"{np.quantile(x, q):.2f} [{x[max(lo, 0)]:.2f}, {x[min(hi, n - 1)]:.2f}]"


def predicted_q95(rig: object, points: tuple[str, ...], seed: int) -> str:
    """The Monte Carlo's 95 % error of the set ``points`` on ``rig`` (one sensor a campaign);
    the Monte Carlo has no reversal: "n/a" for a set with one."""
    if any(p.endswith("~") for p in points):
        return "n/a"
    sc = Scenario.from_rig(rig)  # type: ignore[arg-type]
    group = tuple(sc.ids.index(p) for p in points)
    res = simulate(sc, ErrorModel.from_rig(rig), [group], 20_000, seed)  # type: ignore[arg-type]
    return f"{float(res.group_q95_mm[0]):.2f}"


def run(wire: str, name: str, declared: bool, n: int, seed: int) -> list[str]:
    points = SETS[name]
    rig = load_rig(default_rig_path())
    phys = RigPhysics.from_file(default_rig_path())
    if declared:
        inc = replace(
            rig.inclinometer,
            offset_deg=FIGURES[0],
            scale_error_rel=FIGURES[1],
            mounting_misalignment_deg=FIGURES[2],
        )
        rig = replace(rig, inclinometer=inc)
    d2, flagged, errors, sigma = [], 0, [], []
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "campaign.csv"
        for i in range(n):
            c = generate(
                phys,
                seed,
                i,
                wire=wire,
                sensor_offset_deg=FIGURES[0],
                sensor_scale_rel=FIGURES[1],
                mounting_deg=FIGURES[2],
                reversals=tuple(p[:-1] for p in points if p.endswith("~")),
            )
            write_csv(phys, c, path, quantise=True)
            sus = [s for s in read_readings(path, rig.inclinometer) if s.id in points]
            est = estimate_for_rig(rig, sus)
            e = est.cog_mm - phys.pm_cog_mm
            errors.append(e)
            d2.append(float(e @ np.linalg.solve(est.cov_mm2, e)))
            sigma.append(float(np.sqrt(np.trace(est.cov_mm2))))
            flagged += any(r.inconsistent for r in est.joint.residuals)
    d2a = np.array(d2)
    inside = int(np.sum(d2a <= stats.chi2.ppf(0.95, 3)))
    bias = np.mean(errors, axis=0)
    norms = [float(np.linalg.norm(e)) for e in errors]
    return [
        wire,
        name,
        "declared" if declared else "not declared",
        rate(inside, n),
        f"{d2a.mean():.2f}",
        rate(flagged, n),
        "(" + ", ".join(f"{b:+.2f}" for b in bias) + ")",
        f"{np.mean(sigma):.2f}",
        quantile_interval(norms),
        predicted_q95(rig, points, seed),
    ]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--campaigns", type=int, default=200)
    ap.add_argument("--seed", type=int, default=31)
    args = ap.parse_args()
    t0 = time.time()
    rows = []
    for wire in ("flexible", "stiff"):
        for name in SETS:
            rows.append(run(wire, name, True, args.campaigns, args.seed))
        rows.append(run(wire, "S1-S6", False, args.campaigns, args.seed))
    head = ["wire", "hangs", "sensor figures", "95 % covers", "mean d²", "flagged", "bias mm",
            "stated σ mm", "q95 \\|e\\| mm [95 % CI]", "Monte Carlo q95 mm"]  # fmt: skip
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for r in rows:
        print("| " + " | ".join(r) + " |")
    print(
        f"\n{args.campaigns} campaigns per row, seed {args.seed}, "
        f"{time.time() - t0:.0f} s, pid {os.getpid()}"
    )


if __name__ == "__main__":
    main()
