"""``cadcog simulate``'s groups: with the wire scale self-calibrated, the groups whose points
cannot determine it are left out (``cadcog estimate`` refuses them) instead of giving NaN."""

from __future__ import annotations

from dataclasses import replace
from itertools import combinations

import numpy as np

from cadcog.method.errormodel import ErrorModel
from cadcog.uncertainty.montecarlo import draw_points
from cadcog.uncertainty.random_points import SimulationSettings, run_simulation, wire_identifiable


def _paper_wire(rig):
    """The rig with the paper's wire model: an offset of constant shape along each bolt axis,
    which a CoG shift reproduces when every point is on one face. (With the elastica's shape,
    as the one-wire default has it, the offsets differ with each hang's angle, and λ is
    weakly determined even then.)"""
    return replace(rig, error_options=replace(rig.error_options, wire_model="paper"))


def _one_face(scenario, group):
    n = scenario.normals[list(group)]
    return bool(np.all(np.abs(n @ n[0] - 1.0) < 1e-12))


def test_groups_on_one_face_cannot_determine_the_wire_scale(paper_rig):
    """Every point on one face: the offsets all move along the same bolt axis, which a shift of
    the CoG reproduces exactly, so λ is free; points on two faces or more fix it."""
    rig = _paper_wire(paper_rig)
    sc = draw_points(rig, 25, np.random.default_rng(0))
    model = ErrorModel.from_rig(rig)
    groups = list(combinations(range(25), 3))
    ok = wire_identifiable(sc, model, groups)
    one_face = np.array([_one_face(sc, g) for g in groups])
    assert one_face.sum() >= 5  # the draw has such groups
    np.testing.assert_array_equal(ok, ~one_face)


def test_self_calibrated_simulation_leaves_them_out_and_stays_finite(paper_rig):
    settings = SimulationSettings(
        points=25, trials_per_group=50, seed=0, group_size=3, self_calibrate=True
    )
    report = run_simulation(_paper_wire(paper_rig), settings)
    sc = report.scenario
    assert report.unidentifiable_groups > 0
    assert not any(_one_face(sc, g) for g in report.groups)
    assert np.isfinite(report.fits.q95_mm) and np.all(np.isfinite(report.result.axis_std_mm))
    d = report.to_dict()
    assert d["groups_left_out_wire_unidentifiable"] == report.unidentifiable_groups
    assert d["n_groups"] + report.unidentifiable_groups == 300  # MAX_GROUPS drawn


def test_the_progress_total_is_announced_first_and_reached(paper_rig):
    """``simulate``'s bar gets its total (groups × trials) before the first step, and the steps
    add up to it: the groups left out as unidentifiable are not counted."""
    settings = SimulationSettings(
        points=25, trials_per_group=20, seed=1, group_size=3, self_calibrate=True
    )
    calls: list[tuple[str, int]] = []
    report = run_simulation(
        paper_rig,
        settings,
        progress=lambda n: calls.append(("step", n)),
        total=lambda n: calls.append(("total", n)),
    )
    assert calls[0] == ("total", len(report.groups) * 20)
    assert [k for k, _ in calls].count("total") == 1
    assert sum(n for k, n in calls if k == "step") == calls[0][1] == report.result.n_trials
