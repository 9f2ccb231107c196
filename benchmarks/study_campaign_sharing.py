"""What sharing campaigns between pairs costs the pooled figures of ``cadcog simulate``.

``simulate`` estimates every pair from the hangs of one simulated campaign, so the pairs of a
campaign are correlated (as in a lab) while each pair's own trials stay independent. This study
measures how much more the pooled quantiles move from seed to seed than they would with every
pair drawing its own campaigns (each pair simulated alone, on its own seed), on the same 25
random points of the paper rig.

Run: ``.venv/bin/python benchmarks/study_campaign_sharing.py [--seeds 20] [--trials 1000]``; the
figures are quoted in ``docs/montecarlo.md``.
"""

from __future__ import annotations

import argparse

import numpy as np

from cadcog.method.errormodel import ErrorModel
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.uncertainty.montecarlo import NormHistogram, all_pairs, draw_points, simulate


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--trials", type=int, default=1000)
    args = parser.parse_args()
    rig = load_rig(default_rig_path())
    model = ErrorModel.from_rig(rig)
    scenario = draw_points(rig, 25, np.random.default_rng(0))
    pairs = all_pairs(25)
    shared: list[tuple[float, float]] = []
    alone: list[tuple[float, float]] = []
    for s in range(args.seeds):
        h = simulate(scenario, model, pairs, args.trials, seed=s, workers=2).histogram
        shared.append((h.quantile(0.5), h.quantile(0.95)))
        pooled = NormHistogram()
        for g, pair in enumerate(pairs):  # every pair on campaigns of its own
            seed = int(np.random.SeedSequence((s, g)).generate_state(1)[0])
            pooled.merge(simulate(scenario, model, [pair], args.trials, seed=seed).histogram)
        alone.append((pooled.quantile(0.5), pooled.quantile(0.95)))
    print(f"{args.seeds} seeds, 25 points, 300 pairs, {args.trials} trials per pair\n")
    print("| pairs | median: mean, std (mm) | 95 %: mean, std (mm) |")
    print("|---|---|---|")
    for name, rows in (("sharing campaigns", shared), ("on campaigns of their own", alone)):
        q = np.array(rows)
        m, sd = q.mean(axis=0), q.std(axis=0, ddof=1)
        print(f"| {name} | {m[0]:.4f}, {sd[0]:.4f} | {m[1]:.4f}, {sd[1]:.4f} |")


if __name__ == "__main__":
    main()
