"""``cadcog massprops`` on generated STEP assemblies: speed and peak memory of the whole command.

Three models, written through OCCT's XCAF document (``support/stepfixtures.py``):

- ``board80``: a KiCad-like board, a PCB and 26 components of three solids each (body and two
  pins sinking into the PCB: 52 small real overlaps), every component product named
  ``COMPOUND``, placed at 0°, 90°, 45°, 180° or 30` (79 solids);
- ``nested1000``: a 1000-solid nested assembly: 8 subsystems × 5 boards × (PCB + 8 components
  of 3 solids), placements at every level, with every board a distinct product (no instancing
  shortcut for the boards);
- ``flat100``: 100 separate boxes, no overlap (the previous release's benchmark).

Each is run as ``cadcog massprops MODEL --materials M --json`` in a fresh process (start-up and
imports included), ``--repeat`` times; peak memory is the largest maximum resident set size of
the command's processes (the main one or a forked worker: workers share the parent's pages
copy-on-write, so their sizes do not add up).

With ``--curve N ...``, the cost curve instead: ``satellite(N)``, N solids as boards of 25
(a distinct PCB and 8 instances of one 3-solid component, its pins sinking into the PCB) in
subsystems of 5 boards (``nested1000`` is ``satellite(1000)``); each size run ``--repeat``
times through ``bench_commands.measure`` (CPU of the whole process tree, wall, peak PSS of the
tree), then once in one process (``--workers 1``) with the CPU time of each phase: imports,
reading the STEP file, integrating the bodies, the overlap search (boxes, candidate pairs,
booleans), the cuts that count each region once, the topology checks, the rest. ``--flat N``
adds N separate boxes, each its own product (the worst case for OCCT's STEP reader), and
``--step FILE`` any STEP file (e.g. the KiCad board of docs/performance.md), with
``--density-kg-m3 1850`` and the overlap policy of ``--policy``. Every run computes afresh
(``CADCOG_NO_CACHE=1``); ``--cached`` adds each model's second run, its result read from a
cache the first run filled.

Run: ``.venv/bin/python benchmarks/bench_massprops.py [--repeat 3]`` or
``... --curve 10 100 1000 5000 20000 [--flat 20000] [--step board.step]``; figures in
docs/performance.md.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from support.stepfixtures import Assembly, Part, Place, kicad_like_board, write_step

MATERIALS = '[materials]\n"PCB*" = "FR-4"\n"COMPOUND*" = 3000.0\n"*" = "aluminium 6061-T6"\n'


def satellite(n_solids: int, instanced: bool = False) -> Assembly:
    """About ``n_solids`` solids: boards of 25 (a distinct PCB, 8 instances of one 3-solid
    component whose pins sink 0.4 mm into the PCB) in subsystems of 5 boards; below 25 solids,
    one board with ``(n_solids - 1) // 3`` components. ``instanced``: every board is an
    instance of one board product (its booleans then shared), as identical boards or panels
    exported with their assembly structure are."""
    comp = Part(
        "COMPOUND",
        [
            ((4.0, 2.0, 1.0), (-2.0, -1.0, 0.5)),
            ((0.6, 0.6, 0.9), (-1.8, -0.3, -0.4)),
            ((0.6, 0.6, 0.9), (1.2, -0.3, -0.4)),
        ],
    )
    n_boards = max(1, n_solids // 25)
    per_board = 8 if n_solids >= 25 else max(1, (n_solids - 1) // 3)
    sat = Assembly(f"sat{n_solids}")
    shared = None
    for s in range((n_boards + 4) // 5):
        subsystem = Assembly(f"subsystem_{s}")
        for b in range(min(5, n_boards - 5 * s)):
            if shared is not None:
                subsystem.add(shared, Place((0.0, 0.0, 12.0 * b), (0, 0, 1), 90.0 * (b % 2)))
                continue
            board = Assembly(f"board_{s}_{b}")
            board.add(Part(f"PCB_{s}_{b}", [((90.0, 90.0, 1.6), (0.0, 0.0, 0.0))]))
            for k in range(per_board):
                board.add(comp, Place((10.0 + 10 * k, 10.0 + 8 * (k % 3), 1.6), (0, 0, 1), 30 * k))
            if instanced:
                shared = board
            subsystem.add(board, Place((0.0, 0.0, 12.0 * b), (0, 0, 1), 90.0 * (b % 2)))
        sat.add(subsystem, Place((0.0, 0.0, 70.0 * s), (1, 0, 0), 0.0))
    return sat


def flat(n_solids: int) -> Assembly:
    """``n_solids`` separate 5 mm cubes on an 8 mm grid, each its own product."""
    top = Assembly(f"flat{n_solids}")
    side = round(n_solids ** (1 / 3)) + 1
    for i in range(n_solids):
        x, y, z = (i % side) * 8.0, ((i // side) % side) * 8.0, (i // side // side) * 8.0
        top.add(Part(f"block_{i:05d}", [((5.0, 5.0, 5.0), (x, y, z))]))
    return top


def nested_1000() -> Assembly:
    """8 subsystems × 5 distinct boards × 25 solids = 1000 solids."""
    comp = Part(
        "COMPOUND",
        [
            ((4.0, 2.0, 1.0), (-2.0, -1.0, 0.5)),
            ((0.6, 0.6, 0.9), (-1.8, -0.3, -0.4)),
            ((0.6, 0.6, 0.9), (1.2, -0.3, -0.4)),
        ],
    )
    sat = Assembly("sat")
    for s in range(8):
        subsystem = Assembly(f"subsystem_{s}")
        for b in range(5):
            board = Assembly(f"board_{s}_{b}")
            board.add(Part(f"PCB_{s}_{b}", [((90.0, 90.0, 1.6), (0.0, 0.0, 0.0))]))
            for k in range(8):
                board.add(comp, Place((10.0 + 10 * k, 10.0 + 8 * (k % 3), 1.6), (0, 0, 1), 30 * k))
            subsystem.add(board, Place((0.0, 0.0, 12.0 * b), (0, 0, 1), 90.0 * (b % 2)))
        sat.add(subsystem, Place((0.0, 0.0, 70.0 * s), (1, 0, 0), 0.0))
    return sat


def flat_100() -> Assembly:
    top = Assembly("flat100")
    for i in range(100):
        x, y, z = (i % 5) * 30.0, ((i // 5) % 5) * 30.0, (i // 25) * 30.0
        top.add(Part(f"block_{i:03d}", [((20.0, 18.0, 15.0), (x, y, z))]))
    return top


#: Runs one command and prints the peak RSS (kB) of its process tree's largest process: a fresh
#: parent per measurement, since ``ru_maxrss`` of RUSAGE_CHILDREN only ever grows.
_WRAPPER = (
    "import resource, subprocess, sys; "
    "subprocess.run(sys.argv[1:], check=True, capture_output=True); "
    "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)"
)


def run(step: Path, mats: Path, repeat: int) -> tuple[list[float], float]:
    cadcog = str(Path(sys.executable).parent / "cadcog")
    times = []
    peak_mb = 0.0
    for _ in range(repeat):
        t = time.perf_counter()
        out = subprocess.run(
            [
                sys.executable,
                "-c",
                _WRAPPER,
                cadcog,
                "massprops",
                str(step),
                "--materials",
                str(mats),
                "--json",
            ],
            check=True,
            capture_output=True,
            text=True,
            env={**os.environ, "CADCOG_NO_CACHE": "1"},
        )
        times.append(time.perf_counter() - t)
        peak_mb = max(peak_mb, int(out.stdout.split()[-1]) / 1024.0)
    return times, peak_mb


#: One run in this process's child with ``--workers 1``: CPU time (user + system) of each phase.
_PHASES = r"""
import json, sys, time
t0 = time.process_time()
import cadcog.cad.stepmass as sm, cadcog.cad.stepread as sr, cadcog.cad.resolve as rs
from cadcog.cli import main
phases = {"imports (numpy, OCP, cadcog)": time.process_time() - t0}
def timed(module, name, label):
    f = getattr(module, name)
    def wrapper(*a, **k):
        t = time.process_time()
        try:
            return f(*a, **k)
        finally:
            phases[label] = phases.get(label, 0.0) + time.process_time() - t
    setattr(module, name, wrapper)
