"""``cadcog massprops``: mass properties of any STEP model, with its budget and import audit."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from cadcog.cad.massresults import Refusal
from cadcog.cli._options import add_json, add_overlap_modes, overlap_mode
from cadcog.cli._output import print_json, wrote
from cadcog.cli._types import positive_triple
from cadcog.cli.massprops_text import print_configurations, print_report
from cadcog.core.errors import CadcogError
from cadcog.core.fileio import note_input
from cadcog.core.gcpause import gc_paused
from cadcog.core.units import UNIT_CHOICES
from cadcog.mass.inertia import PRODUCT_CONVENTIONS
from cadcog.mass.materials import LIBRARY
from cadcog.spacecraft.envelope import CDS_COG_LIMITS_MM
from cadcog.spacecraft.mass_summary import MassReport, build_mass_report, parse_point

if TYPE_CHECKING:
    from cadcog.cad.stepmass import ModelMassProperties
    from cadcog.cad.stepmodel import StepModel
    from cadcog.spacecraft.configurations import Configuration


def _point(text: str) -> str | tuple[float, float, float]:
    try:
        return parse_point(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "massprops",
        help="mass, CoG, inertia and mass budget of a STEP model, solid by solid",
        description="Reads every body at its global placement through any depth of assembly, "
        "integrates each solid exactly with its own density, combines by mass, and reports the "
        "import audit (declared unit, instances, surface bodies, overlaps, invalid topology, "
        "density sources), the mass budget by assembly node, and the inertia. Materials: "
        + "; ".join(f"{m.name} {m.density_kg_m3:g} kg/m³" for m in LIBRARY.values())
        + ". A second run on unchanged files and options reads the result from a cache "
        "(CADCOG_NO_CACHE=1 computes afresh). See docs/spacecraft.md.",
    )
    p.add_argument("model", type=Path, help="STEP file (part or assembly)")
    _add_density_options(p.add_argument_group("densities"))
    _add_counting_options(p.add_argument_group("what is counted"))
    _add_frame_options(p.add_argument_group("the inertia's frame"))
    _add_envelope_options(p.add_argument_group("the CoG envelope and configurations"))
    _add_output_options(p.add_argument_group("output"))
    p.set_defaults(func=run, also_written=lambda a: [a.csv])


def _add_density_options(p: Any) -> None:
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


def _add_counting_options(p: Any) -> None:
    p.add_argument(
        "--exclude",
        action="append",
        default=[],
        metavar="PATTERN",
        help="leave out bodies or assemblies matching this glob pattern or path (repeatable); "
        "applies before every check",
    )
    o = add_overlap_modes(
        p,
        allow_help="count every solid as it is, whatever the overlap",
        resolve_help="cut each common volume out of the less dense solid of its pair (the denser "
        "keeps it; on equal densities the one earlier in the file)",
    )
    o.add_argument(
        "--skip-overlaps",
        action="store_true",
        help="do not look for overlaps at all (fastest, for models known to be clean): every "
        "solid counted as it is, no overlap summary",
    )
    p.add_argument("--strict", action="store_true", help="turn every note into an error (for CI)")
    p.add_argument(
        "--surface-area",
        action="store_true",
        help="also each body's face area and each assembly's sum (for insulation blankets and "
        "coatings): a column in the budget, surface_area_mm2 in the JSON and the CSV",
    )


def _add_frame_options(p: Any) -> None:
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
        help="axes of that frame: signed model axes, e.g. +y,-x,+z (default +x,+y,+z), or the "
        "frame's x and y (and z) as model vectors, e.g. '1,1,0;-1,1,0' (a rotation's rows; "
        "right-handed, normalised)",
    )
    p.add_argument(
        "--products",
        choices=tuple(PRODUCT_CONVENTIONS),
        default="positive",
        help="sign convention of the products of inertia shown (JSON has both): positive "
        "Pxy = +∫xy dm (default), negative Ixy = −∫xy dm",
    )


def _add_envelope_options(p: Any) -> None:
    p.add_argument(
        "--form-factor",
        choices=tuple(CDS_COG_LIMITS_MM),
        help="check the CoG envelope of a CubeSat (1U...12U) or a PocketQube (1p, 2p, 3p: "
        "provisional limits, ±10 mm)",
    )
    p.add_argument(
        "--cog-limits-mm", type=positive_triple, help="custom CoG envelope half-widths X,Y,Z (mm)"
    )
    p.add_argument(
        "--configurations",
        type=Path,
        metavar="FILE",
        help="also each configuration of a configurations file (TOML: parts moved about a hinge "
        "or along a rail, masses changed): mass, CoG, inertia, uncertainty, envelope",
    )


def _add_output_options(p: Any) -> None:
    p.add_argument("--depth", type=int, default=2, help="budget tree levels shown (default 2)")
    p.add_argument(
        "--collapse-below-percent",
        type=float,
        default=0.0,
        metavar="PCT",
        help="in the text budget, sum the siblings each under PCT %% of the total mass into one "
        "'N others' row (default 0: every node)",
    )
    p.add_argument("--report", type=Path, metavar="DIR", help="write an HTML report to DIR")
    p.add_argument(
        "--csv",
        type=Path,
        metavar="PATH",
        help="write the budget (every level, copies grouped) and every body as CSV: mass, CoG, "
        "inertia (Pxy = +∫xy dm), radii of gyration, density source per row",
    )
    p.add_argument(
        "--workers", type=int, help="processes for integration and overlap checks (default: CPUs)"
    )
    add_json(p)


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


def run(args: argparse.Namespace) -> int:
    with gc_paused():  # a bounded computation keeping ~10⁶ objects alive (core/gcpause.py)
        return _run(args)


def _run(args: argparse.Namespace) -> int:
    if args.depth < 0:
        raise CadcogError("--depth must be 0 or more")
    if not (np.isfinite(args.collapse_below_percent) and 0 <= args.collapse_below_percent < 100):
        raise CadcogError(
            f"--collapse-below-percent: expected a number from 0 to under 100, got "
            f"{args.collapse_below_percent:g}"
        )
    if args.csv is not None:  # before the CAD and any output: a clash writes nothing
        if args.csv.is_dir():
            raise CadcogError(f"--csv {args.csv}: is a directory, expected a file name")
        if args.report is not None and args.csv.resolve() == args.report.resolve():
            raise CadcogError(f"--csv and --report name the same path: {args.csv}")
    configs: tuple[Configuration, ...] = ()
    if args.configurations is not None:  # read before the CAD: a bad file costs nothing
        from cadcog.spacecraft.configurations import load_configurations

        configs = load_configurations(args.configurations)
    policy = overlap_mode(args)
    read: list[StepModel] = []

    def model() -> StepModel:
        """The model, read once and only when needed: a cached result needs no CAD."""
        if not read:
            from cadcog.cad.stepread import read_step

            read.append(read_step(args.model))
        return read[0]

    from cadcog.cad.cache import step_mass_properties
    from cadcog.core.parallel import available_workers

    try:
        result, hit = step_mass_properties(
            args.model,
            args.materials,
            density_kg_m3=args.density_kg_m3,
            total_mass_kg=args.total_mass_kg,
            units=args.units,
            exclude=args.exclude,
            overlaps=policy,
            strict=args.strict,
            surface_areas=args.surface_area,
            workers=args.workers or available_workers(),
            progress=_progress(),
            read=model,
        )
    except CadcogError as exc:
        refusal = exc if isinstance(exc, Refusal) else None
        if refusal is not None and not read:  # kept in the cache: the model was not read
            _say_cached(args)
        if not (args.json or args.report or args.csv):
            raise
        # a refusal carries what it is about, counted as it is (for CI to parse); any other
        # error (an open solid, a file OCCT cannot read) has nothing to count
        as_is = refusal.as_is if refusal is not None else None
        emit_refusal(args, str(exc), as_is, model, policy, configs)
        raise
    if hit:
        _say_cached(args)
    emit(args, result, model, configs)
    return 0


def _model_files(args: argparse.Namespace) -> list[Path]:
    """The files a model's pictures are cached under (the STEP and its materials)."""
    return [args.model] + ([args.materials] if args.materials is not None else [])


