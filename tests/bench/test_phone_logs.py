"""The independent phone/MEMS log generator (support/phone_logs.py) against its own physics.

Two logs of one small test are generated once per module: an ideal sensor (no error, no noise)
and a phone's errors. Their three hangs: a normal one, one knocked during its averaging, one that
never settles. Every expectation below is computed here from the spec, not read from the model.
"""

from __future__ import annotations

import csv
import re
from dataclasses import replace

import numpy as np
import pytest

from support import phone_logs as pl
from support import phone_scenarios as ps

G = 9.80665


def _box(m: float, size: tuple[float, float, float]) -> np.ndarray:
    a, b, c = size
    return np.diag([m * (b * b + c * c), m * (a * a + c * c), m * (a * a + b * b)]) / 12.0


BODY = ps.composite([(2.0, (60.0, 40.0, 30.0), _box(2.0, (120.0, 80.0, 60.0)))])
COG = np.array([60.0, 40.0, 30.0])
COMMON = dict(wire_length_mm=200.0, release_deg=3.0, decay_time_s=1.5, settle_s=10.0,
              average_s=4.0, handling_s=3.0)  # fmt: skip
HANGS = (
    pl.Hang((80.0, 50.0, 64.0), **COMMON),  # +z face
    pl.Hang((20.0, 10.0, -4.0), knock_after_s=1.5, knock_deg=1.0, **COMMON),  # -z face
    pl.Hang((124.0, 40.0, 40.0), never_settles=True, **COMMON),  # +x face
)
AXES = ("-y", "+x", "+z")
SENSOR = pl.SensorSpec((60.0, 40.0, 62.0), axes=AXES, rate_hz=100.0, drop_prob=0.01)
SPEC = pl.LogSpec(BODY, HANGS, SENSOR, quiet_s=2.0, end_handling_s=2.0, end_quiet_s=1.0)


@pytest.fixture(scope="module")
def logs() -> list[pl.PhoneLog]:
    """Both logs in one swing_truth batch (the same geometry: the same step)."""
    return pl.generate_many([replace(SPEC, sensor=SENSOR.ideal()), SPEC], [11, 12])


@pytest.fixture(scope="module")
def ideal(logs) -> pl.PhoneLog:
    return logs[0]


@pytest.fixture(scope="module")
def noisy(logs) -> pl.PhoneLog:
    return logs[1]


def _perm(axes: tuple[str, ...]) -> np.ndarray:
    """The signed permutation written out here, row i = sensor axis i in object axes."""
    rows = {"+x": [1, 0, 0], "-x": [-1, 0, 0], "+y": [0, 1, 0], "-y": [0, -1, 0],
            "+z": [0, 0, 1], "-z": [0, 0, -1]}  # fmt: skip
    return np.array([rows[a] for a in axes], float)


def _up(point: tuple[float, ...]) -> np.ndarray:
    d = np.asarray(point) - COG
    return d / np.linalg.norm(d)


def _in(log: pl.PhoneLog, a: float, b: float) -> np.ndarray:
    return (log.t_s >= a) & (log.t_s < b)


def test_signed_permutation_is_a_proper_rotation_and_a_mirror_is_refused():
    m = pl.axes_matrix(["-y", "+x", "+z"])
    assert np.array_equal(m, _perm(("-y", "+x", "+z")))
    assert np.allclose(m @ m.T, np.eye(3)) and np.linalg.det(m) == pytest.approx(1.0)
    assert m @ np.array([0.0, -1.0, 0.0]) == pytest.approx([1.0, 0.0, 0.0])  # object −y → sensor +x
    for good in (("+y", "+z", "+x"), ("-x", "-y", "+z"), ("+z", "+y", "-x")):
        assert np.linalg.det(pl.axes_matrix(good)) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="mirror"):
        pl.axes_matrix(["+x", "+y", "-z"])
    with pytest.raises(ValueError, match="mirror"):
        pl.SensorSpec((0.0, 0.0, 0.0), axes=("+y", "+x", "+z"))
    with pytest.raises(ValueError, match="once"):
        pl.axes_matrix(["+x", "+x", "+z"])
    with pytest.raises(ValueError, match="sign"):
        pl.axes_matrix(["x", "+y", "+z"])


