"""cadcog from Python: the main entry points, each returning the result object the CLI prints.

Every function here is what one command does, without the printing: it reads the same files,
applies the same defaults (``tests/test_api.py`` compares them with the parsers') and returns
the same object, whose ``to_dict()`` is the command's ``--json`` and ``to_json()`` its text.
Errors are the same too: a bad file or value raises :class:`~cadcog.core.errors.CadcogError`
(its subclasses name the file, line or key), which the command prints in one line.

Lengths are mm, masses kg, angles degrees, inertia kg·mm² (the names say so).

Import them from :mod:`cadcog` itself (``cadcog.simulate``): importing cadcog stays fast, and
each function imports what it needs (the CAD layer, build123d, only for CAD work).

Examples
--------
>>> import cadcog
>>> rig = cadcog.load_rig()  # the paper's rig
>>> rig.name
'paper_rig'
>>> report = cadcog.simulate(rig, points=0, trials=200, seed=1)
>>> report.fits.n > 0
True
"""

from __future__ import annotations

import functools
import numbers
import os
import threading
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, TypeVar

from cadcog.core import tolerances
from cadcog.core.arguments import check_choice, check_text
from cadcog.core.errors import CadcogError

if TYPE_CHECKING:
    from cadcog.dynamics.result import InertiaResult
    from cadcog.method.estimate import CogEstimate
    from cadcog.rig.parameters import Rig
    from cadcog.runs.acquire import AcquireRun
    from cadcog.runs.campaign import CampaignRun
    from cadcog.runs.setup_init import SetupDraft
    from cadcog.spacecraft.balance import BalanceResult
    from cadcog.spacecraft.configurations import Configuration
    from cadcog.spacecraft.mass_summary import MassReport
    from cadcog.spacecraft.plan import Plan
    from cadcog.spacecraft.requirements import CheckResult
    from cadcog.spacecraft.setup import Setup
    from cadcog.spacecraft.update import UpdateResult
    from cadcog.uncertainty.random_points import SimulationReport
    from cadcog.validation.verification import CampaignValidation

_F = TypeVar("_F", bound=Callable[..., Any])


