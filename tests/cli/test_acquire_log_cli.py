"""``cadcog acquire --log`` and an accelerometer recorded from ``--port``, end to end, on logs from
the independent forward model :mod:`support.phone_logs` (no cadcog code in it)."""

from __future__ import annotations

import json
import os
import threading
import tty
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from cadcog.bench.protocol import ACCEL_EXAMPLE, format_header, format_sample
from cadcog.cli import main
from support import phone_logs as pl
from support import phone_scenarios as ps
from support.rigtools import package_rig, paper_rig_dict, write_rig

CHI2_95 = float(stats.chi2.ppf(0.95, 3))


def _phone_rig(folder: Path, axes: tuple[str, str, str], **figures: float) -> Path:
    data = paper_rig_dict()
    data["inclinometer"] = {
        "device": "accelerometer",
        "axes": list(axes),
        "offset_g": 0.02,
        "scale_error_rel": 0.01,
        "mounting_misalignment_deg": 1.0,
        **figures,
    }
    return write_rig(folder / "phone_rig.toml", data)


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """16 phone logs of the paper rig (and one with a knock, one with a hang that never
    settles), written as phyphox exports them."""
    folder = tmp_path_factory.mktemp("logs")
    seeds = list(range(3400, 3416))
    specs = [ps.with_play(ps.scenario("paper_rig", "phone"), "paper_rig", s) for s in seeds]
    base = specs[0]
    knocked = list(base.hangs)
    knocked[2] = replace(knocked[2], knock_after_s=knocked[2].average_s / 2)
    stuck = list(base.hangs)
    stuck[3] = replace(stuck[3], never_settles=True)
    specs += [replace(base, hangs=tuple(knocked)), replace(base, hangs=tuple(stuck))]
    made = pl.generate_many(specs, [*seeds, 9001, 9002])
    paths = []
    for i, log in enumerate(made):
        path = folder / f"log{i}.csv"
        pl.write_phyphox_csv(path, log)
        paths.append(path)
    rig = _phone_rig(folder, base.sensor.axes)
    return {"rig": rig, "paths": paths, "logs": made, "folder": folder}