def test_sign_convention_phone_lying_face_up_reads_plus_g_on_z(ideal, noisy):
    quiet = ideal.t_s < SPEC.quiet_s  # on the table, object +z up; sensor z along object +z
    assert quiet.sum() > 150
    assert ideal.accel_m_s2[quiet] == pytest.approx(
        np.tile([0.0, 0.0, G], (quiet.sum(), 1)), abs=1e-12
    )
    # the phone with its errors: still +9.81 on z, within its ±20 mg offset and 1 % scale
    mean = noisy.accel_m_s2[noisy.t_s < SPEC.quiet_s].mean(axis=0)
    assert mean[2] == pytest.approx(G, abs=G * (0.02 + 0.01 + 0.001))
    assert np.abs(mean[:2]).max() < G * (0.02 + np.radians(1.0) + 0.001)


def test_errors_off_rest_reading_is_the_true_vertical_in_sensor_axes(ideal):
    p = _perm(AXES)
    for i in (0, 1, 2):
        up = _up(HANGS[i].point_mm)
        assert ideal.hangs[i].up == pytest.approx(up, abs=1e-15)
    h = ideal.hangs[0]  # its last second: the swing long dead (envelope under 1e-3°)
    sel = _in(ideal, h.end_t_s - 1.0, h.end_t_s)
    assert sel.sum() > 80
    assert np.abs(ideal.accel_m_s2[sel] - G * p @ _up(HANGS[0].point_mm)).max() < 1e-9 * G
    for i in (0, 1):
        h = ideal.hangs[i]
        # the truth's rest span: within the stated 0.01° of the vertical, from inside the swing
        a, b = h.rest_span_s
        sel = _in(ideal, a, b + 1e-9)
        dev = np.linalg.norm(ideal.accel_m_s2[sel] / G - p @ _up(HANGS[i].point_mm), axis=1)
        assert dev.max() < np.radians(0.01)
        assert h.release_t_s + 3.0 < a < h.averaging_span_s[0]  # the swing took seconds to die


def test_rest_reading_carries_exactly_the_drawn_errors_and_the_noise(noisy):
    s = noisy.sensor
    assert np.abs(s.offset_g).max() <= 0.02 and np.abs(s.offset_g).min() > 0
    assert np.abs(s.scale_rel).max() <= 0.01 and np.linalg.norm(s.misalignment_deg) <= 1.0
    mount = pl.axes_matrix(AXES) @ _rot_deg(s.misalignment_deg).T
    assert s.mount == pytest.approx(mount, abs=1e-15)
    sigma = 0.002
    for i in (0, 1):
        a, b = noisy.hangs[i].rest_span_s
        sel = _in(noisy, a, b)
        r = noisy.accel_m_s2[sel] / G
        n = sel.sum()
        expected = (np.eye(3) + np.diag(s.scale_rel)) @ mount @ _up(HANGS[i].point_mm) + s.offset_g
        bound = 4 * sigma / np.sqrt(n) + np.radians(0.01) + 0.1 * s.lsb_g
        assert np.abs(r.mean(axis=0) - expected).max() < bound
        assert r.std(axis=0) == pytest.approx([sigma] * 3, rel=0.15)
        # every sample's magnitude: g within the drawn offsets, scale and noise
        worst = np.abs(s.scale_rel).max() + np.linalg.norm(s.offset_g) + 5 * sigma * np.sqrt(3)
        mag = np.linalg.norm(r, axis=1)
        assert np.abs(mag - 1.0).max() < worst + s.lsb_g
        assert abs(mag.mean() - 1.0) > 1e-4  # the errors are there: not an ideal g


def _rot_deg(rotvec_deg: np.ndarray) -> np.ndarray:
    """Rodrigues' formula, written here."""
    v = np.radians(np.asarray(rotvec_deg, float))
    a = np.linalg.norm(v)
    if a == 0:
        return np.eye(3)
    k = v / a
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(a) * kx + (1 - np.cos(a)) * kx @ kx


def test_noise_density_and_bandwidth_give_the_per_sample_sigma():
    assert ps.MPU6050.sigma_g == pytest.approx(400e-6 * np.sqrt(44.0))
    assert ps.ADXL355.sigma_g == pytest.approx(25e-6 * np.sqrt(125.0 / 4))
    assert replace(ps.ADXL355, bandwidth_hz=None).sigma_g == pytest.approx(25e-6 * np.sqrt(62.5))
    assert ps.PHONE.sigma_g == 0.002