class _BlasLimit:
    """One BLAS thread while any entry point runs, however many run at once (threads) or
    inside each other: the limit is process-wide (threadpoolctl), so it is set when the first
    call enters and restored when the last one leaves, never by a call that ends while another
    still runs."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._depth = 0
        self._limiter: Any = None

    def __enter__(self) -> None:
        with self._lock:
            if self._depth == 0:
                from threadpoolctl import threadpool_limits

                self._limiter = threadpool_limits(limits=1, user_api="blas")
            self._depth += 1

    def __exit__(self, *exc: object) -> None:
        with self._lock:
            self._depth -= 1
            if self._depth == 0 and self._limiter is not None:
                self._limiter.restore_original_limits()
                self._limiter = None


_BLAS_LIMIT = _BlasLimit()


def _one_blas_thread(function: _F) -> _F:
    """Run ``function`` with the BLAS libraries' thread pools limited to one thread, as the
    console command runs (:data:`cadcog.cli.BLAS_THREAD_VARIABLES`): cadcog's matrices are
    small, and a default pool of many threads made ``update`` 9× slower from Python than from
    the command. The limit holds for the whole process while any entry point runs. A limit the
    user set in the environment wins, as it does for the command."""
    from cadcog.cli import BLAS_THREAD_VARIABLES

    @functools.wraps(function)
    def limited(*args: Any, **kwargs: Any) -> Any:
        if any(name in os.environ for name in BLAS_THREAD_VARIABLES):
            return function(*args, **kwargs)
        with _BLAS_LIMIT:
            return function(*args, **kwargs)

    return limited  # type: ignore[return-value]


__all__ = [
    "acquire",
    "balance",
    "campaign",
    "check",
    "estimate",
    "inertia",
    "load_rig",
    "load_setup",
    "mass_properties",
    "plan",
    "setup_init",
    "simulate",
    "update",
    "validate",
]


def _fail(function: str, name: str, value: object, expected: str) -> CadcogError:
    """The one-line error about argument ``name`` of ``function``."""
    shown = repr(value)
    if len(shown) > 60:
        shown = shown[:57] + "..."
    return CadcogError(f"{function}({name}={shown}): {expected}")


def _numbers(function: str, **values: object) -> None:
    """The checks the command line applies to its numeric options (types, then the bounds of
    :mod:`cadcog.core.bounds`, by the same names), for keyword arguments."""
    from cadcog.core import bounds

    for name, value in values.items():
        if value is None:
            continue
        items = list(value) if isinstance(value, (list, tuple)) else [value]
        bound = bounds.bound_for(name)
        for v in items:
            if isinstance(v, bool) or not isinstance(v, numbers.Real):  # numpy's count too
                raise _fail(function, name, value, f"expected a number, got {type(v).__name__}")
            if bound is not None and bound.integer and not isinstance(v, numbers.Integral):
                raise _fail(function, name, value, "expected an integer")
            problem = bounds.check(name, float(v))
            if problem is not None:
                raise _fail(function, name, value, problem)


def _given(function: str, **values: object) -> None:
    """Arguments that have no default meaning for None (a mass, a σ): None is refused as the
    command refuses an empty option, not left to fail as a TypeError deep inside."""
    for name, value in values.items():
        if value is None:
            raise _fail(function, name, value, "expected a number, got None")


def _point_ids(function: str, points: Sequence[str] | None) -> None:
    """``points``: None, or a sequence of point ids (a string alone is refused: its letters
    are not ids)."""
    if points is not None and (
        isinstance(points, str) or not all(isinstance(p, str) for p in points)
    ):
        raise _fail(function, "points", points, "expected a sequence of point ids (str)")


def _positive(function: str, **values: float | None) -> None:
    """Masses and σ that must be > 0 (the bounds allow 0)."""
    for name, value in values.items():
        if value is not None and not value > 0:
            raise _fail(function, name, value, "expected a positive number")


def _path(function: str, name: str, value: object) -> Path:
    """A file argument: a str or path-like, else a clear error (with the keyword it may be)."""
    if isinstance(value, (str, os.PathLike)):
        return Path(value)
    kind = type(value).__name__
    hint = {"Setup": " (a set-up goes in setup=)", "Rig": " (a rig goes in rig=)"}.get(kind, "")
    raise _fail(function, name, value, f"expected a file path (str or Path), got {kind}{hint}")


def _as_user_error(function: str, source: object, exc: ValueError) -> CadcogError:
    """A ValueError about the data (not the arguments), as the command reports it."""
    return CadcogError(f"{source}: {exc}" if source is not None else f"{function}: {exc}")


@_one_blas_thread
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


@_one_blas_thread
def load_setup(path: str | Path) -> Setup:
    """A spacecraft's test set-up file: model, measurement equipment, candidate points.

    ``docs/spacecraft.md`` documents the file; ``parts/cubesat_3u_setup.toml`` is an example.
    """
    from cadcog.spacecraft.setup import load_setup as _load_setup

    return _load_setup(_path("load_setup", "path", path))


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


@_one_blas_thread
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
    check_text(f, "axes", axes, "'+y,-x,+z'")
    if materials is not None and density_kg_m3 is not None:
        raise CadcogError(f"{f}: give either materials or density_kg_m3, not both")
    _numbers(f, density_kg_m3=density_kg_m3, total_mass_kg=total_mass_kg, workers=workers)
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


@_one_blas_thread
def estimate(
    readings: str | Path,
    rig: Rig | str | Path | None = None,
    *,
    setup: Setup | str | Path | None = None,
    wire_correction: bool = True,
    self_calibrate_wire: bool = False,
    weighed_mass_kg: float | None = None,
    mass_sigma_kg: float = tolerances.DEFAULT_WEIGHING_SIGMA_KG,
) -> CogEstimate:
    """The compensated CoG from a readings CSV (``cadcog estimate --rig`` or ``--setup``).

    Parameters
    ----------
    readings : str or Path
        Readings CSV: one row per inclinometer sample (``docs/estimate.md``).
    rig : Rig, str or Path, optional
        The rig that was hung: its inclinometer, error model, bolt axes and measurement
        equipment, which is compensated. Without ``rig`` or ``setup``, as the command without
        ``--rig``: the CoG of the hung assembly, ME included, with the default inclinometer and
        isotropic line weights.
    setup : Setup, str or Path, optional
        A spacecraft set-up instead of a rig: its inclinometer, error model and ME.
    wire_correction : bool
        Correct each point for the expected wire offset (default, as the command).
    self_calibrate_wire : bool
        Estimate the wire offset scale with the CoG (3 or more hangs).
    weighed_mass_kg : float, optional
        With a rig or a set-up: the object's weighed mass (without the ME), used to remove the
        ME (``--weighed-mass-kg``). Without it a set-up's CAD mass is used, and its own
        uncertainty carried into the CoG's covariance.
    mass_sigma_kg : float
        1 σ of the weighing (default 1 g).

    Returns
    -------
    CogEstimate
        The CoG (mm), its covariance (mm²), the per-line diagnostics and warnings; with a
        set-up, ``.cad`` compares it with the CAD's CoG (both covariances) and the CubeSat
        envelope.

    Examples
    --------
    A virtual campaign on the paper's rig, written as a lab would record it, then estimated:

    >>> import tempfile, pathlib, cadcog
    >>> from cadcog.validation.campaign import virtual_campaign, write_campaign
    >>> rig = cadcog.load_rig()
    >>> csv = pathlib.Path(tempfile.mkdtemp()) / "campaign.csv"
    >>> write_campaign(csv, virtual_campaign(rig, seed=1))
    >>> est = cadcog.estimate(csv, rig)
    >>> error_mm = est.cog_mm - rig.analytic_proof_mass.cog_mm
    >>> bool((error_mm**2).sum() ** 0.5 < 3.0), est.cov_mm2.shape
    (True, (3, 3))
    """
    from cadcog.method.estimate import estimate_cog, estimate_for_rig
    from cadcog.method.readings import read_readings
    from cadcog.spacecraft.setup import estimate_for_setup

    f = "estimate"
    path = _path(f, "readings", readings)
    if setup is not None and rig is not None:
        raise CadcogError(f"{f}: give rig or setup, not both (a set-up names its rig)")
    _given(f, mass_sigma_kg=mass_sigma_kg)
    _numbers(f, weighed_mass_kg=weighed_mass_kg, mass_sigma_kg=mass_sigma_kg)
    _positive(f, weighed_mass_kg=weighed_mass_kg, mass_sigma_kg=mass_sigma_kg)
    if weighed_mass_kg is not None and setup is None and rig is None:
        raise CadcogError(f"{f}: weighed_mass_kg needs a rig or a set-up (the ME to remove)")
    try:
        if setup is not None:
            s = _setup(f, setup)
            return estimate_for_setup(
                s,
                read_readings(path, s.rig.inclinometer),
                wire_correction=wire_correction,
                self_calibrate=self_calibrate_wire,
                compare=True,
                weighed_mass_kg=weighed_mass_kg,
                mass_sigma_kg=mass_sigma_kg,
            )
        if rig is None:
            from cadcog.rig.inclinometer import InclinometerConfig

            config = InclinometerConfig()
            return estimate_cog(
                read_readings(path, config),
                config,
                None,
                wire_correction=wire_correction,
                self_calibrate=self_calibrate_wire,
            )
        r = _rig(f, rig)
        return estimate_for_rig(
            r,
            read_readings(path, r.inclinometer),
            weighed_mass_kg=weighed_mass_kg,
            mass_sigma_kg=mass_sigma_kg,
            wire_correction=wire_correction,
            self_calibrate=self_calibrate_wire,
        )
    except CadcogError:
        raise
    except ValueError as exc:  # a combination of options and data the estimator refuses
        raise _as_user_error(f, path, exc) from None


@_one_blas_thread
def inertia(
    swings: str | Path,
    readings: str | Path,
    *,
    rig: Rig | str | Path | None = None,
    setup: Setup | str | Path | None = None,
    weighed_mass_kg: float | None = None,
    mass_sigma_kg: float = tolerances.DEFAULT_WEIGHING_SIGMA_KG,
) -> InertiaResult:
    """The object's inertia tensor about its CoG from its hangs' swings
    (``cadcog inertia``; ``docs/inertia.md``).

    Parameters
    ----------
    swings : str or Path
        Swing CSV (``point_id,t_s,inc_x_deg,inc_y_deg``): each hang's samples from release to
        settle, at least three hangs.
    readings : str or Path
        Readings CSV of the same hangs (settled): the CoG, so each pivot's distance.
    rig : Rig, str or Path, optional
        The rig that was hung (default: the paper's, when no set-up is given).
    setup : Setup, str or Path, optional
        A spacecraft set-up instead: its CAD, ME, inclinometer and ``[swing]`` table.
    weighed_mass_kg : float, optional
        The object's weighed mass without the ME (default: the CAD's or the rig's).
    mass_sigma_kg : float
        1 σ of the weighing (default 1 g).

    Returns
    -------
    InertiaResult
        The tensor (kg·mm², tensor convention) and the covariance of its six entries, principal
        moments and axes with their σ, each hang's frequencies, the χ² of the fit, the
        variance budget and the comparison with the CAD.

    Examples
    --------
    A virtual campaign of the paper's rig with its swings, then the tensor from it:

    >>> import tempfile, pathlib, cadcog
    >>> from cadcog.validation.campaign import (
    ...     campaign_suspensions, virtual_campaign, write_campaign)
    >>> from cadcog.dynamics.measure import context_for_rig
    >>> from cadcog.dynamics.swingfile import write_swings
    >>> from cadcog.dynamics.virtual import virtual_swings
    >>> rig = cadcog.load_rig()
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> campaign = virtual_campaign(rig, seed=1)
    >>> write_campaign(folder / "campaign.csv", campaign)
    >>> hangs = campaign_suspensions(campaign, rig.inclinometer)
    >>> write_swings(folder / "swings.csv", virtual_swings(context_for_rig(rig), hangs, seed=1))
    >>> r = cadcog.inertia(folder / "swings.csv", folder / "campaign.csv", rig=rig)
    >>> truth = rig.analytic_proof_mass.inertia_kg_mm2
    >>> bool(abs(r.inertia_kg_mm2[0, 0] - truth[0, 0]) < 4 * r.sigma_kg_mm2[0, 0])
    True
    """
    from cadcog.dynamics.measure import inertia_from_files

    f = "inertia"
    swings_path = _path(f, "swings", swings)
    readings_path = _path(f, "readings", readings)
    if setup is not None and rig is not None:
        raise CadcogError(f"{f}: give rig or setup, not both (a set-up names its rig)")
    _given(f, mass_sigma_kg=mass_sigma_kg)
    _numbers(f, weighed_mass_kg=weighed_mass_kg, mass_sigma_kg=mass_sigma_kg)
    _positive(f, weighed_mass_kg=weighed_mass_kg, mass_sigma_kg=mass_sigma_kg)
    try:
        return inertia_from_files(
            swings_path,
            readings_path,
            rig=None if setup is not None else _rig(f, rig),
            setup=None if setup is None else _setup(f, setup),
            weighed_mass_kg=weighed_mass_kg,
            mass_sigma_kg=mass_sigma_kg,
        )
    except CadcogError:
        raise
    except ValueError as exc:
        raise _as_user_error(f, swings_path, exc) from None


@_one_blas_thread
def simulate(
    rig: Rig | str | Path | None = None,
    *,
    points: int = 25,
    trials: int = 1000,
    seed: int = 0,
    group_size: int = 2,
    min_angle_deg: float = 0.0,
    wire_correction: bool = True,
    paper: bool = False,
    workers: int = 1,
    self_calibrate_wire: bool = False,
    samples: int | None = None,
    inclinometer_model: str | None = None,
    wire_model: str | None = None,
) -> SimulationReport:
    """The Monte Carlo of the method over random suspension points (``cadcog simulate``).

    Parameters
    ----------
    rig : Rig, str or Path, optional
        The rig (default: the paper's).
    points : int
        Random suspension points drawn on the proof mass (0: the rig's own points).
    trials : int
        Simulated campaigns; each gives one trial of every pair (or group) of points.
    seed : int
        Root seed: the same seed gives the same result whatever ``workers``.
    group_size : int
        2: pairs by eq. 8 as the paper; K > 2: the joint estimate over K points.
    min_angle_deg : float
        Leave out groups whose plumb lines meet at less than this.
    wire_correction : bool
        Correct each point for the expected wire offset, as ``estimate`` does.
    paper : bool
        The paper's Monte Carlo: averaged inclinometer model, no sensor noise, equal weights,
        no wire correction.
    workers : int
        Processes.
    self_calibrate_wire : bool
        Estimate the wire offset scale with the CoG (groups of 3 or more, with the correction).
    samples : int, optional
        Readings averaged per suspension (default: the rig's).
    inclinometer_model : str, optional
        Inclinometer error model, one of ``cadcog.rig.parameters.INCLINOMETER_MODELS``
        (default: the rig's).
    wire_model : str, optional
        Wire offset model, one of ``cadcog.rig.parameters.WIRE_MODELS`` (default: the rig's).

    Returns
    -------
    SimulationReport
        Error statistics, Rayleigh/Maxwell fits and the error budget.

    Examples
    --------
    >>> import cadcog
    >>> r = cadcog.simulate(points=0, trials=500, seed=3)
    >>> 0.0 < r.fits.q50_mm < 5.0
    True
    """
    from cadcog.rig.parameters import INCLINOMETER_MODELS, WIRE_MODELS
    from cadcog.uncertainty.simulate_rig import simulate_rig

    f = "simulate"
    numbers: dict[str, Any] = {  # checked here, then passed on as they are
        "points": points,
        "trials": trials,
        "seed": seed,
        "group_size": group_size,
        "min_angle_deg": min_angle_deg,
        "workers": workers,
    }
    _numbers(f, **numbers)
    if points == 1:
        raise _fail(f, "points", points, "give 0 (the rig's own points) or at least 2")
    if samples is not None:
        _numbers(f, samples=samples)
    if inclinometer_model is not None:
        check_choice(f, "inclinometer_model", inclinometer_model, INCLINOMETER_MODELS)
    if wire_model is not None:
        check_choice(f, "wire_model", wire_model, WIRE_MODELS)
    if self_calibrate_wire and (paper or group_size < 3 or not wire_correction):
        raise _fail(
            f,
            "self_calibrate_wire",
            self_calibrate_wire,
            "needs group_size 3 or more and wire_correction, and not paper",
        )
    try:
        return simulate_rig(
            _rig(f, rig),
            **numbers,
            wire_correction=wire_correction,
            paper=paper,
            self_calibrate_wire=self_calibrate_wire,
            samples=samples,
            inclinometer_model=inclinometer_model,  # type: ignore[arg-type]
            wire_model=wire_model,  # type: ignore[arg-type]
        )
    except CadcogError:
        raise
    except ValueError as exc:
        raise _as_user_error(f, None, exc) from None


@_one_blas_thread
def validate(
    readings: str | Path,
    rig: Rig | str | Path | None = None,
    *,
    windows_mm: Sequence[float] | None = None,
    campaigns: int = 2000,
    seed: int = 0,
    level: float = 0.05,
) -> CampaignValidation:
    """Does a campaign's scatter match the Monte Carlo's prediction (``cadcog validate``)?

    The Bernoulli check of docs/method.md §6 per window, and one campaign verdict with a
    false-alarm rate of ``level`` against ``campaigns`` simulated whole campaigns.

    Parameters
    ----------
    readings : str or Path
        Readings CSV of the campaign (3 or more suspension points).
    rig : Rig, str or Path, optional
        The rig (default: the paper's).
    windows_mm : sequence of float, optional
        Error windows ε (mm); default those of the command, 0.5, 1, 1.5, 2 and 3 mm.
    campaigns : int
        Simulated whole campaigns for the null distribution (at least 20).
    seed : int
        Seed of those simulations.
    level : float
        False-alarm rate of the verdict, in (0, 1).

    Returns
    -------
    CampaignValidation
        The per-window table, the campaign verdict (``.consistent``) and its null distribution.
    """
    from cadcog.validation.validate_readings import validate_readings
    from cadcog.validation.verification import DEFAULT_WINDOWS_MM

    f = "validate"
    path = _path(f, "readings", readings)
    _numbers(f, campaigns=campaigns, seed=seed, level=level)
    if campaigns < 20:
        raise _fail(f, "campaigns", campaigns, "expected at least 20 (a null distribution)")
    if windows_mm is not None:
        if isinstance(windows_mm, (str, bytes)) or not isinstance(windows_mm, Sequence):
            raise _fail(f, "windows_mm", windows_mm, "expected a sequence of numbers (mm)")
        _numbers(f, windows_mm=list(windows_mm))
        if not windows_mm or min(windows_mm) <= 0:
            raise _fail(f, "windows_mm", windows_mm, "expected positive windows (mm)")
    return validate_readings(
        _rig(f, rig),
        path,
        DEFAULT_WINDOWS_MM if windows_mm is None else windows_mm,
        campaigns=campaigns,
        seed=seed,
        level=level,
    )


@_one_blas_thread
def update(
    readings: str | Path,
    setup: Setup | str | Path,
    weighed_mass_kg: float,
    *,
    mass_sigma_kg: float = tolerances.DEFAULT_WEIGHING_SIGMA_KG,
    unmodelled_region_mm: Sequence[float] | None = None,
    unmodelled_mass_kg: float = 0.0,
    unmodelled_sigma_kg: float | None = None,
    swings: str | Path | None = None,
) -> UpdateResult:
    """What the test and the weighing say about the CAD (``cadcog update``).

    Parameters
    ----------
    readings : str or Path
        Readings CSV of the suspension test.
    setup : Setup, str or Path
        The spacecraft's set-up (or its file).
    weighed_mass_kg : float
        The spacecraft's weighed mass, without the measurement equipment.
    mass_sigma_kg : float
        1 σ of the weighing (default 1 g).
    unmodelled_region_mm : sequence of 6 floats, optional
        ``(x0, y0, z0, x1, y1, z1)``: a box where an unmodelled mass (harness, fasteners) may
        be; needs ``unmodelled_sigma_kg``.
    unmodelled_mass_kg : float
        Its prior mean (default 0).
    unmodelled_sigma_kg : float, optional
        Its prior 1 σ (needed with a region).
    swings : str or Path, optional
        The same hangs' swing CSV (``--swings``): the inertia tensor it measures
        (:func:`inertia`) is observed too, and constrains the same items.

    Returns
    -------
    UpdateResult
        The verdicts (``differs``, ``consistent``, ``model_rejected``), the explanations with
        their probabilities, each item's change, the unmodelled mass, and the revised mass,
        CoG and inertia with their covariance (``docs/spacecraft.md``).
    """
    from cadcog.dynamics.update_files import update_from_files
    from cadcog.spacecraft.update import unmodelled_from_region

    f = "update"
    path = _path(f, "readings", readings)
    _given(
        f,
        weighed_mass_kg=weighed_mass_kg,
        mass_sigma_kg=mass_sigma_kg,
        unmodelled_mass_kg=unmodelled_mass_kg,
    )
    _numbers(
        f,
        weighed_mass_kg=weighed_mass_kg,
        mass_sigma_kg=mass_sigma_kg,
        unmodelled_mass_kg=unmodelled_mass_kg,
        unmodelled_sigma_kg=unmodelled_sigma_kg,
    )
    _positive(f, weighed_mass_kg=weighed_mass_kg, mass_sigma_kg=mass_sigma_kg)
    _positive(f, unmodelled_sigma_kg=unmodelled_sigma_kg)
    region = None
    if unmodelled_region_mm is not None:
        region = (
            list(unmodelled_region_mm) if isinstance(unmodelled_region_mm, (list, tuple)) else []
        )
        if len(region) != 6:
            raise _fail(f, "unmodelled_region_mm", unmodelled_region_mm, "expected six numbers")
        _numbers(f, unmodelled_region_mm=region)
    try:
        prior = unmodelled_from_region(region, float(unmodelled_mass_kg), unmodelled_sigma_kg)
    except ValueError as exc:
        raise _fail(f, "unmodelled_region_mm", unmodelled_region_mm, str(exc)) from None
    swings_path = None if swings is None else _path(f, "swings", swings)
    result, _ = update_from_files(
        _setup(f, setup),
        path,
        float(weighed_mass_kg),
        mass_sigma_kg=float(mass_sigma_kg),
        unmodelled=prior,
        swings=swings_path,
    )
    return result


@_one_blas_thread
def plan(
    setup: Setup | str | Path,
    *,
    trials: int = 10_000,
    max_set: int = 4,
    seed: int = 0,
    goal: Literal["cog", "inertia", "both"] = "cog",
    weighing: bool = True,
    max_inertia_set: int = 8,
) -> Plan:
    """Which candidate points to hang a spacecraft from (``cadcog plan``).

    Parameters
    ----------
    setup : Setup, str or Path
        The set-up (or its file).
    trials : int
        Monte Carlo trials per finalist set.
    max_set : int
        Largest set of hangs considered (2 to 8).
    seed : int
        Seed of the Monte Carlo of the finalists.
    goal : "cog", "inertia" or "both"
        What the hangs should determine best (``--for``): the CoG, the inertia tensor from
        their swings, or both (the CoG's set, grown for the inertia).
    weighing : bool
        Plan the inertia with a 1 g weighing (else the CAD's mass uncertainty).
    max_inertia_set : int
        Largest set of hangs for the inertia.

    Returns
    -------
    Plan
        The recommended set, the finalists with their predicted errors, and the candidates
        that cannot be used (with why); with a ``goal`` other than the CoG, ``inertia`` (the
        hangs for the tensor) or ``inertia_refused`` (why none).
    """
    from cadcog.runs.plan import run_plan

    f = "plan"
    _numbers(f, trials=trials, max_set=max_set, seed=seed, max_inertia_set=max_inertia_set)
    check_choice(f, "goal", goal, ("cog", "inertia", "both"))
    return run_plan(
        _setup(f, setup),
        trials=trials,
        max_set=max_set,
        seed=seed,
        goal=goal,
        weighed=bool(weighing),
        max_inertia_set=max_inertia_set,
    )


@_one_blas_thread
def check(requirements: str | Path, *, strict: bool = False) -> CheckResult:
    """Check a model against its mass-properties requirements (``cadcog check``).

    Parameters
    ----------
    requirements : str or Path
        The requirements file (``docs/ci.md``); it names the model and, optionally, a baseline.
    strict : bool
        A note about the model is an error.

    Returns
    -------
    CheckResult
        One result per requirement; ``.passed`` when all hold.
    """
    from cadcog.spacecraft.requirements import check_requirements

    return check_requirements(_path("check", "requirements", requirements), strict=strict)


@_one_blas_thread
def campaign(
    out: str | Path,
    *,
    rig: Rig | str | Path | None = None,
    setup: Setup | str | Path | None = None,
    points: Sequence[str] | None = None,
    seed: int = 0,
    samples: int | None = None,
    noise_deg: float | None = None,
    swings: str | Path | None = None,
) -> CampaignRun:
    """Simulate a test campaign and write it as a lab would record it (``cadcog campaign``).

    Parameters
    ----------
    out : str or Path
        The readings CSV to write.
    rig : Rig, str or Path, optional
        The rig (or its file): one hang per suspension point (default: the paper's rig).
    setup : Setup, str or Path, optional
        A spacecraft's set-up instead, hanging from ``points`` (candidate ids).
    seed : int
    samples : int, optional
        Raw samples per hang (default: the error model's).
    noise_deg : float, optional
        Sensor noise of one sample (default: the error model's).
    swings : str or Path, optional
        Also write each hang's swing (a swing CSV for :func:`inertia`).

    Returns
    -------
    CampaignRun
        What was written; ``to_dict()`` is the command's ``--json``.
    """
    from cadcog.runs.campaign import run_campaign

    _numbers("campaign", seed=seed, samples=samples, noise_deg=noise_deg)
    out_path = _path("campaign", "out", out)
    swings_path = None if swings is None else _path("campaign", "swings", swings)
    if setup is not None and rig is not None:
        raise _fail("campaign", "rig", rig, "give a rig or a set-up, not both")
    _point_ids("campaign", points)
    return run_campaign(
        out_path,
        rig=None if setup is not None else _rig("campaign", rig),
        setup=None if setup is None else _setup("campaign", setup),
        points=points,
        seed=seed,
        samples=samples,
        noise_deg=noise_deg,
        swings=swings_path,
    )


@_one_blas_thread
def balance(
    ballast: str | Path,
    model: str | Path | None = None,
    materials: str | Path | None = None,
    *,
    setup: str | Path | None = None,
    units: str | None = None,
    form_factor: str | None = None,
    cog_limits_mm: Sequence[float] | None = None,
    confidence: float = 0.95,
    readings: str | Path | None = None,
    weighed_mass_kg: float | None = None,
    mass_sigma_kg: float | None = None,
    workers: int | None = None,
    configurations: str | Path | None = None,
    overlaps: Literal["check", "allow", "resolve"] = "check",
    max_product_kg_mm2: float | None = None,
    max_axis_angle_deg: float | None = None,
    inertia_confidence: float | None = None,
) -> BalanceResult:
    """The least ballast that puts the CoG inside its envelope with at least ``confidence``
    (``cadcog balance``; :mod:`cadcog.spacecraft.balance` says how).

    Parameters
    ----------
    ballast : str or Path
        The ballast file (TOML: ``[[points]]`` with ``id``, ``position_mm``, optional
        ``max_mass_kg``; optional ``sizes_kg`` and ``max_total_mass_kg``).
    model : str or Path, optional
        A STEP model (the CAD's mass, CoG and stated uncertainty).
    materials : str or Path, optional
        The model's materials file (densities and ``[mass_uncertainty]``).
    setup : str or Path, optional
        A set-up file instead of a model (its envelope is the default).
    units : str, optional
        The model's true length unit.
    form_factor : str, optional
        The envelope of a CubeSat or PocketQube form factor (``'1U'`` ... ``'3p'``).
    cog_limits_mm : sequence of 3 floats, optional
        Envelope half-widths (mm).
    confidence : float
        Least probability that the CoG is inside the whole envelope, in (0, 1).
    readings : str or Path, optional
        With ``setup`` and ``weighed_mass_kg``: balance what ``update`` makes of the test.
    weighed_mass_kg : float, optional
        The weighed mass, without the measurement equipment (kg).
    mass_sigma_kg : float, optional
        1 σ of the weighing (kg, default 1 g; with ``readings``).
    workers : int, optional
        Processes for the mass properties (default: the CPUs available).
    configurations : str or Path, optional
        A configurations file: the same ballast must meet the envelope in each configuration.
    overlaps : {'check', 'allow', 'resolve'}
        A model's overlapping solids, as :func:`mass_properties`'s.
    max_product_kg_mm2 : float, optional
        Inertia objective: each product of inertia about the new CoG within ± this (kg·mm²).
    max_axis_angle_deg : float, optional
        Inertia objective: each pair of principal axes turned at most this from the model's
        axes (degrees, below 45).
    inertia_confidence : float, optional
        Least probability that the inertia objectives hold (default ``confidence``);
        :mod:`cadcog.spacecraft.balance_inertia` says how.

    Returns
    -------
    BalanceResult
        ``to_dict()`` is the command's ``--json``; ``feasible`` False with ``shortfall`` when no
        ballast within the file's limits meets the envelope.
    """
    from cadcog.core.parallel import available_workers
    from cadcog.runs.balance import MAX_CONFIDENCE, MIN_CONFIDENCE, run_balance

    f = "balance"
    _given(f, confidence=confidence)
    _numbers(
        f,
        confidence=confidence,
        weighed_mass_kg=weighed_mass_kg,
        mass_sigma_kg=mass_sigma_kg,
        workers=workers,
        max_product_kg_mm2=max_product_kg_mm2,
        max_axis_angle_deg=max_axis_angle_deg,
        inertia_confidence=inertia_confidence,
    )
    _positive(f, weighed_mass_kg=weighed_mass_kg, mass_sigma_kg=mass_sigma_kg)
    check_choice(f, "overlaps", overlaps, ("check", "allow", "resolve"))
    if not MIN_CONFIDENCE <= confidence <= MAX_CONFIDENCE:
        raise _fail(
            f,
            "confidence",
            confidence,
            f"expected a probability from {MIN_CONFIDENCE} to {MAX_CONFIDENCE}",
        )
    if mass_sigma_kg is not None and readings is None:
        raise _fail(f, "mass_sigma_kg", mass_sigma_kg, "goes with readings and weighed_mass_kg")
    if (readings is None) != (weighed_mass_kg is None):
        raise _fail(f, "readings", readings, "goes with weighed_mass_kg (a test is weighed)")
    if readings is not None and setup is None:
        raise _fail(f, "readings", readings, "needs a setup (its measurement equipment)")
    limits = None
    if cog_limits_mm is not None:
        if isinstance(cog_limits_mm, str):
            raise _fail(f, "cog_limits_mm", cog_limits_mm, "expected three numbers, not a string")
        _numbers(f, cog_limits_mm=list(cog_limits_mm))
        if len(cog_limits_mm) != 3 or min(cog_limits_mm) <= 0:
            raise _fail(f, "cog_limits_mm", cog_limits_mm, "expected three positive half-widths")
        limits = (float(cog_limits_mm[0]), float(cog_limits_mm[1]), float(cog_limits_mm[2]))
    if (model is None) == (setup is None):
        raise _fail(f, "setup", setup, "give a model or a set-up (one of them)")
    if form_factor is not None and cog_limits_mm is not None:
        raise _fail(f, "form_factor", form_factor, "give form_factor or cog_limits_mm, not both")
    return run_balance(
        _path(f, "ballast", ballast),
        model=None if model is None else _path(f, "model", model),
        materials=None if materials is None else _path(f, "materials", materials),
        units=units,
        setup=None if setup is None else _path(f, "setup", setup),
        form_factor=form_factor,
        cog_limits_mm=limits,
        confidence=float(confidence),
        readings=None if readings is None else _path(f, "readings", readings),
        weighed_mass_kg=weighed_mass_kg,
        mass_sigma_kg=mass_sigma_kg,
        workers=workers or available_workers(),
        configurations=None
        if configurations is None
        else _path(f, "configurations", configurations),
        overlaps=overlaps,
        max_product_kg_mm2=max_product_kg_mm2,
        max_axis_angle_deg=max_axis_angle_deg,
        inertia_confidence=inertia_confidence,
    )


@_one_blas_thread
def setup_init(
    model: str | Path,
    *,
    out: str | Path | None = None,
    units: str | None = None,
    force: bool = False,
) -> SetupDraft:
    """Draft a set-up file and its materials file from a STEP model (``cadcog setup init``).

    Parameters
    ----------
    model : str or Path
        The STEP file.
    out : str or Path, optional
        The set-up file (default: ``MODEL_setup.toml`` beside the model); the materials file
        goes beside it.
    units : str, optional
        The file's true length unit, when its declared unit is wrong.
    force : bool
        Replace existing files.

    Returns
    -------
    SetupDraft
        The files written and what they hold; ``to_dict()`` is the command's ``--json``.
    """
    from cadcog.core.units import UNIT_CHOICES
    from cadcog.runs.setup_init import run_setup_init

    if units is not None:
        check_choice("setup_init", "units", units, UNIT_CHOICES)
    return run_setup_init(
        _path("setup_init", "model", model),
        out=None if out is None else _path("setup_init", "out", out),
        units=units,
        force=bool(force),
    )


@_one_blas_thread
def acquire(
    out: str | Path,
    *,
    rig: Rig | str | Path | None = None,
    setup: Setup | str | Path | None = None,
    points: Sequence[str] | None = None,
    swings: str | Path | None = None,
    port: str | None = None,
    seed: int = 0,
    device: Literal["analog", "digital"] = "analog",
    time_scale: float = 20.0,
    report: str | Path | None = None,
) -> AcquireRun:
    """A test run recorded into ``out`` (``cadcog acquire --non-interactive``): from a simulated
    device by default (``--simulate``: a dry run of the whole bench, as a notebook would run
    it), or from the serial ``port``. Every hang is appended durably: the same call resumes.

    Parameters
    ----------
    out : str or Path
        The readings CSV.
    rig : Rig, str or Path, optional
        The rig (default: the paper's).
    setup : Setup, str or Path, optional
        A spacecraft's set-up instead.
    points : sequence of str, optional
        The hangs, in order (default: every rig point, or the set ``plan`` recommends); each
        set-up point is checked as ``plan`` checks it before the first hang.
    swings : str or Path, optional
        The swing file (default: beside ``out``).
    port : str, optional
        A serial port instead of the simulated device.
    seed : int
        The simulated device's seed.
    device : "analog" or "digital"
        The simulated device's kind.
    time_scale : float
        Simulated seconds per real second.
    report : str or Path, optional
        A folder for the record page.

    Returns
    -------
    AcquireRun
        The estimate, its comparison with the CAD, the inertia from the swings (or why none);
        ``to_dict()`` is the command's ``--json``.
    """
    from cadcog.runs.acquire import Simulation, acquire_target, run_acquire

    f = "acquire"
    _numbers(f, seed=seed, time_scale=time_scale)
    check_choice(f, "device", device, ("analog", "digital"))
    out_path = _path(f, "out", out)
    if setup is not None and rig is not None:
        raise CadcogError(f"{f}: give rig or setup, not both (a set-up names its rig)")
    _point_ids(f, points)
    target = acquire_target(
        rig=None if setup is not None else _rig(f, rig),
        setup=None if setup is None else _setup(f, setup),
        points=points,
    )
    return run_acquire(
        target,
        out_path,
        swings=None if swings is None else _path(f, "swings", swings),
        port=port,
        simulation=None if port is not None else Simulation(device, None, seed, time_scale),
        report=None if report is None else _path(f, "report", report),
    )
