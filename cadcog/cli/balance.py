"""``cadcog balance``: the least ballast that puts the CoG inside its envelope at a confidence."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from cadcog.cli._options import add_json, add_overlap_modes, overlap_mode
from cadcog.cli._output import print_json
from cadcog.cli._table import text_table
from cadcog.cli._types import positive_triple
from cadcog.core.units import UNIT_CHOICES
from cadcog.spacecraft.envelope import CDS_COG_LIMITS_MM
from cadcog.spacecraft.items import DEFAULT_WEIGHING_SIGMA_KG

#: Exit status when no ballast within the file's limits meets the envelope (everything said).
EXIT_INFEASIBLE = 1


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "balance",
        help="the least ballast that puts the CoG inside its envelope at a confidence",
        description="Find the least total ballast at the allowed locations of a ballast file "
        "(TOML: [[points]] id, position_mm, max_mass_kg; optional sizes_kg for discrete pieces "
        "and max_total_mass_kg) that puts the CoG inside the CubeSat envelope (or half-widths "
        "given) with at least the stated confidence, the CoG's uncertainty carried: the CAD's "
        "(a model and its materials, or a set-up), or, with --readings and --weighed-mass-kg, "
        "what `cadcog update` makes of the test and the CAD. A convex programme (integer with "
        "sizes) solved to within 0.2 % of a proven lower bound. Exit 0 with a ballast (none "
        "may be needed), 1 when none within the limits meets the envelope (which face is "
        "short, by how much moment), 2 bad input. See docs/spacecraft.md.",
    )
    p.add_argument("model", type=Path, nargs="?", help="STEP model (or give --setup)")
    p.add_argument("--setup", type=Path, help="spacecraft set-up file (TOML) instead of a model")
    p.add_argument("--materials", type=Path, help="materials file (TOML) of the model")
    p.add_argument("--units", choices=UNIT_CHOICES, help="the STEP file's true length unit")
    p.add_argument("--ballast", type=Path, required=True, help="ballast file (TOML)")
    p.add_argument(
        "--form-factor",
        choices=tuple(CDS_COG_LIMITS_MM),
        help="the envelope of a CubeSat (1U...12U) or a PocketQube (1p, 2p, 3p)",
    )
    p.add_argument("--cog-limits-mm", type=positive_triple, help="envelope half-widths X,Y,Z (mm)")
    p.add_argument(
        "--confidence",
        type=float,
        default=0.95,
        help="least probability that the CoG is inside the whole envelope (default 0.95)",
    )
    p.add_argument(
        "--configurations",
        type=Path,
        metavar="FILE",
        help="configurations file (TOML): the same ballast must meet the envelope in each",
    )
    p.add_argument("--readings", type=Path, help="the test's readings CSV (with --setup)")
    p.add_argument("--weighed-mass-kg", type=float, help="the weighed mass, without the ME")
    p.add_argument(
        "--mass-sigma-kg",
        type=float,
        help=f"1-σ of the weighing (with --readings; default {DEFAULT_WEIGHING_SIGMA_KG:g} kg)",
    )
    p.add_argument(
        "--max-product-kg-mm2",
        type=float,
        metavar="L",
        help="inertia objective: each product of inertia about the new CoG within ±L kg·mm²",
    )
    p.add_argument(
        "--max-axis-angle-deg",
        type=float,
        metavar="DEG",
        help="inertia objective: each pair of principal axes turned at most DEG (< 45) from "
        "the model's axes",
    )
    p.add_argument(
        "--inertia-confidence",
        type=float,
        help="least probability that the inertia objectives hold (default: --confidence)",
    )
    add_overlap_modes(
        p,
        allow_help="count a MODEL's overlapping solids as they are (as massprops)",
        resolve_help="cut each common volume out of the less dense solid of a MODEL (as massprops)",
    )
    add_json(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from cadcog.core.errors import CadcogError
    from cadcog.core.parallel import available_workers
    from cadcog.runs.balance import run_balance

    if args.model is not None and args.setup is not None:
        raise CadcogError("give a MODEL or --setup, not both (a set-up names its model)")
    if args.setup is not None and (args.materials is not None or args.units is not None):
        raise CadcogError("--materials and --units go with a MODEL (a set-up names its own)")
    result = run_balance(
        args.ballast,
        model=args.model,
        materials=args.materials,
        units=args.units,
        setup=args.setup,
        form_factor=args.form_factor,
        cog_limits_mm=args.cog_limits_mm,
        confidence=args.confidence,
        readings=args.readings,
        weighed_mass_kg=args.weighed_mass_kg,
        mass_sigma_kg=args.mass_sigma_kg,
        workers=available_workers(),
        configurations=args.configurations,
        overlaps=overlap_mode(args),
        max_product_kg_mm2=args.max_product_kg_mm2,
        max_axis_angle_deg=args.max_axis_angle_deg,
        inertia_confidence=args.inertia_confidence,
    )
    if args.json:
        print_json(result.to_dict())
    else:
        print_balance(result)
    return 0 if result.feasible else EXIT_INFEASIBLE


def _vec(v: Any, digits: int = 2) -> str:
    """``[a, b, c]`` to ``digits`` decimals, without a "-0.00"."""
    tiny = 0.5 * 10.0**-digits
    return "[" + ", ".join(f"{(0.0 if abs(x) < tiny else float(x)):.{digits}f}" for x in v) + "]"


def print_balance(r: Any) -> None:
    """Readable report of a :class:`~cadcog.spacecraft.balance_result.BalanceResult`."""
    d = r.to_dict()
    conf = f"{r.confidence:.4g}"
    print(
        f"envelope ±{_vec(r.limits_mm, 1)} mm around {_vec(r.geometric_center_mm)} mm; "
        f"figures: {r.state.source}; confidence {conf} (a union bound over the six faces)"
    )
    print(f"limits: {r.envelope_source}")
    b = d["before"]
    print(
        f"as it is:  CoG {_vec(b['cog_mm'])} mm, margin {_vec(b['margin_mm'])} mm, "
        f"P(inside) {b['probability_inside']:.4f}"
    )
    if b["axes_without_budget"]:
        axes = " and ".join(b["axes_without_budget"])
        print(
            f"           ({axes}: negative only because the other axes' faces already miss "
            f"with a probability above {1 - r.confidence:.3g}, which leaves {axes} none to "
            "spend; on its own it is inside)"
        )
    if not r.feasible and r.inertia is not None and not r.shortfall:
        print("no ballast found that meets the envelope and the inertia objectives:")
        print_inertia_objectives(r.inertia)
        for note in r.notes:
            print(f"note: {note}")
        return
    if not r.feasible:
        print(
            "no ballast within the file's limits meets the envelope at this confidence"
            + (":" if r.shortfall else "")
        )
        for s in r.shortfall:
            where = f" ({s['configuration']})" if "configuration" in s else ""
            print(
                f"  {s['side']}{s['axis']} face{where}: short by at least "
                f"{s['moment_kg_mm']:.4g} kg·mm of moment (the CoG {s['cog_shift_mm']:.3g} mm "
                "further in), with all the ballast the file allows"
            )
        for note in r.notes:
            print(f"note: {note}")
        return
    if r.total_ballast_kg == 0.0:
        print("no ballast needed: the CoG meets the envelope at this confidence as it is")
    else:
        rows = []
        for item in d["ballast"]:
            pieces = ", ".join(
                f"{p['count']} × {p['size_kg'] * 1000:g} g" for p in item.get("pieces", [])
            )
            rows.append(
                [item["id"], f"{item['mass_kg'] * 1000:.4g}", _vec(item["position_mm"], 1), pieces]
            )
        print(text_table(["location", "ballast (g)", "at (mm)", "pieces"], rows, "lrll"))
        proof = "the least possible" if r.optimal else f"proven bound {r.bound_kg:.6g} kg"
        print(f"total ballast {r.total_ballast_kg * 1000:.4g} g ({proof})")
    print(
        f"with it:   mass {r.mass_kg:.6g} kg, CoG {_vec(r.cog_mm)} mm "
        f"± {_vec(r.cog_cov_mm2.diagonal() ** 0.5)} mm (1σ)"
    )
    print(f"           margin {_vec(r.margin_mm)} mm, P(inside) {r.probability_inside:.4f}")
    if r.inertia is not None:
        print_inertia_objectives(r.inertia)
    for c in r.configurations:
        print(
            f"{c['name']}: CoG {_vec(c['cog_mm'])} mm, margin {_vec(c['margin_mm'])} mm, "
            f"P(inside) {c['probability_inside']:.4f} (before: {_vec(c['before']['cog_mm'])} mm)"
        )
    for note in r.notes:
        print(f"note: {note}")


def print_inertia_objectives(info: dict[str, Any]) -> None:
    """The inertia objectives, and the tensor's figures before and after."""
    o = info["objectives"]
    wanted = []
    if o["max_product_kg_mm2"] is not None:
        wanted.append(f"|products| ≤ {o['max_product_kg_mm2']:g} kg·mm²")
    if o["max_axis_angle_deg"] is not None:
        wanted.append(f"principal axes within {o['max_axis_angle_deg']:g}° (each pair)")
    print(
        f"inertia: {', '.join(wanted)}, confidence {o['confidence']:.4g} (union bound over "
        f"{o['conditions']} conditions, z = {o['quantile']:.3f}); tensor: {info['tensor_source']}"
    )
    rows = []
    shown = [("as it is", info["before"])]
    if info.get("after") is not None:
        shown.append(("with it", info["after"]))
    elif info.get("with_cog_ballast") is not None:
        shown.append(("with the CoG's least", info["with_cog_ballast"]))
    for label, f in shown:
        prods = "  ".join(
            f"{k} {v:.4g} ± {f['products_sigma_kg_mm2'][k]:.3g}"
            for k, v in f["products_kg_mm2"].items()
        )
        turns = ", ".join(f"{k} {v:.2f}°" for k, v in f["pair_rotation_deg"].items())
        rows.append([label, prods, turns, "yes" if f["met"] else "no"])
    print(
        text_table(
            ["", "products about the CoG (kg·mm², ± 1σ)", "pair rotations", "met"], rows, "llll"
        )
    )
    print(f"how: {info['search']}")
