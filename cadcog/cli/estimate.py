"""``cadcog estimate``: the compensated CoG from a readings CSV."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from cadcog.cli._options import add_json, add_rig, refuse_rig_and_setup
from cadcog.cli._output import print_json, warn
from cadcog.cli._table import text_table
from cadcog.cli._types import weighing_sigma_kg
from cadcog.core import tolerances
from cadcog.core.errors import CadcogError
from cadcog.core.numformat import signed
from cadcog.core.plusminus import mass_pm
from cadcog.core.tolerances import DEFAULT_WEIGHING_SIGMA_KG
from cadcog.method.cogestimate import CogEstimate
from cadcog.method.medata import MEData
from cadcog.rig.file import load_rig
from cadcog.rig.parameters import Rig
from cadcog.runs.estimate import estimate_from_file


def _vector3(text: str) -> tuple[float, float, float]:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected X,Y,Z numbers, got {text!r}") from None
    if len(values) != 3 or not all(np.isfinite(values)):
        raise argparse.ArgumentTypeError(f"expected three finite numbers X,Y,Z, got {text!r}")
    return values[0], values[1], values[2]


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "estimate",
        help="compensated CoG from a readings CSV",
        description="Estimate the CoG from inclinometer readings at two or more suspension "
        "points, and remove the measurement equipment (eq. 10). See docs/estimate.md.",
    )
    p.add_argument("readings", type=Path, help="readings CSV (point_id,x_mm,y_mm,z_mm,...)")
    add_rig(p, "rig file: object mass, ME mass and CoG (and its uncertainty), inclinometer set-up")
    p.add_argument(
        "--setup",
        type=Path,
        help="spacecraft set-up file: masses and ME from its CAD, the CAD comparison and the "
        "CubeSat envelope check",
    )
    p.add_argument(
        "--weighed-mass-kg",
        type=float,
        help="with --setup or --rig: the object's weighed mass without the ME, used to remove "
        "the ME (default: the CAD's or the rig's mass; with --setup the CAD mass's own "
        "uncertainty is then carried into the CoG)",
    )
    p.add_argument(
        "--mass-sigma-kg",
        type=float,
        help=f"1-σ of the weighing (with --weighed-mass-kg; default "
        f"{DEFAULT_WEIGHING_SIGMA_KG:g} kg)",
    )
    p.add_argument("--object-mass-kg", type=float, help="mass of the object without the ME")
    p.add_argument("--me-mass-kg", type=float, help="mass of the measurement equipment")
    p.add_argument("--me-cog-mm", type=_vector3, help="ME CoG in the body frame, X,Y,Z")
    p.add_argument(
        "--me-cog-sigma-mm",
        type=float,
        help="per-axis standard deviation of the ME CoG, with --me-cog-mm (default 0)",
    )
    p.add_argument(
        "--angle-sigma-deg",
        type=float,
        help="override: per-axis std of a hang's mean reading (default: from the error model: "
        "the accuracy bias per hang, noise and ADC per sample)",
    )
    p.add_argument(
        "--point-sigma-mm",
        type=float,
        help="override: isotropic per-axis std of a suspension point (default: from the error "
        "model: the play in the face plane, the wire offset's spread along the bolt axis)",
    )
    p.add_argument(
        "--min-angle-deg",
        type=float,
        default=tolerances.MIN_PAIR_ANGLE_DEG,
        help="pairs of plumb lines meeting at less than this are ill-conditioned "
        f"(default {tolerances.MIN_PAIR_ANGLE_DEG:g})",
    )
    p.add_argument(
        "--wire-correction",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="move each point along its bolt axis by the wire offset the error model expects "
        "(default on with --rig or --setup, which give the bolt axes)",
    )
    p.add_argument(
        "--self-calibrate-wire",
        action="store_true",
        help="estimate the wire offset scale λ with the CoG (3 or more hangs) and report it",
    )
    add_json(p)
    p.set_defaults(func=run)


def _me_data(args: argparse.Namespace) -> tuple[MEData | None, Rig | None]:
    direct = (args.object_mass_kg, args.me_mass_kg, args.me_cog_mm)
    if args.me_cog_sigma_mm is not None and args.me_cog_mm is None:
        raise CadcogError("--me-cog-sigma-mm goes with --me-cog-mm (the ME's CoG)")
    if args.rig is not None:
        if any(v is not None for v in direct):
            raise CadcogError("give either --rig or --object-mass-kg/--me-mass-kg/--me-cog-mm")
        return None, load_rig(args.rig)  # the rig's estimate composes its own ME data
    if args.weighed_mass_kg is not None:
        raise CadcogError(
            "--weighed-mass-kg goes with --setup or --rig (with the ME given on the command "
            "line, --object-mass-kg is the mass)"
        )
    if args.wire_correction or args.self_calibrate_wire:
        raise CadcogError(
            "--wire-correction/--self-calibrate-wire need --rig or --setup (they give the bolt "
            "axes and the wire model)"
        )
    if all(v is None for v in direct):
        return None, None
    if any(v is None for v in direct):
        raise CadcogError("--object-mass-kg, --me-mass-kg and --me-cog-mm go together")
    # their ranges (a positive object mass, the ME's ≥ 0, a σ ≥ 0) are core.bounds', checked
    # with every option before any command runs
    sigma = 0.0 if args.me_cog_sigma_mm is None else args.me_cog_sigma_mm
    me = MEData(
        args.object_mass_kg,
        args.me_mass_kg,
        np.array(args.me_cog_mm),
        sigma**2 * np.eye(3),
        "command line",
    )
    return me, None


def run(args: argparse.Namespace) -> int:
    args.mass_sigma_kg = weighing_sigma_kg(args.weighed_mass_kg, args.mass_sigma_kg)
    if args.setup is not None:
        return run_setup(args)
    me, rig = _me_data(args)
    result = estimate_from_file(args.readings, rig=rig, me=me, **_options(args))
    return _emit(result, args.json)


def _options(args: argparse.Namespace) -> dict[str, Any]:
    """The estimator's options as the command gives them (the weighing checked above)."""
    return {
        "wire_correction": args.wire_correction is not False,
        "self_calibrate": args.self_calibrate_wire,
        "weighed_mass_kg": args.weighed_mass_kg,
        "mass_sigma_kg": args.mass_sigma_kg,
        "angle_sigma_deg": args.angle_sigma_deg,
        "point_sigma_mm": args.point_sigma_mm,
        "min_angle_deg": args.min_angle_deg,
    }


