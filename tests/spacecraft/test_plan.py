"""``cadcog/spacecraft/plan.py``: a candidate the inclinometer cannot read says why; with a
sensor's shared figures, which reversal would help, and by how much, said by the joint fit's
covariance and checked against the Monte Carlo of the same set."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from cadcog.method import gls
from cadcog.method.reversal import best_reversal
from cadcog.spacecraft.plan import plan_test
from cadcog.uncertainty.montecarlo import simulate

FIGURES = {"offset_deg": 0.3, "scale_error_rel": 0.01, "mounting_misalignment_deg": 0.5}


@pytest.fixture(scope="module")
def mems_setup(cubesat_setup):
    rig = cubesat_setup.rig
    return replace(
        cubesat_setup, rig=replace(rig, inclinometer=replace(rig.inclinometer, **FIGURES))
    )


def test_the_plan_names_the_reversal_that_helps(mems_setup, cubesat_setup):
    plan = plan_test(mems_setup, trials=2000, max_set=3)
    rev = plan.reversal
    assert rev is not None and rev.advised
    assert rev.point in plan.recommended["points"]
    assert rev.sigma_with_mm < 0.95 * rev.sigma_mm
    assert max(rev.offset_sigma_with_deg) < max(rev.offset_sigma_deg)
    assert plan.to_dict()["reversal"]["point"] == rev.point
    # Without a declared zero offset a reversal cancels nothing: no advice.
    assert plan_test(cubesat_setup, trials=500, max_set=2).reversal is None


def test_the_advices_sigma_is_the_monte_carlos_spread(mems_setup):
    """Two routes to the set's CoG spread: the joint fit's covariance at the nominal readings
    (the advice's σ, √trace) and the Monte Carlo's RMS error of the same set, one sensor per
    campaign. The fit's prior on the wire scale (σ half the bound) is wider than the uniform
    draw (bound/√12), so the covariance may exceed the spread; it must not fall short of it."""
    plan = plan_test(mems_setup, trials=500, max_set=3)
    ids = plan.recommended["points"]
    usable = tuple(c for c in mems_setup.candidates if c.id in ids)
    scenario = mems_setup.scenario(usable)
    model = mems_setup.error_model()
    res = simulate(scenario, model, [tuple(range(len(usable)))], 20_000, seed=4)
    rms = float(np.sqrt(res.norm_sumsq_mm2 / res.n_trials))
    advice = best_reversal(
        [c.id for c in usable],
        scenario.points_mm,
        scenario.normals,
        mems_setup.assembly_cog_mm,
        gls.LineErrors.from_model(model),
        gls.WireTerm.from_model(model, scenario.weight_n),
        model.shared_sensor_sigmas,
        mems_setup.rig.inclinometer,
        me_ratio=scenario.me_mass_kg / scenario.pm_mass_kg,
        me_sigma_mm=model.me_sigma_mm,
    )
    assert advice is not None
    # 20 000 campaigns: the RMS is known to ~1 %; the two agree to 0.3 % on this set.
    assert 0.95 * rms <= advice.sigma_mm <= 1.1 * rms, (advice.sigma_mm, rms)


def test_candidate_out_of_range_says_why(cubesat_setup):
    from cadcog.spacecraft.plan import plan_test
    from cadcog.spacecraft.setup import Candidate

    far = Candidate(
        "edge",
        np.array([50.0, 0.0, cubesat_setup.assembly_cog_mm[2] + 5.0]),
        np.array([1.0, 0.0, 0.0]),
    )
    plan = plan_test(
        replace(cubesat_setup, candidates=(far, *cubesat_setup.candidates[:3])), trials=200
    )
    check = plan.checks[0]
    assert not check.usable and "X = " in check.reason and "beyond the ±60° range" in check.reason
