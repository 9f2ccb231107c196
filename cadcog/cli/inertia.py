"""``cadcog inertia``: the object's inertia tensor from its hangs' swings."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from cadcog.cli._options import add_json, add_rig, rig_or_setup
from cadcog.cli._output import print_json, warn
from cadcog.cli._types import weighing_sigma_kg
from cadcog.core.fittest import TEST_LEVEL, FitTest
from cadcog.core.numformat import signed
from cadcog.core.plusminus import mass_pm, pm
from cadcog.core.tolerances import DEFAULT_WEIGHING_SIGMA_KG


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "inertia",
        help="inertia tensor from the swings of the same hangs",
        description="Estimate the object's inertia tensor about its CoG from each hang's swing "
        "(a swing file) and the settled readings of the same hangs, with its uncertainty and "
        "the comparison with the CAD. See docs/inertia.md.",
    )
    p.add_argument("swings", type=Path, help="swing CSV (point_id,t_s,inc_x_deg,inc_y_deg)")
    p.add_argument(
        "--readings", type=Path, required=True, help="readings CSV of the same hangs (settled)"
    )
    add_rig(p, "rig file (the object is its proof mass)")
    p.add_argument("--setup", type=Path, help="spacecraft set-up file")
    p.add_argument(
        "--weighed-mass-kg",
        type=float,
        help="the object's weighed mass without the ME (default: the CAD's or the rig's)",
    )
    p.add_argument(
        "--mass-sigma-kg",
        type=float,
        help="1-σ of the weighing, with --weighed-mass-kg "
        f"(default {DEFAULT_WEIGHING_SIGMA_KG:g} kg)",
    )
    add_json(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from cadcog.runs.inertia import inertia_from_files

    args.mass_sigma_kg = weighing_sigma_kg(args.weighed_mass_kg, args.mass_sigma_kg)
    rig, setup = rig_or_setup(args)
    result = inertia_from_files(
        args.swings,
        args.readings,
        rig=rig,
        setup=setup,
        weighed_mass_kg=args.weighed_mass_kg,
        mass_sigma_kg=args.mass_sigma_kg,
    )
    if args.json:
        print_json(result.to_dict())
    else:
        print_inertia(result)
    for w in result.warnings:
        warn(w)
    return 0


def _g(v: float, sig: int = 5) -> str:
    return f"{v:.{sig}g}"


def print_inertia(result: Any) -> None:
    """Readable report of an :class:`~cadcog.dynamics.result.InertiaResult`."""
    ids = [h.point_id for h in result.hangs]
    w = max(5, *(len(i) for i in ids))
    print(f"{'hang':<{w}}  {'mode_hz':>9}  {'sigma_hz':>9}  {'model_hz':>9}  {'zeta':>6}  amp_deg")
    for h in result.hangs:
        for j in range(len(h.frequencies_hz)):
            print(
                f"{h.point_id if j == 0 else '':<{w}}  {h.frequencies_hz[j]:>9.5f}  "
                f"{h.sigma_hz[j]:>9.2g}  {h.model_hz[j]:>9.5f}  {h.damping_ratios[j]:>6.4f}  "
                f"{h.amplitudes_deg[j]:.2f}"
            )
    if result.dof > 0:
        print(
            f"\nfrequencies' consistency: χ² = {result.chi2:.2f} with {result.dof} dof "
            f"(p = {result.consistency_p:.3f})"
        )
    else:
        print(
            "\nfrequencies' consistency: not checked (as many frequencies as unknowns: a hang "
            "more would check the fit)"
        )
    t, s = result.inertia_kg_mm2, result.sigma_kg_mm2
    print(
        "\ninertia tensor about the object's CoG, model axes, kg·mm² "
        "(off-diagonal = −∫xy dm), ± 1 σ:"
    )
    cells = [[pm(t[i, j], s[i, j]) for j in range(3)] for i in range(3)]
    width = max(len(c) for row in cells for c in row)
    for row in cells:
        print("  " + "  ".join(f"{c:>{width}}" for c in row))
    pr = result.principal
    print("\nprincipal moments (kg·mm², ± 1 σ, 95 % ≈ ± 2 σ) and axes (model frame, ± 1 σ):")
    for k in range(3):
        rel = pr.moments_sigma_kg_mm2[k] / pr.moments_kg_mm2[k] * 100
        axis = ", ".join(signed(a, 4) for a in pr.axes[k])
        print(
            f"  I{k + 1} = {pm(pr.moments_kg_mm2[k], pr.moments_sigma_kg_mm2[k]):>16} "
            f"({rel:.2f} %)   axis [{axis}] "
            + (f"± {pr.axes_sigma_deg[k]:.2g}°" if pr.axes_sigma_deg[k] < 90 else "undetermined")
        )
    print(
        f"about the CoG {np.round(result.cog_mm, 3).tolist()} mm; object mass "
        f"{mass_pm(result.mass_kg, result.mass_sigma_kg)} ({result.mass_source})"
    )
    print("\nwhere the uncertainty comes from (share of the principal moments' variance):")
    for name, share in result.budget:
        if share >= 0.005:
            print(f"  {share * 100:5.1f} %  {name}")
    cad = result.cad
    if cad is not None:
        print("\nagainst the CAD's tensor (difference in σ of measurement and CAD combined):")
        d = np.asarray(cad["difference_kg_mm2"])
        z = np.asarray(cad["difference_sigma"])
        for i in range(3):
            print(
                "  " + "  ".join(f"{_g(d[i, j], 3):>9} ({signed(z[i, j], 1)} σ)" for j in range(3))
            )
        print(
            f"  joint χ² = {cad['chi2']:.2f} with {cad['dof']} dof (p = {cad['p']:.3f}): "
            + (
                "consistent with the CAD"
                if FitTest(cad["chi2"], cad["dof"]).passes
                else f"differs from the CAD beyond the uncertainties ({TEST_LEVEL * 100:g} % level)"
            )
        )