def _emit(result: CogEstimate, as_json: bool) -> int:
    """Print an estimate (JSON or table, with the CAD comparison if any); warnings to stderr."""
    if as_json:
        print_json(result.to_dict())
    else:
        print_estimate(result)
        if result.cad is not None:
            print_cad_comparison(result.cad)
    for w in result.warnings:
        warn(w)
    return 0


def _fmt(values: Any, width: int = 9, digits: int = 3) -> str:
    return "[" + ", ".join(f"{v:{width}.{digits}f}" for v in values) + "]"


def print_estimate(result: CogEstimate) -> None:
    """Readable report of an estimate."""
    residuals = {r.id: r for r in result.joint.residuals}
    rows = []
    for s in result.suspensions:
        r = residuals[s.id]
        rows.append(
            [
                s.id,
                str(s.n_samples),
                f"{s.inc_x_deg:.3f}",
                f"{s.inc_y_deg:.3f}",
                "yes" if s.top_face_up else "no",
                f"{r.distance_mm:.3f}",
                f"{r.normalized:.2f}",
                "<- inconsistent" if r.inconsistent else "",
            ]
        )
    headers = ["point", "n", "inc_x_deg", "inc_y_deg", "top_up", "residual_mm", "sigma", ""]
    print(text_table(headers, rows, "lrrrlrrl"))
    print()
    pair_rows = [
        [f"{p.a} & {p.b}", _fmt(p.midpoint_mm), f"{p.gap_mm:.3f}", f"{p.angle_deg:.2f}"]
        for p in result.joint.pairs
    ]
    print(text_table(["pair", "midpoint_mm", "gap_mm", "angle_deg"], pair_rows, "llrr"))
    print()
    sigma = np.sqrt(np.diag(result.joint.cov_mm2))
    j = result.joint
    print(f"lines' consistency: χ² = {j.chi2:.2f} with {j.dof} dof (p = {j.chi2_p_value:.3f})")
    if j.wire is not None:
        if j.wire.estimated:
            what = "estimated"
        elif j.wire.sigma_mm:
            what = f"from the hangs and the error model's {j.wire.prior_mm:.3f} mm"
        else:
            what = "expected (error model)"
        spread = f" ± {j.wire.sigma_mm:.3f}" if j.wire.sigma_mm else ""
        print(f"wire offset scale λ, {what}: {j.wire.scale_mm:.3f}{spread} mm")
    shared = result.model.get("shared_sensor")
    if shared:
        parts = [
            f"{name} {v['estimate']:+.3g} ± {v['sigma']:.2g}"
            + (" (calibrated)" if v["calibrated_by_hangs"] else " (prior)")
            for name, v in shared.items()
        ]
        print("sensor, shared by the hangs: " + "; ".join(parts))
    print(f"assembly CoG (object + ME): {_fmt(result.assembly_cog_mm)} mm  ± {_fmt(sigma)} mm")
    if result.compensation is None:
        print("no ME data given: the CoG above is not compensated for the measurement equipment")
    else:
        c = result.compensation
        sigma = np.sqrt(np.diag(c.cov_mm2))
        mass = f"object {mass_pm(c.object_mass_kg, c.object_mass_sigma_kg)}"
        mass += f" ({c.object_mass_source})"
        print(
            f"object CoG (ME removed):    {_fmt(c.cog_mm)} mm  ± {_fmt(sigma)} mm  "
            f"({mass}, ME {c.me_mass_kg:g} kg at {_fmt(c.me_cog_mm, 0, 2)})"
        )


