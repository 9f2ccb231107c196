"""``cadcog massprops`` on a 100-solid STEP model (boxes and cylinders, three materials).

Run: ``.venv/bin/python benchmarks/bench_massprops.py``; the figure is in docs/performance.md.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

import build123d as bd


def make_model(directory: Path, n: int = 100) -> tuple[Path, Path]:
    solids = []
    for i in range(n):
        x, y, z = (i % 5) * 30.0, ((i // 5) % 5) * 30.0, (i // 25) * 30.0
        if i % 3 == 0:
            s = bd.Solid.make_cylinder(8.0, 20.0, bd.Plane(origin=(x + 10, y + 10, z)))
        else:
            s = bd.Solid.make_box(20.0, 18.0, 15.0, bd.Plane(origin=(x, y, z)))
        s.label = f"{('alu', 'fr4', 'steel')[i % 3]}_{i:03d}"
        solids.append(s)
    step = directory / "model100.step"
    bd.export_step(bd.Compound(children=solids, label="model100"), step)
    mats = directory / "materials.toml"
    mats.write_text(
        '[materials]\n"alu*" = "aluminium 6061-T6"\n"fr4*" = "FR-4"\n'
        '"steel*" = "stainless steel 304"\n',
        encoding="utf-8",
    )
    return step, mats


def main() -> None:
    cadcog = str(Path(sys.executable).parent / "cadcog")
    with tempfile.TemporaryDirectory() as tmp:
        step, mats = make_model(Path(tmp))
        times = []
        for _ in range(3):
            t = time.perf_counter()
            subprocess.run(
                [cadcog, "massprops", str(step), "--materials", str(mats), "--json"],
                check=True,
                capture_output=True,
            )
            times.append(time.perf_counter() - t)
    print(
        f"cadcog massprops, 100 solids: best {min(times):.2f} s, worst {max(times):.2f} s "
        "(whole command, including start-up and import build123d)"
    )


if __name__ == "__main__":
    main()
