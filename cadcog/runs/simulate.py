"""The one composition behind ``cadcog simulate`` and ``cadcog.simulate``.

:func:`simulate_rig` turns the command's options into the error model and the settings of
:func:`~cadcog.uncertainty.random_points.run_simulation` and runs it. The command
(:mod:`cadcog.cli.simulate`) and the API (:func:`cadcog.api.simulate`) each check their own
arguments (in their own words: ``--points 1`` or ``simulate(points=1)``), then call it, so
that the two cannot compose the simulation differently.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

from cadcog.method.errormodel import ErrorModel
from cadcog.rig.parameters import InclinometerModel, Rig, WireModel
from cadcog.uncertainty.random_points import SimulationReport, SimulationSettings, run_simulation


def simulate_rig(
    rig: Rig,
    *,
    points: int,
    trials: int,
    seed: int,
    group_size: int,
    min_angle_deg: float,
    wire_correction: bool,
    paper: bool,
    workers: int,
    self_calibrate_wire: bool = False,
    samples: int | None = None,
    inclinometer_model: InclinometerModel | None = None,
    wire_model: WireModel | None = None,
    progress: Callable[[int], None] | None = None,
    total: Callable[[int], None] | None = None,
) -> SimulationReport:
    """The Monte Carlo of ``rig`` as ``cadcog simulate`` runs it, from checked arguments.

    Parameters
    ----------
    rig : Rig
    points : int
        Random suspension points (0: the rig's own points).
    trials : int
        Simulated campaigns, each one trial of every pair or group.
    seed : int
        Root seed.
    group_size : int
        2: pairs; K > 2: the joint estimate over K points.
    min_angle_deg : float
        Groups whose plumb lines meet at less than this are left out (degrees).
    wire_correction : bool
        Correct each point for the expected wire offset (off with ``paper``).
    paper : bool
        The paper's Monte Carlo: its error model (averaged inclinometer model, no sensor
        noise), equal weights (eq. 8) and no wire correction.
    workers : int
        Processes.
    self_calibrate_wire : bool
        Estimate the wire offset scale with the CoG (groups of 3 or more).
    samples : int, optional
        Readings averaged per suspension (default: the rig's).
    inclinometer_model, wire_model : str, optional
        Override the rig's (:data:`~cadcog.rig.parameters.INCLINOMETER_MODELS`,
        :data:`~cadcog.rig.parameters.WIRE_MODELS`).
    progress, total
        Progress callbacks of :func:`~cadcog.uncertainty.random_points.run_simulation`.

    Returns
    -------
    SimulationReport
        ``to_dict()`` is ``cadcog simulate --json``.

    Raises
    ------
    ValueError
        Settings the simulation refuses (no group conditioned well enough, no group that
        identifies the wire scale...); each caller says it in its words.
    """
    model = ErrorModel.from_rig(rig)
    if paper:
        model = model.paper()
    if samples is not None:
        model = replace(model, samples=samples)
    if inclinometer_model is not None:
        model = replace(model, inclinometer_model=inclinometer_model)
    if wire_model is not None:
        model = replace(model, wire_model=wire_model)
    settings = SimulationSettings(
        points,
        trials,
        seed,
        group_size,
        min_angle_deg,
        weighted=not paper,
        wire_correction=wire_correction and not paper,
        self_calibrate=self_calibrate_wire,
    )
    return run_simulation(rig, settings, model, workers=workers, progress=progress, total=total)
