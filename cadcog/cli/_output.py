"""What a command says besides its result and its error, each in the one form scripts and the
tests read: a warning (``cadcog: warning: TEXT``) and a file written (``report: PATH``) on
standard error, and a result as one JSON object on standard output.

An error is said once, by :func:`cadcog.cli._main.main` (``cadcog: error: TEXT``, exit 2).
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any, TextIO

from cadcog.core.jsontext import write_json


def warn(text: str) -> None:
    """``cadcog: warning: TEXT`` on standard error: the result stands, something in it is
    worth a look."""
    print(f"cadcog: warning: {text}", file=sys.stderr)


def wrote(path: Path | str) -> None:
    """``report: PATH`` on standard error: a file or folder the command has written whole."""
    print(f"report: {path}", file=sys.stderr)


def print_json(data: Any, stream: TextIO | None = None) -> None:
    """``data`` (a result's ``to_dict()``) as one JSON object, two-space indent, newline-ended
    (:func:`~cadcog.core.jsontext.dumps_json`), on standard output or ``stream``."""
    write_json(data, sys.stdout if stream is None else stream)
