"""Principal axes, frames and product-of-inertia conventions against closed forms."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.mass.inertia import (
    Frame,
    inertia_in_frame,
    principal_axes,
    products_of_inertia,
)
from cadcog.mass.properties import box_properties


def _rotation(a: float, b: float, c: float) -> np.ndarray:
    """A rotation matrix from three angles (z-y-x), for random frames."""
    rz = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    rx = np.array([[1, 0, 0], [0, np.cos(c), -np.sin(c)], [0, np.sin(c), np.cos(c)]])
    return rz @ ry @ rx


angle = st.floats(-np.pi, np.pi)
moment = st.floats(0.1, 100.0)


@given(moment, moment, moment, angle, angle, angle)
def test_principal_axes_recover_a_rotated_diagonal_tensor(m1, m2, m3, a, b, c):
    r = _rotation(a, b, c)
    moments = np.array([m1, m2, m3])
    j = r @ np.diag(moments) @ r.T
    p = principal_axes(j)
    np.testing.assert_allclose(p.moments_kg_mm2, np.sort(moments), rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(p.axes @ p.axes.T, np.eye(3), atol=1e-9)
    assert np.linalg.det(p.axes) == pytest.approx(1.0)
    np.testing.assert_allclose(p.axes @ j @ p.axes.T, np.diag(p.moments_kg_mm2), atol=1e-7)
    if not p.degenerate:
        for k in range(3):  # each axis is an eigenvector with the largest component positive
            np.testing.assert_allclose(j @ p.axes[k], p.moments_kg_mm2[k] * p.axes[k], atol=1e-6)
            if k < 2:
                assert p.axes[k][np.argmax(np.abs(p.axes[k]))] > 0


def test_degenerate_moments_are_flagged():
    assert principal_axes(np.diag([2.0, 2.0, 5.0])).degenerate
    assert not principal_axes(np.diag([1.0, 2.0, 5.0])).degenerate


def test_products_conventions_of_a_tilted_body():
    # Two point masses at (1, 1, 0) and (-1, -1, 0): ∫ x y dm = 2 m.
    m = 0.5
    pts = np.array([[1.0, 1.0, 0.0], [-1.0, -1.0, 0.0]])
    j = sum(m * (np.dot(p, p) * np.eye(3) - np.outer(p, p)) for p in pts)
    assert products_of_inertia(j, "positive")["xy"] == pytest.approx(2 * m)
    assert products_of_inertia(j, "negative")["xy"] == pytest.approx(-2 * m)
    with pytest.raises(ValueError, match="convention"):
        products_of_inertia(j, "sideways")  # type: ignore[arg-type]


def test_inertia_about_an_offset_point_in_swapped_axes():
    # Box 2 × 4 × 6 of 1 kg at the origin; frame at (0, 0, 10), axes x' = +y, y' = -x, z' = +z.
    box = box_properties([2.0, 4.0, 6.0], [0, 0, 0], mass_kg=1.0)
    f = Frame.parse("+y,-x,+z", [0.0, 0.0, 10.0])
    j = inertia_in_frame(box, f)
    ixx, iyy, izz = 52 / 12, 40 / 12, 20 / 12
    # about the origin shifted 10 mm along z: +m d² on x and y; axes swapped x <-> y
    np.testing.assert_allclose(np.diag(j), [iyy + 100, ixx + 100, izz])
    np.testing.assert_allclose(f.point_to_frame(box.cog_mm), [0, 0, -10])


@given(angle, angle, angle, st.tuples(*[st.floats(-50, 50)] * 3))
def test_frame_inertia_is_invariant_in_trace_and_eigenvalues(a, b, c, origin):
    box = box_properties([3.0, 5.0, 7.0], [1.0, 2.0, 3.0], mass_kg=2.0)
    r = _rotation(a, b, c)
    f = Frame(np.asarray(origin), r)
    j = inertia_in_frame(box, f)
    j_model = box.inertia_about(origin)
    np.testing.assert_allclose(np.linalg.eigvalsh(j), np.linalg.eigvalsh(j_model), rtol=1e-9)


@pytest.mark.parametrize(
    ("axes", "message"),
    [("+x,+y", "three signed axes"), ("+x,+x,+z", "orthonormal"), ("+x,+y,-z", "right-handed")],
)
def test_bad_frames_are_refused(axes, message):
    with pytest.raises(ValueError, match=message):
        Frame.parse(axes, [0, 0, 0])


def test_axis_vectors_give_any_right_handed_frame():
    """A box's inertia in axes turned 45° about z: the closed form of a rotated tensor."""
    from cadcog.mass.inertia import Frame, inertia_in_frame
    from cadcog.mass.properties import box_properties

    box = box_properties([40.0, 20.0, 10.0], [0.0, 0.0, 0.0], mass_kg=1.2)
    a, b = box.inertia_kg_mm2[0, 0], box.inertia_kg_mm2[1, 1]
    j = inertia_in_frame(box, Frame.parse("1,1,0;-1,1,0", [0.0, 0.0, 0.0]))
    assert j[0, 0] == pytest.approx((a + b) / 2) and j[1, 1] == pytest.approx((a + b) / 2)
    # x' = (x + y)/√2, y' = (y − x)/√2: ∫x'y' dm = (∫y² − ∫x²)/2 = (Ixx − Iyy)/2, entry −that
    assert j[0, 1] == pytest.approx((b - a) / 2) and b - a == pytest.approx(120.0)
    # three vectors, one typed to four figures: squared up to the same frame
    k = inertia_in_frame(box, Frame.parse("0.7071,0.7071,0;-0.7071,0.7071,0;0,0,2", [0, 0, 0]))
    np.testing.assert_allclose(k, j, atol=1e-9)
    for bad, text in [
        ("1,0,0;1,1,0", "from perpendicular"),
        ("1,0,0;0,1,0;0,0,-1", "left-handed"),
        ("1,0,0;0,0,0", "expected two or three axis vectors"),
    ]:
        with pytest.raises(ValueError, match=text):
            Frame.parse(bad, [0, 0, 0])