def test_a_phone_log_gives_the_same_estimate_as_cadcog_estimate(logs, tmp_path, capsys):
    out = tmp_path / "run" / "readings.csv"
    args = ["acquire", "--rig", str(logs["rig"]), "--log", str(logs["paths"][0])]
    assert main([*args, "--out", str(out), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [h["id"] for h in data["hangs"]] == ["S1", "S2", "S3", "S4", "S5", "S6"]
    truth = logs["logs"][0]
    for h, t in zip(data["hangs"], truth.hangs, strict=True):
        # Every averaged bin lies where the body truly hung still (its settle hold inside it).
        for a, b in h["averaged_s"]:
            assert t.release_t_s < a and b <= t.end_t_s + 0.05
    assert main(["estimate", str(out), "--rig", str(logs["rig"]), "--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    np.testing.assert_allclose(again["cog_mm"], data["estimate"]["cog_mm"], rtol=0, atol=1e-12)
    shared = data["estimate"]["model"]["shared_sensor"]
    assert set(shared) == {
        f"{k}_{a}_{u}"
        for k, u in (("offset", "g"), ("scale", "rel"), ("mounting", "deg"))
        for a in "xyz"
    }  # fmt: skip (a phone declares no cross-axis figure)


def test_the_estimate_covers_the_truth_over_many_logs(logs, tmp_path, capsys):
    """A fast subset of benchmarks/study_phone_logs.py: 16 logs, each its own sensor and play."""
    inside = 0
    for i, path in enumerate(logs["paths"][:16]):
        out = tmp_path / f"r{i}.csv"
        assert main(["acquire", "--rig", str(logs["rig"]), "--log", str(path), "--out",
                     str(out), "--json"]) == 0  # fmt: skip
        est = json.loads(capsys.readouterr().out)["estimate"]
        e = np.asarray(est["assembly_cog_mm"]) - logs["logs"][i].cog_mm
        inside += float(e @ np.linalg.solve(np.asarray(est["assembly_cov_mm2"]), e)) < CHI2_95
    # At 95 % coverage, 12 or fewer of 16 happen with probability 0.007.
    assert inside >= 13


def test_a_knock_during_the_averaging_is_one_hang(logs, tmp_path, capsys):
    out = tmp_path / "r.csv"
    assert main(["acquire", "--rig", str(logs["rig"]), "--log", str(logs["paths"][16]),
                 "--out", str(out), "--json"]) == 0  # fmt: skip
    data = json.loads(capsys.readouterr().out)
    knock = logs["logs"][16].hangs[2].knock_t_s
    spans = data["hangs"][2]["averaged_s"]
    assert len(spans) == 2 and spans[0][1] <= knock + 0.05 < spans[1][0]


def test_a_hang_that_never_settled_is_named_with_its_time_span(logs, tmp_path, capsys):
    out = tmp_path / "r.csv"
    path = logs["paths"][17]
    assert main(["acquire", "--rig", str(logs["rig"]), "--log", str(path), "--out",
                 str(out)]) == 2  # fmt: skip
    err = capsys.readouterr().err
    assert err.count("cadcog: error:") == 1 and str(path) in err
    assert "5 settled hang(s) for 6 point(s)" in err
    stuck = logs["logs"][17].hangs[3]
    start = float(err.split("a hang never settled at ")[1].split("-")[0])
    assert stuck.release_t_s - 1.0 <= start <= stuck.release_t_s + 5.0
    assert not out.exists() and not list(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--swings", "r.csv"], "--swings and --out name the same file"),
        (["--swings", "sub/../r.csv"], "--swings and --out name the same file"),
        (["--swings", "-"], "--swings -: expected a new file"),
        (["--out", "-"], "--out -: expected a new file"),
        (["--report", "rep"], "--report: not written from a log yet"),
        (["--duration-s", "5"], "--duration-s: for recording from --port"),
        (["--points", "S1,S9"], "unknown point(s) S9"),
    ],
)
def test_what_a_log_run_refuses(logs, tmp_path, capsys, monkeypatch, extra, message):
    out = tmp_path / "r.csv"
    args = ["acquire", "--rig", str(logs["rig"]), "--log", str(logs["paths"][0])]
    if "--out" not in extra:
        args += ["--out", str(out)]
    monkeypatch.chdir(tmp_path)  # relative outputs land here, and the folder is checked empty
    assert main([*args, *extra]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("cadcog: error:") == 1
    assert list(tmp_path.iterdir()) == []


def test_nothing_is_written_when_the_log_cannot_be_cut(logs, tmp_path, capsys):
    """The readings and the swings are written together or not at all."""
    out, swings = tmp_path / "r.csv", tmp_path / "s.csv"
    assert main(["acquire", "--rig", str(logs["rig"]), "--log", str(logs["paths"][17]),
                 "--out", str(out), "--swings", str(swings)]) == 2  # fmt: skip
    assert "a hang never settled" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_an_inclinometer_rig_refuses_a_log(logs, tmp_path, capsys):
    out = tmp_path / "r.csv"
    assert main(["acquire", "--log", str(logs["paths"][0]), "--out", str(out)]) == 2
    assert 'declare device = "accelerometer"' in capsys.readouterr().err
    assert not out.exists()


def test_a_mounting_or_an_order_given_wrong_is_refused(logs, tmp_path, capsys):
    """The log's phone sits as ("-y", "+x", "+z"); a rig that says square, or the hangs given
    in reverse, put hangs where the CAD says no point hangs: refused, nothing written."""
    rig = _phone_rig(tmp_path, ("+x", "+y", "+z"))
    out = tmp_path / "r.csv"
    log = str(logs["paths"][0])
    assert main(["acquire", "--rig", str(rig), "--log", log, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "hangs far from where the CAD says their points hang" in err
    assert "check [inclinometer] axes" in err and not out.exists()
    backwards = "S6,S5,S4,S3,S2,S1"
    assert main(["acquire", "--rig", str(logs["rig"]), "--log", log, "--points", backwards,
                 "--out", str(out)]) == 2  # fmt: skip
    assert "give --points in the order the hangs were made" in capsys.readouterr().err


def test_an_existing_readings_file_is_never_overwritten(logs, tmp_path, capsys):
    out = tmp_path / "precious.csv"
    out.write_text("point_id,x_mm\n")
    assert main(["acquire", "--rig", str(logs["rig"]), "--log", str(logs["paths"][0]),
                 "--out", str(out)]) == 2  # fmt: skip
    assert "exists; a log's readings and swings go to new files" in capsys.readouterr().err
    assert out.read_text() == "point_id,x_mm\n"
    swings = tmp_path / "precious.swings.csv"
    swings.write_text("point_id,t_s,inc_x_deg,inc_y_deg\n")
    assert main(["acquire", "--rig", str(logs["rig"]), "--log", str(logs["paths"][0]),
                 "--out", str(tmp_path / "new.csv"), "--swings", str(swings)]) == 2  # fmt: skip
    assert f"--swings {swings}: exists" in capsys.readouterr().err
    assert swings.read_text() == "point_id,t_s,inc_x_deg,inc_y_deg\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["precious.csv", "precious.swings.csv"]


def test_a_hang_redone_is_dropped_by_its_number(logs, tmp_path, capsys):
    """Six hangs for the five points S2-S6: the refusal numbers them, --drop-hangs 1 leaves
    the first out, and the rest are the points in order."""
    out = tmp_path / "r.csv"
    args = ["acquire", "--rig", str(logs["rig"]), "--log", str(logs["paths"][0]), "--points",
            "S2,S3,S4,S5,S6", "--out", str(out)]  # fmt: skip
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "6 settled hang(s) for 5 point(s)" in err and "#6 " in err
    assert "--drop-hangs" in err and not out.exists()
    assert main([*args, "--drop-hangs", "1", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [h["id"] for h in data["hangs"]] == ["S2", "S3", "S4", "S5", "S6"]
    args[-1] = str(tmp_path / "other.csv")
    assert main([*args, "--drop-hangs", "9"]) == 2
    assert "--drop-hangs: 9 is not a hang of the log (it holds 6)" in capsys.readouterr().err


def test_a_log_that_ends_during_a_hang_says_so(logs, tmp_path, capsys):
    """The log cut 5 s after the last hang's release: not a hang that never settled."""
    log = logs["logs"][0]
    cut = log.hangs[-1].release_t_s + 5.0
    text = logs["paths"][0].read_text().splitlines()
    keep = [text[0]] + [ln for ln in text[1:] if float(ln.split(",")[0]) < cut]
    short = tmp_path / "short.csv"
    short.write_text("\n".join(keep) + "\n")
    assert main(["acquire", "--rig", str(logs["rig"]), "--log", str(short), "--out",
                 str(tmp_path / "r.csv")]) == 2  # fmt: skip
    err = capsys.readouterr().err
    assert "the log ends during a hang" in err and "never settled" not in err


def _feed(master: int, lines: list[bytes], stop: threading.Event) -> None:
    """Write the lines as the sketch does: its header first and every 200 samples (a reader that
    opens the port late, or flushes it, sees one soon)."""
    header = (format_header(ACCEL_EXAMPLE) + "\n").encode()
    for chunk in range(0, len(lines), 200):
        if stop.is_set():
            return
        try:
            os.write(master, header + b"".join(lines[chunk : chunk + 200]))
        except OSError:
            return


def _board_lines(log: pl.PhoneLog, upto: np.ndarray | None = None) -> tuple[list[bytes], float]:
    """The ADXL355 sketch's sample lines of ``log`` (counts, whole-ms clock), and the span of
    device time they cover (s)."""
    upto = np.ones(len(log.t_s), bool) if upto is None else upto
    counts = np.round(log.accel_m_s2[upto] / 9.80665 / ACCEL_EXAMPLE.lsb_g).astype(np.int64)
    t_ms = np.round((log.t_s[upto] - log.t_s[0]) * 1000).astype(np.int64) + 5
    keep = np.concatenate([[True], np.diff(t_ms) > 0])  # the device's clock is whole ms
    lines = [
        (format_sample(i, int(t), int(c[0]), int(c[1]), z=int(c[2])) + "\n").encode()
        for i, (t, c) in enumerate(zip(t_ms[keep], counts[keep], strict=True))
    ]
    return lines, float(t_ms[keep][-1] - t_ms[0]) / 1000.0


def _on_a_port(lines: list[bytes], record):
    """``record(port)`` while a thread feeds ``lines`` into a pseudo-terminal."""
    master, slave = os.openpty()
    tty.setraw(slave)
    stop = threading.Event()
    th = threading.Thread(target=_feed, args=(master, lines, stop), daemon=True)
    th.start()
    try:
        return record(os.ttyname(slave))
    finally:
        stop.set()
        th.join(timeout=10)
        os.close(master)
        os.close(slave)


def test_an_accelerometer_on_a_port_is_recorded_as_a_log_then_cut(logs, tmp_path, capsys):
    """The ADXL355 sketch's lines (its header, six-field samples of counts) on a pseudo-terminal:
    the recording, cut, gives what the same log gives through --log."""
    log = logs["logs"][1]
    lines, span_s = _board_lines(log)
    out = tmp_path / "r.csv"
    duration = span_s - 6.0  # the end: handling, quiet
    code = _on_a_port(lines, lambda port: main([
        "acquire", "--rig", str(logs["rig"]), "--port", port, "--out", str(out),
        "--duration-s", f"{duration}", "--json", "--timeout-s", "5"]))  # fmt: skip
    assert code == 0, capsys.readouterr().err
    data = json.loads(capsys.readouterr().out)
    recorded = tmp_path / "r.log.csv"
    assert recorded.exists()
    assert main(["acquire", "--rig", str(logs["rig"]), "--log", str(recorded), "--log-format",
                 "csv", "--out", str(tmp_path / "again.csv"), "--json"]) == 0  # fmt: skip
    again = json.loads(capsys.readouterr().out)
    assert again["estimate"]["cog_mm"] == data["estimate"]["cog_mm"]
    e = np.asarray(data["estimate"]["assembly_cog_mm"]) - log.cog_mm
    assert e @ np.linalg.solve(np.asarray(data["estimate"]["assembly_cov_mm2"]), e) < float(
        stats.chi2.ppf(0.999, 3)
    )


def test_the_api_records_an_accelerometer_on_a_port_as_the_command_does(logs, tmp_path):
    """cadcog.acquire(port=...) with an accelerometer's rig: the first two hangs' lines on a
    pseudo-terminal, recorded into a log beside ``out`` and cut (it said the rig declared an
    inclinometer, and recorded nothing)."""
    import cadcog

    log = logs["logs"][1]
    lines, span_s = _board_lines(log, log.t_s <= log.hangs[1].end_t_s + 8.0)
    out = tmp_path / "r.csv"
    run = _on_a_port(lines, lambda port: cadcog.acquire(
        out, rig=logs["rig"], points=["S1", "S2"], port=port, duration_s=span_s - 6.0))  # fmt: skip
    assert [h["id"] for h in run.to_dict()["hangs"]] == ["S1", "S2"]
    assert (tmp_path / "r.log.csv").exists() and out.exists()
    again = cadcog.acquire_log(tmp_path / "r.log.csv", tmp_path / "again.csv", rig=logs["rig"],
                               points=["S1", "S2"], log_format="csv")  # fmt: skip
    assert again.estimate.cog_mm.tolist() == run.estimate.cog_mm.tolist()


def test_the_api_gives_what_the_command_prints(logs, tmp_path, capsys):
    import cadcog

    out = tmp_path / "cli.csv"
    assert main(["acquire", "--rig", str(logs["rig"]), "--log", str(logs["paths"][2]),
                 "--out", str(out), "--json"]) == 0  # fmt: skip
    printed = json.loads(capsys.readouterr().out)
    run = cadcog.acquire_log(logs["paths"][2], tmp_path / "api.csv", rig=logs["rig"])
    api = json.loads(run.to_json())
    assert api["estimate"] == printed["estimate"] and api["hangs"] == printed["hangs"]
    assert (tmp_path / "api.csv").read_text() == out.read_text()
    with pytest.raises(cadcog.core.errors.CadcogError, match="a set-up needs points"):
        cadcog.acquire_log(logs["paths"][2], tmp_path / "x.csv", setup="any.toml")


def test_a_board_at_20_hz_on_whole_milliseconds_is_cut(tmp_path, capsys):
    """The ADXL355 sketch sends 20 samples a second (its filter at 7.8 Hz) on a clock of whole
    milliseconds: the same test's log, each 50 ms averaged, is cut into its hangs."""
    spec = ps.scenario("paper_rig", "adxl355")
    log = pl.generate(spec, 11)
    slot = np.floor(log.t_s * 20.0).astype(int)
    edges = np.flatnonzero(np.diff(slot, prepend=-1) > 0)
    t = np.round(slot[edges] / 20.0 + 0.003, 3)
    a = np.add.reduceat(log.accel_m_s2, edges, axis=0) / np.diff(edges, append=len(slot))[:, None]
    path = tmp_path / "board.csv"
    path.write_text(
        "t_s,ax,ay,az\n"
        + "".join(f"{ti:.3f},{x:.6f},{y:.6f},{z:.6f}\n" for ti, (x, y, z) in zip(t, a, strict=True))
    )
    figures = {"offset_g": 0.025, "cross_axis_rel": 0.01}
    rig = _phone_rig(tmp_path, spec.sensor.axes, **figures)
    out = tmp_path / "r.csv"
    assert main(["acquire", "--rig", str(rig), "--log", str(path), "--log-format", "csv",
                 "--out", str(out), "--json"]) == 0, capsys.readouterr().err  # fmt: skip
    data = json.loads(capsys.readouterr().out)
    assert [h["id"] for h in data["hangs"]] == ["S1", "S2", "S3", "S4", "S5", "S6"]
    e = np.asarray(data["estimate"]["assembly_cog_mm"]) - log.cog_mm
    cov = np.asarray(data["estimate"]["assembly_cov_mm2"])
    assert e @ np.linalg.solve(cov, e) < float(stats.chi2.ppf(0.999, 3))


def test_a_recording_never_replaces_a_file_and_checks_before_it_records(logs, tmp_path, capsys):
    out = tmp_path / "r.csv"
    out.write_text("x\n")
    # the port does not exist: the refusal comes before any attempt to open it
    assert main(["acquire", "--rig", str(logs["rig"]), "--port", str(tmp_path / "no-port"),
                 "--out", str(out), "--duration-s", "5"]) == 2  # fmt: skip
    assert "--out" in capsys.readouterr().err and out.read_text() == "x\n"
    (tmp_path / "s.log.csv").write_text("y\n")
    assert main(["acquire", "--rig", str(logs["rig"]), "--port", str(tmp_path / "no-port"),
                 "--out", str(tmp_path / "s.csv"), "--duration-s", "5"]) == 2  # fmt: skip
    assert "--log-out" in capsys.readouterr().err
    assert (tmp_path / "s.log.csv").read_text() == "y\n"
    assert main(["acquire", "--rig", str(logs["rig"]), "--port", "x", "--out",
                 str(tmp_path / "t.csv"), "--drop-hangs", "1"]) == 2  # fmt: skip
    assert "--drop-hangs: for a log" in capsys.readouterr().err


# ------------------------------------------------------------------ the swings of a log: inertia
#: The MPU-6050 board's package as the generator carries it (kg, mm) and where it senses.
MPU_PACKAGE = (0.176, (101.6, 37.5, 112.2), (68.6, 53.4, 60.0))


def _mpu_rig(folder: Path, spec: pl.LogSpec) -> Path:
    """The paper rig read by the MPU-6050 board: its package as the ME, the generator's
    declared figures, and a ``[swing]`` table."""
    s = spec.sensor
    return package_rig(
        folder / "mpu_rig.toml",
        package=MPU_PACKAGE,
        volume_name="mpu6050_accelerometer",
        inclinometer={
            "device": "accelerometer",
            "axes": list(s.axes),
            "offset_g": 0.08,
            "scale_error_rel": s.scale_rel,
            "cross_axis_rel": s.cross_axis_rel,
            "mounting_misalignment_deg": s.misalignment_deg,
        },
        swing={"wire_length_mm": 300.0, "wire_length_sigma_mm": 2.0},
    )


@pytest.fixture(scope="module")
def swing_log(tmp_path_factory):
    """One MPU-6050 log of the paper rig left to swing (decay 12 s, released at 4-6°) and the
    rig that describes it."""
    folder = tmp_path_factory.mktemp("swing_log")
    spec = ps.with_play(ps.scenario("paper_rig", "mpu6050"), "paper_rig", 3434)
    rng = np.random.default_rng(3434)
    hangs = []
    for h in spec.hangs:
        release = float(rng.uniform(4.0, 6.0))
        hangs.append(replace(h, release_deg=release, decay_time_s=12.0,
                             settle_s=12.0 * np.log(1.3 * release / 0.05)))  # fmt: skip
    spec = replace(spec, hangs=tuple(hangs))
    log = pl.generate(spec, 3434)
    path = folder / "mpu.csv"
    pl.write_phyphox_csv(path, log)
    return {"rig": _mpu_rig(folder, spec), "path": path, "log": log}


def test_a_logs_swings_give_the_tensor_cadcog_inertia_gives(swing_log, tmp_path, capsys):
    """``--swings``: each hang's swing from after the release to the end of its averaging, in
    order; the tensor the run reports is the one ``cadcog inertia`` computes from the files it
    wrote, and it covers the generator's object (the steel box without the package)."""
    out, swings = tmp_path / "r.csv", tmp_path / "s.csv"
    rig = str(swing_log["rig"])
    assert main(["acquire", "--rig", rig, "--log", str(swing_log["path"]), "--out", str(out),
                 "--swings", str(swings), "--json"]) == 0  # fmt: skip
    data = json.loads(capsys.readouterr().out)
    assert data["swings"] == str(swings)
    from cadcog.dynamics.swingfile import read_swings

    read = read_swings(swings)
    assert [s.point_id for s in read] == ["S1", "S2", "S3", "S4", "S5", "S6"]
    for s, h, t in zip(read, data["hangs"], swing_log["log"].hangs, strict=True):
        assert t.release_t_s < s.t_s[0] and s.t_s[-1] <= h["averaged_s"][0][1] <= t.end_t_s
        assert h["swing_samples"] == len(s.t_s) > 3000  # ≥ 30 s at 100 Hz
    assert main(["inertia", str(swings), "--readings", str(out), "--rig", rig, "--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    np.testing.assert_allclose(
        again["inertia_kg_mm2"], data["inertia"]["inertia_kg_mm2"], rtol=1e-12
    )
    j = np.asarray(again["inertia_kg_mm2"])
    truth = ps._box(9.2, (200.0, 75.0, 78.0))
    idx = ([0, 1, 2, 0, 0, 1], [0, 1, 2, 1, 2, 2])
    d = j[idx] - truth[idx]
    chi2 = float(d @ np.linalg.solve(np.asarray(again["inertia_cov"]), d))
    assert chi2 < stats.chi2.ppf(0.999, 6)


def test_a_log_that_shows_no_tensor_still_gives_its_readings(logs, tmp_path, capsys):
    """Fewer than three hangs (the tensor needs three): the readings and swings are written,
    the run says why there is no tensor, exit 0."""
    out, swings = tmp_path / "r.csv", tmp_path / "s.csv"
    assert main(["acquire", "--rig", str(logs["rig"]), "--log", str(logs["paths"][1]),
                 "--points", "S1,S2", "--drop-hangs", "3,4,5,6", "--out", str(out),
                 "--swings", str(swings)]) == 0  # fmt: skip
    text = capsys.readouterr().out
    assert "no inertia from the swings: 2 hang(s) with a swing: the tensor needs 3" in text
    assert out.exists() and swings.exists()
