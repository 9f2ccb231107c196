"""Entry point of the ``cadcog`` command.

Each subcommand lives in its own module with two functions: ``add_parser(subparsers)`` declares its
arguments and ``run(args)`` does the work by calling the library; no maths happens here. User errors
(:class:`cadcog.core.errors.CadcogError`) print one line on stderr and exit with status 2.
"""

from __future__ import annotations

import argparse
import errno
import importlib
import signal
import sys
from collections.abc import Iterator, Sequence
from contextlib import ExitStack, contextmanager
from pathlib import Path
from types import FrameType
from typing import NoReturn

from cadcog.core import bounds
from cadcog.core.errors import CadcogError, capped
from cadcog.core.fileio import (
    guarding_inputs,
    noted_inputs,
    output_lock,
    reset_written,
    written_outputs,
)
from cadcog.core.terminal import SafeStream
from cadcog.core.version import __version__

#: Exit status for bad input (same as argparse's usage errors).
EXIT_USAGE = 2

#: The options (argparse ``dest``) of every command that name a file or folder it writes: each is
#: locked for the whole run (:func:`cadcog.core.fileio.output_lock`), so that two runs on one
#: output cannot mix (``acquire`` appends hang by hang; a report is written at the end). A
#: command whose other options are outputs for it only (``acquire --swings``, where ``update
#: --swings`` reads) names them with ``set_defaults(also_written=...)``.
OUTPUT_OPTIONS = ("out", "report", "junit", "plot")


class UsageError(CadcogError):
    """A command line argparse refuses (unknown option, missing or malformed value)."""


class OneLineParser(argparse.ArgumentParser):
    """An :class:`argparse.ArgumentParser` whose usage errors are one line naming the command,
    raised as :class:`UsageError` so that :func:`main` returns 2 like any bad input (its
    subcommand parsers are of this class too)."""

    #: The subcommand being parsed, set by :func:`main`: the top-level parser reports a
    #: subcommand's unrecognized arguments, and should name it.
    command: str | None = None

    def error(self, message: str) -> NoReturn:
        command = self.prog.partition(" ")[2] or self.command  # "cadcog massprops" → massprops
        if command:
            raise UsageError(f"{command}: {message} (see `cadcog {command} --help`)")
        raise UsageError(f"{message} (see `{self.prog} --help`)")


#: Every subcommand, in the order ``cadcog --help`` lists them: its name and the module that
#: declares it (``add_parser(subparsers)``) and runs it. A run imports only its command's module
#: (numpy, scipy or OCP come with it, not with the others); ``--help`` and usage errors without a
#: known command import them all, to list them.
COMMANDS: dict[str, str] = {
    "parts": "cadcog.cli.parts",
    "estimate": "cadcog.cli.estimate",
    "budget": "cadcog.cli.budget",
    "simulate": "cadcog.cli.simulate",
    "campaign": "cadcog.cli.campaign",
    "validate": "cadcog.cli.validate",
    "report": "cadcog.cli.report",
    "massprops": "cadcog.cli.massprops",
    "plan": "cadcog.cli.plan",
    "check": "cadcog.cli.check",
    "balance": "cadcog.cli.balance",
    "acquire": "cadcog.cli.acquire",
    "update": "cadcog.cli.update",
    "inertia": "cadcog.cli.inertia",
    "setup": "cadcog.cli.setup",
    "cache": "cadcog.cli.cache",
}


def build_parser(command: str | None = None) -> OneLineParser:
    """The ``cadcog`` parser: with ``command`` (a name of :data:`COMMANDS`), only that command's
    module is imported and the others are bare names; with ``command=""``, none is (enough for
    ``--version``); with None, every one (``--help``)."""
    parser = OneLineParser(
        prog="cadcog",
        description="Centre of gravity of small spacecraft from CAD and from a double-suspension "
        "inclinometer measurement.",
    )
    parser.add_argument("--version", action="version", version=f"cadcog {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, module in COMMANDS.items():
        if command is None or name == command:
            importlib.import_module(module).add_parser(sub)
        else:
            sub.add_parser(name)  # a name for argparse's list of choices, never run
    return parser


def _command_of(words: Sequence[str]) -> str | None:
    """The command to load for ``words``: its name, "" for ``--version`` alone (nothing to
    load), None when every command is needed (``--help``, no command, an unknown one)."""
    if words and words[0] in COMMANDS:
        return words[0]
    if words and words[0] == "--version":
        return ""
    return None


class Terminated(BaseException):
    """SIGTERM, raised in the main thread so that staged outputs are cleaned up."""


#: The signal that stopped the running command, if one did. An extension module being imported
#: when the signal arrives turns the exception its handler raises into an ImportError
#: ("initialization failed"), so :func:`main` also looks here.
_STOPPED_BY: list[int] = []


def _terminate(signum: int, frame: FrameType | None) -> None:
    _STOPPED_BY.append(signum)
    raise Terminated(signum)


def _interrupt(signum: int, frame: FrameType | None) -> None:
    _STOPPED_BY.append(signum)
    raise KeyboardInterrupt


@contextmanager
def _sigterm_raises() -> Iterator[None]:
    """While the command runs, SIGTERM raises :class:`Terminated` and SIGINT
    :class:`KeyboardInterrupt`, each noted in :data:`_STOPPED_BY` (then the handlers before are
    restored: tests call :func:`main` in-process)."""
    import threading

    _STOPPED_BY.clear()
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _terminate)
    previous_int = signal.signal(signal.SIGINT, _interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)
        signal.signal(signal.SIGINT, previous_int)


