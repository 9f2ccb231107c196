"""``cadcog/method/medata.py``: what the compensation takes, from a rig's closed forms, and a
weighing that replaces the model's mass only where it can be this object's."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from cadcog.core.errors import CadcogError
from cadcog.method.medata import MIN_WEIGHING_SIGMA_REL, WEIGHED_TO_MODEL, MEData


def test_a_rigs_me_is_its_analytic_me_and_its_proof_mass(paper_rig):
    me = MEData.from_rig(paper_rig)
    assert me.object_mass_kg == paper_rig.proof_mass.mass_kg and me.object_mass_source == "rig"
    assert me.me_mass_kg == paper_rig.analytic_me.mass_kg
    np.testing.assert_array_equal(me.me_cog_mm, paper_rig.analytic_me.cog_mm)
    np.testing.assert_array_equal(me.me_cog_cov_mm2, paper_rig.me_cog_cov_mm2)
    assert me.object_mass_sigma_kg == 0.0


@example(100.0, 1e-3)  # the band's edges are in it
@example(0.01, 1e-3)
@given(st.floats(1e-3, 1e3), st.floats(1e-9, 1.0))
def test_a_weighing_replaces_the_mass_only_within_its_band_of_the_model(ratio, rel):
    me = MEData(2.6, 0.2, np.zeros(3), np.zeros((3, 3)), "t")
    mass = 2.6 * ratio
    sigma = rel * mass
    in_band = (1.0 / WEIGHED_TO_MODEL) * 2.6 <= mass <= WEIGHED_TO_MODEL * 2.6
    sharp_enough = sigma >= MIN_WEIGHING_SIGMA_REL * mass
    if in_band and sharp_enough:
        w = me.weighed(mass, sigma)
        assert (w.object_mass_kg, w.object_mass_sigma_kg, w.object_mass_source) == (
            mass,
            sigma,
            "weighed",
        )
        assert (w.me_mass_kg, w.source) == (me.me_mass_kg, me.source)  # the ME is untouched
        return
    option = "--weighed-mass-kg" if not in_band else "--mass-sigma-kg"
    with pytest.raises(CadcogError, match=f"^{option} "):
        me.weighed(mass, sigma)
