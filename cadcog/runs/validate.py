"""The one composition behind ``cadcog validate`` and ``cadcog.validate``.

:func:`validate_readings` reads a campaign's readings CSV with the rig's inclinometer, refuses
fewer than three suspension points, and runs
:func:`~cadcog.validation.verification.validate_campaign`. The command
(:mod:`cadcog.cli.validate`) and the API (:func:`cadcog.api.validate`) each check their own
arguments, in their own words, then call it: the two cannot compose the validation
differently.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from cadcog.core.errors import CadcogError
from cadcog.method.foreignhangs import refuse_foreign_hangs
from cadcog.method.readings import read_readings
from cadcog.rig.parameters import Rig
from cadcog.validation.verification import CampaignValidation, validate_campaign

#: Fewest suspension points a campaign is validated from (three pairs of plumb lines).
MIN_POINTS = 3


def validate_readings(
    rig: Rig,
    readings: Path,
    windows_mm: Sequence[float],
    *,
    campaigns: int,
    seed: int,
    level: float,
) -> CampaignValidation:
    """A measured campaign (its readings CSV) against ``campaigns`` simulated whole campaigns.

    Parameters
    ----------
    rig : Rig
        The rig that was hung: its inclinometer reads the file, its proof mass is the truth.
    readings : Path
        Readings CSV of the campaign (:data:`MIN_POINTS` or more suspension points).
    windows_mm : sequence of float
        Error windows ε (mm), positive.
    campaigns : int
        Simulated whole campaigns for the null distribution.
    seed : int
        Seed of those simulations.
    level : float
        False-alarm rate of the campaign verdict, in (0, 1).

    Returns
    -------
    CampaignValidation
        ``to_dict()`` is ``cadcog validate --json``.

    Raises
    ------
    CadcogError
        The file cannot be read, holds fewer than :data:`MIN_POINTS` points, or the
        validation refuses its data; the message names the file.
    """
    suspensions = read_readings(readings, rig.inclinometer)
    refuse_foreign_hangs(rig, suspensions, readings)
    if len(suspensions) < MIN_POINTS:
        raise CadcogError(
            f"{readings}: validation needs {MIN_POINTS} or more suspension points, got "
            f"{len(suspensions)}"
        )
    try:
        return validate_campaign(
            rig, suspensions, tuple(windows_mm), n_campaigns=campaigns, seed=seed, level=level
        )
    except CadcogError:
        raise
    except ValueError as exc:
        raise CadcogError(f"{readings}: {exc}") from None
