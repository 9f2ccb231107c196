"""JSON text: json's own text to the byte, in one pass and in chunks; nothing on a bad value."""

from __future__ import annotations

import io
import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cadcog.core import jsontext
from cadcog.core.jsontext import _rounded_repr, dumps_json, json_chunks, round_floats, write_json

_json_leaves = (
    st.none()
    | st.booleans()
    | st.integers(-(10**20), 10**20)
    | st.floats(allow_nan=False, allow_infinity=False)
    | st.text(max_size=8)
)
_json_values = st.recursive(
    _json_leaves,
    lambda inner: (
        st.lists(inner, max_size=4)
        | st.tuples(inner, inner)
        | st.dictionaries(st.text(max_size=6), inner, max_size=4)
    ),
    max_leaves=30,
)


@given(_json_values)
def test_dumps_json_writes_what_json_writes(value):
    # dumps_json has its own one-pass writer (speed); the text must be json's, to the byte.
    try:
        expected = json.dumps(round_floats(value), indent=2, ensure_ascii=False, allow_nan=False)
    except ValueError:  # a float that rounds to infinity (near the largest float)
        with pytest.raises(ValueError, match="non-finite"):
            dumps_json(value)
        return
    assert dumps_json(value) == expected + "\n"


def test_dumps_json_leaves_other_keys_and_types_to_json():
    assert (
        dumps_json({1: 0.1 + 0.2, None: [True]})
        == json.dumps({"1": 0.3, "null": [True]}, indent=2) + "\n"
    )
    with pytest.raises(TypeError, match="not JSON serializable"):
        dumps_json({"a": {1, 2}})
    with pytest.raises(ValueError, match="non-finite"):
        dumps_json({"a": [1.0, float("nan")]})


@settings(max_examples=2000)
@given(st.floats(allow_nan=False, allow_infinity=False))
def test_a_rounded_float_is_written_as_json_writes_it(value):
    try:
        expected = json.dumps(round_floats(value), allow_nan=False)
    except ValueError:
        with pytest.raises(ValueError, match="non-finite"):
            _rounded_repr(value, 15)
        return
    assert _rounded_repr(value, 15) == expected


@settings(max_examples=300)
@given(_json_values, st.integers(1, 6))
def test_chunk_boundaries_do_not_change_the_text(value, pieces):
    # a real document is cut every 2**14 pieces; tiny chunks put a boundary everywhere
    old = jsontext._PIECES_PER_CHUNK
    jsontext._PIECES_PER_CHUNK = pieces
    try:
        try:
            whole = json.dumps(round_floats(value), indent=2, ensure_ascii=False, allow_nan=False)
            whole += "\n"
        except ValueError:
            return
        chunks = json_chunks(value)
    finally:
        jsontext._PIECES_PER_CHUNK = old
    assert "".join(chunks) == whole
    assert all(chunks)


def test_a_large_document_comes_in_several_chunks_and_streams_whole():
    rng = np.random.default_rng(7)
    data = {"bodies": [{"cog_mm": rng.normal(size=3).tolist(), "n": k} for k in range(12000)]}
    chunks = json_chunks(data)
    assert len(chunks) > 3
    stream = io.StringIO()
    write_json(data, stream)
    assert stream.getvalue() == json.dumps(round_floats(data), indent=2) + "\n"


def test_write_json_writes_nothing_when_a_value_is_refused():
    stream = io.StringIO()
    data = {"first": list(range(40000)), "last": [1.0, float("inf")]}
    with pytest.raises(ValueError, match="non-finite value inf"):
        write_json(data, stream)
    assert stream.getvalue() == ""


def test_numpy_floats_are_written_as_floats():
    value = {"a": [np.float64(0.1) + np.float64(0.2), 2.5], "b": np.float64(1e17)}
    assert dumps_json(value) == json.dumps({"a": [0.3, 2.5], "b": 1e17}, indent=2) + "\n"
