"""Rigid placements: recognised to the tolerance, refused when they scale."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt, gp_Trsf, gp_Vec
from OCP.TopLoc import TopLoc_Location

from cadcog.cad.occt import rigid_transform

_unit = st.floats(-1.0, 1.0)


def _location(axis, angle_rad, shift, scale=1.0):
    t = gp_Trsf()
    t.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(*axis)), angle_rad)
    t.SetTranslationPart(gp_Vec(*shift))
    if scale != 1.0:
        s = gp_Trsf()
        s.SetScale(gp_Pnt(0, 0, 0), scale)
        t = t.Multiplied(s)
    return TopLoc_Location(t)


@settings(max_examples=200)
@given(
    st.tuples(_unit, _unit, _unit).filter(lambda v: math.hypot(*v) > 0.1),
    st.floats(-7.0, 7.0),
    st.tuples(*(st.floats(-1e4, 1e4),) * 3),
)
def test_a_rotation_and_shift_come_back_as_gp_trsf_holds_them(axis, angle, shift):
    loc = _location(axis, angle, shift)
    rigid = rigid_transform(loc)
    assert rigid is not None
    r, t = rigid
    trsf = loc.Transformation()
    assert np.array_equal(r, [[trsf.Value(i, j) for j in (1, 2, 3)] for i in (1, 2, 3)])
    assert np.array_equal(t, shift)  # the translation is set last, kept exactly
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(r), 1.0, atol=1e-12)


def test_a_scaled_placement_is_not_rigid():
    assert rigid_transform(_location((0, 0, 1), 0.3, (1, 2, 3), scale=1.001)) is None
    assert rigid_transform(_location((0, 0, 1), 0.3, (1, 2, 3), scale=1 + 1e-7)) is None
    assert rigid_transform(_location((0, 0, 1), 0.3, (1, 2, 3), scale=1 + 1e-12)) is not None
