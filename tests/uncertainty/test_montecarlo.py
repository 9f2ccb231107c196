"""The Monte Carlo core: zero errors give zero, single sources match linear propagation,
reproducibility whatever the chunking or workers, and the drawn points obey the constraints."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from cadcog.method.errormodel import SOURCES, ErrorModel
from cadcog.method.sym3 import sym_to_full
from cadcog.rig.geometry import ideal_reading
from cadcog.uncertainty import montecarlo
from cadcog.uncertainty.error_budget import linearised_covariance, representative_pair
from cadcog.uncertainty.montecarlo import (
    Scenario,
    all_pairs,
    draw_perturbations,
    draw_points,
    estimate_trials,
    propagate,
    simulate,
    simulate_block,
)


@pytest.fixture(scope="module")
def model(paper_rig):
    return ErrorModel.from_rig(paper_rig)


@pytest.fixture(scope="module")
def scenario(paper_rig):
    return Scenario.from_rig(paper_rig)


def test_no_error_sources_give_zero_error(scenario, model):
    rng = np.random.default_rng(0)
    for group in [*all_pairs(6), tuple(range(6))]:
        e = simulate_block(scenario, model.only(), group, 50, rng)
        assert np.max(np.abs(e)) < 1e-10


def _one_source(model, source, n, seed):
    """Draws with only ``source`` random; the wire offset otherwise at its mean (0.5 mm)."""
    pert = draw_perturbations(model.only(source), np.random.default_rng(seed), n, 2)
    if source != "wire_offset":
        pert = replace(pert, wire=np.full_like(pert.wire, 0.5 * model.wire_offset_max_mm))
    return pert


@pytest.mark.parametrize("source", SOURCES)
def test_single_source_matches_linearised_prediction(scenario, model, source):
    """The budget's linearised share of each source against a Monte Carlo of that source alone,
    both through the full model's estimator (the one a user runs)."""
    pair = representative_pair(scenario)
    bias, covs = linearised_covariance(scenario, model, pair)
    e = propagate(scenario, model, pair, _one_source(model, source, 40_000, 5))
    np.testing.assert_allclose(
        np.cov(e.T).diagonal(), covs[source].diagonal(), rtol=0.05, atol=1e-6
    )
    # With the expected wire offset corrected, no source leaves a bias.
    np.testing.assert_allclose(bias, 0.0, atol=1e-9)
    np.testing.assert_allclose(e.mean(axis=0), 0.0, atol=0.01)


@pytest.mark.parametrize("wire_model", ["paper", "elastica", "one-wire"])
def test_linearised_budget_equals_the_estimators_own_covariance(scenario, model, wire_model):
    """Two independent routes to one number: finite differences of the whole simulation (the
    budget) and the closed-form generalised least-squares covariance, compensated (eq. 16).

    The one-wire model's estimator takes λ's prior σ as half the bound (a string and the
    stiffest wire both within 1 σ), wider than the uniform draw's bound/√12: its covariance
    is then the budget's plus the difference along λ's direction, and never smaller."""
    model = replace(model, wire_model=wire_model)
    pair = representative_pair(scenario)
    _, covs = linearised_covariance(scenario, model, pair)
    total = sum(covs.values())
    pert = _one_source(model, "me_cog", 1, 0)
    pert = replace(pert, me_mm=np.zeros((3, 1)))
    est = estimate_trials(scenario, model, pair, pert)
    ratio = scenario.me_mass_kg / scenario.pm_mass_kg
    closed = (1 + ratio) ** 2 * sym_to_full(est.cov_mm2)[
        0
    ] + ratio**2 * model.me_sigma_mm**2 * np.eye(3)
    if wire_model == "one-wire":
        m = model.wire_offset_max_mm
        wider = model.wire_prior(scenario.weight_n).scale_var_mm2 / (m * m / 12.0)
        _, covs_wide = linearised_covariance(scenario, model, pair)
        # The wire's share grows by the prior's variance ratio; the rest is the same.
        total = total + (wider - 1.0) * covs_wide["wire_offset"]
    np.testing.assert_allclose(total, closed, rtol=0.02, atol=1e-5)


