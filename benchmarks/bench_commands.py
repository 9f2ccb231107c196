"""Everyday commands: CPU time, wall time and peak memory of the whole process tree.

Each command runs in a fresh process, ``--repeat`` times (after one warm-up run, so Python's
bytecode cache is written as an installed package's would be): the CPU time is user + system
of the command and every child it waited for (``RUSAGE_CHILDREN`` of a fresh parent), the
memory the largest proportional set size (PSS: shared pages split between the processes
sharing them) of the whole tree, sampled every 50 ms from ``/proc``, and the largest resident
set of any one process. The machine is shared: CPU time is the figure to compare; the load
average is printed with the results.

Commands: ``cadcog --version``; ``estimate`` of a virtual campaign of the paper's rig (six
hangs); ``budget``; ``plan`` of the example 3U CubeSat, first with an empty mass-properties
cache (it builds the CubeSat and reads its STEP) and then with the entry that run left.

With ``--first-day FOLDER`` (a folder ``benchmarks/study_first_day.py`` left for one STEP
file: its model, drafted set-up, readings, swings and requirements), it times instead the
commands of a team's first day on that unchanged model, each after one warm-up run that fills
the cache: ``setup init``, ``massprops --report``, ``plan --for both``, ``update --swings``,
``check --strict`` and ``inertia``.

Run: ``.venv/bin/python benchmarks/bench_commands.py [--repeat 5] [--first-day FOLDER]``;
figures in docs/performance.md.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CADCOG = [str(Path(sys.executable).parent / "cadcog")]  # the console script a user runs

#: A fresh parent per measurement: runs the command, samples its tree's memory, then prints
#: the children's CPU time and peak sizes as JSON (``ru_maxrss`` of RUSAGE_CHILDREN only grows).
_WRAPPER = r"""
import json, os, resource, subprocess, sys, threading, time

def tree(root):
    out, todo = [], [root]
    while todo:
        p = todo.pop()
        out.append(p)
        try:
            with open(f'/proc/{p}/task/{p}/children') as f:
                todo.extend(int(c) for c in f.read().split())
        except OSError:
            pass
    return out

def pss_kb(pid):
    try:
        with open(f'/proc/{pid}/smaps_rollup') as f:
            for line in f:
                if line.startswith('Pss:'):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0

