"""Study: the guided run against the simulated device, over many seeds (docs/bench.md).

For each seed, a whole run on the paper rig (simulated time, default physics and link faults):
the compensated CoG against the truth (Mahalanobis distance with the estimate's covariance),
and per hang the measured swing period and decay time against the simulation's own modes.

    .venv/bin/python benchmarks/study_bench.py [--seeds 40] [--device analog|digital]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from tempfile import TemporaryDirectory

import numpy as np
from scipy import stats

from cadcog.bench.recorder import Recorder
from cadcog.bench.session import SimulatedOperator, run_session
from cadcog.bench.simulator import DeviceSpec, SimulatedDevice, SimulatedLink
from cadcog.bench.target import target_from_rig
from cadcog.rig.file import default_rig_path, load_rig


class _Watching(SimulatedOperator):
    """The simulated operator, keeping the truth of each hang."""

    truths: list | None = None

    def hang(self, index, planned, attempt):
        began = super().hang(index, planned, attempt)
        assert self.truths is not None
        self.truths.append(self.device.device.truth)
        return began


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=40)
    ap.add_argument("--device", choices=("analog", "digital"), default="analog")
    args = ap.parse_args()
    target = target_from_rig(load_rig(default_rig_path()))
    d2, norms, sig, per_err, dec_err, settle, dominant = [], [], [], [], [], [], []
    start = time.perf_counter()
    with TemporaryDirectory() as tmp:
        for seed in range(args.seeds):
            device = SimulatedDevice(target, DeviceSpec(kind=args.device), seed=seed)
            link = SimulatedLink(device)
            op = _Watching(1, link)
            op.truths = []
            result = run_session(
                target, Recorder(link, target.inclinometer), Path(tmp) / f"{seed}.csv", op,
                lambda _t: None,
            )  # fmt: skip
            est = result.estimate
            e = est.cog_mm - device.true_object_cog_mm
            d2.append(float(e @ np.linalg.solve(est.cov_mm2, e)))
            norms.append(float(np.linalg.norm(e)))
            sig.append(np.sqrt(np.diag(est.cov_mm2)))
            for h, tr in zip(result.hangs, op.truths, strict=True):
                settle.append(h.settled_after_s)
                # The mode it measured: the nearer of the two (their periods differ by 0-20 %).
                if h.period_s is None:
                    continue
                k = int(np.argmin(np.abs(tr.modes.periods_s - h.period_s)))
                per_err.append(h.period_s / tr.modes.periods_s[k] - 1.0)
                dominant.append(k == int(np.argmax(tr.amplitudes_deg)))
                if h.decay_time_s is not None:
                    dec_err.append(h.decay_time_s / tr.modes.decay_times_s[k] - 1.0)
    d2 = np.array(d2)
    n = len(d2)
    print(f"{n} runs of {len(target.hangs)} hangs ({args.device}), "
          f"{time.perf_counter() - start:.1f} s wall")  # fmt: skip
    for q in (0.5, 0.9, 0.95, 0.99):
        inside = int(np.sum(d2 <= stats.chi2.ppf(q, 3)))
        lo, hi = stats.binomtest(inside, n).proportion_ci(0.95, method="exact")
        print(f"  inside the {q:.0%} ellipsoid: {inside}/{n} = {inside / n:.2f} "
              f"(95 % CI {lo:.2f}-{hi:.2f})")  # fmt: skip
    print(
        f"  |error|: median {np.median(norms):.3f} mm, max {np.max(norms):.3f} mm; "
        f"stated σ per axis (median) {np.round(np.median(sig, axis=0), 3).tolist()} mm"
    )
    pe, de = np.abs(per_err), np.abs(dec_err)
    print(f"  period vs the nearer mode: median |rel. error| {np.median(pe):.3%}, "
          f"90 % below {np.quantile(pe, 0.9):.2%}, max {np.max(pe):.2%} ({len(pe)} hangs; "
          f"the mode of larger start amplitude in {np.mean(dominant):.0%})")  # fmt: skip
    print(f"  decay time vs that mode: median |rel. error| {np.median(de):.1%}, "
          f"90 % below {np.quantile(de, 0.9):.1%} ({len(de)} hangs)")  # fmt: skip
    print(f"  settle after: median {np.median(settle):.1f} s, max {np.max(settle):.1f} s")


if __name__ == "__main__":
    main()
