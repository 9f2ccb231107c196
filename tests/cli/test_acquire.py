"""``cadcog acquire`` end to end: a simulated device on a pseudo-terminal, opened by pyserial."""

from __future__ import annotations

import json
import os
import threading
import tty
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from cadcog.cli import main

FAST = ["--time-scale", "300", "--average-s", "4", "--non-interactive"]


def test_dry_run_records_every_hang_and_recovers_the_cog(tmp_path, capsys):
    out = tmp_path / "run" / "readings.csv"
    assert main(["acquire", "--simulate", "--seed", "2", "--out", str(out), "--json", *FAST]) == 0
    data = json.loads(capsys.readouterr().out)
    # The simulated device streams in (scaled) real time, so what a hang's mean holds depends on
    # the scheduling: now and then the consistency check (a test at its stated level) asks for
    # a hang again, and the non-interactive operator redoes it.
    kept = [h for h in data["hangs"] if h["outcome"] != "redone"]
    assert [h["id"] for h in kept] == ["S1", "S2", "S3", "S4", "S5", "S6"]
    assert all(h["outcome"] == "recorded" and h["period_s"] > 0.4 for h in kept)
    assert len(data["hangs"]) - len(kept) <= 1
    assert data["simulated_truth"]["mahalanobis"] < np.sqrt(stats.chi2.ppf(0.999, 3))
    # The same file through `cadcog estimate` gives the same CoG.
    assert main(["estimate", str(out), "--rig", _rig(), "--wire-correction", "--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    np.testing.assert_allclose(again["cog_mm"], data["estimate"]["cog_mm"], atol=1e-9)
    # Running it again resumes: nothing left to do, nothing duplicated.
    before = out.read_text()
    assert main(["acquire", "--simulate", "--out", str(out), *FAST]) == 0
    assert out.read_text() == before
    assert "resuming" in capsys.readouterr().out


def _rig():
    from cadcog.rig.file import default_rig_path

    return str(default_rig_path())


def test_a_missing_port_is_one_line(tmp_path, capsys):
    out = tmp_path / "r.csv"
    assert main(["acquire", "--port", str(tmp_path / "ttyNONE"), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("cadcog: error: serial port ") and "cannot open it" in err
    assert "\n" not in err and not out.exists()


@pytest.mark.parametrize(
    ("fault", "message"),
    [
        ("foreign", "does not speak the cadcog protocol"),
        ("stall", "the stream stopped: no valid sample for 0.5 s"),
        ("never-settle", "hang S1: the swing did not settle in 20 s"),
    ],
)
def test_rehearsed_failures_are_clear_and_record_nothing_partial(tmp_path, capsys, fault, message):
    out = tmp_path / "r.csv"
    args = ["acquire", "--simulate", "--sim-fault", fault, "--out", str(out), *FAST]
    settle = ["--max-settle-s", "20"] if fault == "never-settle" else []
    assert main([*args, "--timeout-s", "0.5", *settle]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("cadcog: error:") == 1
    if out.exists():  # the stall comes after the first hangs: only whole hangs are in the file
        text = out.read_text()
        assert text.count(" begin ") == text.count(" end samples=")


def test_a_real_port_with_another_device_is_refused(tmp_path, capsys):
    """A pseudo-terminal fed by a thread that speaks NMEA, opened through --port."""
    master, slave = os.openpty()
    tty.setraw(slave)
    stop = threading.Event()

    def talk():
        while not stop.is_set():
            try:
                os.write(master, b"$GPGGA,123519,4807.038,N,01131.000,E*47\r\n")
            except OSError:
                return
            stop.wait(0.02)

    th = threading.Thread(target=talk, daemon=True)
    th.start()
    try:
        code = main(["acquire", "--port", os.ttyname(slave), "--out", str(tmp_path / "r.csv"),
                     "--timeout-s", "0.5"])  # fmt: skip
    finally:
        stop.set()
        th.join()
        os.close(master)
        os.close(slave)
    assert code == 2
    err = capsys.readouterr().err
    assert "does not speak the cadcog protocol" in err and "GPGGA" in err


def test_a_report_that_cannot_be_written_is_refused_before_the_run(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("", encoding="utf-8")
    out = tmp_path / "r.csv"
    assert main(["acquire", "--simulate", "--out", str(out), "--report", str(blocker), *FAST]) == 2
    assert "exists and is not a directory" in capsys.readouterr().err
    assert not out.exists()


def test_bad_options_are_refused(tmp_path, capsys):
    out = str(tmp_path / "r.csv")
    assert main(["acquire", "--simulate", "--out", out, "--average-s", "0"]) == 2
    assert "--average-s 0.0: expected more than 0" in capsys.readouterr().err
    assert main(["acquire", "--simulate", "--out", out, "--points", "S1,S9"]) == 2
    assert "unknown point(s) S9" in capsys.readouterr().err
    # A reversal: of a known point only, and it does not count as a second point.
    assert main(["acquire", "--simulate", "--out", out, "--points", "S1,S9~"]) == 2
    assert "unknown point(s) S9~" in capsys.readouterr().err
    assert main(["acquire", "--simulate", "--out", out, "--points", "S1,S1~"]) == 2
    assert "a point and its reversal hang alike" in capsys.readouterr().err
    assert (
        main(["acquire", "--simulate", "--out", out, "--points", "S1,S2," + "x" * 200 + "~"]) == 2
    )
    assert "longer than 200 characters" in capsys.readouterr().err
    assert not Path(out).exists()


def test_an_id_that_is_both_a_point_and_a_reversal_is_refused(tmp_path):
    from cadcog.bench.target import point_of

    assert point_of("S1~", ["S1", "S2"]) == ("S1", True)
    assert point_of("S1~", ["S1~", "S2"]) == ("S1~", False)
    with pytest.raises(ValueError, match="both a point and the reversal of point 'S1'"):
        point_of("S1~", ["S1", "S1~"])


@pytest.mark.slow
def test_a_spacecraft_set_up_dry_run_compares_with_its_cad(tmp_path, capsys):
    from cadcog.rig.file import default_rig_path

    setup = default_rig_path().parent / "cubesat_3u_setup.toml"
    out = tmp_path / "sat.csv"
    points = "+x_-30_-30,-x_-30_90,-y_-30_-30,Z1"
    args = ["acquire", "--setup", str(setup), "--points", points, "--simulate", "--json"]
    report = tmp_path / "record"
    assert main([*args, "--seed", "1", "--out", str(out), "--report", str(report), *FAST]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [h["id"] for h in data["hangs"]] == points.split(",")
    # The test record: the page, its figure, and the same summary as --json.
    assert {p.name for p in report.iterdir()} == {"index.html", "cog.png", "acquire.json"}
    assert json.loads((report / "acquire.json").read_text()) == data
    page = (report / "index.html").read_text()
    assert all(f'<td class="l">{i}</td>' in page for i in points.split(","))
    assert "Measured − CAD" in page and "3U CoG envelope" in page
    # Four hangs with swings: the record gives the tensor (or says why not) on the page and in
    # the JSON, and the swing file sits beside the readings.
    assert "Inertia from the swings" in page
    inertia = data["inertia"]
    assert "principal_moments_kg_mm2" in inertia or inertia["not_estimated"]
    assert (tmp_path / "sat.swings.csv").is_file()
    assert data["cad"]["mahalanobis"] < np.sqrt(stats.chi2.ppf(0.999, 3))
    assert data["simulated_truth"]["mahalanobis"] < np.sqrt(stats.chi2.ppf(0.999, 3))
    assert main(["estimate", str(out), "--setup", str(setup), "--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    np.testing.assert_allclose(again["cog_mm"], data["estimate"]["cog_mm"], atol=1e-9)


@pytest.mark.parametrize("swings", [None, "sw.csv"])
def test_a_swing_file_another_run_writes_is_refused_before_anything(tmp_path, capsys, swings):
    """A second run on the same swing file (given, or the default beside --out) stops at once,
    naming it: two runs had both exit 0 and interleaved their hangs in one file."""
    out = tmp_path / "a.csv"
    target = tmp_path / (swings or "a.swings.csv")
    args = ["acquire", "--simulate", "--non-interactive", "--time-scale", "50", "--out", str(out)]
    if swings:
        args += ["--swings", str(target)]
    import subprocess
    import sys

    holder = subprocess.Popen(
        [sys.executable, "-c",
         "import sys, time\nfrom cadcog.core.fileio import output_lock\n"
         f"with output_lock({str(target)!r}):\n    print('held', flush=True)\n    time.sleep(30)"],
        stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert holder.stdout is not None and holder.stdout.readline().strip() == "held"
        assert main(args) == 2
        err = capsys.readouterr().err
        assert str(target) in err and len(err.strip().splitlines()) == 1
        assert not out.exists() and not target.exists()
    finally:
        holder.kill()
        holder.wait()
