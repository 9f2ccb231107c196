"""Byte links to a device: a serial port (pyserial) or anything with the same four methods.

A link hands out bytes as they arrive; it knows nothing of lines. ``clock()`` is the time the
link's timeouts are measured in: the wall clock for a real port, simulated time for a simulated
device driven without a port (so tests of a stalled stream take no real time).
"""

from __future__ import annotations

import time
from typing import Any, Protocol

from cadcog.core.errors import CadcogError

#: Default serial speed (bits/s) of the firmware in ``firmware/``.
DEFAULT_BAUD = 115200


class LinkError(CadcogError):
    """The device cannot be reached or stopped talking."""


class ByteLink(Protocol):
    """What the recorder needs from a connection to a device."""

    name: str

    def read(self, max_wait_s: float) -> bytes:
        """Bytes received, waiting at most ``max_wait_s`` for the first one (b"" if none)."""
        ...

    def write(self, data: bytes) -> None:
        """Send bytes to the device (``?`` asks for a header)."""
        ...

    def flush_input(self) -> None:
        """Discard whatever has been received and not read yet."""
        ...

    def clock(self) -> float:
        """Seconds, monotonic: the time base of timeouts."""
        ...

    def close(self) -> None: ...


class SerialLink:
    """A serial port opened with pyserial (8N1, no flow control).

    Raises
    ------
    LinkError
        If the port does not exist or cannot be opened, naming it.
    """

    def __init__(self, port: str, baud: int = DEFAULT_BAUD) -> None:
        import serial  # imported here: only acquisition needs pyserial

        self.name = port
        try:
            self._port: Any = serial.Serial(port, baudrate=baud, timeout=0.05, write_timeout=1.0)
        except (serial.SerialException, OSError, ValueError) as exc:
            reason = str(exc).split(": ", 1)[-1] if ": " in str(exc) else str(exc)
            raise LinkError(f"serial port {port}: cannot open it ({reason})") from None

    def read(self, max_wait_s: float) -> bytes:
        import serial

        deadline = time.monotonic() + max_wait_s
        try:
            while True:
                waiting = self._port.in_waiting
                data: bytes = self._port.read(max(waiting, 1))
                if data or time.monotonic() >= deadline:
                    return data
        except (serial.SerialException, OSError) as exc:
            raise LinkError(f"serial port {self.name}: read failed ({exc})") from None

    def write(self, data: bytes) -> None:
        import serial

        try:
            self._port.write(data)
        except (serial.SerialException, OSError):
            pass  # a device that cannot hear us still streams; the header comes periodically

    def flush_input(self) -> None:
        self._port.reset_input_buffer()

    def clock(self) -> float:
        return time.monotonic()

    def close(self) -> None:
        self._port.close()
