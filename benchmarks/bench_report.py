"""``cadcog report --out``: CPU time of the whole command, and where it goes.

1. The command in a fresh process, as a user runs it: one warm-up run (Python's bytecode
   written, as for an installed package: this machine sets ``PYTHONDONTWRITEBYTECODE``, which
   is dropped here as ``bench_commands.py`` does; and the rig's parts put in a fresh cache
   folder), then ``--runs`` runs on that cache (the everyday case: an unchanged rig), then
   ``--cold`` runs each with an empty cache folder (the first report of a rig: build123d
   builds the parts). CPU is user + sys of the process and its children (``os.wait4``);
   min and median, and the wall time.
2. Its parts, each in a fresh process (so that an import is not already done): importing
   build123d (the CAD layer, first run only), ``scipy.stats`` (no longer imported by the
   report: for comparison), ``scipy.special`` (the validation's beta quantiles and KS tail),
   ``matplotlib.pyplot``; and the four figures drawn from the report's own results (the rig
   view, the histogram, the validation plot, the ellipses), CPU of each.

``--code DIR`` measures the cadcog package in DIR instead of this checkout (run in DIR, and
DIR first on ``PYTHONPATH``): e.g. ``git archive main | tar -x -C /tmp/before`` for a
before/after in the same sitting.

Run: ``nice -n 5 .venv/bin/python benchmarks/bench_report.py [--runs 5] [--cold 2]``;
figures in docs/performance.md ("cadcog report --out").
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

from bench_commands import environment

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


def _cpu(argv: list[str], env: dict[str, str] | None = None) -> tuple[float, float, str]:
    """CPU (user + sys, children included) and wall seconds of one process, and its stdout."""
    start = time.perf_counter()
    with tempfile.TemporaryFile() as out:
        proc = subprocess.Popen(
            argv, stdout=out, stderr=subprocess.DEVNULL, cwd=_CWD[0], env=env or _ENV
        )
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - start
        if os.waitstatus_to_exitcode(status) != 0:
            raise SystemExit(f"{argv} failed")
        out.seek(0)
        text = out.read().decode()
    return usage.ru_utime + usage.ru_stime, wall, text


#: The folder the processes run in: the code measured (``python -m`` puts it first on the path).
_CWD = [ROOT]

#: The environment of every measured process: the user's, writing bytecode (see above).
_ENV = environment()


def _summary(name: str, cpus: list[float], walls: list[float]) -> str:
    return (
        f"{name}: CPU min {min(cpus):.2f} s, median {statistics.median(cpus):.2f} s; wall min "
        f"{min(walls):.2f} s, median {statistics.median(walls):.2f} s ({len(cpus)} runs; "
        f"load average {os.getloadavg()[0]:.1f})"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5, help="runs on a warm cache (default 5)")
    ap.add_argument("--cold", type=int, default=2, help="runs on an empty cache (default 2)")
    ap.add_argument("--code", type=Path, help="the cadcog checkout to measure (default: this)")
    ap.add_argument("--no-parts", action="store_true", help="the whole command only")
    args = ap.parse_args()
    if args.code is not None:
        _CWD[0] = args.code.resolve()
        _ENV["PYTHONPATH"] = os.pathsep.join(
            [str(args.code.resolve()), *filter(None, [os.environ.get("PYTHONPATH")])]
        )
    py = sys.executable
    print(f"{time.strftime('%Y-%m-%d %H:%M %Z')}; {os.cpu_count()} CPUs; code {args.code or ROOT}")
    with tempfile.TemporaryDirectory() as tmp:
        report = [py, "-m", "cadcog", "report", "--out"]
        warm = {**_ENV, "CADCOG_CACHE_DIR": f"{tmp}/cache"}
        _cpu([*report, f"{tmp}/warm-up"], warm)
        warm_runs = [_cpu([*report, f"{tmp}/r{k}"], warm) for k in range(args.runs)]
        print(_summary("cadcog report --out, unchanged rig", *_columns(warm_runs)), flush=True)
        if args.cold:
            cold = [
                _cpu([*report, f"{tmp}/c{k}"], {**_ENV, "CADCOG_CACHE_DIR": f"{tmp}/cache{k}"})
                for k in range(args.cold)
            ]
            print(_summary("cadcog report --out, empty cache", *_columns(cold)), flush=True)
        if args.no_parts:
            return
        base = [_cpu([py, "-c", "import numpy"])[0] for _ in range(3)]
        print(f"python + numpy alone: CPU min {min(base):.2f} s")
        for what in ("build123d", "scipy.stats", "scipy.special", "matplotlib.pyplot"):
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


def _columns(runs: list[tuple[float, float, str]]) -> tuple[list[float], list[float]]:
    return [r[0] for r in runs], [r[1] for r in runs]


if __name__ == "__main__":
    main()
