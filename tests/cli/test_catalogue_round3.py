"""The third reliability catalogue's failures (issue 33), each as a case: one line on stderr
naming the file, key or option, exit 2, nothing written; checked to fail on the code before."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

import cadcog
from cadcog.cli import main
from cadcog.core.errors import CadcogError

PARTS = Path(cadcog.__file__).resolve().parents[1] / "parts"
SETUP = PARTS / "cubesat_3u_setup.toml"


def _refused(capsys, args, *names: str) -> str:
    assert main(args) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1, err
    for name in names:
        assert name in err, err
    return err


def test_a_fifo_as_a_parameter_file_is_refused_not_waited_on(tmp_path, capsys):
    fifo = tmp_path / "m.toml"
    os.mkfifo(fifo)
    _refused(capsys, ["plan", str(fifo)], str(fifo), "not a regular file")


def test_an_integer_too_long_for_python_names_its_line(tmp_path, capsys):
    big = tmp_path / "rig.toml"
    big.write_text("# a rig\n[proof_mass]\nmass_kg = 1" + "0" * 4999 + "\n", encoding="utf-8")
    _refused(capsys, ["campaign", "--rig", str(big), "--out", str(tmp_path / "c.csv")],
             f"{big}: line 3: an integer of 5000 digits")  # fmt: skip
    assert not (tmp_path / "c.csv").exists()


def test_campaign_swings_onto_a_device_writes_neither_output(tmp_path, capsys):
    out = tmp_path / "c.csv"
    _refused(capsys, ["campaign", "--out", str(out), "--swings", "/dev/full"], "/dev/full")
    assert not out.exists()
    _refused(capsys, ["campaign", "--out", str(out), "--swings", str(out)], str(out))


def test_acquire_swings_onto_a_device_creates_no_readings_file(tmp_path, capsys):
    out = tmp_path / "a.csv"
    args = ["acquire", "--simulate", "--non-interactive", "--out", str(out), "--swings"]
    _refused(capsys, [*args, "/dev/full"], "/dev/full")
    assert not out.exists()


def test_massprops_csv_and_report_on_one_path_write_nothing(tmp_path, capsys):
    step = tmp_path / "cs" / "cubesat_3u.step"
    assert main(["parts", "cubesat", "--out", str(step.parent)]) == 0
    capsys.readouterr()
    rep = tmp_path / "rep"
    mats = step.parent / "cubesat_3u_materials.toml"
    args = ["massprops", str(step), "--materials", str(mats), "--report", str(rep)]
    _refused(capsys, [*args, "--csv", str(rep)], "--csv and --report name the same path")
    assert not rep.exists()
    rep.mkdir()
    _refused(capsys, [*args[:4], "--csv", str(rep)], "--csv", "is a directory")
    _refused(capsys, [*args[:4], "--total-mass-kg", "1e-300"], "--total-mass-kg")


def test_options_that_would_be_ignored_are_refused(tmp_path, capsys):
    readings = tmp_path / "c.csv"
    assert main(["campaign", "--out", str(readings)]) == 0
    capsys.readouterr()
    _refused(capsys, ["estimate", str(readings), "--mass-sigma-kg", "0.002"],
             "--mass-sigma-kg goes with --weighed-mass-kg")  # fmt: skip
    _refused(capsys, ["update", str(readings), "--setup", str(SETUP), "--weighed-mass-kg", "2.6",
                      "--unmodelled-mass-kg", "0.1"], "--unmodelled-mass-kg goes with")  # fmt: skip


def test_a_sensor_far_from_the_object_is_refused_naming_the_key(tmp_path, capsys):
    import shutil

    shutil.copytree(PARTS, tmp_path / "parts")
    setup = tmp_path / "parts" / SETUP.name
    text = setup.read_text(encoding="utf-8")
    setup.write_text(text + "\n[swing]\nsensor_position_mm = [10000.0, 0.0, 0.0]\n")
    _refused(capsys, ["plan", str(setup)], "swing.sensor_position_mm", "9")


@pytest.mark.parametrize(("change", "reason"), [("ms", "milliseconds"), ("5hz", "too slow")])
def test_a_swing_record_in_ms_or_sampled_too_slowly_says_so(tmp_path, capsys, change, reason):
    readings, swings = tmp_path / "c.csv", tmp_path / "s.csv"
    assert main(["campaign", "--out", str(readings), "--swings", str(swings)]) == 0
    capsys.readouterr()
    lines = swings.read_text(encoding="utf-8").splitlines()
    out = []
    for k, line in enumerate(lines):
        cells = line.split(",")
        if line.startswith("#") or cells[0] == "point_id":
            out.append(line)
        elif change == "ms":
            out.append(",".join([cells[0], f"{float(cells[1]) * 1000:.3f}", *cells[2:]]))
        elif k % 10 == 0:  # 50 Hz to 5 Hz
            out.append(line)
    swings.write_text("\n".join(out) + "\n", encoding="utf-8")
    err = _refused(capsys, ["inertia", str(swings), "--readings", str(readings)])
    assert reason in err and "hang S1" in err


def test_the_api_refuses_none_for_a_confidence():
    with pytest.raises(CadcogError, match=r"balance\(confidence=None\)"):
        cadcog.balance("b.toml", "m.step", "m.toml", cog_limits_mm=[20, 20, 10], confidence=None)
