"""Strict TOML reading helpers."""

from __future__ import annotations

import re
import tomllib

import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.core.paramfile import toml_string


@given(st.text())
def test_any_text_round_trips_through_a_toml_string(text):
    assert tomllib.loads("k = " + toml_string(text))["k"] == text


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("a = " + "[" * 1000 + "]" * 1000, "nested too deep"),
        ("a = " + "[" * 400 + "]" * 400, "key 'a[0]"),
        ("[t]\nb = " + "9" * 401, "key 't.b': an integer of 401 digits"),
        ("b = " + "9" * 5000, "line 1: an integer of 5000 digits"),
        ('[materials]\n"*" = 1' + "0" * 20, "key 'materials.*': an integer of 21 digits"),
    ],
)
def test_unreasonable_toml_is_refused_naming_the_file_and_key(tmp_path, text, message):
    """Nesting hundreds deep and integers of hundreds of digits were tracebacks
    (RecursionError, OverflowError) wherever a parameter file is read."""
    from cadcog.core.errors import ParameterFileError
    from cadcog.core.paramfile import read_toml

    path = tmp_path / "p.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ParameterFileError, match=re.escape(message)) as info:
        read_toml(path)
    assert str(path) in str(info.value) and "\n" not in str(info.value)


@pytest.mark.parametrize(
    ("written", "hint"),
    [
        ({"base_centre_mm": [1, 2, 3]}, "(the table has 'base_centre_mm': a misspelling?)"),
        ({"something_else": 1}, None),
        ({}, None),
    ],
)
def test_a_missing_key_names_a_close_spelling_the_table_has(tmp_path, written, hint):
    """A required key spelt the British way is 'missing'; the message says what was written."""
    from cadcog.core.errors import ParameterFileError
    from cadcog.core.paramfile import TableReader

    t = TableReader(written, tmp_path / "s.toml", "measurement_equipment")
    with pytest.raises(ParameterFileError) as info:
        t.vector("base_center_mm")
    text = str(info.value)
    assert "key 'measurement_equipment.base_center_mm': missing required key" in text
    assert (hint in text) if hint else ("misspelling" not in text)
