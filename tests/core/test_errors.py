"""``cadcog/core/errors.py``: a refusal names its source once; a quoted value and a whole line
are cut to a readable length, keeping both ends."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.core.errors import (
    MESSAGE_MAX_CHARS,
    QUOTE_MAX_CHARS,
    CadcogError,
    DegenerateGeometryError,
    ReadingsError,
    capped,
    named_by,
    quote,
)


@given(st.text(max_size=400), st.integers(10, 200))
def test_a_quote_is_the_repr_or_its_two_ends_and_its_length(value, limit):
    text, out = repr(value), quote(value, limit)
    if len(text) <= limit:
        assert out == text
    else:
        keep = max(1, (limit - 4) // 2)
        assert out == f"{text[:keep]}…({len(text)} characters)…{text[-keep:]}"
        assert len(out) < limit + 30


@given(st.text(alphabet=st.characters(blacklist_characters="'\"\n"), max_size=3000))
def test_a_capped_line_is_short_and_keeps_its_end(words):
    message = f"key 'x': got '{words}'; {words}: give another"
    out = capped(message)
    assert len(out) <= MESSAGE_MAX_CHARS + 40
    if len(message) <= MESSAGE_MAX_CHARS and len(words) < QUOTE_MAX_CHARS:
        assert out == message
    assert out.endswith("give another")


def test_named_by_prefixes_the_source_once_and_keeps_the_kind():
    with pytest.raises(DegenerateGeometryError, match=r"^r\.csv: parallel$"):
        with named_by("r.csv"):
            raise DegenerateGeometryError("parallel")
    with pytest.raises(CadcogError, match=r"^r\.csv: bad option$") as exc:
        with named_by("r.csv"):
            raise ValueError("bad option")
    assert type(exc.value) is CadcogError
    with pytest.raises(ValueError, match=r"^bad option$"):  # values=False: passed as it is
        with named_by("r.csv", values=False):
            raise ValueError("bad option")
    with pytest.raises(DegenerateGeometryError, match=r"^parallel$"):  # no source
        with named_by(None):
            raise DegenerateGeometryError("parallel")
    with pytest.raises(CadcogError, match=r"^already named$"):
        with named_by("r.csv"):
            raise CadcogError("already named")


def test_an_error_naming_its_file_already_is_not_named_twice():
    """A ReadingsError is a ValueError (for callers that catch those): one naming its file was
    prefixed again, 'r.csv: r.csv, line 3: ...', and lost its kind. One that names only its
    line is named (the estimator's refusals of a hang)."""
    with pytest.raises(ReadingsError, match=r"^r\.csv, line 3: bad$"):
        with named_by("r.csv"):
            raise ReadingsError("r.csv, line 3: bad")
    with pytest.raises(CadcogError, match=r"^r\.csv: line 8: inside$"):
        with named_by("r.csv"):
            raise ReadingsError("line 8: inside")
    with pytest.raises(DegenerateGeometryError, match=r"^s\.csv: no tensor$"):
        with named_by("s.csv"):
            raise DegenerateGeometryError("s.csv: no tensor")
