"""``cadcog massprops`` on generated STEP assemblies: speed and peak memory of the whole command.

Three models, written through OCCT's XCAF document (``tests/cad/stepfixtures.py``):

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

Run: ``.venv/bin/python benchmarks/bench_massprops.py [--repeat 3]``; figures in
docs/performance.md.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tests.cad.stepfixtures import Assembly, Part, Place, kicad_like_board, write_step

MATERIALS = '[materials]\n"PCB*" = "FR-4"\n"COMPOUND*" = 3000.0\n"*" = "aluminium 6061-T6"\n'


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
        )
        times.append(time.perf_counter() - t)
        peak_mb = max(peak_mb, int(out.stdout.split()[-1]) / 1024.0)
    return times, peak_mb


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(f"{os.cpu_count()} CPUs; load average {os.getloadavg()[0]:.2f}")
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
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
