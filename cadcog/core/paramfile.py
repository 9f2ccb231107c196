"""Strict, typed reading of TOML parameter files.

Parameter files are data: they are parsed with :mod:`tomllib` and never evaluated. A
:class:`TableReader` hands out typed values by key, records which keys were read, and
:meth:`TableReader.finish` rejects any key left over, so a misspelt key is an error instead of a
silently ignored value. Every error names the file and the dotted key.
"""

from __future__ import annotations

import difflib
import math
import os
import re
import stat
import tomllib
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from cadcog.core import bounds
from cadcog.core.errors import ParameterFileError
from cadcog.core.fileio import note_input

#: Largest parameter file read (bytes): real ones are a few kB.
MAX_TOML_BYTES = 10_000_000


#: The first bytes of every STEP file (ISO 10303-21), after :func:`file_head`'s trimming.
STEP_MAGIC = b"ISO-10303-21"


def file_head(data: bytes) -> bytes:
    """The start of a file's bytes without a UTF-8 byte-order mark and leading blanks: what
    tells which kind of file it is.

    Examples
    --------
    >>> file_head(b"\\xef\\xbb\\xbf\\n ISO-10303-21;").startswith(STEP_MAGIC)
    True
    """
    return data.lstrip(b"\xef\xbb\xbf \t\r\n")


def _not_toml(data: bytes) -> str | None:
    """What a file that is not TOML is instead, when its first line says so (a STEP model, a
    readings or swing CSV given where a parameter file goes), else None.

    Examples
    --------
    >>> _not_toml(b"ISO-10303-21;\\nHEADER;")
    'a STEP model, not a TOML parameter file (cadcog setup init MODEL drafts a set-up from one)'
    >>> _not_toml(b"name = = 1") is None
    True
    """
    head = file_head(data[:4096])
    if head.startswith(STEP_MAGIC):
        return (
            "a STEP model, not a TOML parameter file (cadcog setup init MODEL drafts a set-up "
            "from one)"
        )
    lines = (line.strip() for line in head.split(b"\n"))
    first = next((line for line in lines if line and not line.startswith(b"#")), b"")
    if first.startswith(b"point_id,"):  # a CSV's header, after its comments
        return "a readings or swing CSV, not a TOML parameter file"
    return None


def read_toml(path: str | Path) -> dict[str, Any]:
    """Parse a TOML file, turning I/O and syntax errors into :class:`ParameterFileError`."""
    p = Path(path)
    try:
        # non-blocking: a FIFO is refused, not waited on; fstat tells what was opened
        fd = os.open(p, os.O_RDONLY | os.O_NONBLOCK)
        with os.fdopen(fd, "rb") as fh:
            mode = os.fstat(fh.fileno()).st_mode
            if stat.S_ISDIR(mode):
                raise IsADirectoryError
            if not stat.S_ISREG(mode):
                raise ParameterFileError(p, "", "is not a regular file, expected a TOML file")
            data = fh.read(MAX_TOML_BYTES + 1)  # bounded: /dev/zero is not a parameter file
    except FileNotFoundError:
        raise ParameterFileError(p, "", "file not found") from None
    except IsADirectoryError:
        raise ParameterFileError(p, "", "is a directory, expected a TOML file") from None
    except OSError as exc:
        raise ParameterFileError(p, "", f"cannot read ({exc.strerror or exc})") from None
    if len(data) > MAX_TOML_BYTES:
        raise ParameterFileError(
            p, "", f"larger than {MAX_TOML_BYTES // 1_000_000} MB: not a parameter file"
        )
    note_input(p, "a parameter file it reads")
    try:
        parsed = tomllib.loads(data.decode("utf-8-sig"))
    except tomllib.TOMLDecodeError as exc:
        raise ParameterFileError(p, "", _not_toml(data) or f"invalid TOML: {exc}") from None
    except UnicodeDecodeError as exc:
        raise ParameterFileError(p, "", f"not UTF-8 text: {exc}") from None
    except RecursionError:
        raise ParameterFileError(
            p,
            "",
            f"arrays or tables nested too deep (a parameter file nests {MAX_TOML_DEPTH} "
            "levels at most)",
        ) from None
    except ValueError as exc:  # tomllib's integer of more than 4300 digits
        line, digits = _longest_digit_run(data.decode("utf-8-sig", "replace"))
        if digits > MAX_INT_DIGITS:
            raise ParameterFileError(
                p,
                "",
                f"line {line}: an integer of {digits} digits; expected one within TOML's "
                "64-bit range",
            ) from None
        raise ParameterFileError(p, "", f"invalid TOML: {exc}") from None
    _check_values(p, parsed, "", 0)
    return parsed


