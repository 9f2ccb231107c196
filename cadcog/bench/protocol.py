"""The cadcog line protocol (version 1), spoken by the firmware in ``firmware/``.

Every line is ASCII, at most :data:`MAX_LINE_BYTES` long, ends with ``\\n`` (a ``\\r`` before it
is ignored) and reads ``$BODY*CC``: ``CC`` is the CRC-8 of ``BODY`` (polynomial 0x07, initial
value 0, no reflection, no final XOR: CRC-8/SMBUS) as two upper-case hex digits. Two kinds:

- header ``$CCH,proto=1,device=...,sensor=...,value=adc_sum|angle|accel,rate_hz=...,...*CC``:
  comma separated ``key=value`` fields (unknown keys are ignored). ``value=adc_sum``: each sample
  is the sum of ``oversample`` conversions of an ``adc_bits``-bit ADC with reference ``vref_v``
  volts. ``value=angle``: each sample is an angle in units of ``deg_per_lsb`` degrees.
  ``value=accel``: each sample is a three-axis acceleration in units of ``lsb_g`` g (standard
  gravity), from an accelerometer set to a range of ±``full_scale_g`` g. The device sends it at
  start, every few seconds, and when it receives ``?``;
- sample ``$CCS,seq,t_ms,x,y,status*CC``, or ``$CCS,seq,t_ms,x,y,z,status*CC`` (six fields)
  from a three-axis ``accel`` device: integers; ``seq`` counts samples (uint32, wraps), ``t_ms``
  is the device clock in ms (uint32, wraps), ``x``, ``y`` (and ``z``) the axes in the header's
  unit, ``status`` 0 when the device saw no fault. An ``accel`` device sends six fields, every
  other kind five; a sample of the other form than its header's is malformed.

A malformed line (bad checksum, bad field, too long, not ASCII) is counted and skipped: noise on
the link never stops a run. Reference: ``docs/bench.md``.

Examples
--------
>>> line = format_sample(7, 1500, 8123, 8201)
>>> line
'$CCS,7,1500,8123,8201,0*BF'
>>> p = LineParser()
>>> text = format_header(ANALOG_EXAMPLE) + "\\n" + line + "\\n"
>>> [type(e).__name__ for e in p.feed(text.encode())]
['Header', 'Sample']

A three-axis accelerometer (the ADXL355 at ±2 g: 256 000 LSB per g):

>>> format_header(ACCEL_EXAMPLE).split(",")[4:]
['value=accel', 'rate_hz=20', 'lsb_g=3.90625e-06', 'full_scale_g=2*55']
>>> line = format_sample(8, 1550, -1024, 512, z=255000)
>>> line
'$CCS,8,1550,-1024,512,255000,0*4B'
>>> p = LineParser()
>>> header, sample = p.feed((format_header(ACCEL_EXAMPLE) + "\\n" + line + "\\n").encode())
>>> sample.z, round(sample.z * header.lsb_g, 6)
(255000, 0.996094)
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Literal

#: Protocol version this module reads and writes.
PROTOCOL_VERSION = 1

#: Longest line accepted, terminator excluded (bytes). Longer runs are noise.
MAX_LINE_BYTES = 160

ValueKind = Literal["adc_sum", "angle", "accel"]

_CRC_TABLE: list[int] = []
for _i in range(256):
    _c = _i
    for _ in range(8):
        _c = ((_c << 1) ^ 0x07) & 0xFF if _c & 0x80 else (_c << 1) & 0xFF
    _CRC_TABLE.append(_c)


def crc8(data: bytes) -> int:
    """CRC-8/SMBUS (polynomial 0x07, init 0) of ``data``.

    Examples
    --------
    >>> hex(crc8(b"123456789"))  # the catalogue check value of CRC-8/SMBUS
    '0xf4'
    """
    c = 0
    for b in data:
        c = _CRC_TABLE[c ^ b]
    return c


@dataclass(frozen=True)
class Header:
    """What a device says about itself.

    Attributes
    ----------
    device, sensor : str
        Free names (e.g. ``arduino-uno``, ``ACS-060``).
    value : "adc_sum", "angle" or "accel"
    rate_hz : float
        Samples per second.
    adc_bits : int or None
        ``adc_sum`` only: ADC resolution.
    vref_v : float or None
        ``adc_sum`` only: ADC reference voltage (V).
    oversample : int
        ``adc_sum``: conversions summed per sample; 1 for ``angle`` and ``accel``.
    deg_per_lsb : float or None
        ``angle`` only: degrees per unit of x and y.
    proto : int
        Protocol version.
    lsb_g : float or None
        ``accel`` only: acceleration per unit of x, y and z, in g (standard gravity).
    full_scale_g : float or None
        ``accel`` only: the accelerometer's configured range, ±``full_scale_g`` g.
    """

    device: str
    sensor: str
    value: ValueKind
    rate_hz: float
    adc_bits: int | None = None
    vref_v: float | None = None
    oversample: int = 1
    deg_per_lsb: float | None = None
    proto: int = PROTOCOL_VERSION
    lsb_g: float | None = None
    full_scale_g: float | None = None

    def describe(self) -> str:
        """One line for people: ``arduino-uno/ACS-060, 10-bit ADC at 5 V, ×16, 20 Hz``."""
        if self.value == "adc_sum":
            unit = f"{self.adc_bits}-bit ADC at {self.vref_v:g} V, x{self.oversample}"
        elif self.value == "accel":
            unit = f"3-axis accelerations of {self.lsb_g:g} g per LSB, ±{self.full_scale_g:g} g"
        else:
            unit = f"angles of {self.deg_per_lsb:g} deg per LSB"
        return f"{self.device}/{self.sensor}, {unit}, {self.rate_hz:g} Hz"


#: The paper's equipment as the analog sketch describes it (for examples and tests).
ANALOG_EXAMPLE = Header("arduino-uno", "ACS-060", "adc_sum", 20.0, 10, 5.0, 16)

#: The ADXL355 sketch's header at its ±2 g range (for examples and tests).
ACCEL_EXAMPLE = Header("arduino", "ADXL355", "accel", 20.0, lsb_g=1 / 256_000, full_scale_g=2.0)


@dataclass(frozen=True)
class Sample:
    """One sample line, with the device clock unwrapped to seconds.

    Attributes
    ----------
    seq : int
        Sample counter as sent (uint32).
    t_s : float
        Device time (s), unwrapped across the uint32 millisecond wrap.
    x, y : int
        Raw values in the header's unit.
    status : int
        0 when the device saw no fault.
    z : int or None
        The third axis of an ``accel`` device (a six-field line); None for the others.
    """

    seq: int
    t_s: float
    x: int
    y: int
    status: int
    z: int | None = None


@dataclass
class LinkStats:
    """Counters of what the parser saw (mutable: the parser updates them).

    Attributes
    ----------
    lines : int
        Complete lines received (valid or not).
    rejected : int
        Lines dropped as malformed (checksum, syntax, length, encoding).
    headers, samples : int
        Valid lines of each kind.
    before_header : int
        Valid samples dropped because no header had been seen yet.
    missing : int
        Samples lost on the way, from gaps in ``seq``.
    faults : int
        Samples the device flagged with a non-zero status (dropped).
    first_rejected : str
        The first malformed line (shortened), to tell what the device speaks.
    """

    lines: int = 0
    rejected: int = 0
    headers: int = 0
    samples: int = 0
    before_header: int = 0
    missing: int = 0
    faults: int = 0
    first_rejected: str = ""

    def summary(self) -> str:
        return (
            f"{self.samples} samples, {self.rejected} malformed line(s) rejected, "
            f"{self.missing} lost, {self.faults} flagged by the device"
        )


def _checked(body: str) -> str:
    return f"${body}*{crc8(body.encode('ascii')):02X}"


def format_header(h: Header) -> str:
    """The header line of ``h`` (no terminator)."""
    fields = [
        "CCH",
        f"proto={h.proto}",
        f"device={h.device}",
        f"sensor={h.sensor}",
        f"value={h.value}",
        f"rate_hz={h.rate_hz:g}",
    ]
    if h.value == "adc_sum":
        fields += [f"adc_bits={h.adc_bits}", f"vref_v={h.vref_v:g}", f"oversample={h.oversample}"]
    elif h.value == "accel":
        fields += [f"lsb_g={h.lsb_g!r}", f"full_scale_g={h.full_scale_g:g}"]
    else:
        fields.append(f"deg_per_lsb={h.deg_per_lsb!r}")
    return _checked(",".join(fields))


def format_sample(
    seq: int, t_ms: int, x: int, y: int, status: int = 0, *, z: int | None = None
) -> str:
    """A sample line (no terminator); ``seq`` and ``t_ms`` are taken modulo 2³².

    With ``z`` (an ``accel`` device), the six-field form ``$CCS,seq,t_ms,x,y,z,status``.
    """
    axes = f"{x},{y}" if z is None else f"{x},{y},{z}"
    return _checked(f"CCS,{seq % 2**32},{t_ms % 2**32},{axes},{status}")


_NAME = re.compile(r"^[A-Za-z0-9_.+-]{1,32}$")
_INT = re.compile(r"^-?[0-9]{1,10}$")


class LineError(ValueError):
    """A malformed line (the parser counts these; it never raises them to its caller)."""


def parse_header(body: str) -> Header:
    """Parse a header body (between ``$`` and ``*``, checksum already verified)."""
    kv: dict[str, str] = {}
    for item in body.split(",")[1:]:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise LineError(f"header field {item!r} is not key=value")
        kv[key] = value

    def get(key: str) -> str:
        if key not in kv:
            raise LineError(f"header lacks {key}")
        return kv[key]

    def num(key: str, kind: type = float) -> float:
        text = get(key)
        try:
            v = float(text) if kind is float else int(text)
        except ValueError:
            raise LineError(f"header {key}={text!r} is not a number") from None
        if not math.isfinite(v) or not v > 0:
            raise LineError(f"header {key}={kv[key]!r} must be positive")
        return v

    proto = int(num("proto", int))
    if proto != PROTOCOL_VERSION:
        raise LineError(f"protocol version {proto}, this cadcog reads {PROTOCOL_VERSION}")
    for key in ("device", "sensor"):
        if not _NAME.match(get(key)):
            raise LineError(f"header {key}={kv[key]!r}: expected a short name")
    value = get("value")
    if value == "adc_sum":
        return Header(
            kv["device"],
            kv["sensor"],
            "adc_sum",
            num("rate_hz"),
            adc_bits=int(num("adc_bits", int)),
            vref_v=num("vref_v"),
            oversample=int(num("oversample", int)),
            proto=proto,
        )
    if value == "angle":
        return Header(
            kv["device"],
            kv["sensor"],
            "angle",
            num("rate_hz"),
            deg_per_lsb=num("deg_per_lsb"),
            proto=proto,
        )
    if value == "accel":
        return Header(
            kv["device"],
            kv["sensor"],
            "accel",
            num("rate_hz"),
            proto=proto,
            lsb_g=num("lsb_g"),
            full_scale_g=num("full_scale_g"),
        )
    raise LineError(f"header value={value!r}: expected adc_sum, angle or accel")


def split_line(raw: bytes) -> tuple[str, str]:
    """Check a line's frame and checksum; return its kind (``CCH``/``CCS``) and body."""
    if len(raw) > MAX_LINE_BYTES:
        raise LineError("line too long")
    try:
        text = raw.decode("ascii")
    except UnicodeDecodeError:
        raise LineError("not ASCII") from None
    if not text.startswith("$") or len(text) < 5 or text[-3] != "*":
        raise LineError("not a $...*CC line")
    body, cc = text[1:-3], text[-2:]
    try:
        expected = int(cc, 16)
    except ValueError:
        raise LineError("checksum is not hex") from None
    if crc8(body.encode("ascii")) != expected:
        raise LineError("checksum mismatch")
    kind = body.split(",", 1)[0]
    if kind not in ("CCH", "CCS"):
        raise LineError(f"unknown line kind {kind!r}")
    return kind, body