def run_setup(args: argparse.Namespace) -> int:
    """``--setup``: a spacecraft's compensated CoG compared with its CAD."""
    refuse_rig_and_setup(args)
    given = [
        option
        for option, value in (
            ("--object-mass-kg", args.object_mass_kg),
            ("--me-mass-kg", args.me_mass_kg),
            ("--me-cog-mm", args.me_cog_mm),
            ("--me-cog-sigma-mm", args.me_cog_sigma_mm),
        )
        if value is not None
    ]
    if given:
        raise CadcogError(
            f"--setup already gives the masses and the ME: drop {', '.join(given)} (a weighing "
            "goes with --weighed-mass-kg)"
        )
    from cadcog.spacecraft.setup import load_setup

    result = estimate_from_file(args.readings, setup=load_setup(args.setup), **_options(args))
    return _emit(result, args.json)


def print_cad_comparison(cad: dict[str, Any]) -> None:
    """Readable lines of :func:`cadcog.spacecraft.compare.compare_with_cad`."""
    d, s, m = cad["difference_mm"], cad["difference_sigma"], cad["measurement_sigma"]
    print(
        "measured − CAD: ["
        + ", ".join(signed(v, 3) for v in d)
        + "] mm = ["
        + ", ".join(signed(v, 1) for v in s)
        + "] σ of measurement and CAD combined (["
        + ", ".join(signed(v, 1) for v in m)
        + "] σ of the measurement alone)"
    )
    if "mass_difference_kg" in cad:
        print(
            f"weighed − CAD mass: {signed(cad['mass_difference_kg'] * 1e3, 1)} g = "
            f"{signed(cad['mass_difference_sigma'], 1)} σ (weighing and CAD combined)"
        )
    verdict = (
        "within the CAD's stated uncertainties"
        if cad["consistent"]
        else "BEYOND the CAD's stated uncertainties (see `cadcog update`)"
    )
    print(
        f"CAD check: χ² = {cad['chi2']:.2f} ({cad['dof']} dof), p = {cad['p_value']:.3g}: {verdict}"
    )
    cs = cad.get("cubesat")
    if cs is None:
        return
    verdict = ("within" if cs["within"] else "OUTSIDE") + " the envelope"
    if cs["within"] and not cs["within_at_95"]:
        verdict += ", but not with 95 % confidence"
    print(
        f"{cs['form_factor']} CoG offset from the geometric centre: ["
        + ", ".join(signed(v, 2) for v in cs["offset_mm"])
        + "] mm, limits ±["
        + ", ".join(f"{v:g}" for v in cs["limits_mm"])
        + f"] mm: {verdict} ({cs['source']})"
    )
