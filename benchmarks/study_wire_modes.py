"""How the wire's length moves the swing's modes, and the torsion period of a solid wire.

For the paper rig's six hangs (its assembly's CAD mass properties, the wire exits of the rig
file): the four pendulum modes of :func:`cadcog.dynamics.hungbody.hang_modes` for wire lengths
from 300 mm down to a pivot (the two slow ones: the wire's own pendulum; the two fast ones: the
body's rocking, which carry the inertia), and the torsion period about the vertical of a solid
steel wire, ``T = 2π √(I_v L / (G J))`` with ``J = π d⁴/32``. Quoted in ``docs/inertia.md``.

Run: ``.venv/bin/python benchmarks/study_wire_modes.py [--diameter-mm 0.8] [--shear-gpa 79]``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from cadcog.dynamics.hungbody import HangGeometry, hang_modes
from cadcog.rig.file import default_rig_path, load_rig

LENGTHS_MM = (300.0, 150.0, 100.0, 75.0, 30.0, 10.0, 0.0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--diameter-mm", type=float, default=0.8)
    ap.add_argument("--shear-gpa", type=float, default=79.0)
    args = ap.parse_args()
    rig = load_rig(default_rig_path())
    a = rig.analytic_assembly
    exits = [np.asarray(rig.wire_exit_mm(p), dtype=float) for p in rig.suspension_points]
    print("| wire mm | wire modes Hz | body modes Hz |")
    print("|---|---|---|")
    for length in LENGTHS_MM:
        f = np.array(
            [
                hang_modes(
                    a.inertia_kg_mm2, a.mass_kg, a.cog_mm, HangGeometry(e, e, length),
                    with_shapes=False,
                ).frequencies_hz
                for e in exits
            ]
        )  # fmt: skip
        if f.shape[1] == 4:
            slow, fast = f[:, :2], f[:, 2:]
            wire_hz = f"{slow.min():.2f}-{slow.max():.2f}"
            print(f"| {length:g} | {wire_hz} | {fast.min():.2f}-{fast.max():.2f} |")
        else:
            print(f"| pivot | {f.min():.2f}-{f.max():.2f} (compound pendulum) | |")
    gj = args.shear_gpa * 1e9 * np.pi * (args.diameter_mm * 1e-3) ** 4 / 32.0  # N·m²
    for length in (300.0, 75.0):
        periods = []
        for e in exits:
            u = (e - a.cog_mm) / np.linalg.norm(e - a.cog_mm)
            i_v = float(u @ a.inertia_kg_mm2 @ u) * 1e-6  # kg·m²
            periods.append(2.0 * np.pi * np.sqrt(i_v * length * 1e-3 / gj))
        print(
            f"torsion, solid {args.diameter_mm:g} mm wire (G {args.shear_gpa:g} GPa), "
            f"{length:g} mm: period {min(periods):.1f}-{max(periods):.1f} s"
        )


if __name__ == "__main__":
    main()
