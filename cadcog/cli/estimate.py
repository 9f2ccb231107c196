"""``cadcog estimate``: the compensated CoG from a readings CSV."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

from cadcog import tolerances
from cadcog.errors import CadcogError
from cadcog.estimator import POINT_SIGMA_MM
from cadcog.fileio import round_floats
from cadcog.inclinometer import InclinometerConfig
from cadcog.measurement import (
    CogEstimate,
    MEData,
    estimate_cog,
    rig_point_sigma_mm,
    wire_corrections,
)
from cadcog.readings import read_readings
from cadcog.rig import Rig
from cadcog.rigfile import load_rig


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
    p.add_argument(
        "--rig",
        type=Path,
        help="rig file: object mass, ME mass and CoG (and its uncertainty), inclinometer set-up",
    )
    p.add_argument(
        "--setup",
        type=Path,
        help="spacecraft set-up file: masses and ME from its CAD, the CAD comparison and the "
        "CubeSat envelope check",
    )
    p.add_argument("--object-mass-kg", type=float, help="mass of the object without the ME")
    p.add_argument("--me-mass-kg", type=float, help="mass of the measurement equipment")
    p.add_argument("--me-cog-mm", type=_vector3, help="ME CoG in the body frame, X,Y,Z")
    p.add_argument(
        "--me-cog-sigma-mm",
        type=float,
        default=0.0,
        help="per-axis standard deviation of the ME CoG, with --me-cog-mm (default 0)",
    )
    p.add_argument(
        "--angle-sigma-deg",
        type=float,
        help="per-axis reading uncertainty (default: from the inclinometer's accuracy and ADC "
        f"step; {InclinometerConfig().angle_sigma_deg:.4f} for the paper's)",
    )
    p.add_argument(
        "--point-sigma-mm",
        type=float,
        help=f"per-axis suspension point uncertainty (default {POINT_SIGMA_MM:.3f}, a 1 mm cube; "
        "with --wire-correction, from the rig's play and wire model)",
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
        action="store_true",
        help="with --rig: move each point along its bolt axis by the wire offset the rig's error "
        "model expects, and take the point uncertainty from that model",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def _me_data(args: argparse.Namespace) -> tuple[MEData | None, InclinometerConfig, Rig | None]:
    direct = (args.object_mass_kg, args.me_mass_kg, args.me_cog_mm)
    if args.rig is not None:
        if any(v is not None for v in direct):
            raise CadcogError("give either --rig or --object-mass-kg/--me-mass-kg/--me-cog-mm")
        rig = load_rig(args.rig)
        return MEData.from_rig(rig), rig.inclinometer, rig
    if args.wire_correction:
        raise CadcogError("--wire-correction needs --rig (the wire model lives in the rig file)")
    if all(v is None for v in direct):
        return None, InclinometerConfig(), None
    if any(v is None for v in direct):
        raise CadcogError("--object-mass-kg, --me-mass-kg and --me-cog-mm go together")
    if not args.object_mass_kg > 0 or not args.me_mass_kg >= 0:
        raise CadcogError("--object-mass-kg must be positive and --me-mass-kg non-negative")
    if not args.me_cog_sigma_mm >= 0:
        raise CadcogError("--me-cog-sigma-mm must be non-negative")
    me = MEData(
        args.object_mass_kg,
        args.me_mass_kg,
        np.array(args.me_cog_mm),
        args.me_cog_sigma_mm**2 * np.eye(3),
        "command line",
    )
    return me, InclinometerConfig(), None


def run(args: argparse.Namespace) -> int:
    for name in ("angle_sigma_deg", "point_sigma_mm", "min_angle_deg"):
        value = getattr(args, name)
        if value is not None and not value > 0:
            raise CadcogError(f"--{name.replace('_', '-')} must be positive, got {value}")
    if args.setup is not None:
        return run_setup(args)
    me, config, rig = _me_data(args)
    suspensions = read_readings(args.readings, config)
    offsets = None
    point_sigma = args.point_sigma_mm
    if args.wire_correction and rig is not None:
        try:
            offsets = wire_corrections(rig, suspensions)
        except ValueError as exc:
            raise CadcogError(f"{args.readings}: {exc}") from None
        if point_sigma is None:
            point_sigma = rig_point_sigma_mm(rig)
    result = estimate_cog(
        suspensions,
        config,
        me,
        angle_sigma_deg=args.angle_sigma_deg,
        point_sigma_mm=POINT_SIGMA_MM if point_sigma is None else point_sigma,
        min_angle_deg=args.min_angle_deg,
        point_offsets_mm=offsets,
    )
    return _emit(result, args.json)


def _emit(result: CogEstimate, as_json: bool, cad: dict[str, Any] | None = None) -> int:
    """Print an estimate (JSON or table, with the CAD comparison if any); warnings to stderr."""
    if as_json:
        data = result.to_dict() if cad is None else {**result.to_dict(), "cad": cad}
        print(json.dumps(round_floats(data), indent=2, ensure_ascii=False))
    else:
        print_estimate(result)
        if cad is not None:
            print_cad_comparison(cad)
    for w in result.warnings:
        print(f"cadcog: warning: {w}", file=sys.stderr)
    return 0


def _fmt(values: Any, width: int = 9, digits: int = 3) -> str:
    return "[" + ", ".join(f"{v:{width}.{digits}f}" for v in values) + "]"


def print_estimate(result: CogEstimate) -> None:
    """Readable report of an estimate."""
    print(f"{'point':<8}{'n':>4}{'inc_x_deg':>11}{'inc_y_deg':>11}  top_up  residual_mm  sigma")
    residuals = {r.id: r for r in result.joint.residuals}
    for s in result.suspensions:
        r = residuals[s.id]
        mark = "  <- inconsistent" if r.inconsistent else ""
        print(
            f"{s.id:<8}{s.n_samples:>4}{s.inc_x_deg:>11.3f}{s.inc_y_deg:>11.3f}  "
            f"{s.top_face_up!s:<7}{r.distance_mm:>12.3f}{r.normalized:>7.2f}{mark}"
        )
    print(f"\n{'pair':<12}{'midpoint_mm':<35}{'gap_mm':>8}{'angle_deg':>11}")
    for p in result.joint.pairs:
        print(f"{p.a + '-' + p.b:<12}{_fmt(p.midpoint_mm):<35}{p.gap_mm:>8.3f}{p.angle_deg:>11.2f}")
    print()
    sigma = np.sqrt(np.diag(result.joint.cov_mm2))
    print(f"assembly CoG (object + ME): {_fmt(result.assembly_cog_mm)} mm  ± {_fmt(sigma)} mm")
    if result.compensation is None:
        print("no ME data given: the CoG above is not compensated for the measurement equipment")
    else:
        c = result.compensation
        sigma = np.sqrt(np.diag(c.cov_mm2))
        print(
            f"object CoG (ME removed):    {_fmt(c.cog_mm)} mm  ± {_fmt(sigma)} mm  "
            f"(object {c.object_mass_kg:g} kg, ME {c.me_mass_kg:g} kg at {_fmt(c.me_cog_mm, 0, 2)})"
        )


def run_setup(args: argparse.Namespace) -> int:
    """``--setup``: a spacecraft's compensated CoG compared with its CAD."""
    if args.rig is not None or args.object_mass_kg is not None or args.me_mass_kg is not None:
        raise CadcogError("--setup already gives the masses and the ME: drop --rig/--*-mass-kg")
    from cadcog.spacecraft import compare_with_cad, load_setup

    setup = load_setup(args.setup)
    suspensions = read_readings(args.readings, setup.rig.inclinometer)
    point_sigma = args.point_sigma_mm
    result = estimate_cog(
        suspensions,
        setup.rig.inclinometer,
        setup.me_data(),
        angle_sigma_deg=args.angle_sigma_deg,
        point_sigma_mm=rig_point_sigma_mm(setup.rig) if point_sigma is None else point_sigma,
        min_angle_deg=args.min_angle_deg,
    )
    return _emit(result, args.json, compare_with_cad(setup, result.cog_mm, result.cov_mm2))


def print_cad_comparison(cad: dict[str, Any]) -> None:
    """Readable lines of :func:`cadcog.spacecraft.compare_with_cad`."""
    d, s = cad["difference_mm"], cad["difference_sigma"]
    print(
        "measured − CAD: ["
        + ", ".join(f"{v:+.3f}" for v in d)
        + "] mm = ["
        + ", ".join(f"{v:+.1f}" for v in s)
        + "] σ"
    )
    cs = cad.get("cubesat")
    if cs is None:
        return
    verdict = ("within" if cs["within"] else "OUTSIDE") + " the envelope"
    if cs["within"] and not cs["within_at_95"]:
        verdict += ", but not with 95 % confidence"
    print(
        f"{cs['form_factor']} CoG offset from the geometric centre: ["
        + ", ".join(f"{v:+.2f}" for v in cs["offset_mm"])
        + "] mm, limits ±["
        + ", ".join(f"{v:g}" for v in cs["limits_mm"])
        + f"] mm: {verdict} ({cs['source']})"
    )
