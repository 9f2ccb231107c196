"""The line protocol: framing, checksum, parsing of noisy streams."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.bench.protocol import (
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