#: Python converts integers of at most this many digits (``sys.get_int_max_str_digits``).
MAX_INT_DIGITS = 4300


def _longest_digit_run(text: str) -> tuple[int, int]:
    """The line (1-based) holding the longest run of digits, and its length."""
    best = (0, 0)
    for number, line in enumerate(text.splitlines(), start=1):
        for run in re.findall(r"\d+", line):
            if len(run) > best[1]:
                best = (number, len(run))
    return best


#: Deepest nesting of tables and arrays in a parameter file (cadcog's own use 3).
MAX_TOML_DEPTH = 16

#: Largest magnitude of an integer in a parameter file: TOML's own range (64-bit signed, as
#: the specification requires parsers to handle); beyond it Python parses any length, and
#: converting such an integer to a float overflows.
MAX_TOML_INTEGER = 2**63 - 1


def _check_values(p: Path, value: Any, key: str, depth: int) -> None:
    """Refuse nesting deeper than :data:`MAX_TOML_DEPTH` and integers beyond
    :data:`MAX_TOML_INTEGER`, naming the key."""
    if depth > MAX_TOML_DEPTH:
        raise ParameterFileError(
            p, key, f"nested deeper than {MAX_TOML_DEPTH} levels: not a parameter file"
        )
    if isinstance(value, dict):
        for k, v in value.items():
            _check_values(p, v, f"{key}.{k}" if key else str(k), depth + 1)
    elif isinstance(value, list):
        for i, v in enumerate(value):
            _check_values(p, v, f"{key}[{i}]", depth + 1)
    elif (
        isinstance(value, int)
        and not isinstance(value, bool)
        and not -MAX_TOML_INTEGER - 1 <= value <= MAX_TOML_INTEGER
    ):
        raise ParameterFileError(
            p,
            key,
            f"an integer of {len(str(abs(value)))} digits; expected one within TOML's 64-bit "
            "range (±9.2e18)",
        )


def toml_string(text: str) -> str:
    """``text`` as a TOML basic string, every quote, backslash and control character escaped.

    Examples
    --------
    >>> text = 'a "quoted" name and a bell \x07'
    >>> tomllib.loads("k = " + toml_string(text))["k"] == text
    True
    """
    out = []
    for ch in text:
        if ch in ('"', "\\"):
            out.append("\\" + ch)
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _type_name(value: object) -> str:
    if isinstance(value, bool):
        return f"boolean {str(value).lower()}"
    if isinstance(value, dict):
        return "a table"
    if isinstance(value, list):
        return "an array"
    if isinstance(value, str):
        return f"string {value!r}"
    return f"{type(value).__name__} {value!r}"


#: Names that may become file names: no separators, no dots, no control characters.
IDENTIFIER_RE = re.compile(r"[A-Za-z][A-Za-z0-9_-]{0,63}")