def _subparsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def attach_dash_values(parser: argparse.ArgumentParser, argv: Sequence[str]) -> list[str]:
    """``["--about", "-10,0,0"]`` → ``["--about=-10,0,0"]``: a value that starts with ``-``
    after an option that takes one value, and is not itself an option of the command.

    argparse reads such a value as an unknown option (negative vectors, suspension point ids
    such as ``-x_30_-30``); the ``--opt=value`` form is what users would otherwise have to
    know to type.
    """
    args = list(argv)
    if not args or args[0] not in _subparsers(parser):
        return args
    sub = _subparsers(parser)[args[0]]
    takes_value = {
        o
        for a in sub._actions
        if a.nargs is None
        and a.option_strings
        and not isinstance(a, argparse._HelpAction)
        and a.const is None
        for o in a.option_strings
        if o.startswith("--")
    }
    known = {o for a in sub._actions for o in a.option_strings}
    out: list[str] = [args[0]]
    i = 1
    while i < len(args):
        token = args[i]
        if token == "--":
            out.extend(args[i:])
            break
        nxt = args[i + 1] if i + 1 < len(args) else None
        if (
            token in takes_value
            and nxt is not None
            and nxt.startswith("-")
            and nxt != "-"
            and nxt.split("=", 1)[0] not in known
        ):
            out.append(f"{token}={nxt}")
            i += 2
            continue
        out.append(token)
        i += 1
    return out


