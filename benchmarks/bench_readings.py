"""``cadcog estimate`` on a large readings file: time and peak memory of the whole command.

The file is a virtual campaign of the paper's rig (``cadcog campaign``, 10 samples per hang)
whose rows are repeated until each of the six hangs has ``--rows-per-hang`` samples; then
``cadcog estimate FILE --rig paper_rig.toml`` runs in a fresh process, and its own maximum
resident set size is read with ``os.wait4``. The reader streams the file into running sums, so
memory should not grow with the number of rows.

Run: ``.venv/bin/python benchmarks/bench_readings.py [--rows-per-hang 100000 1000000]``;
figures in docs/performance.md.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CADCOG = [sys.executable, "-m", "cadcog"]


def big_file(path: Path, rows_per_hang: int) -> None:
    small = path.with_suffix(".small.csv")
    subprocess.run([*CADCOG, "campaign", "--out", str(small)], check=True, capture_output=True)
    lines = [x for x in small.read_text().splitlines() if x and not x.startswith("#")]
    header, rows = lines[0], lines[1:]
    by_hang: dict[str, list[str]] = {}
    for r in rows:
        by_hang.setdefault(r.split(",", 1)[0], []).append(r)
    with path.open("w") as f:
        f.write(header + "\n")
        for hang_rows in by_hang.values():
            block = "\n".join(hang_rows) + "\n"
            for _ in range(rows_per_hang // len(hang_rows)):
                f.write(block)
    small.unlink()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows-per-hang", type=int, nargs="+", default=[100_000, 1_000_000])
    args = parser.parse_args()
    rig = ROOT / "parts" / "paper_rig.toml"
    print(f"{os.cpu_count()} CPUs; load average {os.getloadavg()[0]:.2f}")
    with tempfile.TemporaryDirectory() as tmp:
        for n in args.rows_per_hang:
            csv = Path(tmp) / f"r{n}.csv"
            big_file(csv, n)
            size_mb = csv.stat().st_size / 1e6
            t = time.perf_counter()
            proc = subprocess.Popen(
                [*CADCOG, "estimate", str(csv), "--rig", str(rig)],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
            )
            _, status, usage = os.wait4(proc.pid, 0)
            elapsed = time.perf_counter() - t
            assert os.waitstatus_to_exitcode(status) == 0
            print(
                f"{6 * n} rows ({size_mb:.0f} MB): {elapsed:.1f} s, "
                f"peak RSS {usage.ru_maxrss / 1024:.0f} MB"
            )
            csv.unlink()


if __name__ == "__main__":
    main()
