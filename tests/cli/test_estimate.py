"""``cadcog estimate`` in-process: JSON contract, compensation sources, errors."""

from __future__ import annotations

import hashlib
import json

import numpy as np
import pytest

from cadcog.cli import main
from support.rigtools import ideal_rows, paper_rig_dict, write_csv, write_rig


def _run_json(capsys, *argv):
    assert main(["estimate", *argv, "--json"]) == 0
    captured = capsys.readouterr()
    return json.loads(captured.out), captured.err


def test_rig_compensation_recovers_the_proof_mass_cog(tmp_path, capsys, paper_rig):
    csv = write_csv(tmp_path / "r.csv", ideal_rows(paper_rig))
    out, _ = _run_json(capsys, str(csv), "--rig", str(paper_rig.source))
    assert set(out) >= {"assembly_cog_mm", "cog_mm", "cov_mm2", "pairs", "warnings"}
    np.testing.assert_allclose(
        out["assembly_cog_mm"], paper_rig.analytic_assembly.cog_mm, atol=1e-9
    )
    np.testing.assert_allclose(out["cog_mm"], paper_rig.analytic_proof_mass.cog_mm, atol=1e-9)
    assert len(out["pairs"]) == 15
    assert {"a", "b", "midpoint_mm", "gap_mm", "angle_deg"} <= set(out["pairs"][0])
    assert out["compensation"]["applied"] is True
    assert out["warnings"] == []
    cov = np.array(out["cov_mm2"])
    assert cov.shape == (3, 3) and np.all(np.linalg.eigvalsh(cov) > 0)
    # The compensated covariance includes the ME's (m_ME/m)² · 1.67² share.
    assert np.all(np.diag(cov) > np.diag(out["assembly_cov_mm2"]))


def test_min_angle_zero_screens_no_pair(tmp_path, capsys, paper_rig):
    """``--min-angle-deg 0`` is within its documented bound (0 … 90): no pair is screened out,
    and on the paper rig's ideal readings (no pair below the default) the estimate is the
    default's."""
    csv = write_csv(tmp_path / "r.csv", ideal_rows(paper_rig))
    default, _ = _run_json(capsys, str(csv), "--rig", str(paper_rig.source))
    zero, _ = _run_json(capsys, str(csv), "--rig", str(paper_rig.source), "--min-angle-deg", "0")
    assert len(zero["pairs"]) == len(default["pairs"]) == 15
    np.testing.assert_allclose(zero["cog_mm"], default["cog_mm"], rtol=0, atol=1e-12)


def test_readings_of_another_object_under_a_rig_are_warned_about(capsys, paper_rig):
    """The example spacecraft's readings estimated with the paper rig (a wrong --rig): the
    numbers are the rig's object's, and the command says the hangs are none of its points."""
    from cadcog.rig.file import default_rig_path

    examples = default_rig_path().parents[1] / "docs" / "examples"
    out, err = _run_json(capsys, str(examples / "cubesat_3u_readings.csv"), "--rig",
                         str(paper_rig.source))  # fmt: skip
    assert any("hang from none of rig paper_rig's" in w for w in out["warnings"])
    assert "--setup" in err
    out, _ = _run_json(capsys, str(examples / "paper_rig_readings.csv"), "--rig",
                       str(paper_rig.source))  # fmt: skip
    assert not any("none of rig" in w for w in out["warnings"])


def test_direct_me_values_equal_the_rig_path(tmp_path, capsys, paper_rig):
    csv = write_csv(tmp_path / "r.csv", ideal_rows(paper_rig, wire_offset_mm=0.0))
    me = paper_rig.analytic_me
    cog = ",".join(repr(float(c)) for c in me.cog_mm)
    out, _ = _run_json(
        capsys,
        str(csv),
        "--object-mass-kg",
        "9.2",
        "--me-mass-kg",
        repr(me.mass_kg),
        "--me-cog-mm",
        cog,
    )
    np.testing.assert_allclose(out["cog_mm"], paper_rig.analytic_proof_mass.cog_mm, atol=1e-9)


def test_without_me_data_the_result_says_so(tmp_path, capsys, paper_rig):
    csv = write_csv(tmp_path / "r.csv", ideal_rows(paper_rig, wire_offset_mm=0.0))
    out, err = _run_json(capsys, str(csv))
    assert out["cog_mm"] == out["assembly_cog_mm"]
    assert out["compensation"] == {"applied": False}
    assert any("not compensated" in w for w in out["warnings"])
    assert "not compensated" in err


def test_table_output(tmp_path, capsys, paper_rig):
    csv = write_csv(tmp_path / "r.csv", ideal_rows(paper_rig))
    assert main(["estimate", str(csv), "--rig", str(paper_rig.source)]) == 0
    out = capsys.readouterr().out
    assert "object CoG (ME removed)" in out and "S1 & S2" in out and " yes " in out


def test_sign_flip_in_the_rig_file(tmp_path, capsys, paper_rig):
    data = paper_rig_dict()
    data["inclinometer"]["sign_x"] = -1
    rig = write_rig(tmp_path / "flipped.toml", data)
    rows = []
    for row in ideal_rows(paper_rig):
        f = row.split(",")
        f[4] = repr(-float(f[4]))  # a device whose x axis reads reversed
        rows.append(",".join(f))
    out, _ = _run_json(capsys, str(write_csv(tmp_path / "r.csv", rows)), "--rig", str(rig))
    np.testing.assert_allclose(out["cog_mm"], paper_rig.analytic_proof_mass.cog_mm, atol=1e-9)