def _say_cached(args: argparse.Namespace) -> None:
    """One line on stderr: the cache answered; the files are still inputs of the run."""
    note_input(args.model, "the STEP model it reads")
    if args.materials is not None:
        note_input(args.materials, "a parameter file it reads")
    print(
        f"cadcog: {args.model}: mass properties from the cache (inputs unchanged; "
        "CADCOG_NO_CACHE=1 computes afresh)",
        file=sys.stderr,
    )


def _build_report(
    args: argparse.Namespace,
    result: ModelMassProperties,
    configs: Sequence[Configuration] = (),
) -> MassReport:
    try:
        return build_mass_report(
            result,
            about=args.about,
            axes=args.axes,
            form_factor=args.form_factor,
            cog_limits_mm=args.cog_limits_mm,
            configurations=configs,
            configurations_source=str(args.configurations or ""),
        )
    except ValueError as exc:
        raise CadcogError(f"--about/--axes: {exc}") from None


def emit(
    args: argparse.Namespace,
    result: ModelMassProperties,
    model: Callable[[], StepModel],
    configs: Sequence[Configuration] = (),
) -> None:
    """Every output the command line asks for: report, CSV, then JSON or text on stdout
    (``model()`` reads the model, for the HTML report's views)."""
    report = _build_report(args, result, configs)
    if args.configurations is not None:  # moved parts that overlap others (cached by content)
        from cadcog.spacecraft.configurations import report_overlaps

        report = report_overlaps(
            report,
            configs,
            model,
            args.model,
            args.configurations,
            units=args.units,
            strict=args.strict,
        )
    if args.report is not None:
        from cadcog.reports.massprops_report import write_mass_report

        page = write_mass_report(report, model, args.report, cache_files=_model_files(args))
        wrote(page)
    if args.csv is not None:
        from cadcog.reports.budget_csv import write_budget_csv

        wrote(write_budget_csv(report, args.csv))
    if args.json:
        print_json(report.to_dict())
    else:
        print_report(report, args.depth, args.products, args.collapse_below_percent / 100.0)
        print_configurations(report)


