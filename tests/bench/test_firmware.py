"""The firmware in ``firmware/``, compiled and run on the host against stand-ins.

``tests/bench/firmware_host/`` has a minimal Arduino core (virtual clock, serial, ADC, SPI, I2C)
and emulated chips: an SCL3300 and an ADXL355 on SPI, an MPU-6050 on I2C, the accelerometers fed
with x, y, z counts from the test. The sketches' output must parse with cadcog's reader, carry
exactly what the stand-ins fed them, and format byte for byte as :mod:`cadcog.bench.protocol`
does.
"""

from __future__ import annotations

import dataclasses
import re
import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

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
    assert len(copies) == 4
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


#: The emulated chip (``firmware_host/chip_*.cpp``) each sketch talks to.
CHIPS = {
    "cadcog_analog": "none",
    "cadcog_scl3300": "scl3300",
    "cadcog_adxl355": "adxl355",
    "cadcog_mpu6050": "mpu6050",
}


@pytest.fixture(scope="module")
def run_sketch(tmp_path_factory):
    """``run(name, *options)``: build the sketch once, run it with the harness's options."""
    if GXX is None:
        pytest.skip("no C++ compiler on this machine")
    out_dir = tmp_path_factory.mktemp("firmware")
    built: dict[str, Path] = {}

    def run(name: str, *options: str) -> tuple[bytes, str]:
        if name not in built:
            exe = out_dir / name
            subprocess.run(
                [GXX, "-std=c++17", "-Wall", "-Wextra", "-Werror", "-O1", f"-I{HOST}",
                 "-include", "Arduino.h", "-x", "c++", str(FIRMWARE / name / f"{name}.ino"),
                 "-x", "c++", str(HOST / "harness.cpp"), str(HOST / f"chip_{CHIPS[name]}.cpp"),
                 "-o", str(exe)],
                check=True, capture_output=True,
            )  # fmt: skip
            built[name] = exe
        done = subprocess.run(
            [str(built[name]), *options], check=True, capture_output=True, timeout=60
        )
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


# The three-axis accelerometers: the emulated chip converts the test's x, y, z counts, one triple
# per burst read of its data registers, and reports its configuration registers at the end.


def _adxl355_range(regs: dict[int, int]) -> tuple[float, float]:
    """lsb_g and full_scale_g of the ADXL355's RANGE register (bits 1:0: 01 ±2 g, 10 ±4 g,
    11 ±8 g; 256 000, 128 000, 64 000 LSB/g)."""
    code = regs[0x2C] & 0x03
    assert code != 0, "RANGE bits 1:0 = 00 is not a range"
    return 1 / (256_000 >> (code - 1)), float(2 << (code - 1))


def _mpu6050_range(regs: dict[int, int]) -> tuple[float, float]:
    """lsb_g and full_scale_g of the MPU-6050's ACCEL_CONFIG (AFS_SEL, bits 4:3: ±2/4/8/16 g,
    16384/8192/4096/2048 LSB/g)."""
    afs_sel = (regs[0x1C] >> 3) & 0x03
    return 1 / (16384 >> afs_sel), float(2 << afs_sel)


class Accelerometer(NamedTuple):
    header: Header  # what the sketch says at its ±2 g range
    bits: int  # of the counts
    range_of: Callable[[dict[int, int]], tuple[float, float]]  # lsb_g, full_scale_g of registers
    measuring: Callable[[dict[int, int]], bool]  # out of standby / sleep, from the registers
    wrong_chip: str  # the harness's option for a chip of another ID


ACCELEROMETERS = {
    "cadcog_adxl355": Accelerometer(
        Header("arduino", "ADXL355", "accel", 20.0, lsb_g=1 / 256_000, full_scale_g=2.0),
        20,
        _adxl355_range,
        lambda r: (r[0x2D] & 0x01) == 0,  # POWER_CTL standby bit
        "--id=0xE9",  # an ADXL359's PARTID
    ),
    "cadcog_mpu6050": Accelerometer(
        Header("arduino", "MPU-6050", "accel", 20.0, lsb_g=1 / 16384, full_scale_g=2.0),
        16,
        _mpu6050_range,
        lambda r: (r[0x6B] & 0x40) == 0,  # PWR_MGMT_1 SLEEP bit
        "--id=0x70",  # an MPU-6500's WHO_AM_I (some boards sold as GY-521 carry one)
    ),
}


def _vectors(tmp_path: Path, bits: int, n: int = 160) -> tuple[np.ndarray, str]:
    """x, y, z counts for the emulated chip: the extremes of a ``bits``-bit two's complement
    value and its neighbours first, then random ones; and the harness's option naming them."""
    lo, hi = -(2 ** (bits - 1)), 2 ** (bits - 1) - 1
    head = np.array([[lo, hi, 0], [-1, 1, lo + 1], [hi, lo, -1], [hi - 1, 0, hi], [0, lo, 1]])
    rest = np.random.default_rng(bits).integers(lo, hi, size=(n - len(head), 3), endpoint=True)
    xyz = np.vstack([head, rest])
    path = tmp_path / f"xyz{bits}.txt"
    np.savetxt(path, xyz, fmt="%d")
    return xyz, f"--vectors={path}"


