"""``cadcog/method/estimate.py``: the estimate behind ``cadcog estimate``, against closed forms.

The readings are made here from geometry alone (the upward vertical is the unit vector from the
CoG to the suspension point; eq. 2 read as ``x = asin(u_x)``, ``y = asin(u_y)``), not from
cadcog's forward model: noise-free readings give back the CoG they were made from, whatever
the points; the estimate does not depend on the order of the hangs; the covariance is the
error model's propagation, quadratic in the reading σ.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from cadcog.method.estimate import estimate_cog, estimate_for_rig
from cadcog.method.readings import suspension_from_samples

COORD = st.floats(-60.0, 60.0, allow_nan=False)
DIRECTION = st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(0.3, 1))


def _hangs(cog_mm, directions, radius_mm: float = 150.0):
    """A hang from ``cog + radius · d̂`` for each direction: its one noise-free sample."""
    out = []
    for i, d in enumerate(directions):
        u = np.asarray(d, float) / np.linalg.norm(d)
        p = np.asarray(cog_mm, float) + radius_mm * u
        x, y = math.degrees(math.asin(u[0])), math.degrees(math.asin(u[1]))
        out.append(suspension_from_samples(f"P{i}", tuple(p), bool(u[2] > 0), [x], [y], i + 2))
    return out


def _min_angle_deg(directions) -> float:
    u = [np.asarray(d, float) / np.linalg.norm(d) for d in directions]
    return min(
        math.degrees(math.acos(min(1.0, abs(float(a @ b)))))
        for i, a in enumerate(u)
        for b in u[i + 1 :]
    )


@settings(max_examples=60, deadline=None)
@given(st.tuples(COORD, COORD, COORD), st.lists(DIRECTION, min_size=2, max_size=6))
def test_noise_free_readings_give_back_the_cog_they_were_made_from(cog_mm, directions):
    assume(all(np.linalg.norm(d) > 0.3 for d in directions))
    assume(_min_angle_deg(directions) > 20.0)  # well-conditioned pairs (the estimator's own
    # screen refuses near-parallel ones, tested in test_plumblines)
    u = [np.asarray(d, float) / np.linalg.norm(d) for d in directions]
    assume(all(abs(math.degrees(math.asin(v[k]))) < 59.0 for v in u for k in (0, 1)))  # in range
    est = estimate_cog(_hangs(cog_mm, directions))
    np.testing.assert_allclose(est.assembly_cog_mm, cog_mm, rtol=0, atol=1e-8)
    assert est.compensation is None  # no ME given: said in the warnings
    assert any("not compensated" in w for w in est.warnings)


def test_the_order_of_the_hangs_does_not_matter():
    hangs = _hangs((3.0, -7.0, 12.0), [(1, 0, 1), (-1, 0.2, 1), (0, 1, 1), (0.3, -1, 1.2)])
    a, b = estimate_cog(hangs), estimate_cog(hangs[::-1])
    np.testing.assert_allclose(b.assembly_cog_mm, a.assembly_cog_mm, rtol=0, atol=1e-12)
    np.testing.assert_allclose(b.joint.cov_mm2, a.joint.cov_mm2, rtol=1e-12, atol=1e-15)


def test_the_covariance_is_quadratic_in_the_reading_sigma():
    """With the point error set to zero, the lines' scatter is the readings' alone: twice the
    reading σ, four times the covariance (to the model's tiny fixed terms)."""
    hangs = _hangs((0.0, 0.0, 0.0), [(1, 0, 1), (-1, 0.2, 1), (0, 1, 1), (0.3, -1, 1.2)])
    one = estimate_cog(hangs, angle_sigma_deg=0.1, point_sigma_mm=0.0).joint.cov_mm2
    two = estimate_cog(hangs, angle_sigma_deg=0.2, point_sigma_mm=0.0).joint.cov_mm2
    np.testing.assert_allclose(two, 4.0 * one, rtol=1e-6)
    assert np.all(np.linalg.eigvalsh(one) > 0)


def test_self_calibration_needs_three_hangs_and_the_bolt_axes():
    two = _hangs((0.0, 0.0, 0.0), [(1, 0, 1), (-1, 0.2, 1)])
    with pytest.raises(ValueError, match="needs three or more suspensions, got 2"):
        estimate_cog(two, self_calibrate=True)
    three = _hangs((0.0, 0.0, 0.0), [(1, 0, 1), (-1, 0.2, 1), (0, 1, 1)])
    with pytest.raises(ValueError, match="needs the bolt axes"):
        estimate_cog(three, self_calibrate=True)


def test_a_rig_says_when_a_hang_is_from_none_of_its_points(paper_rig):
    """The rig's example readings pass quietly; the same with one hang moved 10 mm name it."""
    from dataclasses import replace
    from pathlib import Path

    from cadcog.method.readings import read_readings

    examples = Path(__file__).resolve().parents[2] / "docs" / "examples"
    hangs = read_readings(examples / "paper_rig_readings.csv", paper_rig.inclinometer)
    ok = estimate_for_rig(paper_rig, hangs)
    assert not any("hang from none" in w for w in ok.warnings)
    moved = replace(hangs[-1], id="X9", position_mm=tuple(np.add(hangs[-1].position_mm, 10.0)))
    warned = estimate_for_rig(paper_rig, [*hangs[:-1], moved])
    assert any(
        "suspension(s) X9 hang from none of rig paper_rig's suspension" in w
        for w in warned.warnings
    )
