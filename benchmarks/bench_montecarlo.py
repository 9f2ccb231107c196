"""Monte Carlo speed and memory: the paper's 3·10⁵ trials, 10⁷ trials, a naive loop, the RNG.

Run: ``.venv/bin/python benchmarks/bench_montecarlo.py [--big 10000000] [--workers 2]``.
Results are recorded in ``docs/performance.md``.
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np

from cadcog.errormodel import ErrorModel
from cadcog.estimator import PlumbLine, pair_estimate
from cadcog.montecarlo import (
    BLOCK_TRIALS,
    Scenario,
    _tangents,
    all_pairs,
    draw_perturbations,
    draw_points,
    simulate,
)
from cadcog.rigfile import default_rig_path, load_rig
from cadcog.simulation import SimulationSettings, run_simulation


def _peak_mb() -> float:
    own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return max(own, children) / 1024.0


def naive_trial(sc: Scenario, model: ErrorModel, a: int, b: int, rng: np.random.Generator) -> float:
    """One trial in plain Python with the library's scalar estimator: the baseline."""
    ratio = sc.me_mass_kg / sc.total_mass_kg
    w = np.array(model.me_masses_kg) / sum(model.me_masses_kg) * np.array(model.me_edges_mm)
    e_me = np.array([sum(wk * (rng.random() - 0.5) for wk in w) for _ in range(3)])
    g = sc.assembly_cog_mm + ratio * e_me
    lines = []
    t1s, t2s = _tangents(sc.normals[[a, b]])
    for j, i in enumerate((a, b)):
        h = model.play_mm / 2
        q = sc.points_mm[i] + rng.uniform(-h, h) * t1s[j] + rng.uniform(-h, h) * t2s[j]
        q = q + rng.uniform(0, model.wire_offset_max_mm) * sc.normals[i]
        u = (q - g) / np.linalg.norm(q - g)
        x = np.arcsin(u[0]) + np.deg2rad(rng.normal(0, model.reading_sigma_deg))
        y = np.arcsin(u[1]) + np.deg2rad(rng.normal(0, model.reading_sigma_deg))
        sx, sy = np.sin(x), np.sin(y)
        r2 = sx * sx + sy * sy
        if r2 > 1:
            sx, sy, sz = sx / np.sqrt(r2), sy / np.sqrt(r2), 0.0
        else:
            sz = np.copysign(np.sqrt(1 - r2), u[2])
        lines.append(PlumbLine(sc.ids[i], sc.points_mm[i], np.array([sx, sy, sz])))
    r_est = pair_estimate(lines[0], lines[1], 0.0).midpoint_mm
    r_pm = (sc.total_mass_kg * r_est - sc.me_mass_kg * sc.me_cog_mm) / sc.pm_mass_kg
    return float(np.linalg.norm(r_pm - sc.pm_cog_mm))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--big", type=int, default=10_000_000)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--naive", type=int, default=20_000)
    args = parser.parse_args()
    rig = load_rig(default_rig_path())
    model = ErrorModel.from_rig(rig)

    run_simulation(rig, SimulationSettings(trials_per_group=50))  # warm-up
    times = []
    for _ in range(5):
        t = time.perf_counter()
        run_simulation(rig, SimulationSettings())
        times.append(time.perf_counter() - t)
    print(
        f"paper run, 3e5 trials (25 points, 300 pairs, 1000 each): "
        f"median {np.median(times):.3f} s, min {min(times):.3f} s"
    )

    sc = draw_points(rig, 25, np.random.default_rng(0))
    pairs = all_pairs(25)
    per_pair = -(-args.big // len(pairs))
    t = time.perf_counter()
    res = simulate(sc, model, pairs, per_pair, seed=1, workers=args.workers)
    dt = time.perf_counter() - t
    print(
        f"{res.n_trials:.3g} trials, {args.workers} workers: {dt:.2f} s, "
        f"{res.n_trials / dt / 1e6:.2f}e6 trials/s, peak RSS {_peak_mb():.0f} MB"
    )
    t = time.perf_counter()
    res1 = simulate(sc, model, pairs[:30], per_pair, seed=1, workers=1)
    dt1 = time.perf_counter() - t
    rate1 = res1.n_trials / dt1
    print(f"one worker: {rate1 / 1e6:.2f}e6 trials/s")

    # Random-number generation alone, same draws as the simulation, one worker.
    t = time.perf_counter()
    n_blocks = 0
    for g in range(30):
        for b in range(-(-per_pair // BLOCK_TRIALS)):
            rng = np.random.default_rng(np.random.SeedSequence(1, spawn_key=(g, b)))
            draw_perturbations(model, rng, min(BLOCK_TRIALS, per_pair - b * BLOCK_TRIALS), 2)
            n_blocks += 1
    rng_rate = 30 * per_pair / (time.perf_counter() - t)
    print(
        f"RNG alone: {rng_rate / 1e6:.2f}e6 trials/s; the full simulation runs at "
        f"{rate1 / rng_rate:.0%} of the RNG-only rate"
    )

    rng = np.random.default_rng(0)
    t = time.perf_counter()
    for i in range(args.naive):
        a, b = pairs[i % len(pairs)]
        naive_trial(sc, model, a, b, rng)
    naive_rate = args.naive / (time.perf_counter() - t)
    print(
        f"naive per-trial Python loop: {naive_rate:.0f} trials/s; vectorised is "
        f"{rate1 / naive_rate:.0f}× faster (one worker each)"
    )


if __name__ == "__main__":
    main()
