"""A set-up drafted and a test run: ``cadcog setup init``, ``acquire`` (``--log``)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from cadcog.api._checks import (
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
    from cadcog.runs.acquire import AcquireRun
    from cadcog.runs.acquire_log import LogRun
    from cadcog.runs.setup_init import SetupDraft
    from cadcog.spacecraft.setup import Setup


@_public
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
    _flags("setup_init", force=force)
    return run_setup_init(
        _path("setup_init", "model", model),
        out=None if out is None else _path("setup_init", "out", out),
        units=units,
        force=force,
    )


@_public
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
    duration_s: float | None = None,
) -> AcquireRun | LogRun:
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
        A serial port instead of the simulated device. A set-up whose sensor is an accelerometer
        is recorded whole into a log beside ``out`` (``NAME.log.csv``), then cut as
        :func:`acquire_log` cuts it (``cadcog acquire --port`` with an accelerometer; its swings
        written only when ``swings`` is given).
    seed : int
        The simulated device's seed.
    device : "analog" or "digital"
        The simulated device's kind.
    time_scale : float
        Simulated seconds per real second.
    report : str or Path, optional
        A folder for the record page.
    duration_s : float, optional
        An accelerometer's recording: stop after this long (device time); default until
        Ctrl-C (KeyboardInterrupt; a device that falls silent for 5 s is an error, and the
        samples so far are not kept).

    Returns
    -------
    AcquireRun or LogRun
        The estimate, its comparison with the CAD, the inertia from the swings (or why none);
        ``to_dict()`` is the command's ``--json``. A recorded accelerometer's: a LogRun.
    """
    from cadcog.runs.acquire import Simulation, run_acquire

    f = "acquire"
    _numbers(f, seed=seed, time_scale=time_scale, duration_s=duration_s)
    if duration_s is not None and not (np.isfinite(duration_s) and duration_s > 0):
        raise CadcogError(f"acquire: duration_s must be positive, got {duration_s}")
    check_choice(f, "device", device, ("analog", "digital"))
    out_path = _path(f, "out", out)
    target = _target(f, rig, setup, points)
    if port is not None and target.inclinometer.accelerometer:
        from cadcog.runs.acquire_log import acquire_recorded, log_path_for

        if report is not None:
            raise CadcogError("acquire: report is not written from an accelerometer's recording")
        return acquire_recorded(
            target,
            port,
            out_path,
            log_path_for(out_path),
            duration_s=duration_s,
            swings=None if swings is None else _path(f, "swings", swings),
        )
    if duration_s is not None:
        raise CadcogError("acquire: duration_s is for an accelerometer's recording from a port")
    return run_acquire(
        target,
        out_path,
        swings=None if swings is None else _path(f, "swings", swings),
        port=port,
        simulation=None if port is not None else Simulation(device, None, seed, time_scale),
        report=None if report is None else _path(f, "report", report),
    )


@_public
def acquire_log(
    log: str | Path,
    out: str | Path,
    *,
    rig: Rig | str | Path | None = None,
    setup: Setup | str | Path | None = None,
    points: Sequence[str] | None = None,
    log_format: Literal["phyphox", "csv"] = "phyphox",
    average_s: float = 10.0,
    swings: str | Path | None = None,
) -> LogRun:
    """A test from a recorded accelerometer log (``cadcog acquire --log``): a phone's phyphox
    export or a ``t_s,ax,ay,az`` CSV, cut into the hangs of ``points`` in that order, written
    to the readings CSV ``out`` and estimated from it (and, with ``swings``, each hang's swing
    written there and the inertia tensor estimated from it).

    Parameters
    ----------
    log : str or Path
        The recorded log.
    out : str or Path
        The readings CSV to write.
    rig, setup : optional
        The rig (default: the paper's) or a set-up; its ``[inclinometer]`` must declare
        ``device = "accelerometer"``.
    points : sequence of str, optional
        The hangs, in the order the log holds them (default: every rig point; a set-up needs
        them).
    log_format : "phyphox" or "csv"
    average_s : float
        A settled stretch shorter than this is not a hang.
    swings : str or Path, optional
        A new swing CSV for ``cadcog inertia``: each hang's samples from just after its release
        to the end of its undisturbed decay, in object-axis angles (docs/bench.md §8).

    Returns
    -------
    LogRun
        The hangs found (their time spans), the estimate, and (set-ups) its comparison with
        the CAD; with ``swings``, ``inertia`` (or ``inertia_note``: why there is none);
        ``to_dict()`` is the command's ``--json``.
    """
    from cadcog.bench.accellog import LOG_FORMATS
    from cadcog.runs.acquire_log import acquire_log as run_log

    f = "acquire_log"
    _numbers(f, average_s=average_s)
    check_choice(f, "log_format", log_format, LOG_FORMATS)
    target = _target(f, rig, setup, points, set_up_needs_points=True)
    return run_log(
        target,
        _path(f, "log", log),
        _path(f, "out", out),
        fmt=log_format,
        min_average_s=average_s,
        swings=None if swings is None else _path(f, "swings", swings),
    )


def _target(
    f: str,
    rig: Rig | str | Path | None,
    setup: Setup | str | Path | None,
    points: Sequence[str] | None,
    *,
    set_up_needs_points: bool = False,
) -> Any:
    """The hangs of a run (:func:`cadcog.runs.acquire.acquire_target`), the arguments checked
    as ``f``'s (``set_up_needs_points``: a log's hangs are in the order they were made)."""
    from cadcog.runs.acquire import acquire_target

    if setup is not None and rig is not None:
        raise CadcogError(f"{f}: give rig or setup, not both (a set-up names its rig)")
    if set_up_needs_points and setup is not None and points is None:
        raise CadcogError(f"{f}: a set-up needs points, the hangs in the order they were made")
    _point_ids(f, points)
    return acquire_target(
        rig=None if setup is not None else _rig(f, rig),
        setup=None if setup is None else _setup(f, setup),
        points=points,
    )
