"""``cadcog parts build`` end to end, in-process."""

from __future__ import annotations

import hashlib
import json

import pytest

pytest.importorskip("build123d")

from cadcog.cad.build import GROUND_TRUTH_FILE, STEP_FILE
from cadcog.cli import main
from support.rigtools import paper_rig_dict, write_rig


def _digest(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_build_default_rig_writes_everything_and_is_deterministic(tmp_path, capsys):
    out1, out2 = tmp_path / "a", tmp_path / "b"
    assert main(["parts", "build", "--out", str(out1)]) == 0
    printed = capsys.readouterr().out
    assert "paper_rig" in printed and "assembly" in printed
    assert main(["parts", "build", "--out", str(out2)]) == 0
    names = sorted(p.relative_to(out1).as_posix() for p in out1.rglob("*") if p.is_file())
    assert names == [
        "assembly.step",
        "ground_truth.json",
        "stl/arduino_uno.stl",
        "stl/battery.stl",
        "stl/proof_mass.stl",
        "stl/protoboard_inclinometer.stl",
        "stl/transmitter.stl",
    ]
    # Byte-identical rebuild. The STEP file is left out here: OCCT numbers its assembly usages
    # with a per-process counter, so only rebuilds in fresh processes give identical STEP files.
    for name in names:
        if name != STEP_FILE:
            assert _digest(out1 / name) == _digest(out2 / name), name
    truth = json.loads((out1 / GROUND_TRUTH_FILE).read_text())
    for key in ("proof_mass", "measurement_equipment", "arduino_uno", "battery"):
        assert set(truth["bodies"][key]) >= {"mass_kg", "cog_mm", "inertia_kg_mm2", "volume_mm3"}
    assert set(truth["suspension_points"][0]) >= {"id", "position_mm", "normal"}
    assert "estimated_relative_error" in truth["integration"]
    assert not list(tmp_path.glob(".*partial"))  # no staging directory left behind


def test_a_modified_copy_of_the_rig_builds_with_its_new_values(tmp_path):
    data = paper_rig_dict()
    data["proof_mass"]["mass_kg"] = 10.0
    data["measurement_equipment"]["volumes"][3]["mass_kg"] = 0.1
    rig = write_rig(tmp_path / "heavier.toml", data)
    assert main(["parts", "build", str(rig), "--out", str(tmp_path / "out")]) == 0
    truth = json.loads((tmp_path / "out" / GROUND_TRUTH_FILE).read_text())
    assert truth["bodies"]["proof_mass"]["mass_kg"] == pytest.approx(10.0)
    assert truth["bodies"]["measurement_equipment"]["mass_kg"] == pytest.approx(0.23)


def test_bad_rig_exits_2_names_the_key_and_writes_nothing(tmp_path, capsys):
    data = paper_rig_dict()
    data["holes"]["depth_mm"] = 100.0
    rig = write_rig(tmp_path / "bad.toml", data)
    before = _digest(rig)
    out = tmp_path / "out"
    assert main(["parts", "build", str(rig), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "bad.toml" in err and "holes.depth_mm" in err
    assert not out.exists()
    assert _digest(rig) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]


def test_existing_outputs_survive_a_failed_build(tmp_path):
    out = tmp_path / "out"
    assert main(["parts", "build", "--out", str(out)]) == 0
    before = _digest(out / STEP_FILE)
    data = paper_rig_dict()
    data["proof_mass"]["mass_kg"] = -1
    rig = write_rig(tmp_path / "bad.toml", data)
    assert main(["parts", "build", str(rig), "--out", str(out)]) == 2
    assert _digest(out / STEP_FILE) == before


def test_campaign_json_and_report_line(tmp_path, capsys):
    """``campaign --json`` says what it wrote; the file it wrote is named on stderr."""
    from cadcog.method.readings import read_readings

    out = tmp_path / "c.csv"
    assert main(["campaign", "--seed", "4", "--out", str(out), "--json"]) == 0
    captured = capsys.readouterr()
    data = json.loads(captured.out)
    assert captured.err.strip() == f"report: {out}"
    assert data["n_hangs"] == len(read_readings(out)) and data["seed"] == 4
    assert data["n_samples"] == sum(1 for _ in out.open(encoding="utf-8")) - 2  # comment, header