def test_same_seed_gives_the_same_bytes_and_batches_change_nothing(tmp_path):
    hang = pl.Hang((80.0, 50.0, 64.0), wire_length_mm=200.0, decay_time_s=0.5, settle_s=1.5,
                   average_s=0.5, handling_s=1.0)  # fmt: skip
    spec = pl.LogSpec(BODY, (hang,), SENSOR, quiet_s=1.0, end_handling_s=1.0, end_quiet_s=0.5)
    eight, seven = pl.generate_many([spec, spec], [8, 7])  # batched with another log
    out = []
    for k, log in enumerate((pl.generate(spec, 7), seven, eight)):
        pl.write_phyphox_csv(tmp_path / f"{k}.csv", log)
        out.append((tmp_path / f"{k}.csv").read_bytes())
    assert out[0] == out[1]
    assert out[0] != out[2]
    assert not np.array_equal(eight.t_s[:100], seven.t_s[:100])


def test_a_knock_makes_a_transient_in_its_hang_only(ideal):
    p = _perm(AXES)
    h = ideal.hangs[1]
    assert h.knock_t_s == pytest.approx(h.averaging_span_s[0] + 1.5)
    rest = G * p @ _up(HANGS[1].point_mm)
    dev = np.linalg.norm(ideal.accel_m_s2 - rest, axis=1) / G
    before = _in(ideal, h.averaging_span_s[0], h.knock_t_s - 0.025)
    assert dev[before].max() < 2e-4  # at rest (the release swing's residue: ~1e-4)
    assert dev[_in(ideal, h.knock_t_s - 0.025, h.knock_t_s + 0.01)].max() > 0.02  # the impulse
    assert dev[_in(ideal, h.knock_t_s + 0.3, h.end_t_s)].max() > 1e-3  # a swing again
    assert h.rest_span_s is not None and h.rest_span_s[1] < h.knock_t_s
    h0 = ideal.hangs[0]  # the unknocked hang's averaging stays flat
    dev0 = np.linalg.norm(ideal.accel_m_s2 - G * p @ _up(HANGS[0].point_mm), axis=1) / G
    assert h0.knock_t_s is None
    assert dev0[_in(ideal, *h0.averaging_span_s)].max() < 2e-4


def test_the_never_settling_hang_never_holds_a_direction_for_a_second(ideal):
    h = ideal.hangs[2]
    assert h.rest_span_s is None
    sel = np.nonzero(_in(ideal, h.release_t_s, h.end_t_s))[0]
    t, a = ideal.t_s[sel], ideal.accel_m_s2[sel]
    d = a / np.linalg.norm(a, axis=1)[:, None]
    assert t[-1] - t[0] > 13.5
    for start in np.arange(t[0], t[-1] - 1.0, 0.05):
        w = (t >= start) & (t <= start + 1.0)
        ang = np.degrees(np.arccos(np.clip(d[w] @ d[w][0], -1, 1)))
        # two directions 0.1° apart: no fixed direction is within 0.05° of both
        assert ang.max() > 0.1, start
    late = _in(ideal, h.end_t_s - 2.0, h.end_t_s)
    # still swinging at its end (the sensor sees part of the 3° swing)
    assert np.degrees(np.arccos(d[late[sel]] @ _perm(AXES) @ _up(HANGS[2].point_mm))).max() > 0.3


def test_release_swing_decays_with_the_stated_decay_time(ideal):
    h = ideal.hangs[0]
    u = _up(HANGS[0].point_mm)
    t0 = h.release_t_s
    peaks, centres = [], []
    for k in range(8):  # one-second windows (the slow mode's period is ~1 s)
        w = _in(ideal, t0 + k, t0 + k + 1.0)
        dev = np.linalg.norm(ideal.ideal_body_m_s2[w] / G - u, axis=1)
        peaks.append(dev.max())
        centres.append(t0 + k + 0.5)
    assert peaks[0] > np.radians(0.3)  # a real swing, then
    slope = np.polyfit(centres, np.log(peaks), 1)[0]
    assert -1.0 / slope == pytest.approx(HANGS[0].decay_time_s, rel=0.12)


def test_handling_is_large_and_turns_the_object(ideal):
    for i, h in enumerate(ideal.hangs):
        start = h.release_t_s - HANGS[i].handling_s
        sel = _in(ideal, start, h.release_t_s)
        f = ideal.ideal_body_m_s2[sel]
        mag = np.linalg.norm(f, axis=1) / G
        assert (ideal.segment[sel] == -1).all()
        assert mag.max() - mag.min() > 0.25 and 0.2 < mag.min() and mag.max() < 1.9
        d = f / np.linalg.norm(f, axis=1)[:, None]
        assert np.degrees(np.arccos(np.clip(d @ d[0], -1, 1))).max() > 20.0


