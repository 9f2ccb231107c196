"""Command-line interface: ``cadcog`` (see :func:`main`)."""

from __future__ import annotations

import sys
from collections.abc import Sequence


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``cadcog`` with ``argv`` (default: ``sys.argv[1:]``); return the exit status.

    The command modules are imported here, inside the interrupt handling, so that Ctrl-C while
    they load (scipy, build123d: seconds) ends with one line and status 130, like any other time.
    """
    try:
        from cadcog.cli._main import main as _main
    except KeyboardInterrupt:
        print("cadcog: interrupted; nothing was written", file=sys.stderr)
        return 130
    return _main(argv)


__all__ = ["main"]
