"""The CubeSat CoG envelope check."""

from __future__ import annotations

import numpy as np
import pytest

from cadcog.spacecraft.envelope import CDS_COG_LIMITS_MM, check_envelope, limits_for


def test_limits_table_is_symmetric_in_x_and_y_up_to_3u():
    for ff in ("1U", "1.5U", "2U", "3U"):
        x, y, _ = CDS_COG_LIMITS_MM[ff]
        assert x == y == 20.0
    assert [CDS_COG_LIMITS_MM[f][2] for f in ("1U", "1.5U", "2U", "3U")] == [20, 30, 45, 70]


@pytest.mark.parametrize(
    ("cog", "within", "at95"),
    [([19.0, 0, 0], True, False), ([0, 21.0, 0], False, False), ([0, 0, 60.0], True, True)],
)
def test_nominal_and_95_verdicts(cog, within, at95):
    c = check_envelope(cog, [0, 0, 0], limits_for("3U"), cov_mm2=np.eye(3))
    assert (c.within, c.within_at_95) == (within, at95)
    np.testing.assert_allclose(c.margin_mm, limits_for("3U") - np.abs(cog))


def test_axes_map_the_model_onto_the_cds_frame():
    """A model built with its rails along x: the CDS z is the model's x."""
    axes = np.array([[0.0, 1, 0], [0, 0, 1], [1, 0, 0]])
    c = check_envelope([60.0, 5.0, 1.0], [0, 0, 0], limits_for("3U"), axes=axes)
    np.testing.assert_allclose(c.offset_mm, [5.0, 1.0, 60.0])
    assert c.within and c.within_at_95 is None
    assert "within the envelope" == c.verdict()


def test_pocketqube_limits_are_ten_mm_and_say_they_are_provisional():
    from cadcog.spacecraft.envelope import check_envelope, limits_for

    assert limits_for("2p").tolist() == [10.0, 10.0, 10.0]
    inside = check_envelope([9.0, -9.0, 9.9], [0, 0, 0], limits_for("2p"), form_factor="2p")
    outside = check_envelope([0.0, 0.0, 10.1], [0, 0, 0], limits_for("3p"), form_factor="3p")
    assert inside.within and not outside.within
    assert "PROVISIONAL" in inside.source and "PocketQube Standard" in inside.source
    cubesat = check_envelope([0, 0, 0], [0, 0, 0], limits_for("1U"), form_factor="1U")
    assert "CubeSat Design Specification" in cubesat.source
