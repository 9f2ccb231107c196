"""Faces, the forward model of the inclinometer and line angles."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.rig.geometry import (
    angle_between_lines_deg,
    face_normal,
    face_plane_mm,
    ideal_reading,
    upward_vertical,
)

coords = st.floats(min_value=-300, max_value=300)


@pytest.mark.parametrize("face", ["+x", "-x", "+y", "-y", "+z", "-z"])
def test_face_normal_points_out_of_the_box(face):
    size = np.array([200.0, 75.0, 78.0])
    n = face_normal(face)
    axis = int(np.argmax(np.abs(n)))
    point_on_face = 0.5 * size
    point_on_face[axis] = face_plane_mm(face, size)
    # Stepping along the outward normal leaves the box.
    outside = point_on_face + n
    assert not np.all((outside >= 0) & (outside <= size))


@given(coords, coords, coords, coords, coords, coords)
def test_reading_reconstructs_the_vertical(px, py, pz, gx, gy, gz):
    p, g = np.array([px, py, pz]), np.array([gx, gy, gz])
    if np.linalg.norm(p - g) < 1e-3:
        return
    r = ideal_reading(p, g)
    sx, sy = np.sin(np.deg2rad([r.inc_x_deg, r.inc_y_deg]))
    sz = (1 if r.top_face_up else -1) * np.sqrt(max(0.0, 1 - sx**2 - sy**2))
    # z comes from a square root: near a horizontal vertical an eps-level error in the sines
    # becomes a sqrt(eps) ~ 1.5e-8 error in z, so that is the attainable accuracy.
    np.testing.assert_allclose([sx, sy, sz], (p - g) / np.linalg.norm(p - g), atol=5e-8)


def test_sign_convention_x_positive_when_plus_x_points_up():
    # Suspension point at +x of the CoG: the +x axis points upward, so X > 0.
    r = ideal_reading([10.0, 0.0, 10.0], [0.0, 0.0, 0.0])
    assert r.inc_x_deg == pytest.approx(45.0)
    assert r.inc_y_deg == pytest.approx(0.0)
    assert r.top_face_up
    below = ideal_reading([0.0, -10.0, -10.0], [0.0, 0.0, 0.0])
    assert below.inc_y_deg == pytest.approx(-45.0)
    assert not below.top_face_up


def test_range_check():
    r = ideal_reading([np.sqrt(3.0), 0.0, 1.0], [0.0, 0.0, 0.0])  # 60 degrees about x
    assert r.inc_x_deg == pytest.approx(60.0)
    assert r.in_range(60.0 + 1e-9)
    assert not r.in_range(59.9)


def test_vertical_undefined_at_the_cog():
    with pytest.raises(ValueError, match="coincides with the CoG"):
        upward_vertical([1, 2, 3], [1, 2, 3])


@given(st.floats(0.0, 180.0))
def test_angle_between_lines_is_acute(theta_deg):
    t = np.deg2rad(theta_deg)
    got = angle_between_lines_deg([1, 0, 0], [np.cos(t), np.sin(t), 0])
    assert got == pytest.approx(min(theta_deg, 180 - theta_deg), abs=1e-9)
