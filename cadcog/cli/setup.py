"""``cadcog setup init MODEL.step``: draft a set-up file and a materials file from one's STEP."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import Any

from cadcog.core import tolerances
from cadcog.core.errors import CadcogError
from cadcog.core.fileio import staged_file
from cadcog.core.units import UNIT_CHOICES


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "setup",
        help="draft a test set-up file from your own STEP model (setup init MODEL.step)",
        description="Set-up files for `plan`, `estimate --setup` and `update`. `setup init` "
        "reads a STEP model and drafts SETUP.toml (model, materials, the CubeSat form factor "
        "guessed from the bounding box, the measurement equipment on the +z face, a grid of "
        "candidate points on the side faces) and a materials file beside it listing every part, "
        "heaviest first, to fill in. See docs/spacecraft.md.",
    )
    actions = p.add_subparsers(dest="action", metavar="ACTION", required=True)
    init = actions.add_parser(
        "init",
        help="draft SETUP.toml and its materials file from MODEL.step",
        description="Draft a set-up file and a materials file from a STEP model; neither "
        "replaces an existing file unless --force.",
    )
    init.add_argument("model", type=Path, help="STEP file (part or assembly)")
    init.add_argument(
        "--out",
        type=Path,
        help="the set-up file to write (default: MODEL's name with _setup.toml, beside it); "
        "the materials file goes beside it as NAME_materials.toml",
    )
    init.add_argument(
        "--units",
        choices=UNIT_CHOICES,
        help="the file's true length unit, when its declared unit is wrong",
    )
    init.add_argument("--force", action="store_true", help="replace existing files")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from cadcog.cad.stepmass import model_mass_properties
    from cadcog.cad.stepread import read_step
    from cadcog.cad.surfacepoints import project_grid
    from cadcog.mass.materials import DENSITY_RANGE_KG_M3, MaterialMap, is_placeholder_material
    from cadcog.spacecraft.setup_draft import (
        DRAFT_FACES,
        DraftPart,
        distinct_points,
        draft_materials,
        draft_setup,
        face_grid,
        part_name,
    )

    step = Path(args.model)
    out = Path(args.out) if args.out is not None else step.with_name(f"{step.stem}_setup.toml")
    if out.suffix.lower() != ".toml":
        raise CadcogError(f"--out {out}: expected a file name ending in .toml")
    stem = out.name[: -len("_setup.toml")] if out.name.endswith("_setup.toml") else out.stem
    materials_path = out.with_name(f"{stem}_materials.toml")
    for path in (out, materials_path):
        if path.exists() and not args.force:
            raise CadcogError(f"{path}: exists; --force replaces it (a draft never overwrites)")
    model = read_step(step)
    # geometry only: one density for all, each solid counted whole
    result = model_mass_properties(
        model, MaterialMap.uniform(1000.0), units=args.units, overlaps="allow"
    )
    stamped = {b.path: b.material for b in model.bodies if b.material is not None}
    lo_d, hi_d = DENSITY_RANGE_KG_M3
    parts = []
    for b in result.bodies:
        if b.kind != "solid":
            continue
        xm = stamped.get(b.path)
        rho = xm.density_kg_m3 if xm is not None else None
        usable = rho if rho is not None and lo_d <= rho <= hi_d else None
        parts.append(
            DraftPart(
                b.path,
                b.properties.volume_mm3,
                None if xm is None else xm.name,
                usable,
                xm is not None and is_placeholder_material(xm.name),
            )
        )
    lo, hi = result.bbox_mm
    ov = result.overlaps
    refused = ov.pairs and ov.mass_fraction > tolerances.OVERLAP_REFUSE_MASS_FRACTION
    overlaps = (
        f"{len(ov.pairs)} overlapping pair(s), {ov.mass_fraction:.2%} of the volume"
        if refused
        else ""
    )
    shapes = [b.shape for b in model.bodies if b.kind == "solid"]
    points = distinct_points(
        [
            (face, sp.position_mm, sp.depth_mm)
            for face in DRAFT_FACES
            for sp in project_grid(
                shapes, face, face_grid(face, lo, hi), lo, hi, scale_to_mm=result.audit.scale_to_mm
            )
        ]
    )
    step_rel = Path(os.path.relpath(step.resolve(), out.resolve().parent)).as_posix()
    with staged_file(materials_path) as tmp:
        tmp.write_text(draft_materials(parts, step.name), encoding="utf-8")
    with staged_file(out) as tmp:
        tmp.write_text(
            draft_setup(stem, step_rel, materials_path.name, lo, hi, overlaps, points),
            encoding="utf-8",
        )
    print(f"report: {out}", file=sys.stderr)
    print(f"report: {materials_path}", file=sys.stderr)
    print(
        f"drafted {out} and {materials_path} ({len(parts)} solids in "
        f"{len({part_name(p.path) for p in parts})} part names): fill in the materials, "
        f"check the set-up, then `cadcog plan {out}`"
    )
    return 0
