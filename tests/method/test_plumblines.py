"""The pair (eq. 8) and joint estimators, compensation (eqs. 10, 16) and the range check."""

from __future__ import annotations

from itertools import pairwise

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from cadcog.core.errors import DegenerateGeometryError, IllConditionedError
from cadcog.method.plumblines import (
    PlumbLine,
    compensate_me,
    joint_estimate,
    least_squares_point,
    out_of_range,
    pair_estimate,
)
from cadcog.rig.geometry import angle_between_lines_deg, upward_vertical
from cadcog.rig.inclinometer import readings_from_verticals, verticals_from_readings

ILL_CONDITIONED = "ill-conditioned"
ALL_PAIRS = "every pair of plumb lines"

coord = st.floats(min_value=-300.0, max_value=300.0)
point = st.tuples(coord, coord, coord).map(np.array)


def _lines(points, cog, sigmas=None):
    sigmas = sigmas or [1.0] * len(points)
    return [
        PlumbLine(f"P{i}", p, upward_vertical(p, cog), s)
        for i, (p, s) in enumerate(zip(points, sigmas, strict=True))
    ]


def _well_spread(points, cog, min_angle=10.0):
    if min(np.linalg.norm(p - cog) for p in points) < 10.0:
        return False
    us = [upward_vertical(p, cog) for p in points]
    return all(
        angle_between_lines_deg(a, b) >= min_angle for i, a in enumerate(us) for b in us[i + 1 :]
    )


def _direction(polar_deg: float, azimuth_deg: float) -> np.ndarray:
    t, f = np.deg2rad(polar_deg), np.deg2rad(azimuth_deg)
    return np.array([np.sin(t) * np.cos(f), np.sin(t) * np.sin(f), np.cos(t)])


# A suspension set-up built, not filtered: the CoG, then each point at a distance along a
# direction. Polar angles stay 12° or more away from the horizontal so that eq. 2's square root
# (z = ±√(1 − sin²X − sin²Y)) is well-conditioned (|u_z| ≥ 0.2) for the readings round trip.
polar = st.one_of(st.floats(0.0, 78.0), st.floats(102.0, 180.0))
spoke = st.tuples(polar, st.floats(0.0, 360.0), st.floats(10.0, 400.0))


def _points(cog, spokes):
    return [cog + dist * _direction(t, f) for t, f, dist in spokes]


@settings(max_examples=200)
@given(point, st.lists(spoke, min_size=2, max_size=8))
def test_noise_free_round_trip_recovers_the_cog(cog, spokes):
    points = _points(cog, spokes)
    assume(_well_spread(points, cog))
    lines = _lines(points, cog)
    for a, b in pairwise(lines):
        np.testing.assert_allclose(pair_estimate(a, b).midpoint_mm, cog, rtol=0, atol=1e-9)
        assert pair_estimate(a, b).gap_mm < 1e-9
    np.testing.assert_allclose(joint_estimate(lines).cog_mm, cog, rtol=0, atol=1e-9)


@settings(max_examples=200)
@given(point, st.lists(spoke, min_size=2, max_size=6))
def test_round_trip_through_readings(cog, spokes):
    """Forward model → readings in degrees → eq. 2 → estimator."""
    points = _points(cog, spokes)
    assume(_well_spread(points, cog))
    us = np.array([upward_vertical(p, cog) for p in points])
    x, y, up = readings_from_verticals(us)
    v = verticals_from_readings(x, y, up).u
    lines = [PlumbLine(f"P{i}", p, u) for i, (p, u) in enumerate(zip(points, v, strict=True))]
    np.testing.assert_allclose(joint_estimate(lines).cog_mm, cog, rtol=0, atol=1e-9)


@given(point, point, point, st.floats(0.1, 10.0), st.floats(0.1, 10.0))
def test_two_lines_with_equal_weights_give_eq8(p1, p2, noise, s1, s2):
    cog = np.zeros(3)
    assume(_well_spread([p1, p2], cog))
    # Tilt the lines a little so they are skew.
    a = PlumbLine("A", p1, upward_vertical(p1, cog) + 1e-3 * noise / (1 + np.linalg.norm(noise)))
    b = PlumbLine("B", p2, upward_vertical(p2, cog))
    pair = pair_estimate(a, b)
    joint = joint_estimate([a, b])
    np.testing.assert_allclose(joint.cog_mm, pair.midpoint_mm, rtol=0, atol=1e-9)
    # Unequal weights pull the estimate along the shortest segment, towards the tighter line.
    wa = PlumbLine("A", a.point_mm, a.vertical, s1)
    wb = PlumbLine("B", b.point_mm, b.vertical, s2)
    x = joint_estimate([wa, wb]).cog_mm
    seg = pair.foot_b_mm - pair.foot_a_mm
    if np.linalg.norm(seg) > 1e-5:  # shorter segments leave t to round-off
        t = np.dot(x - pair.foot_a_mm, seg) / np.dot(seg, seg)
        np.testing.assert_allclose(x, pair.foot_a_mm + t * seg, atol=1e-7)
        assert t == pytest.approx(s1**2 / (s1**2 + s2**2), abs=1e-6)


