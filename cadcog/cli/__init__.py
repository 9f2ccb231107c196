"""Command-line interface: ``cadcog`` (see :func:`main`)."""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence

#: Thread pools of the BLAS libraries numpy may load, limited for the console command: cadcog's
#: matrices are small (3 × 3 to a few hundred) and its parallel work runs in worker processes,
#: so a BLAS pool only costs its start-up (~0.1 s of CPU for OpenBLAS on every command) and
#: spinning threads that compete with the workers. A value the user sets wins.
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS")


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


def console_main() -> int:
    """The ``cadcog`` console command: :func:`main` with single-threaded BLAS (unless the
    environment says otherwise); it must run before numpy is imported to take effect."""
    for name in BLAS_THREAD_VARIABLES:
        os.environ.setdefault(name, "1")
    return main()


__all__ = ["console_main", "main"]
