"""``cadcog balance`` end to end: on a STEP model, on the example CubeSat's set-up, on a test's
readings (the ballast checked against the truth the test was simulated on), and bad input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import cadcog
from cadcog.cli import main
from cadcog.rig.file import default_rig_path
from support.stepfixtures import Assembly, Part, write_step

PARTS = default_rig_path().parent
SETUP = PARTS / "cubesat_3u_setup.toml"
POINTS = "+x_-30_-30,-x_30_-30,+y_30_-30,-y_-30_-30"

# free places in the example CubeSat (between its boards and the end plates, inside a rail)
CUBESAT_BALLAST = """
max_total_mass_kg = 0.5
[[points]]
id = "zm"
position_mm = [0.0, 0.0, -160.0]
max_mass_kg = 0.3
[[points]]
id = "zp"
position_mm = [0.0, 0.0, 160.0]
max_mass_kg = 0.3
[[points]]
id = "xm"
position_mm = [-40.0, 0.0, 0.0]
"""


@pytest.fixture(scope="module")
def lopsided(tmp_path_factory):
    """A 100 mm aluminium cube with a 20 mm steel block beyond +x: the box's centre at
    x = 12.5 mm, the CoG at 1.5 mm (11 mm towards -x)."""
    tmp = tmp_path_factory.mktemp("balance")
    top = Assembly("sat")
    top.add(Part("frame", [((100.0, 100.0, 100.0), (-50.0, -50.0, -50.0))], 2700.0, "Al"))
    top.add(Part("weight", [((20.0, 20.0, 20.0), (55.0, -10.0, -10.0))], 7850.0, "steel"))
    step = write_step(top, tmp / "sat.step")
    mats = tmp / "materials.toml"
    mats.write_text('[materials]\n"*" = 2700\nweight = 7850\n[mass_uncertainty]\n"*" = 0.02\n')
    return step, mats


def _ballast(tmp: Path, text: str, name: str = "b.toml") -> Path:
    path = tmp / name
    path.write_text(text, encoding="utf-8")
    return path


def _run(capsys, *args: str) -> tuple[int, str, str]:
    status = main(["balance", *args])
    out, err = capsys.readouterr()
    return status, out, err


def test_a_model_is_balanced_and_the_api_gives_the_command_s_json(lopsided, tmp_path, capsys):
    step, mats = lopsided
    b = _ballast(tmp_path, '[[points]]\nid = "W1"\nposition_mm = [70.0, 30.0, 0.0]\n')
    args = [str(step), "--materials", str(mats), "--ballast", str(b)]
    status, out, _ = _run(capsys, *args, "--cog-limits-mm", "5,20,20", "--json")
    assert status == 0
    d = json.loads(out)
    assert d["feasible"] and d["optimal"] and d["source"] == "CAD"
    assert [x["id"] for x in d["ballast"]] == ["W1"]
    assert d["total_ballast_kg"] == pytest.approx(d["ballast"][0]["mass_kg"])
    assert abs(d["offset_mm"][0]) < 5.0 and min(d["margin_mm"]) > -1e-9
    assert d["probability_inside"] >= 0.95 - 1e-6
    assert d["budget"][-1]["mass_kg"] == pytest.approx(d["mass_kg"])
    api = cadcog.balance(b, step, mats, cog_limits_mm=[5, 20, 20])
    assert json.loads(api.to_json()) == d
    status, text, _ = _run(capsys, *args, "--cog-limits-mm", "5,20,20")
    assert status == 0 and "W1" in text and "P(inside)" in text


def test_no_ballast_within_the_limits_exits_1_naming_the_face(lopsided, tmp_path, capsys):
    step, mats = lopsided
    b = _ballast(
        tmp_path, '[[points]]\nid = "W1"\nposition_mm = [70.0, 30.0, 0.0]\nmax_mass_kg = 0.01\n'
    )
    status, out, _ = _run(
        capsys, str(step), "--materials", str(mats), "--ballast", str(b), "--cog-limits-mm=2,20,20"
    )
    assert status == 1
    assert "-x face: short by" in out


def test_the_example_cubesat_set_up_with_discrete_pieces(tmp_path, capsys):
    b = _ballast(tmp_path, "sizes_kg = [0.005, 0.02]\n" + CUBESAT_BALLAST)
    status, out, _ = _run(
        capsys, "--setup", str(SETUP), "--ballast", str(b), "--cog-limits-mm=20,20,8", "--json"
    )
    assert status == 0, out
    d = json.loads(out)
    assert d["feasible"] and d["optimal"]
    for item in d["ballast"]:
        pieces = sum(p["size_kg"] * p["count"] for p in item["pieces"])
        assert pieces == pytest.approx(item["mass_kg"])
    assert d["margin_mm"][2] >= -1e-9


def test_a_test_s_readings_are_balanced_and_the_truth_lands_inside(tmp_path, capsys):
    """The truth carries 105 g of copper near +z the CAD does not know (its CoG ~4 mm above the
    CAD's); the test on the truth, updated, is balanced into a ±10 mm z envelope: the truth with
    that ballast is inside, and the figures balanced are the truth's within 3 σ."""
    from cadcog.spacecraft.setup import load_setup

    spec = tmp_path / "truth_spec.toml"
    spec.write_text(
        (PARTS / "cubesat_3u.toml").read_text(encoding="utf-8")
        + '\n[[components]]\nname = "copper"\nmaterial = "copper C11000"\n'
        "size_mm = [14.0, 14.0, 60.0]\ncenter_mm = [32.0, -33.0, 120.0]\n"
    )
    text = SETUP.read_text(encoding="utf-8").replace(
        'model = "cubesat_3u.toml"', 'model = "truth_spec.toml"'
    )
    text = text.replace(
        'rig = "paper_rig.toml"', f'rig = "{(PARTS / "paper_rig.toml").as_posix()}"'
    )
    truth_setup = tmp_path / "truth_setup.toml"
    truth_setup.write_text(text)
    truth = load_setup(truth_setup).mass
    readings = tmp_path / "r.csv"
    args = ["campaign", "--setup", str(truth_setup), f"--points={POINTS}", "--seed", "5"]
    assert main([*args, "--out", str(readings)]) == 0
    capsys.readouterr()
    b = _ballast(tmp_path, CUBESAT_BALLAST)
    common = ["--setup", str(SETUP), "--ballast", str(b), "--cog-limits-mm=20,20,10", "--json"]
    w = f"{truth.mass_kg!r}"
    status, out, _ = _run(capsys, *common, "--readings", str(readings), "--weighed-mass-kg", w)
    assert status == 0, out
    d = json.loads(out)
    assert d["source"].startswith("update")
    positions = {"zm": [0, 0, -160.0], "zp": [0, 0, 160.0], "xm": [-40.0, 0, 0]}
    moment = truth.mass_kg * truth.cog_mm
    for item in d["ballast"]:
        moment = moment + item["mass_kg"] * np.array(positions[item["id"]])
    cog = moment / (truth.mass_kg + d["total_ballast_kg"])
    centre = np.asarray(d["geometric_center_mm"])
    assert np.all(np.abs(cog - centre) <= [20, 20, 10]), cog
    assert abs(truth.cog_mm[2] - centre[2]) > 10.0  # the truth needed ballast
    before = d["before"]
    e = np.asarray(before["cog_mm"]) - truth.cog_mm
    assert e @ np.linalg.solve(np.asarray(before["cog_cov_mm2"]), e) < 14.2  # χ²₃ at 99.7 %


@pytest.mark.parametrize(
    ("text", "extra", "message"),
    [
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\n[[points]]\nid = "a"\n'
            "position_mm = [71, 30, 0]\n",
            [],
            "key 'points[1].id': 'a' is listed twice",
        ),
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\nmax_mass_kg = -1\n',
            [],
            "key 'points[0].max_mass_kg': expected a positive number",
        ),
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\nmax_mass_kg = 1e9\n',
            [],
            "key 'points[0].max_mass_kg': expected at most",
        ),
        (
            'sizes_kg = [0.0]\n[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\n',
            [],
            "key 'sizes_kg': element 0: expected a positive number",
        ),
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\nmass = 1\n',
            [],
            "key 'points[0].mass': unknown key",
        ),
        ('[[points]]\nid = "a b"\nposition_mm = [70, 30, 0]\n', [], "key 'points[0].id': 'a b'"),
        (
            '[[points]]\nid = "a"\nposition_mm = [0, 0, 0]\n',
            [],
            "key 'points[0].position_mm': 'a' at [0.0, 0.0, 0.0] mm lies inside the solid",
        ),
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\n',
            ["--confidence", "1.5"],
            "--confidence",
        ),
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\n',
            ["--confidence", "0"],
            "--confidence",
        ),
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\n',
            ["--readings", "r.csv"],
            "--readings needs --setup",
        ),
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30, -10000]\n',
            [],
            "key 'points[0].position_mm': 'a' at [70.0, 30.0, -10000.0] mm lies outside the "
            "model's bounding box",
        ),
        (
            'sizes_kg = [1e-9]\n[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\n',
            [],
            "key 'sizes_kg': 1e-09 kg: a piece lighter than 0.1 g is not ballast",
        ),
        (
            'max_total_mass_kg = 0.001\nsizes_kg = [0.005]\n[[points]]\nid = "a"\n'
            "position_mm = [70, 30, 0]\n",
            [],
            "key 'max_total_mass_kg': 0.001 kg is less than the smallest size",
        ),
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\n',
            ["--confidence", "0.3"],
            "--confidence 0.3: expected a probability from 0.5 to 0.9999",
        ),
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\n',
            ["--mass-sigma-kg", "0.002"],
            "--mass-sigma-kg goes with --readings",
        ),
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30]\n',
            [],
            "key 'points[0].position_mm': expected an array of 3 numbers, got an array of 2",
        ),
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\n',
            ["--max-axis-angle-deg", "50"],
            "--max-axis-angle-deg 50.0: expected an angle above 0 and below 45°",
        ),
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\n',
            ["--inertia-confidence", "0.9"],
            "--inertia-confidence goes with --max-product-kg-mm2 or --max-axis-angle-deg",
        ),
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\n',
            ["--max-product-kg-mm2", "100", "--configurations", "c.toml"],
            "balance the spacecraft as it stands, not its configurations",
        ),
        (
            '[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\n',
            ["--max-product-kg-mm2", "-1"],
            "--max-product-kg-mm2",
        ),
    ],
)
def test_bad_input_exits_2_with_one_line_naming_the_key(
    lopsided, tmp_path, capsys, text, extra, message
):
    step, mats = lopsided
    b = _ballast(tmp_path, text)
    limits = ["--cog-limits-mm=5,20,20"]
    status, out, err = _run(
        capsys, str(step), "--materials", str(mats), "--ballast", str(b), *limits, *extra
    )
    assert status == 2, (out, err)
    assert out == ""
    assert message in err, err
    assert len(err.strip().splitlines()) == 1, err


