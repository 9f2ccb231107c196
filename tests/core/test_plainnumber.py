"""``cadcog.core.plainnumber``: what a data file's number may be, for any text."""

from __future__ import annotations

import math

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from cadcog.core.plainnumber import parse_float


@given(st.floats(allow_nan=False))
def test_every_float_as_python_writes_it_reads_back_exactly(x):
    assert parse_float(repr(x)) == x
    assert parse_float(f"{x:.17e}") == x
    assert parse_float(f"{x:.6f}") == float(f"{x:.6f}")


@given(st.text(alphabet="0123456789+-.eE_ xinfatyINFATY", max_size=12))
@example("4_5")
@example("1_000.0")
@example(" 1")
@example("0x10")
@example("1e")
@example(".")
def test_what_it_takes_python_takes_too_and_never_separators_or_spaces(text):
    try:
        value = parse_float(text)
    except ValueError:
        return
    assert "_" not in text and text == text.strip()
    expected = float(text)
    assert value == expected or (math.isnan(value) and math.isnan(expected))


@pytest.mark.parametrize("text", ["4_5", " 1", "1 ", "0x10", "1e", ".", "", "+-1", "1.2.3"])
def test_not_a_decimal_number(text):
    with pytest.raises(ValueError, match="not a decimal number"):
        parse_float(text)
