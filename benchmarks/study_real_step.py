"""cadcog's STEP reader on real exports, against OCCT's own root-compound explorer.

For every ``*.step`` / ``*.stp`` file in a directory: read it with
:func:`cadcog.cad.stepread.read_step`, integrate every solid at one uniform density, and compare
the total volume and volume-weighted centroid with an independent computation: OCCT's plain
``STEPControl_Reader`` (no XCAF), whose ``OneShape()`` is the root compound and whose
``TopExp_Explorer`` composes every location itself. Also reports the exporter's declared unit,
products and instances, surface bodies, overlaps found (and the share of mass they
double-count), and the time of the cadcog computation. With ``--leaves``, also the CoG error
of the previous release's reader (solids taken from the leaves of build123d's
``import_step`` tree, which drops the parents' placements).

The files are not part of cadcog: fetch public exports of small-satellite hardware (the table in
``docs/spacecraft.md`` names the repositories and commits used) into a directory and run

    .venv/bin/python benchmarks/study_real_step.py DIR
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from OCP.BRepGProp import BRepGProp
from OCP.GProp import GProp_GProps
from OCP.STEPControl import STEPControl_Reader
from OCP.TopAbs import TopAbs_SOLID
from OCP.TopExp import TopExp_Explorer

from cadcog.cad.stepmass import model_mass_properties
from cadcog.cad.stepread import read_step
from cadcog.core.errors import CadcogError
from cadcog.mass.materials import MaterialMap


def root_compound(path: Path) -> tuple[int, float, np.ndarray]:
    """Solids, total volume and volume-weighted centroid from the root compound."""
    reader = STEPControl_Reader()
    reader.ReadFile(str(path))
    reader.TransferRoots()
    explorer = TopExp_Explorer(reader.OneShape(), TopAbs_SOLID)
    n, volume, moment = 0, 0.0, np.zeros(3)
    while explorer.More():
        props = GProp_GProps()
        BRepGProp.VolumeProperties_s(explorer.Current(), props, 1e-9, True)
        c = props.CentreOfMass()
        volume += props.Mass()
        moment += props.Mass() * np.array([c.X(), c.Y(), c.Z()])
        n += 1
        explorer.Next()
    return n, volume, moment / volume


def leaves_cog(path: Path) -> np.ndarray:
    """Volume-weighted centroid of the solids of build123d's tree leaves (the old reader)."""
    import build123d as bd

    def leaves(node):  # type: ignore[no-untyped-def]
        children = list(node.children)
        return [x for c in children for x in leaves(c)] if children else [node]

    volume, moment = 0.0, np.zeros(3)
    for leaf in leaves(bd.import_step(path)):
        for solid in leaf.solids():
            props = GProp_GProps()
            BRepGProp.VolumeProperties_s(solid.wrapped, props, 1e-9, True)
            c = props.CentreOfMass()
            volume += props.Mass()
            moment += props.Mass() * np.array([c.X(), c.Y(), c.Z()])
    return moment / volume


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("directory", type=Path)
    parser.add_argument("--leaves", action="store_true", help="add the old reader's CoG error")
    args = parser.parse_args()
    files = sorted(p for p in args.directory.iterdir() if p.suffix.lower() in (".step", ".stp"))
    if not files:
        sys.exit(f"no .step files in {args.directory}")
    header = [
        "file",
        "unit",
        "products / instances",
        "solids (ours / root)",
        "surfaces",
        "volume difference",
        "CoG difference (mm)",
        "overlaps (mass share)",
        "time (s)",
    ]
    if args.leaves:
        header.append("leaf solids' CoG error (mm)")
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for f in files:
        t = time.perf_counter()
        try:
            model = read_step(f)
            r = model_mass_properties(
                model, MaterialMap.uniform(1000.0), overlaps="allow", workers=2
            )
        except CadcogError as exc:
            print(f"| {f.name} | error: {exc} |")
            continue
        elapsed = time.perf_counter() - t
        n, volume, cog = root_compound(f)
        solids = r.solids
        ours_v = sum(b.properties.volume_mm3 for b in solids)
        ours_c = sum(b.properties.volume_mm3 * b.properties.cog_mm for b in solids) / ours_v
        ov = r.overlaps
        print(
            f"| {f.name} | {', '.join(model.declared_units)} | {model.n_products} / "
            f"{model.n_instances} | {len(solids)} / {n} | {r.audit.n_surfaces} | "
            f"{abs(ours_v - volume) / volume:.1e} | {np.linalg.norm(ours_c - cog):.1e} | "
            f"{len(ov.pairs)} ({ov.mass_fraction:.2%}) | {elapsed:.1f} |"
            + (f" {np.linalg.norm(leaves_cog(f) - cog):.3g} |" if args.leaves else "")
        )


if __name__ == "__main__":
    main()
