"""``cadcog update``: what the suspension test and the weighing say about the CAD."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from cadcog.cli._options import add_json
from cadcog.cli._output import print_json, warn, wrote
from cadcog.cli._table import text_table
from cadcog.core.errors import CadcogError
from cadcog.spacecraft.update import INCONSISTENT_NOTE, REJECTED_NOTE, unmodelled_from_region

if TYPE_CHECKING:
    from cadcog.spacecraft.update import UpdateResult
from cadcog.spacecraft.items import DEFAULT_WEIGHING_SIGMA_KG as DEFAULT_MASS_SIGMA_KG

#: Exit status when the gap between test and CAD is larger than the CAD's uncertainties allow
#: (every output is written; a CI job fails on it, as on a failed requirement in ``check``).
EXIT_GAP = 1


def _region(text: str) -> tuple[float, ...]:
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        values = ()
    if len(values) != 6 or not all(np.isfinite(values)):
        raise argparse.ArgumentTypeError(
            f"expected six numbers X0,Y0,Z0,X1,Y1,Z1 (two opposite corners, mm), got {text!r}"
        )
    return values


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "update",
        help="update the CAD mass budget from a measured CoG and a weighing",
        description="Estimate the CoG from the readings as `estimate --setup` does, then find "
        "the item masses (within the materials file's mass uncertainties), and optionally an "
        "unmodelled mass in a region, that explain the measured CoG and the weighed mass: "
        "which items most likely explain the gap, the updated mass, CoG and inertia with their "
        "covariance, and whether the gap is larger than the uncertainties allow. Exit status: 0 "
        "the test agrees with the CAD within its uncertainties, 1 the gap is larger than they "
        "allow (every output still written: a CI job fails here), 2 bad input. See "
        "docs/spacecraft.md.",
    )
    p.add_argument("readings", type=Path, help="readings CSV of the suspension test")
    p.add_argument("--setup", type=Path, required=True, help="spacecraft set-up file (TOML)")
    p.add_argument(
        "--weighed-mass-kg",
        type=float,
        required=True,
        help="the spacecraft's weighed mass, without the measurement equipment",
    )
    p.add_argument(
        "--mass-sigma-kg",
        type=float,
        default=DEFAULT_MASS_SIGMA_KG,
        help=f"1-σ uncertainty of the weighing (default {DEFAULT_MASS_SIGMA_KG:g} kg)",
    )
    p.add_argument(
        "--unmodelled-region-mm",
        type=_region,
        help="allow an unmodelled mass (harness, fasteners, adhesive) somewhere in this box: "
        "X0,Y0,Z0,X1,Y1,Z1",
    )
    p.add_argument(
        "--unmodelled-mass-kg",
        type=float,
        help="prior mean of the unmodelled mass (with --unmodelled-region-mm; default 0)",
    )
    p.add_argument(
        "--unmodelled-sigma-kg",
        type=float,
        help="prior 1-σ of the unmodelled mass (needed with --unmodelled-region-mm)",
    )
    p.add_argument(
        "--swings",
        type=Path,
        help="the same hangs' swing CSV: their inertia tensor (cadcog inertia) is observed too "
        "and constrains the same item masses",
    )
    p.add_argument("--report", type=Path, metavar="DIR", help="write an HTML report to DIR")
    add_json(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from cadcog.runs.update import update_from_files
    from cadcog.spacecraft.setup import load_setup

    if args.unmodelled_region_mm is not None and args.unmodelled_sigma_kg is None:
        raise CadcogError("--unmodelled-region-mm needs --unmodelled-sigma-kg (its prior 1 σ)")
    if args.unmodelled_region_mm is None and args.unmodelled_sigma_kg is not None:
        raise CadcogError("--unmodelled-sigma-kg goes with --unmodelled-region-mm")
    if args.unmodelled_region_mm is None and args.unmodelled_mass_kg is not None:
        raise CadcogError("--unmodelled-mass-kg goes with --unmodelled-region-mm")
    try:
        unmodelled = unmodelled_from_region(
            args.unmodelled_region_mm,
            0.0 if args.unmodelled_mass_kg is None else args.unmodelled_mass_kg,
            args.unmodelled_sigma_kg,
        )
    except ValueError as exc:
        raise CadcogError(f"--unmodelled-region-mm: {exc}") from None
    setup = load_setup(args.setup)
    result, estimate = update_from_files(
        setup,
        args.readings,
        args.weighed_mass_kg,
        mass_sigma_kg=args.mass_sigma_kg,
        unmodelled=unmodelled,
        swings=args.swings,
    )
    if args.report is not None:
        from cadcog.reports.update_report import write_update_report

        page = write_update_report(result, setup, estimate, args.readings, args.report)
        wrote(page)
    if args.json:
        print_json(result.to_dict())
    else:
        print_update(result)
    for w in estimate.warnings:
        warn(w)
    return 0 if result.consistent else EXIT_GAP


def print_update(r: UpdateResult) -> None:
    """Readable report of an :class:`~cadcog.spacecraft.update_result.UpdateResult`: masses and
    inertias to significant figures in a unit that fits, the products' convention named."""
    from cadcog.cli.massprops_text import PRODUCT_LABELS
    from cadcog.spacecraft import update_text as ut

    for line in r.verdict_lines():
        print(line)
    print()
    print(text_table(["(± 1 σ)", "CAD", "measured", "updated"], ut.mass_cog_rows(r), "llll"))
    print("\nwhat explains the gap (posterior probability; prior in brackets):")
    shown = r.explanations[:6]
    width = max((len(e.label) for e in shown), default=0)
    for e in shown:
        print(
            f"  {e.label:<{width}}  {e.probability:6.1%}  ({e.prior_probability:.2g})  "
            f"{e.description}"
        )
    order = (
        "none implicated: the largest stated mass σ first"
        if r.consistent
        else "the most probable first"
    )
    print(f"\nitems (mass change and CoG shift, ± 1 σ; P: probability it is the one off; {order}):")
    headers, rows = ut.item_table(r.ranked_items()[:8])
    print(text_table(headers, rows, "lrrrrl", 2))
    if r.unmodelled_mass_kg is not None:
        print(f"\nunmodelled mass: {ut.unmodelled_summary(r)}")
    if r.model_rejected:
        print(f"\n{REJECTED_NOTE}")
    elif not r.consistent:
        print(f"\n{INCONSISTENT_NOTE}")
    unit = ut.inertia_unit(r)
    print(f"\nupdated inertia about the CoG, model axes ({unit[0]}, ± 1 σ):")
    print("  " + "  ".join(ut.moment_cells(r)))
    products = ut.product_cells(r, "positive")
    print(
        "  "
        + "  ".join(f"P{k} {p}" for k, p in zip(ut.PRODUCT_INDEX, products, strict=True))
        + f"  ({PRODUCT_LABELS['positive']})"
    )
