"""``cadcog/runs/update.py``: the update's own checks come before any file is read, and a file
it cannot use is named."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cadcog.core.errors import CadcogError
from cadcog.runs.update import update_from_files
from cadcog.spacecraft.explanations import UnmodelledPrior

READINGS = Path(__file__).resolve().parents[2] / "docs" / "examples" / "cubesat_3u_readings.csv"
BOX = (np.full(3, -50.0), np.full(3, 50.0))


@pytest.mark.parametrize(
    ("mass_kg", "sigma_kg", "option"),
    [(3.0, 0.1, "--unmodelled-mass-kg 3"), (0.0, 2.7, "--unmodelled-sigma-kg 2.7")],
)
def test_an_unmodelled_mass_heavier_than_the_weighing_is_refused_before_reading(
    cubesat_setup, tmp_path, mass_kg, sigma_kg, option
):
    """A prior of kilograms in a 2.6 kg CubeSat is a unit slip: refused naming the option,
    before the readings (which do not exist here) are read."""
    prior = UnmodelledPrior(*BOX, mass_kg, sigma_kg)
    with pytest.raises(CadcogError, match=rf"^{option}: more than the weighed 2\.6 kg"):
        update_from_files(cubesat_setup, tmp_path / "absent.csv", 2.6, mass_sigma_kg=0.001,
                          unmodelled=prior, swings=None)  # fmt: skip


def test_a_prior_as_heavy_as_the_weighing_is_taken(cubesat_setup):
    result, estimate = update_from_files(
        cubesat_setup, READINGS, 2.6, mass_sigma_kg=0.001,
        unmodelled=UnmodelledPrior(*BOX, 0.0, 2.6), swings=None,
    )  # fmt: skip
    data = result.to_dict()
    assert estimate.compensation is not None and data["unmodelled"] is not None
    assert abs(sum(x["probability"] for x in data["explanations"]) - 1.0) < 1e-9


def test_readings_of_one_hang_are_refused_naming_the_file(cubesat_setup, tmp_path):
    text = READINGS.read_text(encoding="utf-8").splitlines(keepends=True)
    one = tmp_path / "one.csv"
    one.write_text(
        "".join(x for x in text if x.startswith(("#", "point_id")) or x.startswith(text[-1][:8]))
    )
    with pytest.raises(CadcogError, match=r"one\.csv"):
        update_from_files(cubesat_setup, one, 2.6, mass_sigma_kg=0.001, unmodelled=None,
                          swings=None)  # fmt: skip
