"""The firmware in ``firmware/``, compiled and run on the host against stand-ins.

``tests/bench/firmware_host/`` has a minimal Arduino core (virtual clock, serial, ADC) and an
emulated SCL3300 on SPI. The sketches' output must parse with cadcog's reader, carry exactly
what the stand-ins fed them, and format byte for byte as :mod:`cadcog.bench.protocol` does.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from cadcog.bench.protocol import Header, LineParser, Sample, format_header, format_sample

ROOT = Path(__file__).resolve().parents[2]
FIRMWARE = ROOT / "firmware"
HOST = Path(__file__).parent / "firmware_host"
GXX = shutil.which("g++")


def _scl3300_crc(frame: int) -> int:
    crc = 0xFF
    for byte in frame.to_bytes(4, "big")[:3]:
        crc ^= byte
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1D) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc ^ 0xFF


def test_the_protocol_header_is_the_same_in_every_sketch():
    copies = sorted(FIRMWARE.glob("*/cadcog_protocol.h"))
    assert len(copies) == 2
    assert len({c.read_bytes() for c in copies}) == 1


def test_every_scl3300_command_carries_its_crc():
    text = (FIRMWARE / "cadcog_scl3300" / "scl3300_frames.h").read_text()
    commands = {
        m[0]: int(m[1], 16) for m in re.findall(r"#define (SCL3300_\w+) 0x([0-9A-F]{8})UL", text)
    }
    assert len(commands) >= 20
    for name, frame in commands.items():
        assert _scl3300_crc(frame) == frame & 0xFF, name
    # Register addresses as the datasheet gives them (bits 30:26).
    assert (commands["SCL3300_READ_ANG_X"] >> 26) & 0x1F == 0x09
    assert (commands["SCL3300_READ_ANG_Y"] >> 26) & 0x1F == 0x0A
    assert (commands["SCL3300_READ_WHOAMI"] >> 26) & 0x1F == 0x10


@pytest.fixture(scope="module")
def run_sketch(tmp_path_factory):
    if GXX is None:
        pytest.skip("no C++ compiler on this machine")
    out_dir = tmp_path_factory.mktemp("firmware")

    def run(name: str) -> tuple[bytes, str]:
        exe = out_dir / name
        subprocess.run(
            [GXX, "-std=c++17", "-Wall", "-Wextra", "-Werror", "-O1", f"-I{HOST}",
             "-include", "Arduino.h", "-x", "c++", str(FIRMWARE / name / f"{name}.ino"),
             "-x", "c++", str(HOST / "harness.cpp"), "-o", str(exe)],
            check=True, capture_output=True,
        )  # fmt: skip
        done = subprocess.run([str(exe)], check=True, capture_output=True, timeout=60)
        return done.stdout, done.stderr.decode()

    return run


def _lines(stdout: bytes) -> tuple[list[Header], list[Sample], list[str], LineParser]:
    p = LineParser()
    events = p.feed(stdout)
    headers = [e for e in events if isinstance(e, Header)]
    samples = [e for e in events if isinstance(e, Sample)]
    return headers, samples, stdout.decode().split("\r\n"), p


def test_the_analog_sketch_streams_oversampled_sums_at_a_fixed_rate(run_sketch):
    stdout, _ = run_sketch("cadcog_analog")
    headers, samples, text, p = _lines(stdout)
    assert p.stats.rejected == 0 and p.stats.missing == 0
    assert headers[0] == Header("arduino-uno", "ACS-060", "adc_sum", 20.0, 10, 5.0, 16)
    n = len(samples)
    assert n == pytest.approx(5 * 20, abs=2)  # 5 virtual seconds at 20 Hz
    # At start; at once when the host asks ('?' at 1.5 s); then 40 samples after the last one.
    at = [i for i, ln in enumerate(text) if ln.startswith("$CCH")]
    assert len(headers) == len(at) == 3
    assert at[1] - 1 == pytest.approx(30, abs=1) and at[2] - at[1] == 41
    assert [s.seq for s in samples] == list(range(1, n + 1))
    t = np.array([s.t_s for s in samples])
    assert np.all(np.abs(np.diff(t) - 0.05) <= 0.0011)  # 50 ms apart, ms resolution
    assert t[-1] - t[0] == pytest.approx(0.05 * (n - 1), abs=0.002)  # no drift
    k = 1 + np.arange(16 * n).reshape(n, 16)  # setup() discards one conversion per channel
    np.testing.assert_array_equal([s.x for s in samples], (300 + k % 7).sum(axis=1))
    np.testing.assert_array_equal([s.y for s in samples], (700 + (3 * k) % 11).sum(axis=1))
    # Byte for byte what the Python side formats.
    assert text[0] == format_header(headers[0])
    s = samples[0]
    assert text[1] == format_sample(s.seq, round(s.t_s * 1000), s.x, s.y)


def test_the_scl3300_sketch_starts_the_sensor_and_streams_angles(run_sketch):
    stdout, spi = run_sketch("cadcog_scl3300")
    headers, samples, text, p = _lines(stdout)
    assert p.stats.rejected == 0 and p.stats.faults == 0
    assert headers[0] == Header("arduino", "SCL3300", "angle", 20.0, deg_per_lsb=90.0 / 2**14)
    assert text[0] == format_header(headers[0])
    k = np.arange(len(samples))
    np.testing.assert_array_equal([s.x for s in samples], -8000 + 3 * k)
    np.testing.assert_array_equal([s.y for s in samples], 12000 - 5 * k)
    frames = [ln.split()[1] for ln in spi.splitlines() if ln.startswith("SPI ")]
    frames = [f for f in frames if f != "00000000"]  # CS raised before the first frame
    assert frames[:7] == [
        "B4002098",  # software reset
        "B4000338",  # mode 4: inclination, low noise
        "B0001F6F",  # enable the angle outputs
        "180000E5", "180000E5",  # read STATUS (clears it), twice
        "40000091",  # WHOAMI, while the last STATUS answer comes back
        "180000E5",
    ]  # fmt: skip
    assert frames[7:13] == ["240000C7", "280000CD", "180000E5"] * 2
