"""``cadcog.api.measure``: estimate, update and inertia are what the commands compute."""

from __future__ import annotations

import json

import pytest

import cadcog
from cadcog.cli import main
from cadcog.core.errors import CadcogError
from tests.api.commandline import cli_json


def test_estimate_is_what_the_command_prints(campaign_csv, capsys) -> None:
    rig = cadcog.load_rig()
    mine = cadcog.estimate(campaign_csv, rig)
    assert mine.to_json() == cli_json(
        capsys, "estimate", str(campaign_csv), "--rig", str(rig.source)
    )
    assert json.loads(mine.to_json())["cog_mm"] == pytest.approx(mine.cog_mm.tolist(), rel=1e-9)


def test_estimate_without_a_rig_is_the_command_without_one(campaign_csv, capsys) -> None:
    mine = cadcog.estimate(campaign_csv)
    assert mine.compensation is None
    assert mine.to_json() == cli_json(capsys, "estimate", str(campaign_csv))


def test_estimate_refuses_a_hang_naming_the_readings_file_as_the_command(tmp_path) -> None:
    """A point inside the body (no face, no bolt axis): the API's error names the readings
    file and line, as the command's does (it named the line only before runs/estimate.py)."""
    from support.rigtools import ideal_rows, write_csv

    rig = cadcog.load_rig()
    rows = ideal_rows(rig)
    rows.append("S9,100,30,30,10,5,true")
    csv = write_csv(tmp_path / "r.csv", rows)
    with pytest.raises(CadcogError, match=r"r\.csv: line 8: suspension S9 .* inside the bounding"):
        cadcog.estimate(csv, rig)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"weighed_mass_kg": [9.2]}, r"weighed_mass_kg=\[9\.2\]\): expected one number"),
        ({"weighed_mass_kg": (9.2, 1)}, r"expected one number"),
        ({"wire_correction": "no"}, r"wire_correction='no'\): expected True or False, got str"),
        ({"self_calibrate_wire": None}, r"expected True or False, got None\b"),
        ({"mass_sigma_kg": 0.5}, r"mass_sigma_kg=0\.5\): goes with weighed_mass_kg"),
        ({"weighed_mass_kg": 0.1}, r"campaign\.csv: the object CoG .* is outside the object"),
    ],
)
def test_estimate_refuses_what_the_command_refuses(campaign_csv, kwargs, message) -> None:
    """Round 4 of the reliability audit: a list where one number goes, a string or None where
    a yes/no goes ('no' is true to Python), a weighing's σ without a weighing, a weighed mass
    that puts the CoG outside the object: a CadcogError naming the argument (or the file)."""
    with pytest.raises(CadcogError, match=message):
        cadcog.estimate(campaign_csv, cadcog.load_rig(), **kwargs)


def test_update_is_what_the_command_prints(tmp_path, capsys) -> None:
    setup = "parts/cubesat_3u_setup.toml"
    csv = tmp_path / "r.csv"
    points = "--points=+x_-30_-30,-x_30_-30,+y_30_-30,-y_-30_-30"
    assert main(["campaign", "--setup", setup, points, "--out", str(csv)]) == 0
    capsys.readouterr()
    mine = cadcog.update(csv, setup, 2.6, unmodelled_region_mm=(-45, -45, -165, 45, 45, -140),
                         unmodelled_sigma_kg=0.1)  # fmt: skip
    theirs = cli_json(
        capsys, "update", str(csv), "--setup", setup, "--weighed-mass-kg", "2.6",
        "--unmodelled-region-mm=-45,-45,-165,45,45,-140", "--unmodelled-sigma-kg", "0.1",
    )  # fmt: skip
    assert mine.to_json() == theirs
    assert mine.to_dict()["verdict"]["differs"]  # 17 g over the CAD, weighed to 1 g


def test_update_with_swings_is_what_the_command_prints(tmp_path, capsys) -> None:
    setup = "parts/cubesat_3u_setup.toml"
    csv, swings = tmp_path / "r.csv", tmp_path / "swings.csv"
    points = "--points=+x_-30_-30,-x_30_-30,+y_30_-30,-y_-30_-30"
    argv = ["campaign", "--setup", setup, points, "--out", str(csv), "--swings", str(swings)]
    assert main(argv) == 0
    capsys.readouterr()
    mine = cadcog.update(csv, setup, 2.6, mass_sigma_kg=0.002, swings=swings)
    theirs = cli_json(
        capsys, "update", str(csv), "--setup", setup, "--weighed-mass-kg", "2.6",
        "--mass-sigma-kg", "0.002", "--swings", str(swings),
    )  # fmt: skip
    assert mine.to_json() == theirs
    assert mine.dof == 10  # the tensor's six entries observed with the mass and the CoG


def test_swings_that_give_no_inertia_are_a_note_not_a_failure(tmp_path, monkeypatch) -> None:
    """``update --swings`` on swings the modal fit cannot read (a light object, a release with
    no twist): the CoG and mass update still runs, and says which file was not used and why;
    a swing file that cannot be read at all stays an error."""
    from cadcog.core.errors import CadcogError, DegenerateGeometryError
    from cadcog.dynamics import measure

    setup = "parts/cubesat_3u_setup.toml"
    points = ["+x_30_90", "-x_-30_90", "+y_-30_-30", "-y_30_-30"]
    cadcog.campaign(tmp_path / "r.csv", setup=setup, points=points, swings=tmp_path / "s.csv")

    def no_modes(*args, **kwargs):
        raise DegenerateGeometryError("hang +x_30_90: no swing mode stands out of the noise")

    monkeypatch.setattr(measure, "inertia_observation", no_modes)
    r = cadcog.update(tmp_path / "r.csv", setup, 2.583, swings=tmp_path / "s.csv")
    (note,) = [n for n in r.notes if "swings" in n]
    assert "s.csv" in note and "no swing mode stands out" in note
    assert r.dof == 4  # mass and CoG only
    monkeypatch.undo()
    (tmp_path / "bad.csv").write_text("point_id,t_s,inc_x_deg,inc_y_deg\nS1,x,1,2\n", "utf-8")
    with pytest.raises(CadcogError, match=r"bad\.csv"):
        cadcog.update(tmp_path / "r.csv", setup, 2.583, swings=tmp_path / "bad.csv")