class TableReader:
    """Typed, exhaustive access to one TOML table.

    Parameters
    ----------
    data : dict
        The parsed table.
    path : Path
        The file it came from (for messages).
    prefix : str
        Dotted key path of this table inside the file ('' for the root).
    """

    def __init__(self, data: dict[str, Any], path: Path, prefix: str = "") -> None:
        self._data = data
        self._path = path
        self._prefix = prefix
        self._used: set[str] = set()
        self._asked: set[str] = set()

    @property
    def path(self) -> Path:
        return self._path

    def key(self, name: str) -> str:
        """Dotted path of ``name`` inside the file."""
        return f"{self._prefix}.{name}" if self._prefix else name

    def error(self, name: str, message: str) -> ParameterFileError:
        """An error about key ``name`` of this table."""
        return ParameterFileError(self._path, self.key(name), message)

    def has(self, name: str) -> bool:
        self._asked.add(name)  # a key the reader knows, for finish()'s message
        return name in self._data

    def keys(self) -> list[str]:
        """Every key of this table, in file order."""
        return list(self._data)

    def is_string(self, name: str) -> bool:
        return isinstance(self._data.get(name), str)

    def is_table(self, name: str) -> bool:
        return isinstance(self._data.get(name), dict)

    def is_array(self, name: str) -> bool:
        return isinstance(self._data.get(name), list)

    def misspelt(self, *names: str) -> str:
        """`` (the table has 'model_stp': a misspelling?)`` when a key of the table is close to
        one of ``names`` (none of them present), else ''."""
        others = [str(k) for k in self._data if k not in names]
        for name in names:
            written = difflib.get_close_matches(name, others, n=1)
            if written:
                return f" (the table has {written[0]!r}: a misspelling?)"
        return ""

    def _get(self, name: str) -> Any:
        self._used.add(name)
        if name not in self._data:
            raise self.error(name, f"missing required key{self.misspelt(name)}")
        return self._data[name]

    def number(
        self,
        name: str,
        *,
        positive: bool = False,
        nonnegative: bool = False,
        default: float | None = None,
        at_least: float | None = None,
    ) -> float:
        """A finite real number (TOML integer or float, not boolean); ``default`` if absent.

        ``at_least`` is a smallest value beyond the key's unit bound (e.g. the smallest solid
        dimension, :data:`cadcog.core.tolerances.MIN_SOLID_DIMENSION_MM`, for a CAD size)."""
        if default is not None and name not in self._data:
            self._used.add(name)
            return default
        value = self._get(name)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.error(name, f"expected a number, got {_type_name(value)}")
        x = float(value)
        if not math.isfinite(x):
            raise self.error(name, f"expected a finite number, got {value!r}")
        if positive and not x > 0.0:
            raise self.error(name, f"expected a positive number, got {value!r}")
        if nonnegative and x < 0.0:
            raise self.error(name, f"expected a number >= 0, got {value!r}")
        if at_least is not None and x < at_least:
            raise self.error(name, f"expected at least {at_least:g}, got {value!r}")
        problem = bounds.check(name, x)
        if problem is not None:
            raise self.error(name, f"{problem}, got {value!r}")
        return x

    def vector(
        self,
        name: str,
        length: int | None = 3,
        *,
        positive: bool = False,
        at_least: float | None = None,
    ) -> tuple[float, ...]:
        """An array of ``length`` finite numbers (any length from 1 when None; each at least
        ``at_least`` if given)."""
        value = self._get(name)
        if not isinstance(value, list) or (len(value) != length if length else not value):
            count = f"{length} " if length else ""
            got = f"an array of {len(value)}" if isinstance(value, list) else _type_name(value)
            raise self.error(name, f"expected an array of {count}numbers, got {got}")
        out = []
        for i, item in enumerate(value):
            if isinstance(item, bool) or not isinstance(item, (int, float)):
                raise self.error(name, f"element {i}: expected a number, got {_type_name(item)}")
            x = float(item)
            if not math.isfinite(x):
                raise self.error(name, f"element {i}: expected a finite number, got {item!r}")
            if positive and not x > 0.0:
                raise self.error(name, f"element {i}: expected a positive number, got {item!r}")
            if at_least is not None and x < at_least:
                raise self.error(name, f"element {i}: expected at least {at_least:g}, got {item!r}")
            problem = bounds.check(name, x)
            if problem is not None:
                raise self.error(name, f"element {i}: {problem}, got {item!r}")
            out.append(x)
        return tuple(out)

    def string(
        self, name: str, *, choices: Sequence[str] | None = None, default: str | None = None
    ) -> str:
        """A non-empty string, optionally one of ``choices``; ``default`` if absent."""
        if default is not None and name not in self._data:
            self._used.add(name)
            return default
        value = self._get(name)
        if not isinstance(value, str) or not value.strip():
            raise self.error(name, f"expected a non-empty string, got {_type_name(value)}")
        if choices is not None and value not in choices:
            raise self.error(name, f"expected one of {', '.join(choices)}; got {value!r}")
        return value

    def identifier(self, name: str) -> str:
        """A name that is also safe as a file-name component: letters, digits, ``_`` and ``-``,
        starting with a letter, at most 64 characters."""
        value = self.string(name)
        if not IDENTIFIER_RE.fullmatch(value):
            raise self.error(
                name,
                "expected a name of letters, digits, '_' or '-' starting with a letter (at most "
                f"64 characters; it names files), got {value!r}",
            )
        return value

    def strings(self, name: str, *, choices: Sequence[str] | None = None) -> list[str]:
        """A non-empty array of strings, each optionally one of ``choices``."""
        value = self._get(name)
        if not isinstance(value, list) or not value or not all(isinstance(v, str) for v in value):
            raise self.error(
                name, f"expected a non-empty array of strings, got {_type_name(value)}"
            )
        if choices is not None:
            bad = [v for v in value if v not in choices]
            if bad:
                raise self.error(name, f"expected values from {', '.join(choices)}; got {bad}")
        return list(value)

    def integer(
        self,
        name: str,
        *,
        minimum: int | None = None,
        choices: Sequence[int] | None = None,
        default: int | None = None,
    ) -> int:
        """A TOML integer (not boolean); ``default`` if absent."""
        if default is not None and name not in self._data:
            self._used.add(name)
            return default
        value = self._get(name)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(name, f"expected an integer, got {_type_name(value)}")
        if minimum is not None and value < minimum:
            raise self.error(name, f"expected an integer >= {minimum}, got {value}")
        if choices is not None and value not in choices:
            raise self.error(name, f"expected one of {', '.join(map(str, choices))}; got {value}")
        bound = bounds.bound_for(name)
        problem = None if bound is None else bound.message(value)
        if problem is not None:
            raise self.error(name, f"{problem}, got {value}")
        return value

    def boolean(self, name: str, *, default: bool | None = None) -> bool:
        """A TOML boolean; ``default`` if absent."""
        if default is not None and name not in self._data:
            self._used.add(name)
            return default
        value = self._get(name)
        if not isinstance(value, bool):
            raise self.error(name, f"expected true or false, got {_type_name(value)}")
        return value

    def table(self, name: str) -> TableReader:
        """A sub-table."""
        value = self._get(name)
        if not isinstance(value, dict):
            raise self.error(name, f"expected a table, got {_type_name(value)}")
        return TableReader(value, self._path, self.key(name))

    def tables(self, name: str, *, min_count: int = 1) -> list[TableReader]:
        """An array of tables (``[[name]]``) with at least ``min_count`` entries."""
        value = self._get(name)
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            raise self.error(
                name, f"expected an array of tables ([[{name}]]), got {_type_name(value)}"
            )
        if len(value) < min_count:
            raise self.error(name, f"expected at least {min_count} entries, got {len(value)}")
        return [TableReader(v, self._path, f"{self.key(name)}[{i}]") for i, v in enumerate(value)]

    def finish(self, expected: Sequence[str] | None = None) -> None:
        """Raise if the table holds keys nobody asked for.

        ``expected`` lists every key the table may hold (optional ones included), for the
        message; by default the keys that were read. A close match is suggested.
        """
        unknown = sorted(set(self._data) - self._used)
        if unknown:
            known = sorted(set(expected or ()) | self._used | self._asked)
            close = difflib.get_close_matches(unknown[0], known, n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            raise self.error(unknown[0], f"unknown key ({hint}known keys here: {', '.join(known)})")
