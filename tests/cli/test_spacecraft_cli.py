"""The example spacecraft end to end: build, massprops, plan, campaign, estimate vs CAD; the
whole plan checked before the first hang; a weighing in grams refused (the set-up's own checks:
``tests/spacecraft/test_setup.py``)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy import stats

pytest.importorskip("build123d")

from cadcog.cli import main
from cadcog.rig.file import default_rig_path

SETUP = default_rig_path().parent / "cubesat_3u_setup.toml"


@pytest.fixture(scope="module")
def setup(cubesat_setup):
    return cubesat_setup


def test_build_then_massprops_of_the_step(tmp_path, capsys, setup):
    out = tmp_path / "cubesat"
    assert main(["parts", "cubesat", "--out", str(out)]) == 0
    capsys.readouterr()
    step, mats = out / "cubesat_3u.step", out / "cubesat_3u_materials.toml"
    assert main(["massprops", str(step), "--materials", str(mats), "--json"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert set(res) >= {"mass_kg", "cog_mm", "inertia_kg_mm2", "volume_mm3", "bodies", "budget"}
    assert res["mass_kg"] == pytest.approx(setup.mass.mass_kg, rel=1e-9)
    np.testing.assert_allclose(res["cog_mm"], setup.mass.cog_mm, atol=1e-8)
    names = {s["path"].rsplit("/", 1)[-1] for s in res["bodies"]}
    assert names >= {"battery_pack", "rail_1", "payload_camera"}
    battery = next(s for s in res["bodies"] if s["path"].endswith("/battery_pack"))
    assert battery["material"] == "Li-ion cell (18650)"
    assert main(["massprops", str(step)]) == 2
    assert "--materials" in capsys.readouterr().err


def test_plan_campaign_estimate_recovers_the_cad_cog(tmp_path, capsys, setup):
    assert main(["plan", str(SETUP), "--trials", "500", "--max-set", "3", "--json"]) == 0
    plan = json.loads(capsys.readouterr().out)
    # --setup, as the other commands take the set-up, is the same plan to the byte
    assert main(["plan", "--setup", str(SETUP), "--trials", "500", "--max-set", "3", "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == plan
    # In range everywhere; refused only where the vertical lies within 10° of the sensor's
    # plane (sin²X + sin²Y within sin²80° of 1: the z component lost in the noise).
    for c in plan["candidates"]:
        s2 = np.sin(np.radians(c["inc_x_deg"])) ** 2 + np.sin(np.radians(c["inc_y_deg"])) ** 2
        elevation = np.degrees(np.arcsin(np.sqrt(max(0.0, 1.0 - s2))))
        assert c["usable"] == (elevation >= 10.0), c
        assert c["usable"] or "from the inclinometer's plane" in c["reason"]
    assert sum(c["usable"] for c in plan["candidates"]) >= 40
    rec = plan["recommended"]
    assert len(rec["points"]) >= 2 and rec["q95_mm"] < 2.0
    assert plan["error_model"]["inclinometer_model"] == "hang-bias"
    assert "Monte Carlo" in plan["prediction"]
    assert plan["me_share"] == pytest.approx(setup.me_mass_kg / setup.mass.mass_kg)
    csv = tmp_path / "readings.csv"
    assert (
        main(
            [
                "campaign",
                "--setup",
                str(SETUP),
                "--points",
                ",".join(rec["points"]),
                "--seed",
                "5",
                "--out",
                str(csv),
            ]
        )
        == 0
    )
    capsys.readouterr()
    assert main(["estimate", str(csv), "--setup", str(SETUP), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    # The set-up gives the bolt axes: the expected wire offset is corrected by default.
    assert out["model"]["wire_correction"] is True
    # One wire for every hang: its scale is one unknown of mean and σ 0.5 mm a priori, which
    # the hangs narrow.
    assert out["wire"]["estimated"] is False and out["wire"]["prior_mm"] == 0.5
    assert 0.0 < out["wire"]["sigma_mm"] < 0.5
    cad = out["cad"]
    np.testing.assert_allclose(cad["cad_cog_mm"], setup.mass.cog_mm)
    # Within the predicted uncertainty: a 99.9 % ellipsoid of the reported covariance.
    assert cad["mahalanobis"] < np.sqrt(stats.chi2.ppf(0.999, df=3))
    assert cad["cubesat"]["within"] and cad["cubesat"]["limits_mm"] == [20.0, 20.0, 70.0]
    # --no-wire-correction is applied too (it was silently ignored with --setup once).
    assert (
        main(["estimate", str(csv), "--setup", str(SETUP), "--no-wire-correction", "--json"]) == 0
    )
    raw = json.loads(capsys.readouterr().out)
    assert raw["model"]["wire_correction"] is False and raw["wire"] is None
    assert np.linalg.norm(np.subtract(raw["cog_mm"], out["cog_mm"])) > 0.05


def test_acquire_checks_the_whole_plan_before_the_first_hang(tmp_path, capsys):
    """A point the plan would refuse (its vertical 5° from the sensor's plane) stops the run
    before anyone hangs anything: exit 2, the point and why, no file."""
    out = tmp_path / "day.csv"
    args = ["acquire", "--simulate", "--setup", str(SETUP), "--out", str(out)]
    assert main([*args, "--points=+x_30_90,+x_30_30", "--non-interactive"]) == 2
    err = capsys.readouterr().err
    assert "+x_30_30 cannot work" in err and "+x_30_90 cannot work" not in err
    assert not out.exists() and not list(tmp_path.iterdir())


def test_a_weighing_in_grams_given_as_kilograms_is_refused(tmp_path, capsys):
    """2583 for a 2.58 kg CAD (1000×: grams as kg) and a σ of 1e-300 are refused naming the
    option; a weighing 20× the CAD (a structure-only model: the gap `update` is for) passes."""
    csv = tmp_path / "r.csv"
    points = "--points=+x_30_90,-x_-30_90,+y_-30_-30,-y_30_-30"
    assert main(["campaign", "--setup", str(SETUP), points, "--out", str(csv)]) == 0
    base = ["estimate", str(csv), "--setup", str(SETUP)]
    capsys.readouterr()
    assert main([*base, "--weighed-mass-kg", "2583"]) == 2
    err = capsys.readouterr().err
    assert "--weighed-mass-kg 2583" in err and "is the weighing in kg" in err
    assert main([*base, "--weighed-mass-kg", "2.583", "--mass-sigma-kg", "1e-300"]) == 2
    assert "--mass-sigma-kg 1e-300" in capsys.readouterr().err
    assert main([*base, "--weighed-mass-kg", "51.6", "--json"]) == 0
