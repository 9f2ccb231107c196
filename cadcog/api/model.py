"""Reading a rig or a set-up, and a STEP model's mass properties: ``cadcog massprops``."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Literal

from cadcog.api._checks import (
    _fail,
    _flags,
    _numbers,
    _path,
    _public,
)
from cadcog.core.arguments import check_choice, check_text
from cadcog.core.errors import CadcogError

if TYPE_CHECKING:
    from cadcog.rig.parameters import Rig
    from cadcog.spacecraft.configurations import Configuration
    from cadcog.spacecraft.mass_summary import MassReport
    from cadcog.spacecraft.setup import Setup


@_public
def load_rig(path: str | Path | None = None) -> Rig:
    """A rig from its parameter file (TOML), or the paper's rig.

    Parameters
    ----------
    path : str or Path, optional
        The rig file (``docs/rig.md`` documents it); ``None`` for the rig of the paper.

    Returns
    -------
    Rig
        Validated: impossible rigs raise :class:`~cadcog.core.errors.ParameterFileError`
        naming the file and key.

    Examples
    --------
    >>> import cadcog
    >>> rig = cadcog.load_rig()
    >>> rig.name, len(rig.suspension_points), len(rig.me_volumes)
    ('paper_rig', 6, 4)
    """
    from cadcog.rig.file import default_rig_path
    from cadcog.rig.file import load_rig as _load_rig

    return _load_rig(default_rig_path() if path is None else _path("load_rig", "path", path))


@_public
def load_setup(path: str | Path) -> Setup:
    """A spacecraft's test set-up file: model, measurement equipment, candidate points.

    ``docs/spacecraft.md`` documents the file; ``parts/cubesat_3u_setup.toml`` is an example.
    """
    from cadcog.spacecraft.setup import load_setup as _load_setup

    return _load_setup(_path("load_setup", "path", path))


@_public
def mass_properties(
    model: str | Path,
    materials: str | Path | None = None,
    *,
    density_kg_m3: float | None = None,
    total_mass_kg: float | None = None,
    units: str | None = None,
    exclude: str | Sequence[str] = (),
    overlaps: Literal["check", "allow", "resolve", "skip"] = "check",
    strict: bool = False,
    about: str | Sequence[float] = "cog",
    axes: str = "+x,+y,+z",
    form_factor: str | None = None,
    cog_limits_mm: Sequence[float] | None = None,
    workers: int | None = None,
    surface_area: bool = False,
    configurations: str | Path | None = None,
) -> MassReport:
    """Mass properties of a STEP file, solid by solid, with a mass budget (``cadcog massprops``).

    Each solid is integrated exactly by OCCT at its global placement, given the density its
    material rule assigns, and combined by mass; overlapping solids are refused unless
    ``overlaps`` says what to do. The result (or the refusal) is cached by the content of the
    files and every option that changes it, shared with the command (``docs/performance.md``,
    "The mass-properties cache"; ``CADCOG_NO_CACHE=1`` turns it off): a second call on
    unchanged files reads no CAD.

    Parameters
    ----------
    model : str or Path
        A STEP file (part or assembly, any exporter; its declared unit is converted to mm).
    materials : str or Path, optional
        Materials file (TOML): name patterns → material or density (``docs/spacecraft.md``).
    density_kg_m3 : float, optional
        One density for every solid, instead of a materials file.
    total_mass_kg : float, optional
        Scale the densities so the total matches a weighing.
    units : str, optional
        The file's true length unit when its declared one is wrong (never scales twice).
    exclude : str or sequence of str
        Glob patterns or paths of bodies or assemblies to leave out (before every check).
    overlaps : {'check', 'allow', 'resolve', 'skip'}
        Refuse overlapping solids, count them as they are, cut each common volume out of
        the less dense solid, or skip the overlap search altogether (``--skip-overlaps``: for
        a model you know has none).
    strict : bool
        Every note (surfaces left out, overlaps counted, units) becomes an error.
    about : str or sequence of 3 floats
        Reference point of the inertia frame reported: ``'cog'``, ``'origin'``, ``'centre'``
        (of the bounding box) or X, Y, Z in mm.
    axes : str
        Axes of that frame as signed model axes, such as ``'+y,-x,+z'``.
    form_factor : str, optional
        Check the CubeSat CoG envelope of this form factor (``'1U'`` … ``'12U'``).
    cog_limits_mm : sequence of 3 floats, optional
        A custom CoG envelope (half-widths, mm).
    workers : int, optional
        Processes for integration and overlap checks (default: the CPUs available).
    surface_area : bool
        Also every body's face area and each budget node's sum (``--surface-area``:
        ``surface_area_mm2``; for insulation blankets and coatings).
    configurations : str or Path, optional
        A configurations file (``--configurations``): each configuration's mass, CoG, inertia,
        uncertainty, envelope and the moved parts that would overlap others.

    Returns
    -------
    MassReport
        Total mass properties, budget tree, inertia in the frame, envelope check, notes.

    Raises
    ------
    cadcog.cad.massresults.Refusal
        Overlaps above the threshold under ``'check'``, or a note under ``strict``; a
        :class:`~cadcog.core.errors.CadcogError` whose ``as_is`` is the model counted as what
        was refused allows (each solid as it is; notes not errors), as ``--json`` writes it.
    CadcogError
        Any other bad input, naming the file (an open solid, a file OCCT cannot read...).

    Examples
    --------
    ``docs/tutorial.md`` runs it on a STEP file it writes (a test runs the tutorial):

    >>> import cadcog
    >>> report = cadcog.mass_properties(  # doctest: +SKIP
    ...     "sat.step", "materials.toml", form_factor="3U"
    ... )
    >>> report.result.total.mass_kg, report.result.total.cog_mm  # doctest: +SKIP
    """
    from cadcog.cad.cache import step_mass_properties
    from cadcog.core.gcpause import gc_paused
    from cadcog.core.parallel import available_workers
    from cadcog.spacecraft.mass_summary import build_mass_report

    f = "mass_properties"
    check_choice(f, "overlaps", overlaps, ("check", "allow", "resolve", "skip"))
    if form_factor is not None:
        from cadcog.spacecraft.envelope import CDS_COG_LIMITS_MM

        check_choice(f, "form_factor", form_factor, tuple(CDS_COG_LIMITS_MM))
    check_text(f, "axes", axes, "'+y,-x,+z'")
    if materials is not None and density_kg_m3 is not None:
        raise CadcogError(f"{f}: give either materials or density_kg_m3, not both")
    _numbers(f, density_kg_m3=density_kg_m3, total_mass_kg=total_mass_kg, workers=workers)
    _flags(f, strict=strict, surface_area=surface_area)
    if total_mass_kg is not None and not total_mass_kg > 0:
        raise _fail(f, "total_mass_kg", total_mass_kg, "expected a positive mass")
    if cog_limits_mm is not None:
        _numbers(f, cog_limits_mm=list(cog_limits_mm))
        if len(cog_limits_mm) != 3 or min(cog_limits_mm) <= 0:
            raise _fail(f, "cog_limits_mm", cog_limits_mm, "expected three positive half-widths")
    patterns = [exclude] if isinstance(exclude, str) else list(exclude)  # one pattern, not letters
    if not all(isinstance(p, str) for p in patterns):
        raise _fail(f, "exclude", exclude, "expected a pattern or a list of patterns (str)")
    configs: tuple[Configuration, ...] = ()
    config_path = None
    if configurations is not None:
        from cadcog.spacecraft.configurations import load_configurations

        config_path = _path(f, "configurations", configurations)
        configs = load_configurations(config_path)
    with gc_paused():  # a bounded computation keeping ~10⁶ objects alive (core/gcpause.py)
        result, _ = step_mass_properties(
            _path(f, "model", model),
            None if materials is None else _path(f, "materials", materials),
            density_kg_m3=density_kg_m3,
            total_mass_kg=total_mass_kg,
            units=units,
            exclude=patterns,
            overlaps=overlaps,
            strict=strict,
            surface_areas=bool(surface_area),
            workers=workers or available_workers(),
        )
        try:
            report = build_mass_report(
                result,
                about=about,
                axes=axes,
                form_factor=form_factor,
                cog_limits_mm=cog_limits_mm,
                configurations=configs,
                configurations_source=str(config_path or ""),
            )
        except ValueError as exc:
            raise _fail(f, "about/axes", (about, axes), str(exc)) from None
        if config_path is not None:
            from cadcog.cad.stepread import read_step
            from cadcog.spacecraft.configurations import report_overlaps

            model_path = _path(f, "model", model)
            report = report_overlaps(
                report,
                configs,
                lambda: read_step(model_path),
                model_path,
                config_path,
                units=units,
                strict=strict,
            )
        return report


def _rig(function: str, rig: Rig | str | Path | None) -> Rig:
    from cadcog.rig.parameters import Rig

    if isinstance(rig, Rig):
        return rig
    return load_rig(None if rig is None else _path(function, "rig", rig))


def _setup(function: str, setup: Setup | str | Path) -> Setup:
    from cadcog.spacecraft.setup import Setup

    if isinstance(setup, Setup):
        return setup
    return load_setup(_path(function, "setup", setup))
