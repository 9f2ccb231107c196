"""Validation: binomial quantities by hand, a campaign from the simulated law passes, a doubled
error fails; the virtual campaign round-trips through the estimator."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from cadcog.campaign import virtual_campaign, write_campaign
from cadcog.errormodel import ErrorModel
from cadcog.geometry import face_normal_of_point
from cadcog.montecarlo import Scenario, all_pairs, simulate
from cadcog.readings import read_readings
from cadcog.validation import (
    check_against_simulation,
    clopper_pearson,
    validate_campaign,
)


def test_clopper_pearson_by_hand():
    # k = n: lower bound solves p^n = α/2.
    lo, hi = clopper_pearson(15, 15)
    assert hi == 1.0 and lo == pytest.approx(0.025 ** (1 / 15))
    # k = 0: upper bound solves (1 - p)^n = α/2.
    lo, hi = clopper_pearson(0, 15)
    assert lo == 0.0 and hi == pytest.approx(1 - 0.025 ** (1 / 15))
    # Interior: the bounds are where the binomial tails equal α/2.
    lo, hi = clopper_pearson(7, 15)
    assert stats.binom.sf(6, 15, lo) == pytest.approx(0.025)
    assert stats.binom.cdf(7, 15, hi) == pytest.approx(0.025)
    with pytest.raises(ValueError, match="0 <= k <= n"):
        clopper_pearson(5, 4)


def test_window_table_by_hand():
    simulated = np.arange(1, 101) / 100.0  # F(ε) = ε for ε in (0, 1]
    measured = np.array([0.05, 0.2, 0.3, 0.45, 0.9])
    v = check_against_simulation(measured, simulated, windows_mm=[0.25, 0.5])
    w1, w2 = v.windows
    assert (w1.F, w1.k, w1.n, w1.p_hat) == (0.24, 2, 5, 0.4)
    assert (w2.F, w2.k, w2.p_hat) == (0.49, 4, 0.8)
    assert (w1.ci_low, w1.ci_high) == clopper_pearson(2, 5)
    assert w1.consistent == (w1.ci_low <= 0.24 <= w1.ci_high)


@pytest.fixture(scope="module")
def rig_simulation(paper_rig):
    return simulate(
        Scenario.from_rig(paper_rig), ErrorModel.from_rig(paper_rig), all_pairs(6), 20_000, seed=1
    ).norms_mm


def test_errors_drawn_from_the_simulated_law_pass_and_doubled_ones_fail(rig_simulation):
    rng = np.random.default_rng(8)
    measured = rng.choice(rig_simulation, 60)  # a campaign distributed as simulated
    ok = check_against_simulation(measured, rig_simulation)
    assert ok.consistent
    assert ok.ks_p_value > 0.05
    bad = check_against_simulation(2.0 * measured, rig_simulation)
    assert not bad.consistent
    assert bad.ks_p_value < 0.01


def test_virtual_campaign_round_trips_through_estimator_and_validation(paper_rig, tmp_path):
    path = tmp_path / "campaign.csv"
    write_campaign(path, virtual_campaign(paper_rig, seed=4, samples=20), "test")
    sus = read_readings(path, paper_rig.inclinometer)
    assert [s.id for s in sus] == [p.id for p in paper_rig.suspension_points]
    assert all(s.n_samples == 20 for s in sus)
    # Counts quantise: the per-point sample spread is of the order of noise and one LSB.
    assert all(0 < s.std_x_deg < 0.2 for s in sus)
    result = validate_campaign(paper_rig, sus, trials_per_pair=2000, seed=0)
    assert result.validation.windows[0].n == 15
    assert np.all(result.validation.measured_norms_mm < 5.0)


def test_face_normal_of_points_on_and_above_faces():
    size = [200.0, 75.0, 78.0]
    assert face_normal_of_point([45, 20, 82], [0, 0, 0], size).tolist() == [0, 0, 1]
    assert face_normal_of_point([55, -4, 60], [0, 0, 0], size).tolist() == [0, -1, 0]
    assert face_normal_of_point([55, 0, 60], [0, 0, 0], size).tolist() == [0, -1, 0]  # on it
    with pytest.raises(ValueError, match="inside the body"):
        face_normal_of_point([50, 30, 30], [0, 0, 0], size)
