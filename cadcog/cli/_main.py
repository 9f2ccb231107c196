"""Entry point of the ``cadcog`` command.

Each subcommand lives in its own module with two functions: ``add_parser(subparsers)`` declares
its arguments and ``run(args)`` does the work by calling the library; no maths happens here.
User errors (:class:`cadcog.errors.CadcogError`) print one line on stderr and exit with status 2.
"""

from __future__ import annotations

import argparse
import signal
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from types import FrameType

from cadcog import __version__
from cadcog.cli import (
    acquire,
    budget,
    campaign,
    check,
    estimate,
    massprops,
    parts,
    plan,
    report,
    simulate,
    validate,
)
from cadcog.errors import CadcogError

#: Exit status for bad input (same as argparse's usage errors).
EXIT_USAGE = 2


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="cadcog",
        description="Centre of gravity of small spacecraft from CAD and from a double-suspension "
        "inclinometer measurement.",
    )
    parser.add_argument("--version", action="version", version=f"cadcog {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    parts.add_parser(sub)
    estimate.add_parser(sub)
    budget.add_parser(sub)
    simulate.add_parser(sub)
    campaign.add_parser(sub)
    validate.add_parser(sub)
    report.add_parser(sub)
    massprops.add_parser(sub)
    plan.add_parser(sub)
    check.add_parser(sub)
    acquire.add_parser(sub)
    return parser


class Terminated(BaseException):
    """SIGTERM, raised in the main thread so that staged outputs are cleaned up."""


def _terminate(signum: int, frame: FrameType | None) -> None:
    raise Terminated(signum)


@contextmanager
def _sigterm_raises() -> Iterator[None]:
    """While the command runs, SIGTERM raises :class:`Terminated` (then the handler before is
    restored: tests call :func:`main` in-process)."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI with ``argv`` (default: ``sys.argv[1:]``) and return the exit status.

    Bad input (:class:`~cadcog.errors.CadcogError`, and I/O errors) prints one line on stderr
    and returns 2; Ctrl-C returns 130 and SIGTERM 143, after every staged output is removed.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        with _sigterm_raises():
            status: int = args.func(args)
    except KeyboardInterrupt:
        print("cadcog: interrupted; nothing was written", file=sys.stderr)
        return 130
    except Terminated:
        print("cadcog: terminated; nothing was written", file=sys.stderr)
        return 143
    except CadcogError as exc:
        print(f"cadcog: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except BrokenPipeError:  # output piped into `head` and the like: stop quietly
        sys.stderr.close()
        return 0
    except OSError as exc:  # an output path that cannot be written, a full disk, ...
        print(f"cadcog: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    return status
