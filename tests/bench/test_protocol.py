"""The line protocol: framing, checksum, parsing of noisy streams."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.bench.protocol import (
    ACCEL_EXAMPLE,
    ANALOG_EXAMPLE,
    Header,
    LineParser,
    Sample,
    crc8,
    format_header,
    format_sample,
)

U32 = st.integers(0, 2**32 - 1)
I32 = st.integers(-(2**31), 2**31 - 1)


def test_crc8_is_crc8_smbus():
    # Catalogue check value of CRC-8/SMBUS, and a bitwise reference computation.
    assert crc8(b"123456789") == 0xF4

    def bitwise(data: bytes) -> int:
        c = 0
        for b in data:
            c ^= b
            for _ in range(8):
                c = ((c << 1) ^ 0x07) & 0xFF if c & 0x80 else (c << 1) & 0xFF
        return c

    assert all(crc8(bytes([i, 255 - i, 7])) == bitwise(bytes([i, 255 - i, 7])) for i in range(256))


@given(seq=U32, t_ms=U32, x=I32, y=I32, status=st.integers(0, 255))
def test_sample_lines_round_trip(seq, t_ms, x, y, status):
    p = LineParser()
    events = p.feed(
        (
            format_header(ANALOG_EXAMPLE) + "\n" + format_sample(seq, t_ms, x, y, status) + "\r\n"
        ).encode()
    )
    if status == 0:
        assert events[1:] == [Sample(seq, t_ms / 1000.0, x, y, 0)]
    else:
        assert events[1:] == [] and p.stats.faults == 1
    assert p.stats.rejected == 0


@pytest.mark.parametrize(
    "header",
    [ANALOG_EXAMPLE, Header("uno", "SCL3300", "angle", 20.0, deg_per_lsb=90.0 / 2**14)],
)
def test_headers_round_trip(header):
    assert LineParser().feed((format_header(header) + "\n").encode()) == [header]


@given(
    position=st.integers(0, 30),
    delta=st.integers(1, 255),
)
def test_any_single_byte_error_is_rejected(position, delta):
    line = bytearray(format_sample(123456, 987654, -8123, 16383).encode())
    position %= len(line)
    line[position] = (line[position] + delta) % 256
    p = LineParser()
    p.feed(format_header(ANALOG_EXAMPLE).encode() + b"\n")
    events = p.feed(bytes(line) + b"\n")
    # A corrupted byte may split the line in two (a newline) but never yields a sample.
    assert not any(isinstance(e, Sample) for e in events)
    assert p.stats.rejected >= 1


@given(st.binary(max_size=600), st.lists(st.integers(1, 50), max_size=20))
def test_noise_never_raises_and_chunking_does_not_matter(noise, cuts):
    good = "".join(
        line + "\n"
        for line in [format_header(ANALOG_EXAMPLE)]
        + [format_sample(i, 50 * i, i, -i) for i in range(5)]
    ).encode()
    stream = noise + b"\n" + good + noise[:20] + b"\n" + good
    whole = LineParser().feed(stream)
    p = LineParser()
    events, i = [], 0
    for c in cuts:
        events += p.feed(stream[i : i + c])
        i += c
    events += p.feed(stream[i:])
    assert events == whole
    assert sum(isinstance(e, Sample) for e in whole) == 10


def test_clock_wrap_and_lost_samples_are_accounted():
    p = LineParser()
    p.feed(format_header(ANALOG_EXAMPLE).encode() + b"\n")
    top = 2**32 - 20
    lines = [
        format_sample(10, top, 0, 0),
        format_sample(11, top + 50, 0, 0),
        format_sample(14, top + 100, 0, 0),
    ]
    events = p.feed(("\n".join(lines) + "\n").encode())
    assert [e.t_s for e in events] == pytest.approx(
        [top / 1000, (top + 50) / 1000, (top + 100) / 1000]
    )
    assert p.stats.missing == 2


def test_foreign_and_overlong_lines_are_counted_not_raised():
    p = LineParser()
    events = p.feed(b"X:+1.00 Y:-2.00\r\n" + b"A" * 500 + b"\n$GPGGA,1,2*00\n")
    assert events == []
    assert p.stats.rejected == 3
    assert "X:+1.00" in p.stats.first_rejected


def test_samples_before_any_header_are_not_used():
    p = LineParser()
    assert p.feed((format_sample(1, 10, 5, 5) + "\n").encode()) == []
    assert p.stats.before_header == 1


@pytest.mark.parametrize(
    ("body", "reason"),
    [
        ("CCH,proto=2,device=a,sensor=b,value=angle,rate_hz=1,deg_per_lsb=1", "protocol version 2"),
        ("CCH,proto=1,device=a,sensor=b,value=volts,rate_hz=1", "value='volts'"),
        (
            "CCH,proto=1,device=a,sensor=b,value=adc_sum,rate_hz=1,adc_bits=10,vref_v=5",
            "oversample",
        ),
        ("CCH,proto=1,device=a,sensor=b,value=angle,rate_hz=-1,deg_per_lsb=1", "positive"),
    ],
)
def test_bad_headers_are_rejected_with_a_reason(body, reason):
    p = LineParser()
    line = f"${body}*{crc8(body.encode()):02X}\n"
    assert p.feed(line.encode()) == []
    assert reason in p.stats.first_rejected


# Three-axis accelerometers: value=accel headers and six-field samples.

MPU6050_EXAMPLE = Header("arduino", "MPU-6050", "accel", 20.0, lsb_g=1 / 16384, full_scale_g=2.0)


@given(seq=U32, t_ms=U32, x=I32, y=I32, z=I32, status=st.integers(0, 255))
def test_six_field_sample_lines_round_trip(seq, t_ms, x, y, z, status):
    line = format_sample(seq, t_ms, x, y, status, z=z)
    assert line.startswith(f"$CCS,{seq},{t_ms},{x},{y},{z},{status}*")
    p = LineParser()
    events = p.feed((format_header(ACCEL_EXAMPLE) + "\n" + line + "\r\n").encode())
    if status == 0:
        assert events[1:] == [Sample(seq, t_ms / 1000.0, x, y, 0, z)]
    else:
        assert events[1:] == [] and p.stats.faults == 1
    assert p.stats.rejected == 0


@pytest.mark.parametrize(
    "header",
    [
        ACCEL_EXAMPLE,
        MPU6050_EXAMPLE,
        Header("uno", "ADXL355", "accel", 50.0, lsb_g=1 / 64_000, full_scale_g=8.0),
    ],
)
def test_accel_headers_round_trip(header):
    line = format_header(header)
    assert f",value=accel,rate_hz={header.rate_hz:g},lsb_g=" in line
    assert LineParser().feed((line + "\n").encode()) == [header]


@given(
    lsb_g=st.floats(min_value=1e-12, max_value=1e3, allow_nan=False, allow_infinity=False),
    full_scale_g=st.sampled_from([2.0, 4.0, 8.0, 16.0, 2.048, 200.0]),
)
def test_any_accel_unit_round_trips_exactly(lsb_g, full_scale_g):
    header = Header("uno", "acc", "accel", 20.0, lsb_g=lsb_g, full_scale_g=full_scale_g)
    assert LineParser().feed((format_header(header) + "\n").encode()) == [header]


def test_the_accel_fields_are_new_and_optional():
    # Headers of the other kinds are built, written and read as before.
    assert ANALOG_EXAMPLE.lsb_g is None and ANALOG_EXAMPLE.full_scale_g is None
    assert "lsb_g" not in format_header(ANALOG_EXAMPLE)
    assert ACCEL_EXAMPLE.describe() == (
        "arduino/ADXL355, 3-axis accelerations of 3.90625e-06 g per LSB, ±2 g, 20 Hz"
    )


def test_five_field_samples_are_unchanged():
    line = format_sample(7, 1500, 8123, 8201)
    assert line == "$CCS,7,1500,8123,8201,0*BF"  # the bytes of protocol version 1 as first defined
    assert format_sample(7, 1500, 8123, 8201, 0, z=None) == line
    p = LineParser()
    events = p.feed((format_header(ANALOG_EXAMPLE) + "\n" + line + "\n").encode())
    assert events[1:] == [Sample(7, 1.5, 8123, 8201, 0)] and events[1].z is None


@pytest.mark.parametrize(
    ("header", "sample"),
    [
        (ANALOG_EXAMPLE, format_sample(1, 50, 10, 20, z=30)),  # z from a two-axis device
        (ACCEL_EXAMPLE, format_sample(1, 50, 10, 20)),  # an accelerometer's sample without z
    ],
)
def test_a_sample_of_the_wrong_form_for_its_header_is_rejected(header, sample):
    p = LineParser()
    events = p.feed((format_header(header) + "\n" + sample + "\n").encode())
    assert events == [header]
    assert p.stats.rejected == 1 and p.stats.samples == 0
    assert "x, y and z" in p.stats.first_rejected


def test_a_sample_needs_five_or_six_integers():
    p = LineParser()
    p.feed((format_header(ACCEL_EXAMPLE) + "\n").encode())
    for body in ("CCS,1,50,10,20,30,40,0", "CCS,1,50,10", "CCS,1,50,10,20,x,0"):
        assert p.feed(f"${body}*{crc8(body.encode()):02X}\n".encode()) == []
    assert p.stats.rejected == 3 and "6 with z" in p.stats.first_rejected


@pytest.mark.parametrize(
    ("body", "reason"),
    [
        ("CCH,proto=1,device=a,sensor=b,value=accel,rate_hz=20,full_scale_g=2", "lacks lsb_g"),
        ("CCH,proto=1,device=a,sensor=b,value=accel,rate_hz=20,lsb_g=1e-05", "lacks full_scale_g"),
        ("CCH,proto=1,device=a,sensor=b,value=accel,rate_hz=20,lsb_g=0,full_scale_g=2", "positive"),
        (
            "CCH,proto=1,device=a,sensor=b,value=accel,rate_hz=20,lsb_g=1e-05,full_scale_g=-2",
            "positive",
        ),
        (
            "CCH,proto=1,device=a,sensor=b,value=accel,rate_hz=20,lsb_g=nan,full_scale_g=2",
            "positive",
        ),
        (
            "CCH,proto=1,device=a,sensor=b,value=accel,rate_hz=20,lsb_g=1e-05,full_scale_g=two",
            "not a number",
        ),
    ],
)
def test_bad_accel_headers_are_rejected_with_a_reason(body, reason):
    p = LineParser()
    line = f"${body}*{crc8(body.encode()):02X}\n"
    assert p.feed(line.encode()) == []
    assert p.stats.rejected == 1 and p.header is None
    assert reason in p.stats.first_rejected
