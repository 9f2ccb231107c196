"""The guided run against the simulated device (simulated time: no port, no waiting)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from cadcog.bench.link import LinkError
from cadcog.bench.recorder import HangError, Recorder
from cadcog.bench.session import AutoOperator, SimulatedOperator, run_session
from cadcog.bench.simulator import DeviceSpec, SimulatedDevice, SimulatedLink, SimulatorSettings
from cadcog.bench.swing import SettleCriterion
from cadcog.bench.target import estimate_hangs
from cadcog.method.readings import read_readings

#: A Mahalanobis distance beyond this happens with probability 0.001 for a 3-D normal error.
MAHALANOBIS_999 = float(np.sqrt(stats.chi2.ppf(0.999, 3)))

# Faster physics for tests: the swing decays in ~1/3 of the time of the default.
FAST = SimulatorSettings(damping_ratio=0.05)


def _run(target, out, device, *, average_s=5.0, max_redo=1, progress=None, lines=None):
    link = SimulatedLink(device)
    recorder = Recorder(link, target.inclinometer, average_s=average_s, progress=progress)
    return run_session(
        target,
        recorder,
        out,
        SimulatedOperator(max_redo, link),
        say=(lines.append if lines is not None else lambda _t: None),
    )


def _mahalanobis(estimate, truth):
    d = estimate.cog_mm - truth
    return float(np.sqrt(d @ np.linalg.solve(estimate.cov_mm2, d)))


@pytest.mark.parametrize(("kind", "seed"), [("analog", 3), ("digital", 4)])
def test_a_whole_run_recovers_the_cog_within_its_uncertainty(paper_target, tmp_path, kind, seed):
    device = SimulatedDevice(paper_target, DeviceSpec(kind=kind), FAST, seed=seed)
    out = tmp_path / "readings.csv"
    result = _run(paper_target, out, device)
    assert [h.id for h in result.hangs] == [h.id for h in paper_target.hangs]
    assert all(h.outcome == "recorded" for h in result.hangs)
    assert _mahalanobis(result.estimate, device.true_object_cog_mm) < MAHALANOBIS_999
    # The file is an ordinary readings CSV: `cadcog estimate` reads the same suspensions.
    again = estimate_hangs(paper_target, read_readings(out, paper_target.inclinometer))
    np.testing.assert_allclose(again.cog_mm, result.estimate.cog_mm, rtol=0, atol=1e-12)
    col = "inc_x_counts" if kind == "analog" else "inc_x_deg"
    header = next(ln for ln in out.read_text().splitlines() if ln.startswith("point_id"))
    assert col in header.split(",")


def test_each_hang_averages_the_settled_equilibrium(paper_target, tmp_path):
    """The recorded mean equals the hang's true equilibrium reading (bias included) to the
    noise and quantisation: the swing is not in the average."""
    device = SimulatedDevice(paper_target, DeviceSpec(), FAST, seed=5)
    link = SimulatedLink(device)
    recorder = Recorder(link, paper_target.inclinometer, average_s=5.0)
    recorder.open()
    for index in (0, 2, 4):
        began = device.hang(index)
        data = recorder.record_hang(began)
        truth = device.truth
        expected = np.add(truth.readings_deg, truth.bias_deg)
        # Noise 0.05°/√16 per sample, ~100 samples; quantisation dithered: well below 0.01°.
        np.testing.assert_allclose(data.mean_deg, expected, atol=0.01)
        assert data.settled_after_s > 5.0  # it did swing first
        assert data.range_problem is None


def test_a_slipped_wire_is_caught_and_redone_at_once(paper_target, tmp_path):
    device = SimulatedDevice(paper_target, DeviceSpec(), FAST.__class__(
        damping_ratio=0.05, slipped_hangs=(4,), slip_mm=8.0), seed=6)  # fmt: skip
    out = tmp_path / "readings.csv"
    lines: list[str] = []
    result = _run(paper_target, out, device, lines=lines)
    outcomes = [(h.id, h.attempt, h.outcome) for h in result.hangs]
    assert ("S4", 1, "redone") in outcomes and ("S4", 2, "recorded") in outcomes
    assert any("S4" in t and "INCONSISTENT" in t for t in lines)
    text = out.read_text()
    assert "# rejected hang" in text
    # The rejected hang is only comments: S4 is read once, from its good attempt.
    susp = {s.id: s for s in read_readings(out, paper_target.inclinometer)}
    assert susp["S4"].n_samples == next(h.samples for h in result.hangs if h.outcome == "recorded"
                                        and h.id == "S4")  # fmt: skip
    assert _mahalanobis(result.estimate, device.true_object_cog_mm) < MAHALANOBIS_999


def test_interrupted_run_resumes_without_losing_or_duplicating(paper_target, tmp_path):
    device = SimulatedDevice(paper_target, DeviceSpec(), FAST, seed=7)
    out = tmp_path / "readings.csv"
    calls = {"n": 0}

    def ctrl_c_in_third_hang(state, t, x, y, amp):
        if device.truth is not None and device.truth.point_index == 2 and state == "averaging":
            calls["n"] += 1
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        _run(paper_target, out, device, progress=ctrl_c_in_third_hang)
    assert calls["n"] == 1
    ids = [s.id for s in read_readings(out, paper_target.inclinometer)]
    assert ids == ["S1", "S2"]  # nothing of S3
    lines: list[str] = []
    result = _run(paper_target, out, device, lines=lines)
    assert result.resumed == ["S1", "S2"]
    assert [h.id for h in result.hangs] == ["S3", "S4", "S5", "S6"]
    assert [s.id for s in read_readings(out, paper_target.inclinometer)] == [
        h.id for h in paper_target.hangs
    ]
    assert any("resuming" in t for t in lines)
    # The swing file beside it holds each recorded hang once, in order.
    from cadcog.dynamics.swingfile import read_swings

    swings = read_swings(tmp_path / "readings.swings.csv")
    assert [s.point_id for s in swings] == [h.id for h in paper_target.hangs]


def test_a_half_written_hang_is_set_aside_on_resume(paper_target, tmp_path):
    device = SimulatedDevice(paper_target, DeviceSpec(), FAST, seed=8)
    out = tmp_path / "readings.csv"
    first = _run(paper_target, out, device)
    text = out.read_text()
    lines = text.splitlines()
    # Cut the file in the middle of the last block, as a power cut during the write would.
    begin = max(i for i, ln in enumerate(lines) if ln.startswith("# hang S6 begin"))
    out.write_text("\n".join(lines[: begin + 40]) + "\n")
    result = _run(paper_target, out, device)
    assert result.repaired_lines == 40
    assert result.resumed == ["S1", "S2", "S3", "S4", "S5"]
    assert [h.id for h in result.hangs] == ["S6"]
    susp = read_readings(out, paper_target.inclinometer)
    assert [s.id for s in susp] == ["S1", "S2", "S3", "S4", "S5", "S6"]
    assert susp[-1].n_samples >= 90  # a whole new S6 (5 s at 20 Hz, less lost lines)
    assert first.hangs[-1].id == "S6"


def test_a_swing_that_never_settles_records_nothing(paper_target, tmp_path):
    device = SimulatedDevice(paper_target, DeviceSpec(), SimulatorSettings(never_settle=True), 9)
    link = SimulatedLink(device)
    recorder = Recorder(link, paper_target.inclinometer, SettleCriterion(max_wait_s=60.0))
    out = tmp_path / "readings.csv"
    with pytest.raises(HangError, match=r"did not settle in 60 s: amplitude still .*Nothing was"):
        run_session(paper_target, recorder, out, SimulatedOperator(1, link), lambda _t: None)
    assert [ln for ln in out.read_text().splitlines() if not ln.startswith("#")] == [
        "point_id,x_mm,y_mm,z_mm,inc_x_counts,inc_y_counts,top_face_up,t_s"
    ]


def test_a_stream_that_stops_is_a_clear_error(paper_target, tmp_path):
    device = SimulatedDevice(paper_target, DeviceSpec(), SimulatorSettings(stall_after_s=40.0), 1)
    link = SimulatedLink(device)
    recorder = Recorder(link, paper_target.inclinometer, timeout_s=5.0)
    with pytest.raises(LinkError, match=r"simulated device: the stream stopped: no valid sample"):
        run_session(paper_target, recorder, tmp_path / "r.csv", AutoOperator(), lambda _t: None)


def test_a_device_speaking_another_protocol_is_named(paper_target):
    device = SimulatedDevice(paper_target, DeviceSpec(), SimulatorSettings(foreign=True), 1)
    recorder = Recorder(SimulatedLink(device), paper_target.inclinometer)
    with pytest.raises(LinkError, match=r"does not speak the cadcog protocol: .*X:"):
        recorder.open()


def test_an_adc_unlike_the_configured_sensor_is_refused(paper_target):
    from dataclasses import replace

    device = SimulatedDevice(paper_target, DeviceSpec(), FAST, 1)
    device.header = replace(device.header, adc_bits=12, vref_v=3.3)
    recorder = Recorder(SimulatedLink(device), paper_target.inclinometer)
    with pytest.raises(LinkError, match=r"12-bit ADC at 3.3 V.*10-bit at 5 V"):
        recorder.open()


def test_a_reading_beyond_the_range_is_refused(paper_rig, tmp_path):
    """A hang the sensor cannot read (saturated) is not recorded; the run goes on."""
    from dataclasses import replace

    from cadcog.bench.target import target_from_rig

    narrow = replace(paper_rig, inclinometer=replace(paper_rig.inclinometer, range_deg=45.0))
    target = target_from_rig(narrow)
    device = SimulatedDevice(target, DeviceSpec(), FAST, seed=2)
    result = _run(target, tmp_path / "r.csv", device, max_redo=0)
    refused = {h.id for h in result.hangs if h.outcome == "refused"}
    assert refused == {"S1", "S2"}  # |X| ≈ 50.6° > 45°; the others read within 45°
    recorded = [s.id for s in read_readings(tmp_path / "r.csv", target.inclinometer)]
    assert recorded == ["S3", "S4", "S5", "S6"]


def test_an_operator_at_a_terminal_skips_stops_and_decides_on_redos(paper_target, tmp_path):
    """The console operator: Enter when the object hangs, `s` skips, `q` stops, `n` keeps."""
    from cadcog.bench.session import ConsoleOperator, SessionQuit

    settings = SimulatorSettings(damping_ratio=0.05, slipped_hangs=(2,), slip_mm=8.0)  # S3
    device = SimulatedDevice(paper_target, DeviceSpec(), settings, seed=11)
    link = SimulatedLink(device)
    order = iter([0, None, 2, None])  # S1 hung, S2 skipped, S3 hung (slips), stop at S4
    prompts: list[str] = []

    def person(prompt: str) -> str:
        prompts.append(prompt)
        if "redo" in prompt:
            return "n"  # keep the slipped S3 anyway
        index = next(order)
        if index is None:
            return "s" if len(prompts) < 3 else "q"
        device.hang(index)  # the person hangs the object, then presses Enter
        return ""

    out = tmp_path / "r.csv"
    recorder = Recorder(link, paper_target.inclinometer, average_s=5.0)
    with pytest.raises(SessionQuit):
        run_session(paper_target, recorder, out, ConsoleOperator(person), lambda _t: None)
    assert any("redo S3?" in p for p in prompts)
    text = out.read_text()
    assert "# hang S1 begin" in text and "# hang S3 begin" in text and "S2," not in text


def test_each_recorded_hang_keeps_its_swing_and_the_swings_give_the_inertia(
    paper_target, paper_rig, tmp_path
):
    # The simulated device swings on the rig's wire, in the modes the inertia chain models:
    # the chain, given the rig as it is, finds the proof mass's tensor within its uncertainty.
    from cadcog.dynamics.measure import inertia_for_rig
    from cadcog.dynamics.swingfile import read_swings
    from cadcog.dynamics.tensorfit import entries

    device = SimulatedDevice(
        paper_target, DeviceSpec(kind="digital", rate_hz=50.0), SimulatorSettings(0.01), seed=11
    )
    out = tmp_path / "readings.csv"
    _run(paper_target, out, device)
    swings = read_swings(tmp_path / "readings.swings.csv")
    assert [s.point_id for s in swings] == [h.id for h in paper_target.hangs]
    assert all(s.duration_s > 10.0 for s in swings)
    r = inertia_for_rig(paper_rig, swings, read_readings(out, paper_target.inclinometer))
    d = entries(r.inertia_kg_mm2) - entries(paper_rig.analytic_proof_mass.inertia_kg_mm2)
    assert float(d @ np.linalg.solve(r.cov_kg2_mm4, d)) < 22.5  # χ²(6) at 99.9 %


@pytest.mark.parametrize(("wire_model", "same"), [("one-wire", True), ("paper", False)])
def test_the_device_hangs_every_hang_from_one_wire(paper_rig, wire_model, same):
    """The simulated device draws its wire once per test, as a lab has one wire: hung twice
    from the same point without play, the object hangs the same way (the paper's model, an
    offset per hang, is the negative control)."""
    from dataclasses import replace

    from cadcog.bench.target import target_from_rig

    options = replace(paper_rig.error_options, wire_model=wire_model, play_mm=0.0)
    device = SimulatedDevice(
        target_from_rig(replace(paper_rig, error_options=options)), DeviceSpec(), FAST, seed=3
    )
    device.hang(0)
    first = device.truth.vertical.copy()
    device.hang(0)
    assert np.allclose(device.truth.vertical, first, atol=1e-12) is same


def test_a_reversal_is_guided_recorded_and_read_back(paper_rig, tmp_path):
    """``S3~``: the operator is told to turn the sensor, the device reads through the turned
    sensor (its readings negated, its zero offset not), the file gets ``sensor_turned``, a
    resumed run keeps it, and the estimate reads the hang as a reversal."""
    from dataclasses import replace

    from cadcog.bench.target import target_from_rig

    rig = replace(paper_rig, inclinometer=replace(paper_rig.inclinometer, offset_deg=0.3))
    target = target_from_rig(rig, ["S1", "S2", "S3", "S3~"])
    assert [h.sensor_turned for h in target.hangs] == [False, False, False, True]
    assert target.hangs[3].expected_x_deg == -target.hangs[2].expected_x_deg
    device = SimulatedDevice(target, DeviceSpec(), FAST, seed=12)
    out = tmp_path / "readings.csv"
    # The plain hangs first (a file without the column), then the run with the reversal
    # resumes it: the file gains the column, its earlier rows false.
    plain = target_from_rig(rig, ["S1", "S2", "S3"])
    _run(plain, out, SimulatedDevice(plain, DeviceSpec(), FAST, seed=12))
    assert "sensor_turned" not in out.read_text()
    lines: list[str] = []
    result = _run(target, out, device, lines=lines)
    assert result.resumed == ["S1", "S2", "S3"]
    assert [h.id for h in result.hangs] == ["S3~"]
    assert all(h.outcome == "recorded" for h in result.hangs)
    assert any("[4/4] hang from S3~" in t and "TURNED 180°" in t for t in lines)
    header = next(ln for ln in out.read_text().splitlines() if ln.startswith("point_id"))
    assert header.split(",")[-1] == "sensor_turned"
    sus = {s.id: s for s in read_readings(out, rig.inclinometer)}
    assert [s.sensor_turned for s in sus.values()] == [False, False, False, True]
    # The two readings of S3 differ in sign but share the sensor's zero offset: their mean is
    # that offset, to the per-hang bias (±0.1°), noise and the re-hang's play (the mean's
    # spread about the offset: σ 0.16-0.18° per axis over 200 seeds, 0.49° at most: 3.5 σ).
    offset = device.shared_sensor[0:2]
    mean = np.array(
        [
            (sus["S3"].inc_x_deg + sus["S3~"].inc_x_deg) / 2,
            (sus["S3"].inc_y_deg + sus["S3~"].inc_y_deg) / 2,
        ]
    )
    np.testing.assert_allclose(mean, offset, atol=0.6)
    assert abs(sus["S3"].inc_x_deg - sus["S3~"].inc_x_deg) > 10.0
    again = estimate_hangs(target, list(sus.values()))
    np.testing.assert_allclose(again.cog_mm, result.estimate.cog_mm, atol=1e-12)
    assert not any(
        "S3 & S3~" in w for w in again.warnings
    )  # a reversal pair is not "ill-conditioned"
    assert _mahalanobis(again, device.true_object_cog_mm) < MAHALANOBIS_999
    # Resumed: the recorded hangs come back with their flag.
    resumed = _run(target, out, device)
    assert resumed.resumed == ["S1", "S2", "S3", "S3~"]


def test_a_file_of_another_objects_hangs_is_not_resumed(paper_target, tmp_path):
    """A finished 3U run resumed without its --setup (the paper rig by default) appended the
    rig's six hangs to the 3U's, then estimated a CoG 48 mm off (new-user trial). A hang of
    none of the target's points is refused before anything is recorded."""
    from cadcog.core.errors import CadcogError

    out = tmp_path / "readings.csv"
    device = SimulatedDevice(paper_target, DeviceSpec(), FAST, seed=3)
    _run(paper_target, out, device)
    text = out.read_text(encoding="utf-8")
    text = text.replace("\nS2,", "\n+x_30_90,").replace("# hang S2 ", "# hang +x_30_90 ")
    out.write_text(text, encoding="utf-8")
    with pytest.raises(CadcogError, match=r"\+x_30_90 is none of paper_rig's points: the file"):
        _run(paper_target, out, device)
    assert out.read_text(encoding="utf-8") == text