def _parse_sample_fields(body: str) -> tuple[int, int, int, int, int | None, int]:
    """``seq, t_ms, x, y, z, status`` of a sample body; ``z`` None in the five-field form."""
    parts = body.split(",")
    if len(parts) not in (6, 7) or not all(_INT.match(p) for p in parts[1:]):
        raise LineError("sample line needs 5 integers (6 with z)")
    values = [int(p) for p in parts[1:]]
    seq, t_ms, x, y = values[:4]
    z = values[4] if len(values) == 6 else None
    status = values[-1]
    if not (0 <= seq < 2**32 and 0 <= t_ms < 2**32 and status >= 0):
        raise LineError("sample seq/t_ms/status out of range")
    return seq, t_ms, x, y, z, status


@dataclass
class LineParser:
    """Turn a byte stream into :class:`Header` and :class:`Sample` events.

    Feed it whatever bytes arrive (any chunking); it keeps the unfinished tail, unwraps the
    device clock, counts lost samples from ``seq`` gaps and malformed lines in :attr:`stats`.
    A new header resets the clock unwrapping (the device may have restarted).
    """

    stats: LinkStats = field(default_factory=LinkStats)
    header: Header | None = None
    _buffer: bytearray = field(default_factory=bytearray)
    _last_seq: int | None = None
    _last_ms: int | None = None
    _wraps: int = 0

    def feed(self, data: bytes) -> list[Header | Sample]:
        """Parse ``data``; return the valid events in order."""
        self._buffer += data
        events: list[Header | Sample] = []
        while True:
            nl = self._buffer.find(b"\n")
            if nl < 0:
                if len(self._buffer) > MAX_LINE_BYTES:  # a run of noise without a newline
                    self._reject(bytes(self._buffer[:40]), "line too long")
                    self._buffer.clear()
                return events
            raw = bytes(self._buffer[:nl]).rstrip(b"\r")
            del self._buffer[: nl + 1]
            if not raw:
                continue
            self.stats.lines += 1
            try:
                event = self._parse(raw)
            except LineError as exc:
                self._reject(raw, str(exc))
                continue
            if event is not None:
                events.append(event)

    def _reject(self, raw: bytes, reason: str) -> None:
        self.stats.rejected += 1
        if not self.stats.first_rejected:
            text = raw[:40].decode("ascii", errors="replace")
            self.stats.first_rejected = f"{text!r} ({reason})"

    def _parse(self, raw: bytes) -> Header | Sample | None:
        kind, body = split_line(raw)
        if kind == "CCH":
            header = parse_header(body)
            if header != self.header:
                self._last_seq = self._last_ms = None
                self._wraps = 0
            self.header = header
            self.stats.headers += 1
            return header
        seq, t_ms, x, y, z, status = _parse_sample_fields(body)
        if self.header is None:
            self.stats.before_header += 1
            return None
        if (z is not None) != (self.header.value == "accel"):
            raise LineError(
                "an accel device's sample has x, y and z, any other device's x and y only"
            )
        if self._last_seq is not None:
            gap = (seq - self._last_seq - 1) % 2**32
            if gap < 2**16:  # a larger jump is a restart, not a loss
                self.stats.missing += gap
        if self._last_ms is not None and t_ms < self._last_ms and self._last_ms - t_ms > 2**31:
            self._wraps += 1
        self._last_seq, self._last_ms = seq, t_ms
        if status != 0:
            self.stats.faults += 1
            return None
        self.stats.samples += 1
        return Sample(seq, (t_ms + self._wraps * 2**32) / 1000.0, x, y, status, z)
