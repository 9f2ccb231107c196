"""``cadcog inertia`` and ``campaign --swings`` in-process: the JSON contract, the text, the API
giving the command's JSON, and refusals with exit 2 and one line."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import cadcog
from cadcog.cli import main


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    folder = tmp_path_factory.mktemp("inertia")
    readings, swings = folder / "c.csv", folder / "s.csv"
    assert main(["campaign", "--seed", "2", "--out", str(readings), "--swings", str(swings)]) == 0
    return readings, swings


def test_json_contract_and_the_api_agree(campaign, capsys):
    readings, swings = campaign
    capsys.readouterr()
    assert main(["inertia", str(swings), "--readings", str(readings), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    keys = {
        "inertia_kg_mm2", "inertia_cov", "inertia_cov_entries", "inertia_convention",
        "principal_moments_kg_mm2", "principal_moments_sigma_kg_mm2", "principal_axes",
        "principal_axes_sigma_deg", "consistency", "hangs", "budget", "cad",
    }  # fmt: skip
    assert keys <= set(out)
    assert out["inertia_cov_entries"] == ["xx", "yy", "zz", "xy", "xz", "yz"]
    assert "−∫ x·y dm" in out["inertia_convention"]
    api = cadcog.inertia(swings, readings)
    assert json.loads(api.to_json()) == out
    # The swings were drawn from the CAD: it lies within the stated uncertainty.
    truth = cadcog.load_rig().analytic_proof_mass.inertia_kg_mm2
    sigma = np.array(out["inertia_sigma_kg_mm2"])
    assert np.all(np.abs(np.array(out["inertia_kg_mm2"]) - truth) < 4 * sigma)
    assert len(out["hangs"]) == 6 and out["cad"]["dof"] == 6


def test_text_names_the_convention_and_the_budget(campaign, capsys):
    readings, swings = campaign
    capsys.readouterr()
    assert main(["inertia", str(swings), "--readings", str(readings)]) == 0
    text = capsys.readouterr().out
    assert "(off-diagonal = −∫xy dm)" in text
    assert "principal moments" in text and "where the uncertainty comes from" in text
    assert "against the CAD's tensor" in text


@pytest.mark.parametrize(
    ("edit", "match"),
    [
        (lambda s: s.replace("point_id,t_s", "point,t_s"), r"s\.csv, line 1: missing column"),
        (lambda s: s.replace("S2,", "S9,", 1), r"hang 'S9' has 1 sample, expected a swing"),
    ],
)
def test_bad_swing_files_exit_2_naming_file_and_line(campaign, tmp_path, capsys, edit, match):
    readings, swings = campaign
    bad = tmp_path / "s.csv"
    bad.write_text(edit(swings.read_text()))
    assert main(["inertia", str(bad), "--readings", str(readings)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert re.search(match, err), err


def test_options_are_checked(campaign, capsys):
    readings, swings = campaign
    assert (
        main(["inertia", str(swings), "--readings", str(readings), "--weighed-mass-kg", "-1"]) == 2
    )
    assert "--weighed-mass-kg -1.0: expected at least 1e-06" in capsys.readouterr().err
    assert main(["campaign", "--out", str(readings), "--swings", str(readings)]) == 2
    assert "same file" in capsys.readouterr().err


def test_update_observes_the_swings_tensor(tmp_path, capsys):
    setup = "parts/cubesat_3u_setup.toml"
    points = "+x_-30_-30,-x_30_-30,+y_30_-30,-y_-30_-30,+x_30_90,Z1"
    readings, swings = tmp_path / "c.csv", tmp_path / "s.csv"
    argv = ["campaign", "--setup", setup, f"--points={points}", "--seed", "5"]
    assert main([*argv, "--out", str(readings), "--swings", str(swings)]) == 0
    mass = cadcog.load_setup(setup).mass.mass_kg
    capsys.readouterr()
    base = ["update", str(readings), "--setup", setup, "--weighed-mass-kg", str(mass), "--json"]
    assert main([*base, "--swings", str(swings)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["verdict"]["dof"] == 10
    api = cadcog.update(readings, setup, mass, swings=swings)
    assert json.loads(api.to_json()) == out


def test_a_spacecraft_s_files_without_its_setup_are_told_to_give_it(tmp_path, capsys):
    """The 3U example's campaign read with the paper rig (no --setup: the default) ended in
    advice to redo the hangs (a new user from Python); the refusal now says first that the
    readings name none of the rig's points, and what to give."""
    readings, swings = tmp_path / "c.csv", tmp_path / "s.csv"
    setup = "parts/cubesat_3u_setup.toml"
    points = "+x_-30_-150,+x_-30_90,-x_-30_-150,+y_-30_-150,+y_30_-30,-y_-30_-30"
    argv = ["campaign", "--setup", setup, f"--points={points}", "--out", str(readings)]
    assert main([*argv, "--swings", str(swings)]) == 0
    capsys.readouterr()
    assert main(["inertia", str(swings), "--readings", str(readings)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert re.search(r"c\.csv: the readings name none of rig paper_rig's points \(S1, .*S6\): "
                     r"a spacecraft's swings and readings go with its set-up", err)  # fmt: skip
    assert main(["inertia", str(swings), "--readings", str(readings), "--setup", setup]) == 0