@pytest.mark.parametrize("trials", [9000, 4097])  # 4097: a last block of one campaign
def test_same_seed_same_numbers_whatever_the_chunking_or_workers(scenario, model, trials):
    pairs = all_pairs(6)[:4]
    ref = simulate(scenario, model, pairs, trials, seed=3, chunk_blocks=1, keep_norms=True)
    for kwargs in ({"chunk_blocks": 3}, {"chunk_blocks": 64}, {"workers": 2}):
        other = simulate(scenario, model, pairs, trials, seed=3, keep_norms=True, **kwargs)
        np.testing.assert_array_equal(other.norms_mm, ref.norms_mm)
        np.testing.assert_array_equal(other.histogram.counts, ref.histogram.counts)
        assert other.group_q95_mm == ref.group_q95_mm
        np.testing.assert_allclose(other.axis_sum_mm, ref.axis_sum_mm, rtol=1e-12)
    different = simulate(scenario, model, pairs, trials, seed=4, keep_norms=True)
    assert not np.array_equal(different.norms_mm, ref.norms_mm)


def test_estimates_in_slices_of_a_block_give_the_same_numbers(scenario, model, monkeypatch):
    """With many hangs the prepared shares are estimated in slices of a block (their memory
    bound; here 6 hangs in slices of 700 campaigns): slicing changes nothing."""
    groups = [(0, 1), (2, 3, 4), (1, 5)]
    ref = simulate(scenario, model, groups, 5000, seed=8, keep_norms=True)
    monkeypatch.setattr(montecarlo, "PREPARED_BYTES", montecarlo.PREPARED_ROWS * 8 * 6 * 700)
    sliced = simulate(scenario, model, groups, 5000, seed=8, keep_norms=True)
    np.testing.assert_array_equal(sliced.norms_mm, ref.norms_mm)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"groups": [(0,)]}, r"group \(0,\): expected two or more distinct"),
        ({"groups": [(0, 0)]}, r"group \(0, 0\)"),
        ({"groups": [(0, 6)]}, r"indices in 0\.\.5"),
        ({"groups": [(0, -1)]}, r"group \(0, -1\)"),
        ({"groups": []}, "no group"),
        ({"screened": [True]}, "1 flags for 2 groups"),
        ({"workers": 0}, "workers must be at least 1"),
        ({"chunk_blocks": 0}, "chunk_blocks must be at least 1"),
    ],
)
def test_simulate_refuses_what_it_cannot_simulate(scenario, model, kwargs, match):
    args = {"groups": [(0, 1), (2, 3)], **kwargs}
    groups = args.pop("groups")
    with pytest.raises(ValueError, match=match):
        simulate(scenario, model, groups, 10, seed=0, **args)


def test_streamed_axis_moments_match_direct_computation(scenario, model):
    """The streamed results against a direct computation: each block of campaigns drawn for
    every hang of the simulation (points 0-3 here), each pair estimated from its two hangs."""
    pairs = [(0, 1), (0, 2), (1, 3)]
    res = simulate(scenario, model, pairs, 5000, seed=1, chunk_blocks=1, keep_norms=True)
    errors: list[list[np.ndarray]] = [[] for _ in pairs]
    for b in range(2):
        n = min(4096, 5000 - b * 4096)
        rng = np.random.default_rng(np.random.SeedSequence(1, spawn_key=(b,)))
        pert = draw_perturbations(model, rng, n, 4)  # hangs 0, 1, 2, 3
        for g, pair in enumerate(pairs):
            cols = list(pair)
            own = replace(
                pert,
                play_mm=pert.play_mm[:, cols],
                wire=pert.wire[cols] if model.wire_model == "paper" else pert.wire,
                reading_deg=pert.reading_deg[:, cols],
            )
            errors[g].append(propagate(scenario, model, pair, own))
    per_pair = [np.concatenate(e) for e in errors]
    e = np.concatenate(per_pair)
    np.testing.assert_allclose(res.axis_mean_mm, e.mean(axis=0), atol=1e-12)
    np.testing.assert_allclose(res.axis_std_mm, e.std(axis=0, ddof=1), rtol=1e-9)
    np.testing.assert_allclose(res.norms_mm, np.linalg.norm(e, axis=1))
    per_group = res.norms_mm.reshape(len(pairs), 5000)
    np.testing.assert_allclose(res.group_q95_mm, np.quantile(per_group, 0.95, axis=1), rtol=1e-15)
    np.testing.assert_allclose(res.group_q50_mm, np.quantile(per_group, 0.5, axis=1), rtol=1e-15)
    # The streamed histogram's quantiles are within its stated relative bin width.
    for q in (0.5, 0.95):
        exact = np.quantile(res.norms_mm, q)
        assert abs(res.histogram.quantile(q) / exact - 1) < 2 * res.histogram.REL_WIDTH


