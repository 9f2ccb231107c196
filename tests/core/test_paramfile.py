"""Strict TOML reading helpers."""

from __future__ import annotations

import tomllib

from hypothesis import given
from hypothesis import strategies as st

from cadcog.core.paramfile import toml_string


@given(st.text())
def test_any_text_round_trips_through_a_toml_string(text):
    assert tomllib.loads("k = " + toml_string(text))["k"] == text
