"""The Monte Carlo with one sensor per campaign (issue 31): its sensor physics against the
sensor's definition, its estimator against ``cadcog estimate``'s joint fit test by test, its
budget row against a simulation of that row alone, and its numbers whatever the chunking."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from cadcog.method import gls, sharedfit
from cadcog.method.errormodel import ErrorModel
from cadcog.method.sharedbatch import corrected, fit_shared_cog, rotations
from cadcog.rig.inclinometer import corrected_verticals, rotation_matrix, sensor_readings
from cadcog.uncertainty.error_budget import (
    SHARED_SENSOR_ROW,
    error_budget,
    linearised_covariance,
    representative_pair,
)
from cadcog.uncertainty.montecarlo import (
    Scenario,
    all_pairs,
    draw_perturbations,
    group_errors,
    measured_verticals,
    propagate,
    simulate,
)

FIGURES = {"sensor_offset_deg": 0.3, "sensor_scale_rel": 0.01, "mounting_misalignment_deg": 0.5}


@pytest.fixture(scope="module")
def scenario(paper_rig):
    return Scenario.from_rig(paper_rig)


@pytest.fixture(scope="module")
def mems(paper_rig):
    """The paper rig read by a MEMS board: the declared figures of docs/bench.md."""
    return replace(ErrorModel.from_rig(paper_rig), **FIGURES)


def test_rotations_are_the_sensors_rotation_matrix():
    rng = np.random.default_rng(4)
    vec = rng.normal(0.0, 20.0, (3, 7))
    vec[:, 3] = 0.0
    batch = rotations(vec)
    for j in range(7):
        np.testing.assert_allclose(batch[:, :, j], rotation_matrix(vec[:, j]), atol=1e-15)


def test_the_simulated_sensor_reads_what_its_definition_says(scenario, mems):
    """The Monte Carlo's readings (no per-hang error) equal
    :func:`cadcog.rig.inclinometer.sensor_readings` of the true verticals, campaign by
    campaign, and :func:`corrected` undoes them as :func:`corrected_verticals` does."""
    model = mems.only("inclinometer")
    k, n = len(scenario.ids), 40
    pert = draw_perturbations(model, np.random.default_rng(8), n, k)
    pert = replace(pert, reading_deg=np.zeros_like(pert.reading_deg))
    group = list(range(k))
    u = measured_verticals(scenario, model, group, pert)
    truth = measured_verticals(scenario, model, group, replace(pert, shared=None))
    assert pert.shared is not None and np.ptp(pert.shared[0]) > 0.1  # one sensor per campaign
    x_deg = np.degrees(np.arcsin(u[0]))
    y_deg = np.degrees(np.arcsin(u[1]))
    up = np.where(u[2] < 0, -1.0, 1.0)
    back = corrected(x_deg, y_deg, up, pert.shared)
    for j in range(n):
        x, y, top = sensor_readings(truth[:, :, j].T, pert.shared[:, j])
        np.testing.assert_allclose(x_deg[:, j], x, atol=1e-9)
        np.testing.assert_allclose(y_deg[:, j], y, atol=1e-9)
        assert np.array_equal(top, up[:, j] > 0)
        np.testing.assert_allclose(
            back[:, :, j].T, corrected_verticals(x, y, top, pert.shared[:, j]).u, atol=1e-12
        )
        np.testing.assert_allclose(back[:, :, j], truth[:, :, j], atol=1e-12)


@pytest.mark.parametrize(
    ("hangs", "estimate_wire"),
    [
        ((0, 1, 2, 3, 4, 5), False),
        ((0, 3), False),
        ((0, 2, 4, 5), True),
        ((0, 1, 2, 3, 4, 5, 0, 2, 4), False),  # nine: numpy's reductions reorder from eight
    ],
)
def test_the_batch_fit_is_estimates_fit_test_by_test(scenario, mems, hangs, estimate_wire):
    """:func:`fit_shared_cog` over many campaigns gives each campaign's
    :func:`cadcog.method.sharedfit.fit_shared` CoG (the estimator of ``cadcog estimate``)."""
    k, n = len(hangs), 25
    pert = draw_perturbations(mems, np.random.default_rng(11), n, k)
    sub = scenario.with_points(
        [scenario.ids[i] for i in hangs], scenario.points_mm[list(hangs)],
        scenario.normals[list(hangs)],
    )  # fmt: skip
    u = measured_verticals(sub, mems, range(k), pert)
    x_deg, y_deg = np.degrees(np.arcsin(u[0])), np.degrees(np.arcsin(u[1]))
    up = np.where(u[2] < 0, -1.0, 1.0)
    wire = gls.WireTerm.from_model(mems, sub.weight_n, estimate=estimate_wire)
    errors = gls.LineErrors.from_model(mems)
    prior = mems.shared_sensor_sigmas
    batch = fit_shared_cog(
        sub.points_mm.T[:, :, None], x_deg, y_deg, up, sub.normals.T[:, :, None], errors, wire,
        prior,
    )  # fmt: skip
    for j in range(n):
        one = sharedfit.fit_shared(
            sub.points_mm, x_deg[:, j], y_deg[:, j], up[:, j] > 0, sub.normals, errors, wire,
            prior,
        )  # fmt: skip
        np.testing.assert_allclose(batch[:, j], one.cog_mm, atol=1e-8)
    # Alone or in a batch, a campaign's estimate is the same to the bit.
    for lo, hi in ((0, 3), (5, 6)):
        alone = fit_shared_cog(
            sub.points_mm.T[:, :, None], x_deg[:, lo:hi], y_deg[:, lo:hi], up[:, lo:hi],
            sub.normals.T[:, :, None], errors, wire, prior,
        )  # fmt: skip
        assert np.array_equal(alone, batch[:, lo:hi])


def test_shared_errors_widen_the_simulated_error_and_the_fit_recovers_part_of_it(scenario, mems):
    """Six hangs: a sensor's shared errors widen the 95 % error; the joint fit (the command's)
    does better than ignoring them (the per-hang estimator on the same readings)."""
    k, n = len(scenario.ids), 3000
    group = range(k)
    plain = replace(mems, sensor_offset_deg=0.0, sensor_scale_rel=0.0, mounting_misalignment_deg=0)
    pert = draw_perturbations(mems, np.random.default_rng(5), n, k)
    u = measured_verticals(scenario, mems, group, pert)
    with_fit = np.linalg.norm(group_errors(scenario, mems, group, u), axis=1)
    ignored = np.linalg.norm(group_errors(scenario, plain, group, u), axis=1)
    without = np.linalg.norm(propagate(scenario, plain, group, replace(pert, shared=None)), axis=1)
    q = [float(np.quantile(e, 0.95)) for e in (without, with_fit, ignored)]
    assert q[0] < q[1] < q[2], q


def test_the_budget_row_of_the_shared_sensor_matches_a_simulation_of_it_alone(scenario, mems):
    """The linearised share of the shared errors (the budget's row) against the simulated
    covariance of the representative pair's error with only the sensor's shared errors drawn."""
    pair = representative_pair(scenario)
    _, covs = linearised_covariance(scenario, mems, pair)
    pert = draw_perturbations(mems, np.random.default_rng(3), 40_000, 2)
    zero = {f: np.zeros_like(getattr(pert, f)) for f in ("me_mm", "play_mm", "reading_deg")}
    alone = replace(pert, wire=np.full_like(pert.wire, 0.5 * mems.wire_offset_max_mm), **zero)
    e = propagate(scenario, mems, pair, alone)
    # The mounting is uniform in angle (σ per component m/3 with a heavier centre than a
    # normal's): the linearised variance is the draws' to second order.
    np.testing.assert_allclose(
        np.cov(e.T).diagonal(), covs[SHARED_SENSOR_ROW].diagonal(), rtol=0.08
    )
    budget = error_budget(scenario, mems)
    rows = {s.source: s for s in budget.sources}
    assert rows[SHARED_SENSOR_ROW].share == pytest.approx(
        np.trace(covs[SHARED_SENSOR_ROW]) / np.trace(budget.cov_mm2)
    )
    assert SHARED_SENSOR_ROW not in {s.source for s in error_budget(scenario, mems.only()).sources}
    # A mounting alone: its row says so and gives the mounting's σ (m/3 per component).
    mount = replace(mems, sensor_offset_deg=0.0, sensor_scale_rel=0.0)
    row = next(s for s in error_budget(scenario, mount).sources if s.source == SHARED_SENSOR_ROW)
    assert row.sigma == pytest.approx(0.5 / 3) and row.share > 0.1
    assert "mounting within 0.5°" in row.distribution and "offset" not in row.distribution


def test_one_sensor_per_campaign_whatever_the_chunking_or_workers(scenario, mems):
    groups = [*all_pairs(6)[:3], tuple(range(6))]
    ref = simulate(scenario, mems, groups, 4200, seed=7, chunk_blocks=1, keep_norms=True)
    for kwargs in ({"chunk_blocks": 4}, {"workers": 2}):
        other = simulate(scenario, mems, groups, 4200, seed=7, keep_norms=True, **kwargs)
        np.testing.assert_array_equal(other.norms_mm, ref.norms_mm)
