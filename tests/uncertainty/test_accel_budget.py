"""An accelerometer's error said before the test: ``cadcog budget`` and ``cadcog plan``."""

from __future__ import annotations

import itertools
import json
from dataclasses import replace

import numpy as np
import pytest
from scipy import stats

from cadcog.cli import main
from cadcog.method.errormodel import ErrorModel
from cadcog.method.estimate import estimate_for_rig
from cadcog.method.readings import Suspension
from cadcog.rig.accelerometer import accel_angles_deg, accel_readings
from cadcog.rig.file import load_rig
from cadcog.rig.inclinometer import InclinometerConfig
from cadcog.uncertainty.accel_budget import Hangs, grow, predict, q95_mm
from cadcog.uncertainty.trials import Scenario
from support.rigtools import paper_rig_dict, write_rig

PHONE = {"offset_g": 0.02, "scale_error_rel": 0.01, "mounting_misalignment_deg": 1.0}


@pytest.fixture(scope="module")
def phone(tmp_path_factory):
    data = paper_rig_dict()
    data["inclinometer"] = {"device": "accelerometer", "axes": ["-y", "+x", "+z"], **PHONE}
    path = write_rig(tmp_path_factory.mktemp("rig") / "phone.toml", data)
    rig = load_rig(path)
    sc = Scenario.from_rig(rig)
    return path, rig, Hangs(sc.ids, sc.points_mm, sc.normals, sc.assembly_cog_mm, sc.weight_n)


def test_q95_is_the_chi_distributions_for_an_isotropic_normal():
    # |e| of N(0, σ²I₃) is σ·χ₃: its 95th percentile is σ√(χ²₃ 95 %).
    assert q95_mm(4.0 * np.eye(3)) == pytest.approx(2.0 * stats.chi.ppf(0.95, 3), rel=0.01)
    # A degenerate direction counts for nothing; a single axis is |N(0, σ²)|: σ·1.96.
    assert q95_mm(np.diag([9.0, 0.0, 0.0])) == pytest.approx(3.0 * 1.96, rel=0.01)