timed(sr, "read_step", "reading the STEP file (OCCT)")
timed(sm, "integrate", "integrating bodies")
timed(rs, "find_overlaps", "overlap search (boxes, pairs, booleans)")
timed(rs, "_cuts", "cuts (each region counted once)")
timed(sm, "invalid_solids", "topology checks")
import contextlib, io
with contextlib.redirect_stdout(io.StringIO()):
    status = main(sys.argv[1:] + ["--workers", "1"])
total = time.process_time() - t0
phases["the rest (densities, summary, JSON)"] = total - sum(phases.values())
print(json.dumps({"status": status, "total": total, "phases": phases}))
"""


def phases(argv: list[str]) -> dict[str, object]:
    out = subprocess.run(
        [sys.executable, "-c", _PHASES, *argv],
        check=True,
        capture_output=True,
        text=True,
        env={**os.environ, "CADCOG_NO_CACHE": "1"},
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def curve(args: argparse.Namespace, d: Path) -> None:
    from bench_commands import environment, measure, summary

    env = environment(CADCOG_NO_CACHE="1")  # first runs
    cached = environment(CADCOG_CACHE_DIR=str(d / "cache"))  # second runs
    mats = d / "materials.toml"
    mats.write_text(MATERIALS, encoding="utf-8")
    models: list[tuple[str, Path, list[str]]] = []
    for n in args.curve:
        t = time.perf_counter()
        name = f"satellite({n}{', instanced' if args.instanced else ''})"
        step = write_step(satellite(n, args.instanced), d / f"sat{n}.step")
        size = step.stat().st_size / 1e6
        print(f"{name}: written in {time.perf_counter() - t:.1f} s, {size:.1f} MB")
        models.append((name, step, ["--materials", str(mats)]))
    for n in args.flat:
        t = time.perf_counter()
        step = write_step(flat(n), d / f"flat{n}.step")
        size = step.stat().st_size / 1e6
        print(f"flat({n}): written in {time.perf_counter() - t:.1f} s, {size:.1f} MB")
        models.append((f"flat({n})", step, ["--materials", str(mats)]))
    for path in args.step:
        models.append((path.name, path, ["--density-kg-m3", "1850", f"--{args.policy}"]))
    for name, step, options in models:
        argv = [str(Path(sys.executable).parent / "cadcog"), "massprops", str(step), *options]
        argv.append("--json")
        big = step.stat().st_size > 50e6
        runs = [measure(argv, env) for _ in range(1 if big else args.repeat)]
        print(f"{name}: {summary(runs)}", flush=True)
        if args.cached:
            subprocess.run(argv, check=True, capture_output=True, env=cached)  # fills the cache
            runs = [measure(argv, cached) for _ in range(args.repeat)]
            print(f"{name}, second run (cached): {summary(runs)}", flush=True)
        if not big or args.phases_big:
            p = phases(argv[1:])
            shown = ", ".join(f"{k} {v:.2f}" for k, v in p["phases"].items())  # type: ignore[union-attr]
            print(f"  one process, CPU s: total {p['total']:.2f}: {shown}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--curve", type=int, nargs="*", default=[], metavar="N")
    parser.add_argument("--instanced", action="store_true", help="--curve: boards instanced")
    parser.add_argument("--flat", type=int, nargs="*", default=[], metavar="N")
    parser.add_argument("--step", type=Path, nargs="*", default=[], metavar="FILE")
    parser.add_argument(
        "--policy", default="allow-overlap", choices=("allow-overlap", "skip-overlaps")
    )
    parser.add_argument("--phases-big", action="store_true", help="phases of files > 50 MB too")
    parser.add_argument(
        "--cached", action="store_true", help="--curve: also a second run (result cached)"
    )
    args = parser.parse_args()
    print(
        f"{time.strftime('%Y-%m-%d %H:%M')}; {os.cpu_count()} CPUs; load average "
        f"{os.getloadavg()[0]:.2f}"
    )
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        if args.curve or args.flat or args.step:
            curve(args, d)
            print(f"load average after: {os.getloadavg()[0]:.2f}")
            return
        mats = d / "materials.toml"
        mats.write_text(MATERIALS, encoding="utf-8")
        models = {
            "board80 (79 solids, 52 overlaps)": write_step(kicad_like_board(26), d / "b.step"),
            "nested1000 (1000 solids)": write_step(nested_1000(), d / "n.step"),
            "flat100 (100 solids)": write_step(flat_100(), d / "f.step"),
        }
        for name, step in models.items():
            times, peak = run(step, mats, args.repeat)
            print(
                f"{name}: median {sorted(times)[len(times) // 2]:.2f} s, worst {max(times):.2f} s,"
                f" peak RSS {peak:.0f} MB (whole command)"
            )


if __name__ == "__main__":
    main()
