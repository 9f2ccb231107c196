"""A sign of life on stderr while a long call holds the interpreter.

OCCT's STEP reader and transfer run in C++ without releasing Python's GIL, and offer no progress
callback that Python can implement (OCP binds no ``Message_ProgressIndicator`` subclassing): a
336 MB file was silent for minutes (issue 21). :func:`heartbeat` says what starts at once, then
a small helper process (not a thread: the GIL is held) writes the elapsed time every few
seconds until the call ends. The helper ignores Ctrl-C (the command reports it) and exits by
itself if cadcog dies.
"""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager, suppress

#: Seconds between two lines of a heartbeat.
HEARTBEAT_EVERY_S = 5.0

_BEAT = """
import os, signal, sys, time
signal.signal(signal.SIGINT, signal.SIG_IGN)
parent, what, every = int(sys.argv[1]), sys.argv[2], float(sys.argv[3])
start = time.monotonic()
while True:
    time.sleep(every)
    if os.getppid() != parent:
        break
    sys.stderr.write(f"cadcog: still {what}: {time.monotonic() - start:.0f} s\\n")
    sys.stderr.flush()
"""


@contextmanager
def heartbeat(what: str, every_s: float = HEARTBEAT_EVERY_S) -> Iterator[None]:
    """Write ``cadcog: WHAT ...`` on stderr now, then ``cadcog: still WHAT: N s`` every
    ``every_s`` seconds while inside."""
    print(f"cadcog: {what} ...", file=sys.stderr, flush=True)
    child = None
    with suppress(OSError, ValueError):
        child = subprocess.Popen(
            [sys.executable, "-c", _BEAT, str(os.getpid()), what, str(every_s)],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
        )
    try:
        yield
    finally:
        if child is not None:
            child.kill()
            child.wait()
