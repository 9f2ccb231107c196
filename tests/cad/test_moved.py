"""``cadcog/cad/moved.py``: the solids a configuration's move makes overlap, against boxes'
closed forms (the common volume of two axis-aligned boxes is the product of their overlaps)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

pytest.importorskip("build123d")

from cadcog.cad.moved import moved_overlaps
from support.stepfixtures import box_shape

I3 = np.eye(3)


def _overlap_1d(a0: float, a1: float, b0: float, b1: float) -> float:
    return max(0.0, min(a1, b1) - max(a0, b0))


@example((-21.0, 0.0, 0.0), 25.4)  # 50 mm³ in an inch file: judged in in³, it was contact
@settings(max_examples=25, deadline=None)
@given(
    st.tuples(*(st.integers(-25, 25).map(float) for _ in range(3))), st.sampled_from([1.0, 25.4])
)
def test_a_moved_box_overlaps_a_still_one_by_the_closed_form(t_mm, scale):
    """Box 'still' 10 × 10 × 10 mm at the origin, box 'panel' 10 × 20 × 5 mm at x = 30, moved by
    ``t``; the file in mm or in inches (``scale_to_mm``)."""
    still = ("still", box_shape((10 / scale, 10 / scale, 10 / scale), (0.0, 0.0, 0.0)))
    panel = ("panel", box_shape((10 / scale, 20 / scale, 5 / scale), (30 / scale, 0.0, 0.0)))
    t = np.asarray(t_mm)
    lo, hi = np.array([30.0, 0.0, 0.0]) + t, np.array([40.0, 20.0, 5.0]) + t
    common = np.prod([_overlap_1d(0.0, 10.0, lo[k], hi[k]) for k in range(3)])
    found = moved_overlaps([still, panel], {"panel": (I3, t)}, scale_to_mm=scale)
    if common < 1e-3 * 250.0:  # touching faces or a sliver: contact, not an overlap
        assert found == []
        return
    ((moved, other, volume),) = found
    assert (moved, other) == ("panel", "still")
    assert volume == pytest.approx(common, rel=1e-6)


def test_solids_moved_together_or_not_at_all_are_not_checked_against_each_other():
    a = ("a", box_shape((10.0, 10.0, 10.0), (0.0, 0.0, 0.0)))
    b = ("b", box_shape((10.0, 10.0, 10.0), (5.0, 0.0, 0.0)))  # overlap the model itself has
    assert moved_overlaps([a, b], {}) == []
    together = {"a": (I3, np.array([0.0, 50.0, 0.0])), "b": (I3, np.array([0.0, 50.0, 0.0]))}
    assert moved_overlaps([a, b], together) == []


def test_a_hinge_rotation_is_applied_about_the_origin_as_x_to_rx_plus_t():
    """A 90° turn about z maps the panel at x in [30, 40] to y in [30, 40]: onto a box there."""
    rz = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    wall = ("wall", box_shape((10.0, 10.0, 10.0), (-15.0, 30.0, 0.0)))  # x in [-15, -5]
    panel = ("panel", box_shape((10.0, 10.0, 10.0), (30.0, 0.0, 0.0)))  # → x in [-10, 0]
    ((_, _, volume),) = moved_overlaps([wall, panel], {"panel": (rz, np.zeros(3))})
    assert volume == pytest.approx(5.0 * 10.0 * 10.0, rel=1e-6)
