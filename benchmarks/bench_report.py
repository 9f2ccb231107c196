"""``cadcog report --out``: CPU time of the whole command, and where it goes.

1. The command in a fresh process, ``--runs`` times: CPU (user + sys of the process and its
   children, from ``os.wait4``) and wall time; min and median.
2. Its parts, each in a fresh process (so that an import is not already done): importing
   build123d (the CAD layer, for the parts and their ground truth), ``scipy.stats`` (the
   validation's Clopper-Pearson intervals and KS test), ``matplotlib.pyplot``; and the four
   figures drawn from the report's own results (the rig view, the histogram, the validation
   plot, the ellipses), CPU of each.

Run: ``nice -n 5 .venv/bin/python benchmarks/bench_report.py [--runs 5]``; figures in
docs/performance.md ("cadcog report").
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

FIGURES = r"""
import sys, time
from pathlib import Path
out = Path(sys.argv[1])
import numpy as np
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.method.errormodel import ErrorModel
from cadcog.method.estimate import BodyBox, MEData, estimate_cog
from cadcog.uncertainty.random_points import SimulationSettings, run_simulation
from cadcog.validation.campaign import virtual_campaign, write_campaign
from cadcog.validation.verification import validate_campaign
from cadcog.method.readings import read_readings
rig = load_rig(default_rig_path())
sim = run_simulation(rig, SimulationSettings(seed=0))
write_campaign(out / "c.csv", virtual_campaign(rig, 0), "bench")
sus = read_readings(out / "c.csv", rig.inclinometer)
val = validate_campaign(rig, sus, seed=0)
est = estimate_cog(sus, rig.inclinometer, MEData.from_rig(rig), model=ErrorModel.from_rig(rig),
                   body=BodyBox.of_rig(rig))
t = time.process_time()
from cadcog.reports import plots
plots._pyplot()
print(f"import matplotlib.pyplot {time.process_time() - t:.3f}")
cog = np.array([100.0, 37.5, 40.3])
for name, call in [
    ("rig view", lambda: plots.rig_view(rig, cog, out / "rig.png")),
    ("histogram", lambda: plots.error_histogram(sim.result.histogram, sim.fits,
                                                 out / "h.png", "t")),
    ("validation", lambda: plots.validation_plot(val.simulated_norms_mm, val.validation,
                                                  out / "v.png")),
    ("ellipses", lambda: plots.ellipse_plot(est.cog_mm, est.cov_mm2, cog, out / "e.png")),
]:
    t = time.process_time()
    call()
    print(f"figure {name} {time.process_time() - t:.3f}")
"""


def _cpu(argv: list[str]) -> tuple[float, float, str]:
    """CPU (user + sys, children included) and wall seconds of one process, and its stdout."""
    start = time.perf_counter()
    with tempfile.TemporaryFile() as out:
        proc = subprocess.Popen(argv, stdout=out, stderr=subprocess.DEVNULL, cwd=ROOT)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - start
        if os.waitstatus_to_exitcode(status) != 0:
            raise SystemExit(f"{argv} failed")
        out.seek(0)
        text = out.read().decode()
    return usage.ru_utime + usage.ru_stime, wall, text


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args()
    py = sys.executable
    with tempfile.TemporaryDirectory() as tmp:
        cpus, walls = [], []
        for k in range(args.runs):
            cpu, wall, _ = _cpu([py, "-m", "cadcog", "report", "--out", f"{tmp}/r{k}"])
            cpus.append(cpu)
            walls.append(wall)
        print(
            f"cadcog report --out: CPU min {min(cpus):.2f} s, median {statistics.median(cpus):.2f}"
            f" s; wall min {min(walls):.2f} s, median {statistics.median(walls):.2f} s "
            f"({args.runs} runs; load average {os.getloadavg()[0]:.1f})"
        )
        base = [_cpu([py, "-c", "import numpy"])[0] for _ in range(3)]
        print(f"python + numpy alone: CPU min {min(base):.2f} s")
        for what in ("build123d", "scipy.stats", "matplotlib.pyplot"):
            runs = [_cpu([py, "-c", f"import numpy, {what}"])[0] - min(base) for _ in range(3)]
            print(f"import {what}: CPU min {min(runs):.2f} s (beyond numpy)")
        parts: dict[str, list[float]] = {}
        for _ in range(3):
            _, _, text = _cpu([py, "-c", FIGURES, tmp])
            for line in text.splitlines():
                name, value = line.rsplit(" ", 1)
                parts.setdefault(name, []).append(float(value))
        for name, values in parts.items():
            print(f"{name}: CPU min {min(values):.2f} s, median {statistics.median(values):.2f} s")


if __name__ == "__main__":
    main()