def test_no_envelope_is_refused(lopsided, tmp_path, capsys):
    step, mats = lopsided
    b = _ballast(tmp_path, '[[points]]\nid = "a"\nposition_mm = [70, 30, 0]\n')
    status, _, err = _run(capsys, str(step), "--materials", str(mats), "--ballast", str(b))
    assert status == 2 and "no envelope" in err


def test_ballast_that_only_dilutes_the_uncertainty_is_told_from_ballast_that_moves_the_cog():
    """A CoG at the centre with σ 1.5 mm in a ±2 mm envelope, ballast allowed on both sides:
    equal masses on each side, the CoG does not move, its σ shrinks (said); a CoG 10 mm off
    with no uncertainty: the ballast moves it (not said)."""
    from cadcog.runs.balance import mostly_dilutes
    from cadcog.spacecraft.balance import least_ballast
    from cadcog.spacecraft.ballast_spec import BallastPoint, BallastSpec, UncertainMass

    points = (BallastPoint("a", np.array([-50.0, 0, 0])), BallastPoint("b", np.array([50.0, 0, 0])))
    centred = UncertainMass(1.0, 0.0, np.zeros(3), np.diag([2.25, 0.01, 0.01]), np.zeros(3), "")
    r = least_ballast(centred, BallastSpec(points), np.zeros(3), [2.0, 20.0, 20.0])
    assert r.total_ballast_kg > 0 and abs(r.cog_mm[0]) < 0.2 and mostly_dilutes(r)
    off = UncertainMass(1.0, 0.0, np.array([10.0, 0, 0]), np.zeros((3, 3)), np.zeros(3), "")
    r = least_ballast(off, BallastSpec(points), np.zeros(3), [2.0, 20.0, 20.0])
    assert r.total_ballast_kg > 0 and not mostly_dilutes(r)


