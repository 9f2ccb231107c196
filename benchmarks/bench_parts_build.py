"""Wall time of ``cadcog parts build`` on the paper rig, in fresh processes.

Run: ``.venv/bin/python benchmarks/bench_parts_build.py [--repeat 5]``. Prints the wall time of
the whole command and of ``import build123d`` alone, each as median and maximum over the runs.
The figures are recorded in ``docs/performance.md``.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def _wall(cmd: list[str]) -> float:
    start = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    cadcog = str(Path(sys.executable).parent / "cadcog")
    with tempfile.TemporaryDirectory() as tmp:
        build = [_wall([cadcog, "parts", "build", "--out", tmp]) for _ in range(args.repeat)]
    imports = [_wall([sys.executable, "-c", "import build123d"]) for _ in range(args.repeat)]
    for name, times in (("cadcog parts build", build), ("import build123d", imports)):
        print(f"{name:<20} median {statistics.median(times):6.2f} s   max {max(times):6.2f} s")


if __name__ == "__main__":
    main()
