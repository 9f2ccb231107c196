"""``cadcog/cad/surfacepoints.py`` (``setup init``'s candidates and ME base): rays from a box
face meet the model where a stepped block's closed form says, in mm and with the file in
inches."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("build123d")

from cadcog.cad.surfacepoints import project_grid, top_surface_point
from support.stepfixtures import box_shape

# A 40 × 20 mm footprint: x in [0, 20] is 30 mm tall, x in [20, 40] 10 mm tall.
LO, HI = np.array([0.0, 0.0, 0.0]), np.array([40.0, 20.0, 30.0])


def _stepped(scale: float):
    s = 1.0 / scale
    return [
        box_shape((20.0 * s, 20.0 * s, 30.0 * s), (0.0, 0.0, 0.0)),
        box_shape((20.0 * s, 20.0 * s, 10.0 * s), (20.0 * s, 0.0, 0.0)),
    ]


@pytest.mark.parametrize("scale", [1.0, 25.4])
def test_rays_down_the_top_face_meet_each_step_at_its_height(scale):
    grid = [[5.0, 10.0, 30.0], [30.0, 10.0, 30.0], [45.0, 10.0, 30.0]]  # the last misses
    hits = project_grid(_stepped(scale), "+z", grid, LO, HI, scale_to_mm=scale, max_depth_mm=30)
    assert [h.face for h in hits] == ["+z", "+z"]
    np.testing.assert_allclose([h.position_mm for h in hits], [[5, 10, 30], [30, 10, 10]],
                               atol=1e-6)  # fmt: skip
    np.testing.assert_allclose([h.depth_mm for h in hits], [0.0, 20.0], atol=1e-6)


@pytest.mark.parametrize("scale", [1.0, 25.4])
def test_a_point_deeper_than_allowed_is_dropped_and_the_side_face_is_met(scale):
    deep = project_grid(_stepped(scale), "+z", [[30.0, 10.0, 30.0]], LO, HI, scale_to_mm=scale,
                        max_depth_mm=15.0)  # fmt: skip
    assert deep == []
    side = project_grid(_stepped(scale), "+x", [[40.0, 10.0, 5.0], [40.0, 10.0, 20.0]], LO, HI,
                        scale_to_mm=scale)  # fmt: skip
    np.testing.assert_allclose([h.position_mm for h in side], [[40, 10, 5], [20, 10, 20]],
                               atol=1e-6)  # fmt: skip


@pytest.mark.parametrize("scale", [1.0, 25.4])
def test_the_me_base_sits_on_the_highest_surface_under_the_top_face(scale):
    base = top_surface_point(_stepped(scale), LO, HI, scale_to_mm=scale)
    assert base is not None
    np.testing.assert_allclose(base, [20.0, 10.0, 30.0], atol=1e-6)  # the centre: on the step
