"""The one composition behind ``cadcog update`` and ``cadcog.update``, from their files.

:func:`update_from_files` reads the readings CSV with the set-up's inclinometer, the swing CSV
when one is given (its tensor observed with the mass and the CoG, :mod:`cadcog.dynamics.measure`)
and runs :func:`cadcog.spacecraft.setup.update_for_setup`. It sits here, above
:mod:`cadcog.spacecraft`, because the swings need the dynamics layer. The command
(:mod:`cadcog.cli.update`) and the API (:func:`cadcog.api.update`) each check their own
arguments, in their own words, then call it.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from cadcog.core.errors import CadcogError, DegenerateGeometryError, named_by
from cadcog.method.readings import read_readings
from cadcog.spacecraft.setup import Setup, update_for_setup

if TYPE_CHECKING:
    from cadcog.method.cogestimate import CogEstimate
    from cadcog.spacecraft.update import UnmodelledPrior, UpdateResult


def update_from_files(
    setup: Setup,
    readings: Path,
    weighed_mass_kg: float,
    *,
    mass_sigma_kg: float,
    unmodelled: UnmodelledPrior | None,
    swings: Path | None,
) -> tuple[UpdateResult, CogEstimate]:
    """What the test's files and the weighing say about the CAD, from checked arguments.

    Parameters
    ----------
    setup : Setup
    readings : Path
        Readings CSV of the suspension test.
    weighed_mass_kg : float
        The spacecraft's weighed mass without the measurement equipment (kg, > 0).
    mass_sigma_kg : float
        1 σ of the weighing (kg, > 0).
    unmodelled : UnmodelledPrior, optional
        The user's region for an unmodelled mass, with its prior.
    swings : Path, optional
        The same hangs' swing CSV: its inertia tensor is observed too.

    Returns
    -------
    (UpdateResult, CogEstimate)
        The update (``to_dict()`` is ``cadcog update --json``) and the estimate it started
        from (its warnings, the report's figure).

    Raises
    ------
    CadcogError
        A file the update cannot use (a ValueError from reading it or from the update),
        named in the message: the swing CSV for its own errors, else the readings CSV.
    """
    _check_unmodelled(unmodelled, weighed_mass_kg)
    with named_by(readings):
        suspensions = read_readings(readings, setup.rig.inclinometer)
    inertia = None
    notes: list[str] = []
    if swings is not None:
        from cadcog.dynamics.measure import inertia_observation

        try:
            with named_by(swings):
                inertia = inertia_observation(
                    setup,
                    swings,
                    suspensions,
                    weighed_mass_kg=float(weighed_mass_kg),
                    mass_sigma_kg=float(mass_sigma_kg),
                )
        except DegenerateGeometryError as exc:  # the swings measure no tensor: update without
            notes.append(f"the swings were not used, they give no inertia: {exc}")  # names them
    with named_by(readings):
        result, estimate = update_for_setup(
            setup,
            suspensions,
            float(weighed_mass_kg),
            mass_sigma_kg=float(mass_sigma_kg),
            unmodelled=unmodelled,
            inertia=inertia,
        )
    return replace(result, notes=(*result.notes, *notes)), estimate


def _check_unmodelled(unmodelled: UnmodelledPrior | None, weighed_mass_kg: float) -> None:
    """An unmodelled mass is part of the weighed spacecraft: its prior mean and 1 σ cannot
    exceed the weighing (a prior of 100 kg in a 2.6 kg CubeSat is a unit slip, and the update
    would "find" it).

    Raises
    ------
    CadcogError
        Naming the option and the weighed mass.
    """
    if unmodelled is None:
        return
    for option, value in (
        ("--unmodelled-mass-kg", unmodelled.mass_kg),
        ("--unmodelled-sigma-kg", unmodelled.sigma_kg),
    ):
        if value > weighed_mass_kg:
            raise CadcogError(
                f"{option} {value:g}: more than the weighed {weighed_mass_kg:g} kg spacecraft "
                "it is part of (is it in kg?)"
            )
