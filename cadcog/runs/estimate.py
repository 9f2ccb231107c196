"""The CoG from a readings file: the one composition behind ``cadcog estimate`` and
:func:`cadcog.estimate`.

Three cases, as the command's options choose them: a spacecraft set-up (its inclinometer,
error model and ME, compared with its CAD), a rig (its proof mass, the ME compensated), or
neither (the hung assembly's CoG with the default inclinometer; the ME given by the caller, if
any, removed). The readings are read with the inclinometer of the case; a combination of
options and data the estimator refuses is an error naming the readings file.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from cadcog.core import tolerances
from cadcog.core.errors import named_by

if TYPE_CHECKING:
    from cadcog.method.cogestimate import CogEstimate
    from cadcog.method.medata import MEData
    from cadcog.rig.parameters import Rig
    from cadcog.spacecraft.setup import Setup


def estimate_from_file(
    readings: str | Path,
    *,
    rig: Rig | None = None,
    setup: Setup | None = None,
    me: MEData | None = None,
    wire_correction: bool = True,
    self_calibrate: bool = False,
    weighed_mass_kg: float | None = None,
    mass_sigma_kg: float = tolerances.DEFAULT_WEIGHING_SIGMA_KG,
    angle_sigma_deg: float | None = None,
    point_sigma_mm: float | None = None,
    min_angle_deg: float = tolerances.MIN_PAIR_ANGLE_DEG,
) -> CogEstimate:
    """The CoG estimate of a readings CSV for a set-up, a rig, or neither.

    Parameters
    ----------
    readings : str or Path
        The readings CSV (``docs/estimate.md``).
    rig, setup : optional
        At most one (the caller checks): what was hung.
    me : MEData, optional
        Without a rig or a set-up: the ME to remove (the command line's masses and CoG).
    wire_correction, self_calibrate, weighed_mass_kg, mass_sigma_kg, angle_sigma_deg,
    point_sigma_mm, min_angle_deg
        As :func:`cadcog.method.estimate.estimate_for_rig`; the weighing only with a rig or a
        set-up.

    Raises
    ------
    CadcogError
        The readings file's own errors as they are; a ValueError of the estimator (options and
        data it cannot combine, a hang it refuses by its line) as one naming ``readings``.
    DegenerateGeometryError
        Hangs that do not determine the CoG.
    """
    from cadcog.method.estimate import estimate_cog, estimate_for_rig
    from cadcog.method.readings import read_readings
    from cadcog.rig.inclinometer import InclinometerConfig
    from cadcog.spacecraft.setup import estimate_for_setup

    config = (
        setup.rig.inclinometer
        if setup is not None
        else rig.inclinometer
        if rig is not None
        else InclinometerConfig()
    )
    suspensions = read_readings(readings, config)  # its errors name the file and line
    with named_by(readings):  # refusals of the hangs name their file
        if setup is not None:
            return estimate_for_setup(
                setup,
                suspensions,
                wire_correction=wire_correction,
                self_calibrate=self_calibrate,
                angle_sigma_deg=angle_sigma_deg,
                point_sigma_mm=point_sigma_mm,
                min_angle_deg=min_angle_deg,
                compare=True,
                weighed_mass_kg=weighed_mass_kg,
                mass_sigma_kg=mass_sigma_kg,
            )
        if rig is not None:
            return estimate_for_rig(
                rig,
                suspensions,
                weighed_mass_kg=weighed_mass_kg,
                mass_sigma_kg=mass_sigma_kg,
                wire_correction=wire_correction,
                self_calibrate=self_calibrate,
                angle_sigma_deg=angle_sigma_deg,
                point_sigma_mm=point_sigma_mm,
                min_angle_deg=min_angle_deg,
            )
        return estimate_cog(
            suspensions,
            config,
            me,
            wire_correction=wire_correction,
            self_calibrate=self_calibrate,
            angle_sigma_deg=angle_sigma_deg,
            point_sigma_mm=point_sigma_mm,
            min_angle_deg=min_angle_deg,
        )
