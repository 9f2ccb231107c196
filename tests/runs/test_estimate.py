"""``cadcog/runs/estimate.py``: the three cases of ``cadcog estimate`` composed once.

The ME removed from the hung assembly's CoG is eq. 10 in closed form; the lines' fit does not
depend on whether an ME is given; and a refusal of the estimator names the readings file.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cadcog.core.errors import CadcogError
from cadcog.method.medata import MEData
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.runs.estimate import estimate_from_file

EXAMPLES = Path(__file__).resolve().parents[2] / "docs" / "examples"
READINGS = EXAMPLES / "paper_rig_readings.csv"


def _me(object_mass_kg: float, me_mass_kg: float, me_cog_mm) -> MEData:
    return MEData(object_mass_kg, me_mass_kg, np.asarray(me_cog_mm, float), np.zeros((3, 3)), "t")


@pytest.mark.parametrize(
    ("object_mass_kg", "me_mass_kg", "me_cog_mm"),
    [(9.2, 0.176, (101.65, 37.5, 112.16)), (2.6, 0.4, (-5.0, 3.0, 60.0)), (1.0, 1e-3, (0, 0, 0))],
)
def test_the_me_removed_is_eq_10_in_closed_form(object_mass_kg, me_mass_kg, me_cog_mm):
    bare = estimate_from_file(READINGS)
    est = estimate_from_file(READINGS, me=_me(object_mass_kg, me_mass_kg, me_cog_mm))
    assert bare.compensation is None
    np.testing.assert_array_equal(est.assembly_cog_mm, bare.assembly_cog_mm)
    total = object_mass_kg + me_mass_kg
    expected = (total * bare.assembly_cog_mm - me_mass_kg * np.asarray(me_cog_mm)) / object_mass_kg
    assert est.compensation is not None
    np.testing.assert_allclose(est.compensation.cog_mm, expected, rtol=0, atol=1e-9)
    # the ME's CoG known exactly: the object's covariance is the assembly's scaled by (M/m)²
    np.testing.assert_allclose(
        est.compensation.cov_mm2, (total / object_mass_kg) ** 2 * bare.joint.cov_mm2, rtol=1e-9
    )


def test_a_rig_reads_with_its_own_inclinometer_and_removes_its_own_me():
    rig = load_rig(default_rig_path())
    est = estimate_from_file(READINGS, rig=rig)
    me = MEData.from_rig(rig)
    assert est.compensation is not None and est.compensation.object_mass_source == "rig"
    total = me.object_mass_kg + me.me_mass_kg
    expected = (total * est.assembly_cog_mm - me.me_mass_kg * me.me_cog_mm) / me.object_mass_kg
    np.testing.assert_allclose(est.compensation.cog_mm, expected, rtol=0, atol=1e-9)


def test_a_hang_the_estimator_refuses_is_an_error_naming_the_readings(tmp_path):
    one = tmp_path / "one_hang.csv"
    lines = READINGS.read_text(encoding="utf-8").splitlines(keepends=True)
    one.write_text(
        "".join(line for line in lines if not line.startswith(("S2", "S3", "S4", "S5", "S6")))
    )
    with pytest.raises(CadcogError, match=r"one_hang\.csv"):
        estimate_from_file(one)
