"""``cadcog massprops``: mass properties of any STEP model, solid by solid."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from cadcog.errors import CadcogError
from cadcog.fileio import round_floats
from cadcog.materials import LIBRARY, MaterialMap, load_materials


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "massprops",
        help="mass, CoG and inertia of a STEP model by exact integration per solid",
        description="Exact B-rep integration of every solid with its own density, combined by "
        "mass. Checks for open shells, empty or inverted solids, overlaps and unit mistakes, "
        "naming the solid. Materials: "
        + "; ".join(f"{m.name} {m.density_kg_m3:g} kg/m³" for m in LIBRARY.values())
        + ". See docs/spacecraft.md.",
    )
    p.add_argument("model", type=Path, help="STEP file (part or assembly)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--materials", type=Path, help="TOML mapping name patterns to materials")
    g.add_argument("--density-kg-m3", type=float, help="one density for every solid")
    p.add_argument(
        "--total-mass-kg",
        type=float,
        help="scale the densities so the total matches this weighed mass",
    )
    p.add_argument(
        "--units",
        choices=("mm", "m", "in"),
        help="the model's length unit (default mm, after a plausibility check)",
    )
    p.add_argument(
        "--exclude",
        action="append",
        default=[],
        metavar="PATTERN",
        help="leave out solids matching this glob pattern (repeatable)",
    )
    p.add_argument(
        "--allow-overlap",
        action="store_true",
        help="accept overlapping solids (their common volume counts twice)",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.materials is None and args.density_kg_m3 is None and args.total_mass_kg is None:
        raise CadcogError("give --materials, --density-kg-m3 or --total-mass-kg")
    for name in ("density_kg_m3", "total_mass_kg"):
        value = getattr(args, name)
        if value is not None and not value > 0:
            raise CadcogError(f"--{name.replace('_', '-')} must be positive, got {value}")
    materials: MaterialMap | None = None
    if args.materials is not None:
        materials = load_materials(args.materials)
    elif args.density_kg_m3 is not None:
        materials = MaterialMap.uniform(args.density_kg_m3)
    from cadcog.cad.stepmass import model_mass_properties, read_step_solids

    result = model_mass_properties(
        read_step_solids(args.model),
        materials,
        total_mass_kg=args.total_mass_kg,
        units=args.units,
        exclude=args.exclude,
        allow_overlap=args.allow_overlap,
    )
    if args.json:
        print(json.dumps(round_floats(result.to_dict()), indent=2, ensure_ascii=False))
        return 0
    t = result.total
    print(f"{'solid':<28}{'material':<24}{'mass_kg':>10}{'volume_mm3':>14}  cog_mm")
    for s in result.solids:
        p = s.properties
        cog = ", ".join(f"{c:.2f}" for c in p.cog_mm)
        print(f"{s.name:<28}{s.material:<24}{p.mass_kg:>10.4f}{p.volume_mm3:>14.1f}  [{cog}]")
    cog = ", ".join(f"{c:.3f}" for c in t.cog_mm)
    print(f"\ntotal {t.mass_kg:.5f} kg, CoG [{cog}] mm, volume {t.volume_mm3:.1f} mm³")
    print("inertia about the CoG (kg·mm², model axes):")
    for row in t.inertia_kg_mm2:
        print("  " + "  ".join(f"{v:12.3f}" for v in row))
    for n in result.notes:
        print(f"note: {n}")
    if result.excluded:
        print(f"excluded: {', '.join(result.excluded)}")
    return 0
