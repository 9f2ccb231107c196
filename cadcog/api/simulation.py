"""The method's error, a test validated, a virtual test: ``cadcog simulate``, ``validate``,
``campaign``."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from cadcog.api._checks import (
    _as_user_error,
    _fail,
    _flags,
    _numbers,
    _path,
    _point_ids,
    _public,
)
from cadcog.api.model import _rig, _setup
from cadcog.core.arguments import check_choice
from cadcog.core.errors import CadcogError

if TYPE_CHECKING:
    from cadcog.rig.parameters import Rig
    from cadcog.runs.campaign import CampaignRun
    from cadcog.spacecraft.setup import Setup
    from cadcog.uncertainty.random_points import SimulationReport
    from cadcog.validation.verification import CampaignValidation


@_public
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
    from cadcog.runs.simulate import simulate_rig

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
    _flags(f, wire_correction=wire_correction, paper=paper, self_calibrate_wire=self_calibrate_wire)
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


@_public
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
    from cadcog.runs.validate import validate_readings
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


@_public
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
