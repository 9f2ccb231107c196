"""The bolt axis of a suspension point: the box face it sits on, or the face a set-up names
for a point on the model inside the box; never refused for a rounding the tool made."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.core import tolerances
from cadcog.method.estimate import BodyBox

LO, HI = np.array([-50.0, -40.0, -10.0]), np.array([50.0, 40.0, 10.0])


@given(
    face=st.sampled_from(range(6)),
    u=st.floats(-1, 1),
    v=st.floats(-1, 1),
    inside=st.floats(0.0, 0.9999 * tolerances.SUSPENSION_ON_FACE_MM),
)
def test_a_point_within_the_tolerance_of_a_face_takes_that_face(face, u, v, inside):
    axis, sign = face % 3, (1.0 if face < 3 else -1.0)
    p = 0.5 * (LO + HI) + 0.5 * (HI - LO) * 0.9 * np.array([u, v, u * v])  # inside the face
    p[axis] = (HI if sign > 0 else LO)[axis] - sign * inside
    n = BodyBox(LO, HI, "test").normal_at(p)
    expected = np.zeros(3)
    expected[axis] = sign
    np.testing.assert_array_equal(n, expected)


def test_a_listed_point_inside_the_box_takes_its_named_face():
    deep = np.array([38.525, -20.0, 10.787 - 20.0])  # 11.475 mm inside the +x box face
    box = BodyBox(LO, HI, "test", known=((deep, np.array([1.0, 0.0, 0.0])),))
    # as a readings file writes it back (3 decimals), and 0.009 mm off on every axis
    for p in (np.round(deep, 3), deep + 0.009):
        np.testing.assert_array_equal(box.normal_at(p), [1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="inside the body"):
        box.normal_at(deep + np.array([0.02, 0.0, 0.0]))  # not the listed point: refused
    with pytest.raises(ValueError, match="inside the body"):
        BodyBox(LO, HI, "test").normal_at(deep)
