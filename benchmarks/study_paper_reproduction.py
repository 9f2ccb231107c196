"""Reproduce the paper's Monte Carlo headline and measure what cadcog's improvements buy.

Run: ``.venv/bin/python benchmarks/study_paper_reproduction.py``; the tables it prints are in
``docs/montecarlo.md``. Every figure is an empirical 95 % (or 50 %) quantile of |e| in mm.

The paper's reproduction uses the paper's own model (``ErrorModel.paper()``: inclinometer errors
averaged per sample, no sensor noise) and estimator (eq. 8, no wire correction). What cadcog's
improvements buy is measured under the physical model (``hang-bias``, the default of every
command), estimator by estimator, on the rig's own points.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from cadcog.method.errormodel import ErrorModel
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.rig.parameters import Rig
from cadcog.uncertainty.montecarlo import EstimatorOptions, Scenario, simulate
from cadcog.uncertainty.random_points import SimulationSettings, run_simulation

PAPER = {"weighted": False, "wire_correction": False}


def q95(rig: Rig, settings: SimulationSettings, model: ErrorModel) -> tuple[float, float]:
    r = run_simulation(rig, settings, model, workers=2)
    return r.fits.q95_mm, r.fits.q50_mm


def main() -> None:
    rig = load_rig(default_rig_path())
    physical = ErrorModel.from_rig(rig)
    paper = physical.paper()
    seeds = range(10)

    print("## Paper set-up: 25 random points, 300 pairs, 1000 trials each (10 seeds)\n")
    print("| variant | q95 mean | q95 range | q50 mean |\n|---|---|---|---|")
    variants = [
        ("paper's model and estimator (eq. 8)", PAPER, paper),
        ("pairs screened at 5°", {**PAPER, "min_angle_deg": 5.0}, paper),
        ("pairs screened at 10°", {**PAPER, "min_angle_deg": 10.0}, paper),
        ("no wire offset at all", PAPER, paper.only("me_cog", "inclinometer", "point_play")),
        ("wire offset's mean corrected", {**PAPER, "wire_correction": True}, paper),
        ("physical inclinometer model (bias per hang), eq. 8", PAPER, physical),
        ("physical model, cadcog's estimator (GLS, corrected)", {}, physical),
    ]
    for name, kw, model in variants:
        res = [q95(rig, SimulationSettings(seed=s, **kw), model) for s in seeds]
        q = np.array([r[0] for r in res])
        print(
            f"| {name} | {q.mean():.2f} | {q.min():.2f}-{q.max():.2f} | "
            f"{np.mean([r[1] for r in res]):.2f} |"
        )

    print("\n## The rig's own points, physical model, 10⁵ trials per group\n")
    print("| hangs | estimator | q95 | q50 |\n|---|---|---|---|")
    sc = Scenario.from_rig(rig)
    ids = list(sc.ids)
    rows = [
        ("15 pairs", [tuple(p) for p in _pairs(6)]),
        ("S1+S3+S5", [(0, 2, 4)]),
        ("S1+S2", [(0, 1)]),
        ("all 6", [tuple(range(6))]),
    ]
    for label, groups in rows:
        for name, opts in (
            ("equal weights, uncorrected (the paper's)", EstimatorOptions.paper()),
            ("equal weights, wire corrected", EstimatorOptions(weighted=False)),
            ("cadcog (GLS, corrected)", EstimatorOptions()),
        ):
            r = simulate(sc, physical, groups, 100_000, seed=1, options=opts, workers=2)
            names = label if len(groups) > 1 else "+".join(ids[i] for i in groups[0])
            print(
                f"| {names} | {name} | {r.histogram.quantile(0.95):.2f} | "
                f"{r.histogram.quantile(0.5):.2f} |"
            )
    elastica = replace(physical, wire_model="elastica")
    for corr in (False, True):
        r = simulate(sc, elastica, [tuple(range(6))], 100_000, seed=1,
                     options=EstimatorOptions(wire_correction=corr), workers=2)  # fmt: skip
        print(
            f"| all 6, elastica wire | cadcog, correction {'on' if corr else 'off'} | "
            f"{r.histogram.quantile(0.95):.2f} | {r.histogram.quantile(0.5):.2f} |"
        )
    for samples in (10, 100):
        m = replace(physical, samples=samples)
        r = simulate(sc, m, [tuple(range(6))], 100_000, seed=1, workers=2)
        print(
            f"| all 6, {samples} samples averaged | cadcog | {r.histogram.quantile(0.95):.2f} | "
            f"{r.histogram.quantile(0.5):.2f} |"
        )


def _pairs(n: int) -> list[tuple[int, int]]:
    return [(a, b) for a in range(n) for b in range(a + 1, n)]


if __name__ == "__main__":
    main()
