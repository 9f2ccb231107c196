"""``cadcog massprops``: mass properties of any STEP model, with its budget and import audit."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from cadcog.core.errors import CadcogError
from cadcog.core.fileio import round_floats
from cadcog.core.units import UNIT_CHOICES
from cadcog.mass.inertia import PRODUCT_CONVENTIONS, products_of_inertia
from cadcog.mass.materials import LIBRARY, MaterialMap, load_materials
from cadcog.spacecraft.envelope import CDS_COG_LIMITS_MM
from cadcog.spacecraft.mass_summary import MassReport, build_mass_report, parse_point


def _point(text: str) -> str | tuple[float, float, float]:
    try:
        return parse_point(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _limits(text: str) -> tuple[float, float, float]:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 3 or not all(np.isfinite(values)) or min(values) <= 0:
        raise argparse.ArgumentTypeError(f"expected three positive numbers X,Y,Z, got {text!r}")
    return values[0], values[1], values[2]


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "massprops",
        help="mass, CoG, inertia and mass budget of a STEP model, solid by solid",
        description="Reads every body at its global placement through any depth of assembly, "
        "integrates each solid exactly with its own density, combines by mass, and reports the "
        "import audit (declared unit, instances, surface bodies, overlaps, invalid topology, "
        "density sources), the mass budget by assembly node, and the inertia. Materials: "
        + "; ".join(f"{m.name} {m.density_kg_m3:g} kg/m³" for m in LIBRARY.values())
        + ". See docs/spacecraft.md.",
    )
    p.add_argument("model", type=Path, help="STEP file (part or assembly)")
    g = p.add_mutually_exclusive_group()
    g.add_argument(
        "--materials",
        type=Path,
        help="TOML: densities, surface areal densities, mass uncertainties and growth by pattern",
    )
    g.add_argument("--density-kg-m3", type=float, help="one density for every solid")
    p.add_argument(
        "--total-mass-kg", type=float, help="scale the densities so the total matches a weighing"
    )
    p.add_argument(
        "--units",
        choices=UNIT_CHOICES,
        help="the file's true length unit, when its declared unit is wrong (the reader already "
        "converts the declared unit; this never scales twice)",
    )
    p.add_argument(
        "--exclude",
        action="append",
        default=[],
        metavar="PATTERN",
        help="leave out bodies or assemblies matching this glob pattern or path (repeatable); "
        "applies before every check",
    )
    o = p.add_mutually_exclusive_group()
    o.add_argument(
        "--allow-overlap",
        action="store_true",
        help="count every solid as it is, whatever the overlap",
    )
    o.add_argument(
        "--resolve-overlaps",
        action="store_true",
        help="cut each common volume out of the less dense solid of its pair (the denser keeps "
        "it; on equal densities the one earlier in the file)",
    )
    o.add_argument(
        "--skip-overlaps",
        action="store_true",
        help="do not look for overlaps at all (fastest, for models known to be clean): every "
        "solid counted as it is, no overlap summary",
    )
    p.add_argument("--strict", action="store_true", help="turn every note into an error (for CI)")
    p.add_argument(
        "--about",
        type=_point,
        default="cog",
        help="reference point of the frame inertia: cog (default), origin, centre (the bounding "
        "box's centre: a CubeSat's geometric centre) or X,Y,Z in mm",
    )
    p.add_argument(
        "--axes",
        default="+x,+y,+z",
        help="axes of that frame as signed model axes, e.g. +y,-x,+z (default +x,+y,+z)",
    )
    p.add_argument(
        "--products",
        choices=tuple(PRODUCT_CONVENTIONS),
        default="positive",
        help="sign convention of the products of inertia shown (JSON has both): positive "
        "Pxy = +∫xy dm (default), negative Ixy = −∫xy dm",
    )
    p.add_argument(
        "--form-factor", choices=tuple(CDS_COG_LIMITS_MM), help="check the CubeSat CoG envelope"
    )
    p.add_argument(
        "--cog-limits-mm", type=_limits, help="custom CoG envelope half-widths X,Y,Z (mm)"
    )
    p.add_argument("--depth", type=int, default=2, help="budget tree levels shown (default 2)")
    p.add_argument("--report", type=Path, metavar="DIR", help="write an HTML report to DIR")
    p.add_argument(
        "--workers", type=int, help="processes for integration and overlap checks (default: CPUs)"
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


#: Steps from which a phase reports on a stderr that is not a terminal (a log, CI).
LOG_PROGRESS_MIN_STEPS = 500


def _log_progress(desc: str, total: int) -> Callable[[int], None]:
    """Plain lines for a log: the phase at once, then the count every heartbeat interval
    (nothing for small models)."""
    import time

    from cadcog.core.heartbeat import HEARTBEAT_EVERY_S

    if total < LOG_PROGRESS_MIN_STEPS:
        return lambda n: None
    print(f"cadcog: {desc}: 0/{total}", file=sys.stderr, flush=True)
    state = {"done": 0, "last": time.monotonic()}

    def update(n: int) -> None:
        state["done"] += n
        now = time.monotonic()
        if now - state["last"] >= HEARTBEAT_EVERY_S or state["done"] >= total:
            state["last"] = now
            print(f"cadcog: {desc}: {state['done']}/{total}", file=sys.stderr, flush=True)

    return update


def _progress() -> Callable[[str, int], Callable[[int], None]] | None:
    """A tqdm progress factory on a terminal (stderr), else plain lines for large models."""
    if not sys.stderr.isatty():
        return _log_progress
    from tqdm import tqdm

    def factory(desc: str, total: int) -> Callable[[int], None]:
        bar = tqdm(total=total or None, desc=desc, unit="", file=sys.stderr, leave=False)
        return bar.update

    return factory


def _materials(args: argparse.Namespace) -> MaterialMap | None:
    for name in ("density_kg_m3", "total_mass_kg"):
        value = getattr(args, name)
        if value is not None and not (np.isfinite(value) and value > 0):
            raise CadcogError(f"--{name.replace('_', '-')} must be a positive number, got {value}")
    if args.materials is not None:
        return load_materials(args.materials)
    if args.density_kg_m3 is not None:  # its range is checked with every option (bounds.py)
        return MaterialMap.uniform(args.density_kg_m3)
    return None


def run(args: argparse.Namespace) -> int:
    if args.depth < 0:
        raise CadcogError("--depth must be 0 or more")
    if args.workers is not None and args.workers < 1:
        raise CadcogError("--workers must be at least 1")
    materials = _materials(args)
    from cadcog.cad.stepmass import OverlapPolicy, model_mass_properties
    from cadcog.cad.stepread import read_step
    from cadcog.core.parallel import available_workers

    model = read_step(args.model)
    policy: OverlapPolicy = (
        "allow" if args.allow_overlap else "resolve" if args.resolve_overlaps else "check"
    )
    if args.skip_overlaps:
        policy = "skip"
    result = model_mass_properties(
        model,
        materials,
        total_mass_kg=args.total_mass_kg,
        units=args.units,
        exclude=args.exclude,
        overlaps=policy,
        strict=args.strict,
        progress=_progress(),
        workers=args.workers or available_workers(),
    )
    try:
        report = build_mass_report(
            result,
            about=args.about,
            axes=args.axes,
            form_factor=args.form_factor,
            cog_limits_mm=args.cog_limits_mm,
        )
    except ValueError as exc:
        raise CadcogError(f"--about/--axes: {exc}") from None
    if args.report is not None:
        from cadcog.reports.massprops_report import write_mass_report

        page = write_mass_report(report, model, args.report)
        print(f"report: {page}", file=sys.stderr)
    if args.json:
        print(json.dumps(round_floats(report.to_dict()), indent=2, ensure_ascii=False))
    else:
        print_report(report, args.depth, args.products)
    return 0


def _v(values: Any, digits: int = 3) -> str:
    # round first, then add 0.0: round-off must not print as "-0.000"
    return "[" + ", ".join(f"{round(float(v), digits) + 0.0:.{digits}f}" for v in values) + "]"


def _count(n: int, one: str, many: str = "") -> str:
    return f"{n} {one if n == 1 else many or one + 's'}"


def _n(value: float, digits: int = 4) -> str:
    return f"{round(float(value), digits) + 0.0:.{digits}f}"


def print_report(report: MassReport, depth: int, products: str) -> None:
    """Readable report: audit, budget tree, totals, inertia, overlaps, envelope, notes."""
    r, a, b = report.result, report.result.audit, report.budget
    units = ", ".join(a.declared_units) or "none"
    if a.units_override:
        units += f" (overridden: {a.units_override}, lengths × {a.scale_to_mm:g})"
    print(f"{a.source}: declared unit {units}")
    print(
        f"{_count(a.n_products, 'product')}, {_count(a.n_instances, 'instance')}: "
        f"{_count(a.n_solids, 'solid')}, {_count(a.n_surfaces, 'surface body', 'surface bodies')}"
        "; densities from " + ", ".join(f"{k} ×{n}" for k, n in a.density_sources.items())
    )
    if a.excluded:
        print(f"excluded: {len(a.excluded)} bodies")
    nodes = list(b.root.walk(depth))
    width = min(max([len("mass budget")] + [2 * lv + len(n.name) for lv, n in nodes]) + 2, 64)
    print(f"\n{'mass budget':<{width}}{'mass_kg':>11}{'share':>8}{'±_kg':>10}  cog_mm")
    for level, node in nodes:
        sigma = "" if node.mass_sigma_kg is None else f"{node.mass_sigma_kg:.6f}"
        name = "  " * level + node.name
        if len(name) > width - 2:
            name = name[: width - 3] + "…"
        print(
            f"{name:<{width}}{node.mass_kg:>11.6f}{node.share:>8.2%}{sigma:>10}  "
            f"{_v(node.cog_mm, 2)}"
        )
    t = r.total
    line = f"\ntotal {t.mass_kg:.5f} kg"
    if b.mass_sigma_kg is not None:
        line += f" ± {b.mass_sigma_kg:.5f} (1 σ, {b.sigma_coverage:.0%} of the mass has one)"
    print(line + f", volume {t.volume_mm3:.1f} mm³")
    cog = f"CoG {_v(t.cog_mm)} mm"
    if b.cog_cov_mm2 is not None:
        cog += f" ± {_v(np.sqrt(np.diag(b.cog_cov_mm2)))} mm (1 σ)"
    print(cog)
    if b.growth_kg:
        print(
            f"with growth allowances: {b.predicted.mass_kg:.5f} kg (+{b.growth_kg:.5f}), "
            f"CoG {_v(b.predicted.cog_mm)} mm"
        )
    j = t.inertia_kg_mm2
    p = products_of_inertia(j, products)  # type: ignore[arg-type]
    print("\ninertia about the CoG, model axes (kg·mm²):")
    print(f"  Ixx {_n(j[0, 0])}  Iyy {_n(j[1, 1])}  Izz {_n(j[2, 2])}")
    symbol = "P" if products == "positive" else "I"
    print(
        f"  {symbol}xy {_n(p['xy'])}  {symbol}xz {_n(p['xz'])}  {symbol}yz {_n(p['yz'])}"
        f"  ({PRODUCT_CONVENTIONS[products]}; --products)"
    )
    pa = report.principal
    print("principal moments (kg·mm²) and axes (model components):")
    for k in range(3):
        angle = pa.angles_from_frame_deg()[k]
        print(
            f"  {pa.moments_kg_mm2[k]:12.4f}  {_v(pa.axes[k], 4)}  ({angle:.1f}° from a model axis)"
        )
    if pa.degenerate:
        print("  (two moments are equal: their axes are not unique)")
    f = report.frame
    if f.label != "cog, axes +x,+y,+z":
        jf = report.frame_inertia_kg_mm2
        print(f"\nin the frame at {f.label} (origin {_v(f.origin_mm)} mm in model coordinates):")
        print(f"  CoG {_v(f.point_to_frame(t.cog_mm))} mm")
        print("  inertia tensor about the origin, frame axes (kg·mm²; off-diagonal −∫ x·y dm):")
        for row in jf:
            print("  " + "  ".join(f"{_n(v):>12}" for v in row))
    ov = r.overlaps
    if ov.pairs:
        print(f"\noverlaps ({ov.policy}): {ov.headline()}")
        for pair in ov.pairs[:10]:
            print(
                f"  {report.short(pair.a)} & {report.short(pair.b)}: {pair.volume_mm3:.4g} mm³, "
                f"{pair.mass_kg * 1e3:.4g} g ({'kept by' if ov.policy == 'resolve' else 'denser:'} "
                f"{report.short(pair.kept_by)})"
            )
        if len(ov.pairs) > 10:
            print(f"  ... {len(ov.pairs) - 10} more in --json")
    env = report.envelope
    if env is not None:
        label = env.form_factor or "custom"
        print(
            f"\n{label} CoG offset from the geometric centre {_v(env.offset_mm, 2)} mm, limits "
            f"±{_v(env.limits_mm, 1)} mm: {env.verdict()} ({env.source})"
        )
    for n in r.info:
        print(f"info: {n}")
    for n in r.notes:
        print(f"note: {n}")
