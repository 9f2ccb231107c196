"""Entry point of the ``cadcog`` command.

Each subcommand lives in its own module with two functions: ``add_parser(subparsers)`` declares
its arguments and ``run(args)`` does the work by calling the library; no maths happens here.
User errors (:class:`cadcog.errors.CadcogError`) print one line on stderr and exit with status 2.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from cadcog import __version__
from cadcog.cli import (
    acquire,
    budget,
    campaign,
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
    acquire.add_parser(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI with ``argv`` (default: ``sys.argv[1:]``) and return the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        status: int = args.func(args)
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