def emit_refusal(
    args: argparse.Namespace,
    refusal: str,
    as_is: ModelMassProperties | None,
    model: Callable[[], StepModel],
    policy: str,
    configs: Sequence[Configuration] = (),
) -> None:
    """On a refusal, still write what ``--json``/``--report``/``--csv`` asked for.

    The JSON holds ``"refused": {"error": ..., "exit_status": 2}`` and, when the model can be
    counted as it is (each solid whole, notes not errors), the full result of that count with
    ``"refused"["counted_as"]`` saying so; the report and the CSV show that count under the
    refusal. The command still exits 2.
    """
    refused: dict[str, Any] = {"error": refusal, "exit_status": 2}
    report = None
    if as_is is not None:
        refused["counted_as"] = (
            "each solid as it is (--allow-overlap), notes not errors: what was refused"
            if policy == "check"
            else "notes not errors (without --strict): what was refused"
        )
        try:
            report = _build_report(args, as_is, configs)
        except CadcogError:
            report = None
    if report is not None and args.report is not None:
        from cadcog.reports.massprops_report import write_mass_report

        page = write_mass_report(
            report, model, args.report, refusal=refusal, cache_files=_model_files(args)
        )
        wrote(page)
    if report is not None and args.csv is not None:
        from cadcog.reports.budget_csv import write_budget_csv

        wrote(write_budget_csv(report, args.csv))
    if args.json:
        data = {"refused": refused, **(report.to_dict() if report is not None else {})}
        print_json(data)