@given(point, st.lists(point, min_size=3, max_size=5), st.integers(0, 2**31))
def test_estimate_moves_with_the_setup(cog, points, seed):
    """Rotating and translating the whole set-up rotates and translates the estimate."""
    assume(_well_spread(points, cog))
    rng = np.random.default_rng(seed)
    lines = _lines(points, cog)
    # Add the same skew to every line so the estimate is not trivially the CoG.
    lines = [PlumbLine(ln.id, ln.point_mm, ln.vertical + rng.normal(0, 1e-3, 3)) for ln in lines]
    rot = Rotation.random(random_state=seed).as_matrix()
    shift = rng.normal(0, 100, 3)
    moved = [PlumbLine(ln.id, rot @ ln.point_mm + shift, rot @ ln.vertical) for ln in lines]
    np.testing.assert_allclose(
        joint_estimate(moved).cog_mm, rot @ joint_estimate(lines).cog_mm + shift, atol=1e-8
    )


def test_parallel_pair_raises_with_reason():
    a = PlumbLine("A", [0, 0, 10], [0, 0, 1])
    b = PlumbLine("B", [0, 0, -10], [0, 0, -1])  # CoG and both points collinear
    with pytest.raises(IllConditionedError, match=f"suspensions A and B.*{ILL_CONDITIONED}"):
        pair_estimate(a, b)
    c = PlumbLine("C", [1, 0, 10], [0.01, 0, 1])
    with pytest.raises(IllConditionedError, match="below 5°"):
        pair_estimate(a, c)
    assert pair_estimate(a, c, min_angle_deg=0.1).angle_deg == pytest.approx(0.573, abs=1e-3)


def test_joint_estimate_with_all_pairs_ill_conditioned_raises():
    lines = [PlumbLine(f"P{i}", [0, 0, 10 + i], [0, 0.001 * i, 1]) for i in range(3)]
    with pytest.raises(IllConditionedError, match=ALL_PAIRS):
        joint_estimate(lines)


def test_joint_estimate_skips_ill_conditioned_pairs_but_uses_all_lines():
    cog = np.array([1.0, 2.0, 3.0])
    pts = [np.array([0, 0, 50.0]), np.array([0, 0, -50.0]) + cog * 2, np.array([60.0, 0, 0])]
    lines = _lines(pts, cog)
    est = joint_estimate(lines)
    assert [(a, b) for a, b, _ in est.skipped_pairs] == [("P0", "P1")]
    assert len(est.pairs) == 2
    np.testing.assert_allclose(est.cog_mm, cog, atol=1e-9)


def test_least_squares_point_rejects_parallel_lines():
    with pytest.raises(DegenerateGeometryError, match="all parallel"):
        least_squares_point([[0, 0, 0], [1, 0, 0]], [[0, 0, 1], [0, 0, 1]], [1, 1])


def test_joint_needs_two_distinct_lines():
    a = PlumbLine("A", [0, 0, 10], [0, 0, 1])
    with pytest.raises(ValueError, match="at least two"):
        joint_estimate([a])
    with pytest.raises(ValueError, match="duplicate"):
        joint_estimate([a, a])


def test_residual_flags_the_inconsistent_suspension():
    cog = np.zeros(3)
    pts = [np.array(p, float) for p in ([50, 0, 40], [-50, 10, 40], [0, 60, -30], [10, -60, 30])]
    lines = _lines(pts, cog, sigmas=[0.1] * 4)
    bad = lines[2]
    lines[2] = PlumbLine(bad.id, bad.point_mm + np.array([3.0, 0, 0]), bad.vertical, 0.1)
    est = joint_estimate(lines)
    flagged = [r.id for r in est.residuals if r.inconsistent]
    assert flagged == ["P2"]


def test_covariance_matches_monte_carlo_scatter():
    """The predicted covariance agrees with the scatter of estimates under lateral noise."""
    rng = np.random.default_rng(7)
    cog = np.array([100.0, 37.5, 40.0])
    pts = [np.array(p, float) for p in ([45, 20, 82], [155, 55, 82], [60, 60, -4], [55, -4, 60])]
    sig = [0.3, 0.5, 0.4, 0.2]
    clean = _lines(pts, cog, sig)
    predicted = joint_estimate(clean).cov_mm2
    u = np.array([ln.vertical for ln in clean])
    w = 1.0 / np.array(sig) ** 2
    estimates = []
    for _ in range(4000):
        # Shift each line laterally by an isotropic normal of std sigma.
        d = rng.normal(0, 1, (len(pts), 3)) * np.array(sig)[:, None]
        d -= np.sum(d * u, axis=1)[:, None] * u
        estimates.append(least_squares_point(np.array(pts) + d, u, w)[0])
    empirical = np.cov(np.array(estimates).T)
    np.testing.assert_allclose(np.diag(empirical), np.diag(predicted), rtol=0.1)


def test_compensation_by_hand():
    # Object 9 kg at (1, 2, 3); ME 1 kg at (11, 2, 23): assembly at (2, 2, 5).
    c = compensate_me(
        [2.0, 2.0, 5.0],
        np.eye(3) * 0.04,
        object_mass_kg=9.0,
        me_mass_kg=1.0,
        me_cog_mm=[11.0, 2.0, 23.0],
        me_cog_cov_mm2=np.eye(3) * 2.25,
    )
    np.testing.assert_allclose(c.cog_mm, [1.0, 2.0, 3.0])
    # (1 + 1/9)² · 0.04 + (1/9)² · 2.25
    np.testing.assert_allclose(np.diag(c.cov_mm2), (10 / 9) ** 2 * 0.04 + 2.25 / 81)


def test_range_check_names_every_offender():
    bad = out_of_range(
        {"A": [0, 0, 10], "B": [10, 0, 1], "C": [0, -10, 1]}, [0, 0, 0], range_deg=60.0
    )
    assert [b[0] for b in bad] == ["B", "C"]
    assert bad[1][2] == pytest.approx(-84.29, abs=0.01)