def test_the_prediction_is_what_the_estimate_will_state(phone):
    """Two compositions, one answer: the budget's covariance equals the one `cadcog estimate`
    states on the readings the CAD predicts (a sensor without error, no noise)."""
    _, rig, hangs = phone
    cfg, model = rig.inclinometer, ErrorModel.from_rig(rig)
    pr = predict(hangs, hangs.ids, cfg, model)
    lam = model.wire_prior(hangs.weight_n).scale_mm
    u = (hangs.points_mm - hangs.cog_mm) / np.linalg.norm(hangs.points_mm - hangs.cog_mm, axis=1)[
        :, None
    ]
    for _ in range(6):  # the one wire's virtual point: λ/cos(θ/2) along the bolt (docs/method.md)
        half = np.arccos(np.clip(np.einsum("ij,ij->i", u, hangs.normals), -1, 1)) / 2
        q = hangs.points_mm + (lam / np.cos(half))[:, None] * hangs.normals
        u = (q - hangs.cog_mm) / np.linalg.norm(q - hangs.cog_mm, axis=1)[:, None]
    acc = accel_readings(u, np.zeros(15), cfg.axes)
    x, y, up = accel_angles_deg(acc)
    sus = [
        Suspension(
            i,
            tuple(p),
            bool(t),
            200,
            float(a),
            float(b),
            None,
            None,
            2,
            False,
            tuple(g),
            (0.0, 0.0, 0.0),
        )
        for i, p, a, b, t, g in zip(hangs.ids, hangs.points_mm, x, y, up, acc, strict=True)
    ]
    est = estimate_for_rig(rig, sus)
    np.testing.assert_allclose(est.joint.cov_mm2, pr.cov_mm2, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(est.joint.cog_mm, hangs.cog_mm, atol=1e-6)


def test_more_hangs_never_predict_worse_and_calibration_helps(phone):
    _, rig, hangs = phone
    model = ErrorModel.from_rig(rig)
    sizes = grow(hangs, rig.inclinometer, model, max_hangs=7)
    q = [s.q95_mm for s in sizes]
    assert [len(s.hangs) for s in sizes] == list(range(2, 8))
    assert all(b <= a * (1 + 1e-9) for a, b in itertools.pairwise(q))
    for s in sizes:
        assert s.q95_uncalibrated_mm > s.q95_mm
        assert np.all(np.linalg.eigvalsh(s.cov_uncalibrated_mm2 - s.cov_mm2) > -1e-12)
    # With the phone's offsets (±20 mg, ~1°), two hangs cannot calibrate: ~2 mm; six can.
    assert q[0] > 1.0 and q[4] < 0.5
    # A reversal joins the set only after the points (it cancels offsets, adds no line).
    assert not any(h.endswith("~") for h in sizes[3].hangs)


def test_without_shared_figures_self_calibration_changes_nothing(phone):
    _, rig, hangs = phone
    cfg = InclinometerConfig(range_deg=90.0, device="accelerometer", axes=("-y", "+x", "+z"))
    model = replace(ErrorModel.from_rig(rig), sensor_offset_g=0.0, sensor_scale_rel=0.0,
                    mounting_misalignment_deg=0.0)  # fmt: skip
    pr = predict(hangs, hangs.ids, cfg, model)
    np.testing.assert_allclose(pr.cov_uncalibrated_mm2, pr.cov_mm2, rtol=1e-6)


def test_budget_command_for_a_phone(phone, capsys):
    path, _, _ = phone
    assert main(["budget", "--rig", str(path), "--target-mm", "0.45", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["device"] == "accelerometer"
    smallest = data["smallest_set_within_target"]
    sets = {len(s["hangs"]): s for s in data["best_sets"]}
    assert sets[len(smallest)]["q95_mm"] <= 0.45 < sets[len(smallest) - 1]["q95_mm"]
    assert data["all_points"]["q95_without_self_calibration_mm"] > data["all_points"]["q95_mm"]


def test_target_is_for_an_accelerometer(capsys):
    assert main(["budget", "--target-mm", "1"]) == 2
    assert "--target-mm: for an accelerometer's rig" in capsys.readouterr().err


def test_the_plan_of_a_cubesat_read_by_a_phone(cubesat_setup):
    from cadcog.runs.plan import run_accel_plan

    cfg = InclinometerConfig(range_deg=90.0, device="accelerometer", **PHONE)
    setup = replace(cubesat_setup, rig=replace(cubesat_setup.rig, inclinometer=cfg))
    checks, budget = run_accel_plan(setup, max_set=6, target_mm=0.6)
    assert all(c.usable for c in checks)  # an accelerometer reads every orientation
    assert [len(s.hangs) for s in budget.sizes] == [2, 3, 4, 5, 6]
    assert budget.meets is not None and budget.meets.q95_mm <= 0.6


def test_each_hang_keeps_its_own_noise_whatever_the_order(phone):
    """A noisy hang weighs less wherever it stands in the list (each line its own variance)."""
    _, rig, hangs = phone
    cfg = rig.inclinometer
    u = (hangs.points_mm - hangs.cog_mm) / np.linalg.norm(hangs.points_mm - hangs.cog_mm, axis=1)[
        :, None
    ]
    acc = accel_readings(u, np.zeros(15), cfg.axes)
    std = [0.05, 0.0005, 0.0005, 0.0005, 0.0005, 0.0005]  # the first hang 100 times noisier
    x, y, up = accel_angles_deg(acc)
    sus = [
        Suspension(
            i, tuple(p), bool(t), 200, float(a), float(b), None, None, 2, False, tuple(g), (s, s, s)
        )
        for i, p, a, b, t, g, s in zip(hangs.ids, hangs.points_mm, x, y, up, acc, std, strict=True)
    ]
    first = estimate_for_rig(rig, sus)
    last = estimate_for_rig(rig, [*sus[1:], sus[0]])
    np.testing.assert_allclose(last.joint.cov_mm2, first.joint.cov_mm2, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(last.joint.cog_mm, first.joint.cog_mm, atol=1e-9)
