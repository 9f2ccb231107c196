"""Reproduce the paper's Monte Carlo headline and measure what cadcog's improvements buy.

Run: ``.venv/bin/python benchmarks/study_paper_reproduction.py``; the tables it prints are in
``docs/montecarlo.md``. Every figure is an empirical 95 % quantile of |e| in mm.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from cadcog.errormodel import ErrorModel
from cadcog.rig import Rig
from cadcog.rigfile import default_rig_path, load_rig
from cadcog.simulation import SimulationSettings, run_simulation


def q95(rig: Rig, settings: SimulationSettings, model: ErrorModel) -> tuple[float, float]:
    r = run_simulation(rig, settings, model, workers=2)
    return r.fits.q95_mm, r.fits.q50_mm


def main() -> None:
    rig = load_rig(default_rig_path())
    paper = ErrorModel.from_rig(rig)
    seeds = range(10)

    print("## Paper set-up: 25 random points, 300 pairs, 1000 trials each (10 seeds)\n")
    print("| variant | q95 mean | q95 range | q50 mean |\n|---|---|---|---|")
    variants = [
        ("paper's model (pairs, eq. 8)", {}, paper),
        ("pairs screened at 5°", {"min_angle_deg": 5.0}, paper),
        ("pairs screened at 10°", {"min_angle_deg": 10.0}, paper),
        ("no wire offset at all", {}, paper.only("me_cog", "inclinometer", "point_play")),
        ("wire offset's mean corrected", {"wire_correction": True}, paper),
    ]
    for name, kw, model in variants:
        res = [q95(rig, SimulationSettings(seed=s, **kw), model) for s in seeds]
        q = np.array([r[0] for r in res])
        print(
            f"| {name} | {q.mean():.2f} | {q.min():.2f}-{q.max():.2f} | "
            f"{np.mean([r[1] for r in res]):.2f} |"
        )

    print("\n## The paper's campaign: the rig's 6 points, 10⁵ trials per group\n")
    print("| estimator | improvements | q95 | q50 |\n|---|---|---|---|")
    base = SimulationSettings(points=0, trials_per_group=100_000, seed=1)
    rows = [
        ("15 pairs, eq. 8", "none (the paper)", base, paper),
        ("15 pairs, eq. 8", "wire correction", replace(base, wire_correction=True), paper),
        ("15 pairs, eq. 8", "100 samples averaged", base, replace(paper, samples=100)),
        ("15 pairs, eq. 8", "screened at 45°", replace(base, min_angle_deg=45.0), paper),
        ("joint, 3 points", "none", replace(base, group_size=3), paper),
        ("joint, 6 points", "none", replace(base, group_size=6), paper),
        (
            "joint, 6 points",
            "wire correction",
            replace(base, group_size=6, wire_correction=True),
            paper,
        ),
    ]
    for est, imp, settings, model in rows:
        a, b = q95(rig, settings, model)
        print(f"| {est} | {imp} | {a:.2f} | {b:.2f} |")

    print("\n## Inclinometer model (rig's 15 pairs)\n")
    for name, model in (
        ("paper", paper),
        ("conservative", replace(paper, inclinometer_model="conservative")),
    ):
        a, _ = q95(rig, base, model)
        print(f"- {name}: q95 {a:.2f} mm, reading σ {model.reading_sigma_deg:.4f}°")
    elastica = replace(paper, wire_model="elastica")
    for corr in (False, True):
        a, _ = q95(rig, replace(base, wire_correction=corr), elastica)
        print(f"- elastica wire model, correction {'on' if corr else 'off'}: q95 {a:.2f} mm")


if __name__ == "__main__":
    main()