def test_the_envelope_s_source_and_a_form_factor_that_does_not_fit_are_said(
    lopsided, tmp_path, capsys
):
    """A PocketQube's limits are provisional (said in the JSON and the text); a 3U's envelope
    on a 120 mm cube is said not to fit."""
    step, mats = lopsided
    b = _ballast(tmp_path, '[[points]]\nid = "W1"\nposition_mm = [70.0, 30.0, 0.0]\n')
    args = [str(step), "--materials", str(mats), "--ballast", str(b)]
    status, out, _ = _run(capsys, *args, "--form-factor", "1p", "--json")
    assert status in (0, 1) and "PROVISIONAL" in json.loads(out)["envelope_source"]
    status, out, _ = _run(capsys, *args, "--form-factor", "3U")
    assert "limits: CubeSat Design Specification" in out
    assert "form factor 3U: the model's box" in out
    assert "balance takes the model's axes" in out


def test_a_product_limit_on_the_example_cubesat_and_the_api_gives_the_command_s_json(
    tmp_path, capsys
):
    """The 3U's CAD P_yz is 987 kg·mm² (± 120): a limit of 500 at 95 % asks where the CoG's
    118 g goes; the products after meet it with their own margin, the CoG's too."""
    b = _ballast(
        tmp_path,
        CUBESAT_BALLAST
        + '[[points]]\nid = "yp_zm"\nposition_mm = [0.0, 45.0, -160.0]\nmax_mass_kg = 0.3\n',
    )
    args = ["--setup", str(SETUP), "--ballast", str(b), "--cog-limits-mm=20,20,10"]
    status, out, _ = _run(capsys, *args, "--max-product-kg-mm2", "500", "--json")
    assert status == 0, out
    d = json.loads(out)
    info = d["inertia"]
    assert info["before"]["products_kg_mm2"]["Pyz"] > 900 and not info["before"]["met"]
    after, z = info["after"], info["objectives"]["quantile"]
    for name, value in after["products_kg_mm2"].items():
        assert abs(value) + z * after["products_sigma_kg_mm2"][name] <= 500 * (1 + 1e-6)
    assert after["met"] and d["feasible"] and min(d["margin_mm"]) >= -1e-9
    assert [x["id"] for x in d["ballast"]][-1] == "yp_zm"  # the off-axis location does it
    assert d["total_ballast_kg"] >= d["bound_kg"] * (1 - 1e-9)
    api = cadcog.balance(b, setup=SETUP, cog_limits_mm=[20, 20, 10], max_product_kg_mm2=500)
    assert json.loads(api.to_json()) == d
    status, text, _ = _run(capsys, *args, "--max-product-kg-mm2", "500")
    assert status == 0 and "products about the CoG" in text and "with it" in text