def _registers(stderr: str) -> dict[int, int]:
    """The emulated chip's configuration registers at the end of the run."""
    found = re.findall(r"^REG ([0-9A-F]{2}) ([0-9A-F]{2})$", stderr, re.MULTILINE)
    return {int(a, 16): int(v, 16) for a, v in found}


def _sample_lines(text: list[str]) -> list[str]:
    return [ln for ln in text if ln.startswith("$CCS")]


@pytest.mark.parametrize("name", sorted(ACCELEROMETERS))
def test_an_accelerometer_sketch_streams_the_chips_counts(run_sketch, tmp_path, name):
    chip = ACCELEROMETERS[name]
    xyz, option = _vectors(tmp_path, chip.bits)
    stdout, stderr = run_sketch(name, option)
    headers, samples, text, p = _lines(stdout)
    assert p.stats.rejected == 0 and p.stats.missing == 0 and p.stats.faults == 0
    assert headers == [chip.header] * 3
    # The header's unit and range are those of the range register the sketch wrote, read back
    # from the emulated chip, which measures.
    regs = _registers(stderr)
    assert chip.range_of(regs) == (chip.header.lsb_g, chip.header.full_scale_g)
    assert chip.measuring(regs)
    # At start, at once when the host asks ('?' at 1.5 s), then 40 samples after the last one.
    at = [i for i, ln in enumerate(text) if ln.startswith("$CCH")]
    assert len(headers) == len(at) == 3
    asked = at[1] - 1  # samples before the '?'
    assert samples[asked - 1].t_s <= 1.5 <= samples[asked].t_s and at[2] - at[1] == 41
    n = len(samples)
    assert n == pytest.approx(5 * 20, abs=3) and n < len(xyz)
    assert [s.seq for s in samples] == list(range(1, n + 1))
    t = np.array([s.t_s for s in samples])
    assert np.all(np.abs(np.diff(t) - 0.05) <= 0.0011)
    # Every axis of every sample is the count the chip held, extremes and signs included.
    np.testing.assert_array_equal([(s.x, s.y, s.z) for s in samples], xyz[:n])
    # Byte for byte what the Python side formats.
    assert text[0] == format_header(chip.header)
    assert _sample_lines(text) == [
        format_sample(s.seq, round(s.t_s * 1000), s.x, s.y, z=s.z) for s in samples
    ]


@pytest.mark.parametrize(
    ("name", "option"),
    [
        ("cadcog_adxl355", ACCELEROMETERS["cadcog_adxl355"].wrong_chip),
        ("cadcog_mpu6050", ACCELEROMETERS["cadcog_mpu6050"].wrong_chip),
        ("cadcog_mpu6050", "--absent=1"),  # nothing answers on the bus
    ],
)
def test_an_accelerometer_sketch_reports_a_wrong_chip_as_a_fault(run_sketch, name, option):
    chip = ACCELEROMETERS[name]
    stdout, stderr = run_sketch(name, option)
    headers, samples, text, p = _lines(stdout)
    assert p.stats.rejected == 0
    fault = dataclasses.replace(chip.header, sensor=f"{chip.header.sensor}-FAULT")
    assert headers == [fault, fault]  # at start and on '?'
    assert text[0] == format_header(fault)
    assert samples == [] and _sample_lines(text) == []
    assert not chip.measuring(_registers(stderr))  # the wrong chip is left in standby / asleep


@pytest.mark.parametrize("name", sorted(ACCELEROMETERS))
def test_an_accelerometer_sketch_flags_a_sensor_reset_and_restarts_it(run_sketch, tmp_path, name):
    chip = ACCELEROMETERS[name]
    xyz, option = _vectors(tmp_path, chip.bits)
    stdout, stderr = run_sketch(name, option, "--reset-at-ms=2500")
    assert "RESET 25" in stderr
    headers, samples, text, p = _lines(stdout)
    assert headers == [chip.header] * 3 and p.stats.rejected == 0
    # The sample read while the chip was back in its power-on state is flagged (status 2) and
    # dropped; the sketch configures the chip again and the next samples are its conversions.
    statuses = [int(ln.split("*")[0].split(",")[-1]) for ln in _sample_lines(text)]
    n = len(samples)
    assert len(statuses) == n + 1 and [s for s in statuses if s] == [2] and p.stats.faults == 1
    assert [s.seq for s in samples] == [k + 1 for k, status in enumerate(statuses) if status == 0]
    np.testing.assert_array_equal([(s.x, s.y, s.z) for s in samples], xyz[:n])
    regs = _registers(stderr)
    assert chip.measuring(regs)
    assert chip.range_of(regs) == (chip.header.lsb_g, chip.header.full_scale_g)


def test_the_adxl355_sketch_addresses_registers_as_the_data_sheet_says(run_sketch, tmp_path):
    _, option = _vectors(tmp_path, 20)
    _, stderr = run_sketch("cadcog_adxl355", option)
    frames = [ln.split()[1] for ln in stderr.splitlines() if ln.startswith("SPI ")]
    # Command byte (address << 1) | R: write 0x52 to RESET (0x2F), then read DEVID_AD, DEVID_MST
    # and PARTID (0x00-0x02) in one burst.
    assert frames[:2] == ["5E52", "01000000"]
    # Each sample: one burst read of DEVID_AD .. ZDATA1 (17 registers).
    assert frames[-1] == "01" + "00" * 17