def test_groups_of_one_campaign_share_its_me_error_and_hangs(scenario, model):
    """One ME CoG error per campaign: with it the only source, every group of a campaign errs
    alike. Pairs sharing a hang share its reading errors; disjoint pairs are independent."""
    pairs = [(0, 1), (0, 2), (2, 3), (4, 5)]
    me = simulate(scenario, model.only("me_cog"), pairs, 3000, seed=2, keep_norms=True)
    rows = me.norms_mm.reshape(len(pairs), 3000)
    assert rows[0].std() > 0.01
    np.testing.assert_allclose(rows, np.broadcast_to(rows[0], rows.shape), rtol=1e-9)
    incl = simulate(scenario, model.only("inclinometer"), pairs, 20_000, seed=2, keep_norms=True)
    r = np.corrcoef(incl.norms_mm.reshape(len(pairs), 20_000))
    assert r[0, 1] > 0.1  # (0, 1) and (0, 2) share hang 0
    assert abs(r[0, 3]) < 0.03  # (0, 1) and (4, 5): disjoint; 0.03 is 4 standard errors


def test_a_groups_errors_are_those_of_independent_draws(scenario, model):
    """Sharing hangs between groups changes no group's distribution: the 95 % quantile of a pair
    simulated among others matches independent draws of that pair alone, to the sampling error
    (4 standard errors of the difference, from the binomial law of the order statistic)."""
    pair = (1, 4)
    res = simulate(scenario, model, [(0, 1), pair, (2, 4)], 40_000, seed=5)
    alone = simulate_block(scenario, model, pair, 40_000, np.random.default_rng(11))
    ref = np.linalg.norm(alone, axis=1)
    se = np.sqrt(0.95 * 0.05 / 40_000)  # in probability; both samples have it: 4·√2 of them
    lo, hi = np.quantile(ref, [0.95 - 5.7 * se, 0.95 + 5.7 * se])
    assert lo < res.group_q95_mm[1] < hi


def test_drawn_points_respect_range_face_and_me(paper_rig):
    sc = draw_points(paper_rig, 25, np.random.default_rng(9))
    g = paper_rig.analytic_assembly.cog_mm
    size = np.array(paper_rig.proof_mass.size_mm)
    h = paper_rig.holes.wire_exit_height_mm
    for p, n in zip(sc.points_mm, sc.normals, strict=True):
        assert ideal_reading(p, g).in_range(paper_rig.inclinometer_range_deg)
        on_face = p - h * n
        axis = int(np.argmax(np.abs(n)))
        assert on_face[axis] == (size[axis] if n[axis] > 0 else 0.0)
        if n[2] > 0:
            for v in paper_rig.me_volumes:
                inside = np.all(on_face[:2] > v.min_mm[:2]) and np.all(on_face[:2] < v.max_mm[:2])
                assert not inside
    assert len(set(map(tuple, sc.points_mm))) == 25