def check_option_values(parser: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """Every numeric option finite and within its bound (:mod:`cadcog.core.bounds`, by the option's
    name and unit suffix), before any work is done.

    Raises
    ------
    UsageError
        Naming the option, its value and the bound with its reason.
    """
    command = getattr(args, "command", None)
    sub = _subparsers(parser).get(command or "")
    if sub is None:
        return
    for action in sub._actions:
        if not action.option_strings or action.dest not in vars(args):
            continue
        value = getattr(args, action.dest)
        values = value if isinstance(value, tuple) else (value,)
        for v in values:
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                continue
            problem = bounds.check(action.dest, float(v))  # the API checks its arguments so too
            if problem is not None:
                option = max(action.option_strings, key=len)
                raise UsageError(f"{command}: {option} {value!r}: {problem}")


def refuse_repeated_options(
    parser: argparse.ArgumentParser, args: argparse.Namespace, words: Sequence[str]
) -> None:
    """An option that takes one value, given twice (``--ballast a.toml --ballast b.toml``), is
    refused naming it, instead of argparse's silent "the last one wins".

    Raises
    ------
    UsageError
    """
    command = getattr(args, "command", None)
    sub = _subparsers(parser).get(command or "")
    if sub is None:
        return
    for action in sub._actions:
        if not action.option_strings or type(action).__name__ != "_StoreAction":
            continue
        times = sum(
            any(w == o or w.startswith(o + "=") for o in action.option_strings) for w in words
        )
        if times > 1:
            option = max(action.option_strings, key=len)
            raise UsageError(
                f"{command}: {option} given {times} times: give it once (it takes one value)"
            )


def refuse_empty_values(words: Sequence[str]) -> None:
    """An empty argument (``--out ""``, ``--out=``) names its option, before argparse turns it
    into ``.`` (the working folder) or a confusing choice error.

    Raises
    ------
    UsageError
    """
    command = words[0] if words else "cadcog"
    for i, word in enumerate(words):
        option, eq, value = word.partition("=")
        if word.startswith("--") and eq and not value:
            raise UsageError(f"{command}: {option}: expected a value, got an empty one")
        if word == "":
            before = words[i - 1] if i > 0 else ""
            where = before if before.startswith("-") else "an argument"
            raise UsageError(f"{command}: {where}: expected a value, got an empty one")


def _run(args: argparse.Namespace) -> int:
    """Run the parsed command: its inputs guarded, its outputs locked, memory errors named."""
    with guarding_inputs(), ExitStack() as held:
        written = [getattr(args, dest, None) for dest in OUTPUT_OPTIONS]
        also = getattr(args, "also_written", None)  # a command's other outputs (--swings ...)
        written += list(also(args)) if also is not None else []
        for value in written:
            if isinstance(value, Path):
                held.enter_context(output_lock(value))
        try:
            return int(args.func(args))
        except MemoryError:
            read = noted_inputs()
            on = f" on {read[-1]}" if read else ""
            raise CadcogError(
                f"{args.command}: ran out of memory{on} (the machine's memory or a limit such "
                "as ulimit -v); nothing was written"
            ) from None


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI with ``argv`` (default: ``sys.argv[1:]``) and return the exit status.

    Bad input (:class:`~cadcog.core.errors.CadcogError`, and I/O errors) prints one line on stderr
    and returns 2; Ctrl-C returns 130 and SIGTERM 143, after every staged output is removed.
    Standard output and error show control characters from the user's files as escapes
    (:mod:`cadcog.core.terminal`).
    """
    out, err = sys.stdout, sys.stderr
    if out is not None and err is not None:
        sys.stdout, sys.stderr = SafeStream(out), SafeStream(err)
    try:
        return _main(argv)
    finally:
        sys.stdout, sys.stderr = out, err


def _main(argv: Sequence[str] | None) -> int:
    """:func:`main` inside its safe streams."""
    words = list(sys.argv[1:] if argv is None else argv)
    reset_written()
    try:
        with _sigterm_raises():
            command = _command_of(words)
            parser = build_parser(command)  # imports the command's module: a signal may come
            if command:
                parser.command = command
            refuse_empty_values(words)
            args = parser.parse_args(attach_dash_values(parser, words))
            refuse_repeated_options(parser, args, words)
            check_option_values(parser, args)
            status = _run(args)  # no output may replace a file the command read
    except KeyboardInterrupt:
        return _stopped(signal.SIGINT)
    except Terminated:
        return _stopped(signal.SIGTERM)
    except CadcogError as exc:
        print(f"cadcog: error: {capped(str(exc))}", file=sys.stderr)
        return EXIT_USAGE
    except BrokenPipeError:  # output piped into `head` and the like: stop quietly
        sys.stderr.close()
        return 0
    except OSError as exc:  # an output path that cannot be written, a full disk, ...
        print(f"cadcog: error: {capped(_os_error_text(exc))}", file=sys.stderr)
        return EXIT_USAGE
    except ImportError as exc:  # a library that cannot be mapped under a memory limit
        if "map segment" not in str(exc) and "allocate memory" not in str(exc):
            if not _STOPPED_BY:
                raise
            return _stopped(_STOPPED_BY[0])
        print(
            "cadcog: error: ran out of memory loading cadcog's libraries (the machine's memory "
            "or a limit such as ulimit -v); nothing was written",
            file=sys.stderr,
        )
        return EXIT_USAGE
    except MemoryError:  # while loading the command's modules (a limit such as ulimit -v)
        print(
            "cadcog: error: ran out of memory loading cadcog (the machine's memory or a limit "
            "such as ulimit -v); nothing was written",
            file=sys.stderr,
        )
        return EXIT_USAGE
    except Exception:
        if not _STOPPED_BY:
            raise
        # the signal's exception surfaced as another (an import cut short): stopped all the same
        return _stopped(_STOPPED_BY[0])
    return status


def _os_error_text(exc: OSError) -> str:
    """An I/O error in words, naming what could not be written: a file names itself; a full
    or failing device with no file is the standard output (``--json > /dev/full``), and the
    files already put in place are named."""
    if exc.filename is None and exc.errno in (errno.ENOSPC, errno.EIO, errno.EFBIG, errno.EDQUOT):
        written = ", ".join(str(p) for p in written_outputs())
        done = f"written whole before that: {written}" if written else "no file was written"
        return f"standard output: cannot write ({exc.strerror or exc}); {done}"
    return str(exc)


def _stopped(signum: int) -> int:
    """Say that a signal stopped the command, and return its exit status (128 + signal)."""
    word = "interrupted" if signum == signal.SIGINT else "terminated"
    written = written_outputs()
    if written:
        done = ", ".join(str(p) for p in written)
        print(f"cadcog: {word}; written whole before that: {done}", file=sys.stderr)
    else:
        print(f"cadcog: {word}; nothing was written", file=sys.stderr)
    return 128 + signum