peak = [0]
proc = subprocess.Popen(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
def sample():
    while proc.poll() is None:
        peak[0] = max(peak[0], sum(pss_kb(p) for p in tree(proc.pid)))
        time.sleep(0.05)
t = threading.Thread(target=sample, daemon=True)
start = time.perf_counter()
t.start()
err = proc.communicate()[1]
wall = time.perf_counter() - start
t.join()
r = resource.getrusage(resource.RUSAGE_CHILDREN)
print(json.dumps({'status': proc.returncode, 'wall_s': wall, 'cpu_s': r.ru_utime + r.ru_stime,
                  'tree_pss_mb': peak[0] / 1024, 'max_rss_mb': r.ru_maxrss / 1024,
                  'stderr': err.decode(errors='replace')[-400:]}))
"""


def measure(argv: list[str], env: dict[str, str] | None = None) -> dict[str, float]:
    """One run of ``argv`` in a fresh process tree: wall, CPU, memory (see the module doc)."""
    out = subprocess.run(
        [sys.executable, "-c", _WRAPPER, *argv],
        check=True,
        capture_output=True,
        text=True,
        env=env,
    )
    result = json.loads(out.stdout.strip().splitlines()[-1])
    if result["status"] != 0:
        raise RuntimeError(f"{argv}: exit {result['status']}: {result['stderr']}")
    return result


def environment(**extra: str) -> dict[str, str]:
    """The user's environment, writing bytecode as an installed package does."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env.update(extra)
    return env


def summary(runs: list[dict[str, float]]) -> str:
    def stat(key: str) -> str:
        values = [r[key] for r in runs]
        return f"{min(values):.2f}/{statistics.median(values):.2f}"

    return (
        f"CPU {stat('cpu_s')} s, wall {stat('wall_s')} s (min/median of {len(runs)}), "
        f"tree PSS {max(r['tree_pss_mb'] for r in runs):.0f} MB, "
        f"largest process {max(r['max_rss_mb'] for r in runs):.0f} MB"
    )


def first_day(folder: Path, repeat: int) -> None:
    """The first day's commands on an unchanged model (see the module doc), in ``folder``."""
    import re

    log = (folder / "log.txt").read_text(encoding="utf-8")
    weighed = re.search(r"--weighed-mass-kg (\S+)", log)
    if weighed is None:
        raise SystemExit(f"{folder}/log.txt: no --weighed-mass-kg: run study_first_day.py first")
    w = ["--weighed-mass-kg", weighed.group(1)]
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        env = environment(CADCOG_CACHE_DIR=str(d / "cache"))
        commands = {
            "setup init": [
                "setup", "init", "model.step", "--out", str(d / "draft.toml"), "--force",
            ],
            "massprops --report": [
                "massprops", "model.step", "--materials", "model_materials.toml",
                "--report", str(d / "views"),
            ],
            "plan --for both": ["plan", "model_setup.toml", "--for", "both"],
            "update --swings": [
                "update", "r2.csv", "--setup", "model_setup.toml", *w, "--swings", "s2.csv",
            ],
            "check --strict": ["check", "req.toml", "--strict"],
            "inertia": [
                "inertia", "s.csv", "--readings", "r.csv", "--setup", "model_setup.toml", *w,
            ],
        }  # fmt: skip
        for name, argv in commands.items():
            full = [*CADCOG, *argv]
            runs: list[dict[str, float]] = []
            for k in range(repeat + 1):  # the first fills the cache
                out = subprocess.run(
                    [sys.executable, "-c", _WRAPPER, *full],
                    check=True, capture_output=True, text=True, env=env, cwd=folder,
                )  # fmt: skip
                r = json.loads(out.stdout.strip().splitlines()[-1])
                strict_refusal = r["status"] == 2 and "--strict:" in r["stderr"]  # kept too
                if r["status"] not in (0, 1) and not strict_refusal:
                    raise RuntimeError(f"{name}: exit {r['status']}: {r['stderr']}")
                if k:
                    runs.append(r)
            print(f"{name}, unchanged model: {summary(runs)}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--first-day", type=Path, help="a folder study_first_day.py left")
    args = parser.parse_args()
    print(f"{time.strftime('%Y-%m-%d %H:%M')}; {os.cpu_count()} CPUs; load {os.getloadavg()}")
    if args.first_day is not None:
        first_day(args.first_day.resolve(), args.repeat)
        print(f"load after: {os.getloadavg()}")
        return
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        env = environment(CADCOG_CACHE_DIR=str(d / "cache"))
        readings = d / "campaign.csv"
        subprocess.run([*CADCOG, "campaign", "--out", str(readings)], check=True, env=env)
        rig = str(ROOT / "parts" / "paper_rig.toml")
        setup = str(ROOT / "parts" / "cubesat_3u_setup.toml")
        commands = {
            "cadcog --version": [*CADCOG, "--version"],
            "estimate (paper rig, 6 hangs)": [*CADCOG, "estimate", str(readings), "--rig", rig],
            "budget": [*CADCOG, "budget"],
            "plan (3U example), cached model": [*CADCOG, "plan", setup],
        }
        for name, argv in commands.items():
            measure(argv, env)  # warm-up: bytecode written, the plan's cache entry made
            runs = [measure(argv, env) for _ in range(args.repeat)]
            print(f"{name}: {summary(runs)}", flush=True)
        cold = []
        for k in range(max(2, args.repeat // 2)):
            cold.append(measure([*CADCOG, "plan", setup], {**env, "CADCOG_CACHE_DIR": f"{d}/c{k}"}))
        print(f"plan (3U example), empty cache: {summary(cold)}")
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