def test_normalisation_is_warned_and_counted(tmp_path, capsys, paper_rig):
    rows = ideal_rows(paper_rig, wire_offset_mm=0.0)
    rows.append("S9,100,0,0,50,50,true")
    out, _ = _run_json(capsys, str(write_csv(tmp_path / "r.csv", rows)))
    assert out["n_normalized"] == 1
    assert any("S9" in w and "normalised" in w for w in out["warnings"])


def test_outlier_suspension_is_flagged(tmp_path, capsys, paper_rig):
    rows = ideal_rows(paper_rig, wire_offset_mm=0.0)
    f = rows[2].split(",")
    f[4] = repr(float(f[4]) + 3.0)  # 3° off on one suspension
    rows[2] = ",".join(f)
    out, err = _run_json(capsys, str(write_csv(tmp_path / "r.csv", rows)))
    flagged = [s["id"] for s in out["suspensions"] if s["inconsistent"]]
    assert flagged == ["S3"]
    assert "S3" in err and "inconsistent" in err


@pytest.mark.parametrize(
    ("rows", "message"),
    [
        (
            ["S1,0,0,100,10,5,true", "S2,100,0,0,-30,0,false", "S1,0,0,1,10,5,true"],
            "line 4: point S1 at",
        ),
        (["S1,0,0,100,10,5,true"], "needs at least two"),
        (["S1,0,0,100,0,0,true", "S2,0,0,-100,0,0,false"], "every pair of plumb lines"),
        (["S1,0,0,100,10,5,true", "S2,0,0,-100,nan,0,false"], "line 3: column inc_x_deg"),
    ],
    ids=["two positions", "one point", "all pairs parallel", "nan"],
)
def test_errors_exit_2_with_message_and_leave_input_alone(tmp_path, capsys, rows, message):
    csv = write_csv(tmp_path / "r.csv", rows)
    before = hashlib.sha256(csv.read_bytes()).hexdigest()
    assert main(["estimate", str(csv)]) == 2
    captured = capsys.readouterr()
    assert message in captured.err
    assert captured.out == ""
    assert hashlib.sha256(csv.read_bytes()).hexdigest() == before


def test_inconsistent_options(tmp_path, capsys, paper_rig):
    csv = write_csv(tmp_path / "r.csv", ideal_rows(paper_rig))
    assert main(["estimate", str(csv), "--me-mass-kg", "0.2"]) == 2
    assert "go together" in capsys.readouterr().err
    assert main(["estimate", str(csv), "--rig", str(paper_rig.source), "--me-mass-kg", "1"]) == 2
    assert "either --rig" in capsys.readouterr().err


def test_sigma_options_are_checked_with_setup_too(tmp_path, capsys):
    csv = write_csv(tmp_path / "r.csv", ["S1,0,0,100,10,5,true", "S2,100,0,0,-30,0,false"])
    assert main(["estimate", str(csv), "--setup", "unused.toml", "--point-sigma-mm", "0"]) == 2
    assert "--point-sigma-mm 0.0: expected more than 0" in capsys.readouterr().err


def test_self_calibrated_wire_scale_is_found_and_reported(tmp_path, capsys, paper_rig):
    """Noise-free hangs whose wire offset is 0.8 mm, not the 0.5 mm the rig file expects."""
    csv = write_csv(tmp_path / "r.csv", ideal_rows(paper_rig, wire_offset_mm=0.8))
    rig = str(paper_rig.source)
    out, _ = _run_json(capsys, str(csv), "--rig", rig, "--self-calibrate-wire")
    assert out["wire"]["estimated"] is True and out["wire"]["prior_mm"] == 0.5
    assert out["wire"]["scale_mm"] == pytest.approx(0.8, abs=1e-9)
    assert out["wire"]["sigma_mm"] > 0
    np.testing.assert_allclose(out["cog_mm"], paper_rig.analytic_proof_mass.cog_mm, atol=1e-9)
    # Without self-calibration the one-wire model still takes λ as one unknown of the test,
    # with the rig's prior (0.5 ± 0.5 mm): the hangs pull it most of the way to 0.8 mm.
    prior, _ = _run_json(capsys, str(csv), "--rig", rig)
    assert prior["wire"]["estimated"] is False and prior["wire"]["prior_mm"] == 0.5
    assert 0.65 < prior["wire"]["scale_mm"] <= 0.8 and 0 < prior["wire"]["sigma_mm"] < 0.5
    assert main(["estimate", str(csv), "--rig", rig]) == 0
    assert "wire offset scale λ, from the hangs and the error model's 0.500 mm: 0.7" in (
        capsys.readouterr().out
    )


def test_wire_options_need_bolt_axes_and_three_hangs(tmp_path, capsys, paper_rig):
    rows = ideal_rows(paper_rig)
    csv = write_csv(tmp_path / "r.csv", rows)
    assert main(["estimate", str(csv), "--self-calibrate-wire"]) == 2
    assert "need --rig or --setup" in capsys.readouterr().err
    two = write_csv(tmp_path / "two.csv", rows[:2])
    assert (
        main(["estimate", str(two), "--rig", str(paper_rig.source), "--self-calibrate-wire"]) == 2
    )
    err = capsys.readouterr().err
    assert "three or more suspensions" in err and str(two) in err


def test_point_inside_the_body_names_the_line(tmp_path, capsys, paper_rig):
    rows = ideal_rows(paper_rig)
    rows.append("S9,100,30,30,10,5,true")  # inside the proof mass: no face, no bolt axis
    csv = write_csv(tmp_path / "r.csv", rows)
    assert main(["estimate", str(csv), "--rig", str(paper_rig.source)]) == 2
    err = capsys.readouterr().err
    assert f"{csv}: line 8: suspension S9" in err and "inside the bounding box of the body" in err
