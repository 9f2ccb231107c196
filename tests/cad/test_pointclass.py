"""``cadcog/cad/pointclass.py``: which solid holds a point, against a box's closed form."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

pytest.importorskip("build123d")

from cadcog.cad.pointclass import solids_holding
from cadcog.core.tolerances import SUSPENSION_ON_FACE_MM
from support.stepfixtures import box_shape

SIZE = np.array([10.0, 20.0, 30.0])
CORNER = np.array([5.0, -10.0, 0.0])
POINT = st.tuples(*(st.floats(-10.0, 40.0) for _ in range(3)))


def _inside(p: np.ndarray, size: np.ndarray, corner: np.ndarray, tol: float) -> bool | None:
    """Deeper than ``tol`` inside (True), beyond it outside or on a face (False); None within
    a hair of the tolerance band, where either answer is right."""
    depth = np.min(np.minimum(p - corner, corner + size - p))
    if abs(depth - tol) < 1e-6:
        return None
    return bool(depth > tol)


@settings(max_examples=80, deadline=None)
@given(POINT, st.sampled_from([1.0, 25.4]))
def test_a_point_is_held_exactly_when_it_is_inside_beyond_the_tolerance(point, scale):
    """In mm, and with the file in other units (a ``units`` override: the box drawn in file
    units, the point in mm)."""
    p = np.asarray(point)
    expected = _inside(p, SIZE, CORNER, SUSPENSION_ON_FACE_MM)
    assume(expected is not None)
    box = ("box", box_shape(tuple(SIZE / scale), tuple(CORNER / scale)))
    (held,) = solids_holding([box], p[None, :], scale_to_mm=scale)
    assert (held == "box") == expected


def test_the_first_solid_holding_a_point_is_named_and_faces_are_not_inside():
    a = ("a", box_shape((10.0, 10.0, 10.0), (0.0, 0.0, 0.0)))
    b = ("b", box_shape((10.0, 10.0, 10.0), (5.0, 0.0, 0.0)))  # overlaps a on x in [5, 10]
    points = [(7.0, 5.0, 5.0), (2.0, 5.0, 5.0), (12.0, 5.0, 5.0), (10.0, 5.0, 5.0), (20, 5, 5)]
    assert solids_holding([a, b], points) == ["a", "a", "b", "b", None]
    assert solids_holding([a], [(10.0, 5.0, 5.0), (0.0005, 5.0, 5.0)]) == [None, None]  # on faces
