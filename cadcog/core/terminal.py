"""What reaches a terminal: names from files shown, never obeyed.

Body names, ids and paths come from the user's files; a control character in one (an escape
sequence that recolours or clears the terminal, a NUL, a lone surrogate that standard output
cannot even encode) must be shown as text. :class:`SafeStream` wraps standard output and error
for the length of a command and writes every such character as a ``\\uXXXX`` escape
(``\\u001b``, ``\\ud800``); newlines, tabs and carriage returns pass. JSON text stays valid JSON
(JSON escapes the C0 characters itself; DEL, C1 and a lone surrogate become the JSON escapes
they are).
"""

from __future__ import annotations

import re
from typing import Any, TextIO

#: C0 and C1 control characters but tab, newline and carriage return (the live status line of
#: ``acquire`` and the progress bars redraw with it), DEL, and lone surrogates.
_UNSAFE = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f-\x9f\ud800-\udfff]")


def printable(text: str) -> str:
    """``text`` with every control character and lone surrogate written as an escape.

    Examples
    --------
    >>> printable("rail\\x1b[31m RED\\ttab\\n"), printable("x\\ud800y\\x7f")
    ('rail\\\\u001b[31m RED\\ttab\\n', 'x\\\\ud800y\\\\u007f')
    """
    return _UNSAFE.sub(_escape, text)


def _escape(m: re.Match[str]) -> str:
    return f"\\u{ord(m.group()):04x}"  # also a JSON escape: JSON output stays JSON


class SafeStream:
    """A text stream that writes :func:`printable` text to ``stream`` (everything else it
    passes through)."""

    def __init__(self, stream: TextIO) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        self._stream.write(printable(text))
        return len(text)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)
