"""Monte Carlo speed and memory, measured through the command line, as a user runs it.

- ``cadcog simulate`` with 10⁷ trials (25 points, 300 pairs × 33 334 campaigns), 2 workers: wall
  time of the whole command (start-up, simulation, fits, output), then in a second run the peak
  memory of the command and its workers together, sampled from /proc every 20 ms: resident sets
  summed (shared pages counted in every process) and proportional set sizes summed (each shared
  page split between its sharers);
- the same with ``--paper`` (the paper's equal-weight estimator, no wire correction);
- ``cadcog validate`` on a virtual campaign (2000 simulated whole campaigns, the default);
- the cost of a trial on one core: in ``simulate`` (campaigns of 25 hangs, every pair estimated
  from each), and for one pair drawing its own errors; a naive per-trial Python loop for scale.

Run: ``.venv/bin/python benchmarks/bench_montecarlo.py [--trials-per-pair 33334]``. Results
are recorded in ``docs/performance.md``; this machine is shared, so expect ±30 %.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

from cadcog.method.errormodel import ErrorModel
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.uncertainty.montecarlo import (
    EstimatorOptions,
    Scenario,
    all_pairs,
    draw_perturbations,
    draw_points,
    propagate,
    simulate,
    tune_allocator,
)

CADCOG = [sys.executable, "-m", "cadcog"]


def _tree_memory_kb(pid: int) -> tuple[int, int]:
    """Resident and proportional set sizes (kB) of a process and all its descendants, from /proc.

    The resident sets count the pages the workers share with the command (the interpreter,
    numpy, cadcog: forked, copy-on-write) once per process; the proportional set sizes split
    each shared page between its sharers, so their sum is the memory the tree really holds.
    """
    rss = pss = 0
    stack = [pid]
    while stack:
        p = stack.pop()
        try:
            with open(f"/proc/{p}/smaps_rollup", encoding="ascii") as fh:
                for line in fh:
                    if line.startswith("Rss:"):
                        rss += int(line.split()[1])
                    elif line.startswith("Pss:"):
                        pss += int(line.split()[1])
            for task in os.listdir(f"/proc/{p}/task"):
                with open(f"/proc/{p}/task/{task}/children", encoding="ascii") as fh:
                    stack.extend(int(c) for c in fh.read().split())
        except (FileNotFoundError, ProcessLookupError):
            continue
    return rss, pss


def run_timed(argv: list[str]) -> float:
    """Wall time (s) of a command, with nothing else running in this process (reading the
    memory of the command from /proc, as :func:`run_measured` does, costs CPU time)."""
    t = time.perf_counter()
    subprocess.run(argv, stdout=subprocess.DEVNULL, check=True)
    return time.perf_counter() - t


def run_measured(argv: list[str]) -> tuple[float, float, float, str]:
    """Wall time (s), peak tree RSS and PSS (MB) and stdout of a command."""
    t = time.perf_counter()
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, text=True)
    peak_rss = peak_pss = 0
    done = threading.Event()

    def sample() -> None:
        nonlocal peak_rss, peak_pss
        while not done.is_set():
            rss, pss = _tree_memory_kb(proc.pid)
            peak_rss, peak_pss = max(peak_rss, rss), max(peak_pss, pss)
            time.sleep(0.02)

    th = threading.Thread(target=sample)
    th.start()
    out, _ = proc.communicate()
    done.set()
    th.join()
    if proc.returncode:
        raise SystemExit(f"{' '.join(argv)} failed ({proc.returncode})")
    return time.perf_counter() - t, peak_rss / 1024.0, peak_pss / 1024.0, out


def naive_trial(sc: Scenario, model: ErrorModel, a: int, b: int, rng: np.random.Generator) -> None:
    """One trial of the paper's estimator in plain Python: the scale of what vectorising buys."""
    from cadcog.method.plumblines import PlumbLine, pair_estimate
    from cadcog.uncertainty.montecarlo import _tangents

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
        sz = np.copysign(np.sqrt(max(1 - sx * sx - sy * sy, 0.0)), u[2])
        lines.append(PlumbLine(sc.ids[i], sc.points_mm[i], np.array([sx, sy, sz])))
    pair_estimate(lines[0], lines[1], 0.0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--trials-per-pair", type=int, default=33_334)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    base = [*CADCOG, "simulate", "--trials-per-pair", str(args.trials_per_pair)]
    base += ["--workers", str(args.workers), "--json"]
    n = 300 * args.trials_per_pair
    for name, extra in (("cadcog's estimator (default)", []), ("--paper", ["--paper"])):
        wall = run_timed([*base, *extra])
        _, rss, pss, _ = run_measured([*base, *extra])
        print(
            f"simulate {name}: {n:.3g} trials, {args.workers} workers: {wall:.2f} s whole "
            f"command, {n / wall / 1e6:.2f}e6 trials/s, peak memory of command + workers: "
            f"RSS {rss:.0f} MB, PSS {pss:.0f} MB"
        )
    wall, _, _, _ = run_measured([*CADCOG, "--version"])
    print(f"start-up alone (cadcog --version): {wall:.2f} s")

    with tempfile.TemporaryDirectory() as tmp:
        csv = Path(tmp) / "c.csv"
        subprocess.run([*CADCOG, "campaign", "--seed", "1", "--out", str(csv)], check=True,
                       capture_output=True)  # fmt: skip
        wall, rss, _, _ = run_measured([*CADCOG, "validate", str(csv), "--json"])
        print(f"validate (2000 simulated campaigns): {wall:.2f} s whole command, {rss:.0f} MB")

    rig = load_rig(default_rig_path())
    model = ErrorModel.from_rig(rig)
    sc = draw_points(rig, 25, np.random.default_rng(0))
    tune_allocator()
    rng = np.random.default_rng(0)
    for name, opts in (("default", EstimatorOptions()), ("--paper", EstimatorOptions.paper())):
        m = model if name == "default" else model.paper()
        t = time.process_time()
        simulate(sc, m, all_pairs(25), 4096, seed=0, options=opts)
        dt = (time.process_time() - t) / (300 * 4096)
        print(
            f"simulate, one core ({name}): {dt * 1e9:.0f} ns a trial (300 pairs x 4096 campaigns of"
            " 25 hangs: draws and physics per hang, estimate per pair, histograms)"
        )
        t = time.process_time()
        trials = 0
        for _ in range(30):
            pert = draw_perturbations(m, rng, 16_384, 2)
            propagate(sc, m, (0, 1), pert, opts)
            trials += 16_384
        dt = (time.process_time() - t) / trials
        print(f"one pair alone, one core ({name}): {dt * 1e9:.0f} ns a trial (own draws + physics)")
    pairs = all_pairs(25)
    t = time.perf_counter()
    for i in range(5000):
        a, b = pairs[i % len(pairs)]
        naive_trial(sc, model, a, b, rng)
    rate = 5000 / (time.perf_counter() - t)
    print(f"naive per-trial Python loop (paper's estimator): {rate:.0f} trials/s")


if __name__ == "__main__":
    main()
