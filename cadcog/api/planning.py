"""Decisions from the model: ``cadcog plan``, ``check``, ``balance``."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Literal

from cadcog.api._checks import (
    _fail,
    _flags,
    _given,
    _numbers,
    _path,
    _public,
)
from cadcog.api.model import _setup
from cadcog.core.arguments import check_choice

if TYPE_CHECKING:
    from cadcog.spacecraft.balance_result import BalanceResult
    from cadcog.spacecraft.plan import Plan
    from cadcog.spacecraft.requirements import CheckResult
    from cadcog.spacecraft.setup import Setup


@_public
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
    _flags(f, weighing=weighing)
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


@_public
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

    _flags("check", strict=strict)
    return check_requirements(_path("check", "requirements", requirements), strict=strict)


@_public
def balance(
    ballast: str | Path,
    model: str | Path | None = None,
    materials: str | Path | None = None,
    *,
    setup: Setup | str | Path | None = None,
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
    setup : Setup, str or Path, optional
        A set-up (or its file) instead of a model (its envelope is the default).
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
    if isinstance(ballast, (str, Path)) and Path(ballast).suffix.lower() in (".step", ".stp"):
        raise _fail(  # the command's order (MODEL --ballast FILE) is not the function's
            f,
            "ballast",
            ballast,
            "a STEP model; the ballast file (TOML) comes first: "
            "balance(ballast, model, materials) or balance(ballast, setup=...)",
        )
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
        setup=None if setup is None else _setup_path(f, setup),
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


def _setup_path(function: str, setup: Setup | str | Path) -> Path:
    """The set-up file a balance reads: a :class:`~cadcog.spacecraft.setup.Setup`'s own, as
    ``plan``, ``estimate`` and ``update`` accept one, or a path."""
    from cadcog.spacecraft.setup import Setup

    if isinstance(setup, Setup):
        return Path(setup.source)
    return _path(function, "setup", setup)