def test_sample_timing_has_the_rate_jitter_and_dropped_samples(noisy):
    dt = np.diff(noisy.t_s)
    assert (dt > 0).all()
    period = 1.0 / SENSOR.rate_hz
    assert np.median(dt) == pytest.approx(period, rel=0.02)
    regular = dt[dt < 1.5 * period]
    assert 0.8e-3 < regular.std() < 2e-3  # two instants jittered by σ = 1 ms: ~1.4 ms
    n_nom = noisy.t_s[-1] * SENSOR.rate_hz
    dropped = n_nom + 1 - noisy.t_s.size
    assert 0.4 * 0.01 * n_nom < dropped < 1.8 * 0.01 * n_nom


def test_phyphox_writer_reads_back_with_the_csv_module(noisy, tmp_path):
    path = tmp_path / "Raw Data.csv"
    pl.write_phyphox_csv(path, noisy)
    text = path.read_text(encoding="utf-8")
    first = text.split("\n", 1)[0]
    assert first == ('"Time (s)","Acceleration x (m/s^2)","Acceleration y (m/s^2)",'
                     '"Acceleration z (m/s^2)","Absolute acceleration (m/s^2)"')  # fmt: skip
    with path.open(newline="", encoding="utf-8") as fh:
        rows = list(csv.reader(fh))
    assert rows[0][1] == "Acceleration x (m/s^2)" and len(rows) == noisy.t_s.size + 1
    number = re.compile(r"^-?[0-9]\.[0-9]{9}E-?[0-9]+$")
    assert all(number.match(v) for r in rows[1:200] for v in r)
    values = np.array(rows[1:], float)
    assert values[:, 0] == pytest.approx(noisy.t_s, rel=1e-9, abs=1e-300)
    assert values[:, 1:4] == pytest.approx(noisy.accel_m_s2, rel=1e-9)
    assert values[:, 4] == pytest.approx(np.linalg.norm(noisy.accel_m_s2, axis=1), rel=1e-9)
    assert pl._java_e(9.364549e-3) == "9.364549000E-3"  # as in a real export
    assert pl._java_e(9.80665) == "9.806650000E0" and pl._java_e(-12.5) == "-1.250000000E1"
    plain = tmp_path / "log.csv"
    pl.write_plain_csv(plain, noisy)
    rows = list(csv.reader(plain.open(encoding="utf-8")))
    assert rows[0] == ["t_s", "ax", "ay", "az"]
    assert np.array(rows[1:], float)[:, 1:] == pytest.approx(noisy.accel_m_s2, abs=1e-7)


def test_scenarios_are_the_stated_objects():
    rig = ps.scenario("paper_rig")
    assert rig.body.mass_kg == pytest.approx(9.2 + 0.19) and len(rig.hangs) == 6
    assert np.linalg.norm(np.subtract(rig.body.cog_mm, (100.0, 37.5, 39.0))) < 2.0
    sat = ps.scenario("cubesat_3u", "adxl355", decay_time_s=6.0)
    assert 2.9 < sat.body.mass_kg < 3.3 and len(sat.hangs) == 6
    off = np.linalg.norm(np.subtract(sat.body.cog_mm, (50.0, 50.0, 170.25)))
    assert 3.0 < off < 20.0
    assert {h.decay_time_s for h in sat.hangs} == {6.0}
    assert sat.sensor.lsb_g == pytest.approx(3.9e-6, rel=0.01)
    for spec in (rig, sat):
        inertia = np.asarray(spec.body.inertia_kg_mm2)
        assert np.allclose(inertia, inertia.T) and (np.linalg.eigvalsh(inertia) > 0).all()


def test_cli_writes_the_log_and_its_truth(tmp_path, monkeypatch):
    import json

    small = replace(SPEC, hangs=(replace(HANGS[0], settle_s=2.0, average_s=1.0, decay_time_s=0.4),))
    monkeypatch.setattr(ps, "scenario", lambda name, sensor: small)
    assert ps.main(["--seed", "3", "--out", str(tmp_path), "--knock", "1"]) == 0
    truth = json.loads((tmp_path / "truth.json").read_text())
    assert truth["hangs"][0]["knock_t_s"] is not None and truth["seed"] == 3
    assert truth["cog_mm"] == pytest.approx(COG.tolist())
    assert (tmp_path / "Raw Data.csv").read_text().startswith('"Time (s)"')
