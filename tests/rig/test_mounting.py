"""The ME base must touch the model (issue 21: a base 10 m from a 340 mm spacecraft)."""

from __future__ import annotations

import pytest

from cadcog.core import tolerances
from cadcog.rig.mounting import me_base_problem

LO, HI = (-50.0, -50.0, -170.25), (50.0, 50.0, 170.25)  # a 3U CubeSat's box


@pytest.mark.parametrize(
    "base",
    [(0.0, 0.0, 170.25), (0.0, 0.0, -170.25), (50.0, 0.0, 0.0), (0.0, 0.0, 170.25 + 49.9)],
)
def test_a_base_on_or_near_the_model_is_accepted(base):
    assert me_base_problem(base, LO, HI) is None


def test_a_base_ten_metres_away_is_refused_with_the_distance():
    problem = me_base_problem((0.0, 0.0, 10_000.0), LO, HI)
    assert problem is not None
    assert "9829.75 mm away" in problem and "[-50, -50, -170.25] … [50, 50, 170.25] mm" in problem


def test_the_gap_is_measured_to_the_box_not_to_its_centre():
    corner_gap = tolerances.ME_BASE_MAX_GAP_MM / 3**0.5 * 1.01  # just over, diagonally
    base = (50.0 + corner_gap, 50.0 + corner_gap, 170.25 + corner_gap)
    assert me_base_problem(base, LO, HI) is not None
    assert me_base_problem((50.0, 50.0, 170.25 + 0.99 * 50.0), LO, HI) is None
