"""The CoG, the tensor and the CAD updated from a test: ``cadcog estimate``, ``inertia``,
``update``."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from cadcog.api._checks import (
    _as_user_error,
    _fail,
    _flags,
    _given,
    _numbers,
    _path,
    _public,
    _weighing,
)
from cadcog.api.model import _rig, _setup
from cadcog.core import tolerances
from cadcog.core.errors import CadcogError

if TYPE_CHECKING:
    from cadcog.dynamics.result import InertiaResult
    from cadcog.method.cogestimate import CogEstimate
    from cadcog.rig.parameters import Rig
    from cadcog.spacecraft.setup import Setup
    from cadcog.spacecraft.update import UpdateResult


@_public
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
    from cadcog.runs.estimate import estimate_from_file

    f = "estimate"
    path = _path(f, "readings", readings)
    _flags(f, wire_correction=wire_correction, self_calibrate_wire=self_calibrate_wire)
    if setup is not None and rig is not None:
        raise CadcogError(f"{f}: give rig or setup, not both (a set-up names its rig)")
    _weighing(f, weighed_mass_kg, mass_sigma_kg)
    if weighed_mass_kg is not None and setup is None and rig is None:
        raise CadcogError(f"{f}: weighed_mass_kg needs a rig or a set-up (the ME to remove)")
    return estimate_from_file(
        path,
        rig=None if rig is None else _rig(f, rig),
        setup=None if setup is None else _setup(f, setup),
        wire_correction=wire_correction,
        self_calibrate=self_calibrate_wire,
        weighed_mass_kg=weighed_mass_kg,
        mass_sigma_kg=mass_sigma_kg,
    )


@_public
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
    >>> from cadcog.dynamics.context import context_for_rig
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
    from cadcog.runs.inertia import inertia_from_files

    f = "inertia"
    swings_path = _path(f, "swings", swings)
    readings_path = _path(f, "readings", readings)
    if setup is not None and rig is not None:
        raise CadcogError(f"{f}: give rig or setup, not both (a set-up names its rig)")
    _weighing(f, weighed_mass_kg, mass_sigma_kg)
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


@_public
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
    from cadcog.runs.update import update_from_files
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
