"""Calibration: over virtual campaigns (raw ADC counts, per-hang biases, play and wire offset,
one ME error per campaign), `cadcog estimate`'s ellipsoids contain the true CoG as often as they
claim, clean lines are rarely flagged, and `cadcog plan`'s prediction comes true.

Campaigns are read back by :func:`cadcog.validation.campaign.campaign_suspensions`, which equals
reading the CSV (``tests/validation/test_verification.py``), and estimated by the function behind
the command. Counts are lower than in ``benchmarks/study_calibration.py`` (2000 per set,
``docs/estimate.md``); the bounds are the 99.9 % binomial range of a calibrated ellipsoid, so a
covariance 20 % too large or too small fails them.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from cadcog.method.errormodel import ErrorModel
from cadcog.method.estimate import BodyBox, MEData, estimate_cog
from cadcog.uncertainty.montecarlo import Scenario
from cadcog.validation.campaign import campaign_suspensions, simulated_readings

N = 400


def _bounds(p: float, n: int = N) -> tuple[float, float]:
    lo, hi = stats.binom.ppf([0.0005, 0.9995], n, p) / n
    return float(lo), float(hi)


def _run(scenario, model, config, me, body, truth, n=N):
    d2, norms, flagged, lines = [], [], 0, 0
    for seed in range(n):
        sus = campaign_suspensions(simulated_readings(scenario, model, config, seed), config)
        est = estimate_cog(sus, config, me, model=model, body=body)
        e = est.cog_mm - truth
        d2.append(e @ np.linalg.solve(est.cov_mm2, e))
        norms.append(np.linalg.norm(e))
        flagged += sum(r.inconsistent for r in est.joint.residuals)
        lines += len(sus)
    return np.array(d2), np.array(norms), flagged, lines


def _check_coverage(d2, conservative=False):
    """Calibrated coverage; ``conservative``: at least the nominal coverage, above it by no
    more than a stated prior's excess can give (95 % → at most 99.5 %)."""
    c95 = np.mean(d2 <= stats.chi2.ppf(0.95, 3))
    c68 = np.mean(d2 <= stats.chi2.ppf(0.68, 3))
    lo95, hi95 = _bounds(0.95)
    lo68, hi68 = _bounds(0.68)
    if conservative:
        hi95, hi68 = 0.995, 0.85
    assert lo95 <= c95 <= hi95, c95
    assert lo68 <= c68 <= hi68, c68


@pytest.mark.parametrize(
    ("names", "conservative"),
    [
        (("S1", "S2", "S3", "S4", "S5", "S6"), False),
        # Three hangs, and two, cannot determine the one wire's scale λ well: its prior
        # carries it, and the prior's σ (half the bound, so that a string and the stiffest wire
        # both lie within 1 σ) is wider than the uniform draw's (bound/√12): the ellipsoids are
        # then larger (97.3 % and 98.7 % over 2000 campaigns, docs/estimate.md).
        (("S1", "S3", "S5"), True),
        (("S1", "S2"), True),
    ],
)
def test_paper_rig_ellipsoids_cover(paper_rig, names, conservative):
    model = ErrorModel.from_rig(paper_rig)
    full = Scenario.from_rig(paper_rig)
    idx = [full.ids.index(i) for i in names]
    sc = full.with_points(names, full.points_mm[idx], full.normals[idx])
    d2, _, flagged, lines = _run(
        sc,
        model,
        paper_rig.inclinometer,
        MEData.from_rig(paper_rig),
        BodyBox.of_rig(paper_rig),
        paper_rig.analytic_proof_mass.cog_mm,
    )
    _check_coverage(d2, conservative)
    # Clean lines: flagged at about the nominal 0.3 % (uniform errors have light tails).
    assert flagged <= stats.binom.ppf(0.999, lines, 0.003), flagged


@pytest.mark.slow
def test_cubesat_ellipsoids_cover_and_plan_comes_true(cubesat_setup):
    """The recommended set of `cadcog plan` on the example: the estimate's ellipsoids cover,
    and the plan's predicted 95 % error is the realised one (within the sampling error of the
    two quantiles: 4000 planned trials, 400 campaigns)."""
    from cadcog.spacecraft.plan import plan_test

    setup = cubesat_setup
    plan = plan_test(setup, trials=4000, max_set=3)
    rec = plan.recommended
    assert rec is not None
    by_id = {c.id: c for c in setup.candidates}
    sc = setup.scenario(tuple(by_id[i] for i in rec["points"]))
    lo, hi = setup.bbox_mm
    d2, norms, _, _ = _run(
        sc,
        setup.error_model(),
        setup.rig.inclinometer,
        setup.me_data(weighed_mass_kg=setup.mass.mass_kg),  # the truth is the CAD: as weighed
        BodyBox(lo, hi, "setup"),
        setup.mass.cog_mm,
    )
    _check_coverage(d2, conservative=True)  # the one wire's prior, as for S1+S2 (97.8 %)
    # The realised 95 % quantile's 99.9 % order-statistic interval must hold the prediction.
    k_lo, k_hi = stats.binom.ppf([0.0005, 0.9995], N, 0.95).astype(int)
    srt = np.sort(norms)
    assert srt[k_lo - 1] <= rec["q95_mm"] <= srt[min(k_hi, N - 1)]
