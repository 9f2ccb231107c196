"""The Monte Carlo core: zero errors give zero, single sources match linear propagation,
reproducibility whatever the chunking or workers, and the drawn points obey the constraints."""

from __future__ import annotations

import numpy as np
import pytest

from cadcog.budget import linearised_covariance, representative_pair
from cadcog.errormodel import SOURCES, ErrorModel
from cadcog.geometry import ideal_reading
from cadcog.montecarlo import Scenario, all_pairs, draw_points, simulate, simulate_block


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


@pytest.mark.parametrize("source", [s for s in SOURCES if s != "wire_offset"])
def test_single_source_matches_linearised_prediction(scenario, model, source):
    pair = representative_pair(scenario)
    single = model.only(source)
    _, covs = linearised_covariance(scenario, single, pair)
    e = simulate_block(scenario, single, pair, 40_000, np.random.default_rng(5))
    np.testing.assert_allclose(
        np.cov(e.T).diagonal(), covs[source].diagonal(), rtol=0.05, atol=1e-6
    )


def test_wire_offset_alone_matches_linearised_mean_and_spread(scenario, model):
    pair = representative_pair(scenario)
    single = model.only("wire_offset")
    bias, covs = linearised_covariance(scenario, single, pair)
    e = simulate_block(scenario, single, pair, 40_000, np.random.default_rng(6))
    np.testing.assert_allclose(e.mean(axis=0), bias, atol=0.01)
    np.testing.assert_allclose(np.cov(e.T).diagonal(), covs["wire_offset"].diagonal(), rtol=0.05)


def test_same_seed_same_numbers_whatever_the_chunking_or_workers(scenario, model):
    pairs = all_pairs(6)[:4]
    ref = simulate(scenario, model, pairs, 9000, seed=3, chunk_blocks=1)
    for kwargs in ({"chunk_blocks": 3}, {"chunk_blocks": 64}, {"workers": 2}):
        other = simulate(scenario, model, pairs, 9000, seed=3, **kwargs)
        np.testing.assert_array_equal(other.norms_mm, ref.norms_mm)
        np.testing.assert_allclose(other.axis_sum_mm, ref.axis_sum_mm, rtol=1e-12)
    different = simulate(scenario, model, pairs, 9000, seed=4)
    assert not np.array_equal(different.norms_mm, ref.norms_mm)


def test_streamed_axis_moments_match_direct_computation(scenario, model):
    pairs = all_pairs(6)[:3]
    res = simulate(scenario, model, pairs, 5000, seed=1, chunk_blocks=1)
    errors = []
    for g, pair in enumerate(pairs):
        for b in range(2):
            n = min(4096, 5000 - b * 4096)
            rng = np.random.default_rng(np.random.SeedSequence(1, spawn_key=(g, b)))
            errors.append(simulate_block(scenario, model, pair, n, rng))
    e = np.concatenate(errors)
    np.testing.assert_allclose(res.axis_mean_mm, e.mean(axis=0), atol=1e-12)
    np.testing.assert_allclose(res.axis_std_mm, e.std(axis=0, ddof=1), rtol=1e-9)
    np.testing.assert_allclose(res.norms_mm, np.linalg.norm(e, axis=1))


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
