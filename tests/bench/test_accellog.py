"""Recorded accelerometer logs (phyphox, plain CSV) and the readings file's acceleration columns."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cadcog.bench.accellog import LogError, log_text, read_log, write_log
from cadcog.core.errors import ReadingsError
from cadcog.method.readings import read_readings
from cadcog.rig.inclinometer import InclinometerConfig

G = 9.80665
PHYPHOX_HEAD = (
    '"Time (s)","Acceleration x (m/s^2)","Acceleration y (m/s^2)","Acceleration z (m/s^2)"'
)
ACCEL = InclinometerConfig(device="accelerometer")


def _still(n: int = 300, rate: float = 100.0) -> tuple[np.ndarray, np.ndarray]:
    t = np.arange(n) / rate
    return t, np.tile([0.1, -0.2, 0.97467943], (n, 1))


@given(
    st.lists(
        st.tuples(st.floats(-2.0, 2.0), st.floats(-2.0, 2.0), st.floats(0.7, 1.3)),
        min_size=20,
        max_size=60,
    ),
    st.sampled_from(["phyphox", "csv"]),
)
@settings(max_examples=40, deadline=None)
def test_a_written_log_reads_back(tmp_path_factory, rows, fmt):
    path = tmp_path_factory.mktemp("log") / "log.csv"
    a = np.array([(x, y, np.sqrt(z * z)) for x, y, z in rows]) * 0.0
    a[:, 2] = 1.0  # a magnitude that is gravity; the other axes as drawn, small
    a[:, 0] = np.array([r[0] for r in rows]) * 0.01
    t = 0.02 * np.arange(len(rows)) + 3.5
    write_log(path, t, a, fmt)
    log = read_log(path, fmt)
    np.testing.assert_allclose(log.t_s, t, rtol=0, atol=1e-6)
    np.testing.assert_allclose(log.acc_g, a, rtol=1e-8, atol=1e-7)
    assert log.lines.tolist() == list(range(2, len(rows) + 2))


def test_phyphox_in_semicolons_with_decimal_commas_reads_as_in_commas(tmp_path):
    t, a = _still()
    text = log_text(t, a, "phyphox")
    european = "\n".join(
        ";".join(f.replace(".", ",") for f in line.split(",")) for line in text.splitlines()
    )
    (tmp_path / "eu.csv").write_text(european + "\n")
    (tmp_path / "us.csv").write_text(text)
    np.testing.assert_array_equal(
        read_log(tmp_path / "eu.csv").acc_g, read_log(tmp_path / "us.csv").acc_g
    )


def test_the_unit_is_converted_in_one_place(tmp_path):
    (tmp_path / "l.csv").write_text(
        "t_s,ax,ay,az\n" + "".join(f"{i / 50},0,0,{G}\n" for i in range(100))
    )
    assert read_log(tmp_path / "l.csv", "csv").acc_g[0].tolist() == [0.0, 0.0, 1.0]


@pytest.mark.parametrize(
    ("text", "fmt", "message"),
    [
        ("a,b,c\n1,2,3\n", "phyphox", r"line 1: expected phyphox's columns"),
        ("ax,ay,az\n0,0,9.8\n", "csv", r"line 1: expected the columns t_s,ax,ay,az"),
        ("t_s,ax,ay,az\n0,0,0,9.8\n", "phyphox", r"\(a plain log: --log-format csv\)"),
        (PHYPHOX_HEAD + "\n0,0,0,9.8\n", "csv", r"\(phyphox's export: --log-format phyphox\)"),
        (
            '"Time (s)","Linear Acceleration x (m/s^2)","Linear Acceleration y (m/s^2)",'
            '"Linear Acceleration z (m/s^2)"\n0,0,0,0\n',
            "phyphox",
            "Linear Acceleration",
        ),
        (PHYPHOX_HEAD + "\n0,0,0,9.8\n0.01,0,zero,9.8\n", "phyphox", r"line 3: column "),
        (PHYPHOX_HEAD + "\n0,0,0,9.8\n0.01,0,0\n", "phyphox", r"line 3: expected 4 fields"),
        (PHYPHOX_HEAD + "\n0,0,0,9.8\n0.01,0,nan,9.8\n", "phyphox", r"line 3: .*not finite"),
        (
            PHYPHOX_HEAD + "\n0,0,0,9.8\n0.02,0,0,9.8\n0.01,0,0,9.8\n",
            "phyphox",
            r"line 4: time 0.01 s does not increase",
        ),
        (PHYPHOX_HEAD + "\n", "phyphox", r"0 sample\(s\)"),
        ("", "phyphox", "empty file"),
    ],
)
def test_bad_logs_name_the_file_and_line(tmp_path, text, fmt, message):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(LogError, match=message) as info:
        read_log(path, fmt)
    assert str(path) in str(info.value)


def test_a_log_too_slow_for_a_swing_is_refused(tmp_path):
    t = np.arange(40) * 0.2  # 5 Hz
    write_log(tmp_path / "slow.csv", t, np.tile([0, 0, 1.0], (40, 1)), "phyphox")
    with pytest.raises(LogError, match=r"every 200 ms \(5 Hz.*too slow"):
        read_log(tmp_path / "slow.csv")


@pytest.mark.parametrize(("scale", "shown"), [(0.0, "0 m/s²"), (1000.0, "9.81e\\+03 m/s²")])
def test_a_magnitude_that_cannot_be_gravity_is_refused(tmp_path, scale, shown):
    t, a = _still()
    write_log(tmp_path / "l.csv", t, a * scale, "phyphox")
    with pytest.raises(LogError, match=f"median magnitude is {shown}, which cannot be gravity"):
        read_log(tmp_path / "l.csv")


def test_extra_columns_are_not_used_and_a_tab_export_may_use_decimal_commas(tmp_path):
    t, a = _still()
    text = log_text(t, a, "phyphox")
    tabbed = "\n".join(
        "\t".join(f.replace(".", ",") for f in line.split(",")) for line in text.splitlines()
    )
    (tmp_path / "tab.csv").write_text(tabbed + "\n")
    plain = "t_s,ax_g,ay_g,az_g,temperature_c\n" + "".join(
        f"{ti},{x},{y},{z},21.5\n" for ti, (x, y, z) in zip(t, a, strict=True)
    )
    (tmp_path / "plain.csv").write_text(plain)
    np.testing.assert_allclose(read_log(tmp_path / "tab.csv").acc_g, a, rtol=1e-8)
    np.testing.assert_allclose(read_log(tmp_path / "plain.csv", "csv").acc_g, a, rtol=1e-12)


def test_a_log_spanning_days_is_refused_before_it_is_cut(tmp_path):
    t, a = _still()
    t = t.copy()
    t[150:] += 2 * 86400.0  # the recording paused for two days
    write_log(tmp_path / "l.csv", t, a, "phyphox")
    with pytest.raises(LogError, match=r"its times span 48 h .*cut it to the test"):
        read_log(tmp_path / "l.csv")


def test_a_zip_is_named_as_phyphox_shares_it(tmp_path):
    import zipfile

    with zipfile.ZipFile(tmp_path / "share.zip", "w") as z:
        z.writestr("Raw Data.csv", "x")
    with pytest.raises(LogError, match=r'a zip archive .*unzip it and give its "Raw Data\.csv"'):
        read_log(tmp_path / "share.zip")


def test_a_binary_file_and_a_folder_are_refused(tmp_path):
    (tmp_path / "b.csv").write_bytes(b"\x00\x01" * 10)
    with pytest.raises(LogError, match="binary"):
        read_log(tmp_path / "b.csv")
    with pytest.raises(LogError, match="is a directory"):
        read_log(tmp_path)


# --- the readings file's acceleration columns -------------------------------------------------
HEAD = "point_id,x_mm,y_mm,z_mm,acc_x_g,acc_y_g,acc_z_g"


def test_acceleration_rows_average_per_point(tmp_path):
    p = tmp_path / "r.csv"
    p.write_text(HEAD + "\nS1,0,0,10,0.6,0.0,0.8\nS1,0,0,10,0.62,0.0,0.78\nS2,10,0,0,0,0,-1.0\n")
    s1, s2 = read_readings(p, ACCEL)
    assert s1.n_samples == 2 and s1.acc_g == pytest.approx((0.61, 0.0, 0.79))
    assert s1.std_acc_g == pytest.approx((0.01 * 2**0.5, 0.0, 0.01 * 2**0.5))
    assert s1.top_face_up and not s2.top_face_up
    assert np.sin(np.radians(s1.inc_x_deg)) == pytest.approx(0.61 / np.hypot(0.61, 0.79))


@pytest.mark.parametrize(
    ("text", "config", "message"),
    [
        (HEAD + "\nS1,0,0,1,0,0,1\n", InclinometerConfig(), "an accelerometer's readings"),
        (
            "point_id,x_mm,y_mm,z_mm,inc_x_deg,inc_y_deg,top_face_up\nS1,0,0,1,0,0,true\n",
            ACCEL,
            "expected the columns acc_x_g",
        ),
        (HEAD + ",top_face_up\nS1,0,0,1,0,0,1,true\n", ACCEL, "column top_face_up beside"),
        ("point_id,x_mm,y_mm,z_mm,acc_x_g,acc_y_g\nS1,0,0,1,0,0\n", ACCEL, "missing column"),
        (HEAD + "\nS1,0,0,1,0,0,25\n", ACCEL, "line 2: column acc_z_g: 25 g is beyond"),
        (HEAD + "\nS1,0,0,1,0,0,0.01\nS2,1,0,0,0,0,1\n", ACCEL, "line 2: point S1: the mean"),
    ],
)
def test_bad_acceleration_readings_name_the_file_and_line(tmp_path, text, config, message):
    p = tmp_path / "r.csv"
    p.write_text(text)
    with pytest.raises(ReadingsError, match=message) as info:
        read_readings(p, config)
    assert str(p) in str(info.value)


def test_two_hangs_alike_with_handling_between_are_two_hangs():
    """A point hung, taken down (handled) and hung again the same way: not one hang."""
    from cadcog.bench.accellog import AccelLog
    from cadcog.bench.logsegments import segment_log
    from cadcog.bench.swing import SettleCriterion

    rate = 100.0
    d = np.array([0.5, 0.2, 0.84])
    d /= np.linalg.norm(d)
    axis = np.cross(d, [1.0, 0.0, 0.0])
    axis /= np.linalg.norm(axis)

    def hang(n_s: float) -> np.ndarray:
        s = np.arange(int(n_s * rate)) / rate
        th = np.radians(3.0) * np.exp(-s / 3.0) * np.sin(2 * np.pi * 1.2 * s)
        c, sn = np.cos(th)[:, None], np.sin(th)[:, None]
        return d * c + np.cross(axis, d) * sn

    def handling(n_s: float) -> np.ndarray:
        s = np.arange(int(n_s * rate)) / rate
        return np.stack([0.3 * np.sin(3 * s), 0.4 * np.cos(2 * s), 1 + 0.4 * np.sin(5 * s)], 1)

    a = np.concatenate([handling(3), hang(35), handling(4), hang(35), handling(3)])
    t = np.arange(len(a)) / rate
    noisy = a + np.random.default_rng(1).normal(0, 0.002, a.shape)
    seg = segment_log(
        AccelLog(Path("x"), t, noisy, np.arange(len(t))), SettleCriterion(), min_average_s=10.0
    )
    assert len(seg.hangs) == 2
    assert seg.hangs[0].end_s < 38.0 < seg.hangs[1].settled_s


@pytest.mark.parametrize(("bump_deg", "through"), [(0.13, True), (0.6, False)])
def test_a_swing_record_runs_through_a_hover_but_stops_at_a_knock(bump_deg, through):
    """A swing that rises back just over the settle threshold splits the averaging in two: its
    decay goes on through both spans (the swing record ends with the second); a knock (a swing
    of several thresholds) ends the record with the first span."""
    from cadcog.bench.accellog import AccelLog
    from cadcog.bench.logsegments import hang_swing, segment_log
    from cadcog.bench.swing import SettleCriterion

    rate = 100.0
    d = np.array([0.5, 0.2, 0.84])
    d /= np.linalg.norm(d)
    axis = np.cross(d, [1.0, 0.0, 0.0])
    axis /= np.linalg.norm(axis)
    s = np.arange(int(90 * rate)) / rate
    th = np.radians(3.0) * np.exp(-s / 3.0) * np.sin(2 * np.pi * 1.2 * s)
    bump = (s > 50.0) & (s < 53.0)  # 3 s of a small swing, 35 s into the stillness
    th = th + np.radians(bump_deg) * bump * np.sin(2 * np.pi * 1.2 * (s - 50.0))
    hang = d * np.cos(th)[:, None] + np.cross(axis, d) * np.sin(th)[:, None]
    t_h = np.arange(int(3 * rate)) / rate
    handling = np.stack(
        [0.3 * np.sin(3 * t_h), 0.4 * np.cos(2 * t_h), 1 + 0.4 * np.sin(5 * t_h)], 1
    )
    a = np.concatenate([handling, hang, handling])
    t = np.arange(len(a)) / rate
    log = AccelLog(Path("x"), t, a + np.random.default_rng(2).normal(0, 0.001, a.shape),
                   np.arange(len(t)))  # fmt: skip
    (h,) = segment_log(log, SettleCriterion(), min_average_s=10.0).hangs
    assert len(h.spans_s) == 2 and h.spans_s[0][1] < 53.0 < h.spans_s[1][0]
    sw = hang_swing(log, h, "S1", ("+x", "+y", "+z"))
    assert sw.t_s[0] >= h.start_s + 2.0
    assert sw.t_s[-1] == pytest.approx(h.spans_s[1 if through else 0][1], abs=0.02)
