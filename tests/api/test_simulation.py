"""``cadcog.api.simulation``: simulate, validate and campaign are what the commands compute."""

from __future__ import annotations

import json

import pytest

import cadcog
from cadcog.core.errors import CadcogError
from tests.api.commandline import cli_json


def test_validate_is_what_the_command_prints(campaign_csv, capsys) -> None:
    mine = cadcog.validate(campaign_csv, campaigns=40, seed=3)
    assert mine.to_json() == cli_json(
        capsys, "validate", str(campaign_csv), "--campaigns", "40", "--seed", "3"
    )


def test_simulate_is_what_the_command_prints(capsys) -> None:
    mine = cadcog.simulate(points=0, trials=300, seed=5)
    assert mine.to_json() == cli_json(
        capsys, "simulate", "--points", "0", "--trials-per-pair", "300", "--seed", "5"
    )
    assert mine.fits.n == 300 * len(mine.groups)


def test_validate_options_are_the_command_s(campaign_csv, capsys) -> None:
    """Another rig file, windows and level: the same object as the command's JSON, and the
    options reached the result (not only the defaults agree)."""
    rig = cadcog.load_rig()
    mine = cadcog.validate(
        campaign_csv, rig.source, windows_mm=[1.0, 2.5], campaigns=30, seed=1, level=0.1
    )
    assert mine.to_json() == cli_json(
        capsys, "validate", str(campaign_csv), "--rig", str(rig.source), "--windows", "1,2.5",
        "--campaigns", "30", "--seed", "1", "--level", "0.1",
    )  # fmt: skip
    assert [w.eps_mm for w in mine.validation.windows] == [1.0, 2.5]
    assert mine.verdict.level == 0.1 and mine.null.n_campaigns == 30


SIMULATE_CASES = [
    ({"points": 0, "paper": True}, "--points 0 --paper"),
    (
        {"points": 6, "group_size": 3, "min_angle_deg": 20.0, "wire_correction": False},
        "--points 6 --group-size 3 --min-angle-deg 20 --no-wire-correction",
    ),
]


@pytest.mark.parametrize(("keywords", "options"), SIMULATE_CASES)
def test_simulate_options_are_the_command_s(keywords, options, capsys) -> None:
    mine = cadcog.simulate(trials=60, seed=2, **keywords)
    argv = ["simulate", "--trials-per-pair", "60", "--seed", "2", *options.split()]
    assert mine.to_json() == cli_json(capsys, *argv)
    paper = keywords.get("paper", False)
    assert mine.settings.weighted is not paper  # the options reached the settings
    assert mine.settings.wire_correction is (not paper and keywords.get("wire_correction", True))


def test_the_error_model_overrides_are_the_command_s(capsys) -> None:
    """The error model's overrides and the self-calibrated wire: the API gives the command's
    JSON, and the options change the model it reports."""
    mine = cadcog.simulate(
        points=5, trials=30, seed=4, group_size=3, self_calibrate_wire=True, samples=3,
        inclinometer_model="paper-averaged", wire_model="elastica",
    )  # fmt: skip
    assert mine.to_json() == cli_json(
        capsys, "simulate", "--points", "5", "--trials-per-pair", "30", "--seed", "4",
        "--group-size", "3", "--self-calibrate-wire", "--samples", "3",
        "--inclinometer-model", "paper-averaged", "--wire-model", "elastica",
    )  # fmt: skip
    assert (mine.model.samples, mine.model.inclinometer_model, mine.model.wire_model) == (
        3, "paper-averaged", "elastica",
    )  # fmt: skip
    assert mine.settings.self_calibrate


def test_campaign_is_what_the_command_writes(tmp_path, capsys) -> None:
    """The same readings and swings, byte for byte, and the command's --json."""
    setup = "parts/cubesat_3u_setup.toml"
    points = "+x_30_90,-x_-30_90,+y_-30_-30"
    theirs = cli_json(
        capsys, "campaign", "--setup", setup, f"--points={points}", "--seed", "3",
        "--out", str(tmp_path / "a.csv"), "--swings", str(tmp_path / "a_swings.csv"),
    )  # fmt: skip
    mine = cadcog.campaign(
        tmp_path / "b.csv",
        setup=setup,
        points=points.split(","),
        seed=3,
        swings=tmp_path / "b_swings.csv",
    )
    assert mine.to_dict() | {"out": "", "swings": ""} == json.loads(theirs) | {
        "out": "",
        "swings": "",
    }
    for a, b in (("a.csv", "b.csv"), ("a_swings.csv", "b_swings.csv")):
        assert (tmp_path / a).read_bytes() == (tmp_path / b).read_bytes()


def test_a_campaign_that_cannot_write_its_swings_writes_nothing(tmp_path) -> None:
    """All outputs or none: the swings' folder is a file, so the readings are not left."""

    (tmp_path / "blocker").write_text("a file", encoding="utf-8")
    with pytest.raises(CadcogError):
        cadcog.campaign(tmp_path / "r.csv", swings=tmp_path / "blocker" / "s.csv")
    assert not (tmp_path / "r.csv").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["blocker"]
