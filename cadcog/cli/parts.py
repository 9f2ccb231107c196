"""``cadcog parts``: build rig models and their ground truth."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from cadcog.cli._options import add_json, rig_of
from cadcog.cli._output import print_json, wrote


def add_parser(sub: Any) -> None:
    parser = sub.add_parser("parts", help="build the rig's CAD parts and ground truth")
    parts_sub = parser.add_subparsers(dest="parts_command", metavar="ACTION", required=True)
    build = parts_sub.add_parser(
        "build",
        help="build STEP, STL and ground_truth.json from a rig file",
        description="Build the rig's solids with build123d and write a STEP assembly, one STL "
        "per body and ground_truth.json (exact, density-weighted mass properties).",
    )
    build.add_argument(
        "rig",
        nargs="?",
        type=Path,
        help="rig parameter file (TOML); default: the paper's rig, parts/paper_rig.toml",
    )
    build.add_argument(
        "--out", type=Path, default=Path("build"), help="output directory (default: build/)"
    )
    add_json(build)
    build.set_defaults(func=run_build)
    cubesat = parts_sub.add_parser(
        "cubesat",
        help="build the example CubeSat: STEP with named parts and its materials file",
    )
    cubesat.add_argument(
        "spec", nargs="?", type=Path, help="CubeSat spec (TOML); default parts/cubesat_3u.toml"
    )
    cubesat.add_argument(
        "--out",
        type=Path,
        default=Path("build/cubesat"),
        help="output directory (default build/cubesat)",
    )
    add_json(cubesat)
    cubesat.set_defaults(func=run_cubesat)


def _fmt(values: Any) -> str:
    return "[" + ", ".join(f"{v:9.4f}" for v in values) + "]"


def print_ground_truth(truth: dict[str, Any]) -> None:
    """Readable summary of a ground-truth dictionary."""
    print(f"{'body':<26}{'mass_kg':>10}  {'cog_mm':<33}{'volume_mm3':>14}")
    for name, body in [*truth["bodies"].items(), ("assembly", truth["assembly"])]:
        mass, cog, volume = body["mass_kg"], _fmt(body["cog_mm"]), body["volume_mm3"]
        print(f"{name:<26}{mass:>10.5f}  {cog:<33}{volume:>14.2f}")
    density = truth["bodies"]["proof_mass"]["density_kg_m3"]
    shift = _fmt(truth["hole_cog_shift_mm"])
    print(f"proof-mass density: {density:.1f} kg/m3; CoG shift from the holes: {shift} mm")
    print(f"{'point':<8}{'face':<6}{'inc_x_deg':>10}{'inc_y_deg':>10}  top_up  in_range")
    for p in truth["suspension_points"]:
        x_deg, y_deg = p["ideal_reading_deg"]
        flags = f"{p['top_face_up']!s:<7} {p['in_range']}"
        print(f"{p['id']:<8}{p['face']:<6}{x_deg:>10.2f}{y_deg:>10.2f}  {flags}")


def run_build(args: argparse.Namespace) -> int:
    rig = rig_of(args)
    # Imported here: build123d takes seconds to import and only this command needs it.
    from cadcog.cad.build import build_parts

    result = build_parts(rig, args.out)
    wrote(result.out_dir)
    if args.json:
        print_json(result.ground_truth)
        return 0
    print(f"rig {rig.name!r} from {rig.source}")
    print_ground_truth(result.ground_truth)
    error = result.ground_truth["integration"]["estimated_relative_error"]
    print(f"wrote {len(result.files)} files to {result.out_dir}/ (integration error {error:.1g})")
    return 0


def run_cubesat(args: argparse.Namespace) -> int:
    from importlib import resources

    from cadcog.cad.assembly import write_assembly
    from cadcog.cad.cubesat import (
        build_cubesat,
        configurations_toml,
        load_cubesat,
        materials_toml,
    )
    from cadcog.core.fileio import refuse_overwriting_inputs, staged_output_dir

    spec_path = args.spec or Path(str(resources.files("cadcog._rigs").joinpath("cubesat_3u.toml")))
    spec = load_cubesat(spec_path)
    names = [f"{spec.name}.step", f"{spec.name}_materials.toml"]
    if spec.deployables:
        names.append(f"{spec.name}_configurations.toml")
    for name in names:
        refuse_overwriting_inputs(args.out / name, {"SPEC": spec_path})
    asm, materials = build_cubesat(spec)
    with staged_output_dir(args.out) as stage:
        write_assembly(asm, stage / f"{spec.name}.step")
        (stage / f"{spec.name}_materials.toml").write_text(materials_toml(spec, materials), "utf-8")
        if spec.deployables:
            (stage / names[2]).write_text(configurations_toml(spec), "utf-8")
    step, mats = args.out / f"{spec.name}.step", args.out / f"{spec.name}_materials.toml"
    wrote(step)
    wrote(mats)
    if spec.deployables:
        wrote(args.out / names[2])
    if args.json:
        out = {"step": str(step), "materials": str(mats), "n_solids": len(materials)}
        if spec.deployables:
            out["configurations"] = str(args.out / names[2])
        print_json(out)
        return 0
    written = (
        f"{step} ({len(materials)} solids), {mats}"
        if spec.deployables
        else f"{step} ({len(materials)} solids) and {mats}"
    )
    if spec.deployables:
        written += f" and {args.out / names[2]} (stowed, deployed)"
    print(f"wrote {written}")
    return 0
