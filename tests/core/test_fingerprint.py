"""The results cache's fingerprint of objects: equal content, equal key; any changed bit, field,
type or order, another key; an unknown type refused (never silently left out of a key)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.core.fingerprint import fingerprint


@dataclasses.dataclass(frozen=True)
class _Point:
    name: str
    position_mm: np.ndarray
    mass_kg: float


@dataclasses.dataclass(frozen=True)
class _Other:
    name: str
    position_mm: np.ndarray
    mass_kg: float


def _point(x: float = 1.0, m: float = 0.5) -> _Point:
    return _Point("a", np.array([x, 2.0, 3.0]), m)


leaves = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(),
    st.floats(allow_nan=False),
    st.text(max_size=8),
)
nested = st.recursive(
    leaves,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4),
        st.tuples(inner, inner),
        st.dictionaries(st.text(max_size=4), inner, max_size=4),
    ),
    max_leaves=12,
)


@given(nested)
def test_equal_content_gives_the_same_fingerprint(value):
    import copy

    assert fingerprint(value) == fingerprint(copy.deepcopy(value))


@given(st.floats(allow_nan=False, allow_infinity=False))
def test_the_last_bit_of_a_float_changes_it(x):
    y = float(np.nextafter(x, 0.0 if x else 1.0))
    assert fingerprint(_point(x)) != fingerprint(_point(y))
    assert fingerprint(np.array([x])) != fingerprint(np.array([y]))


@given(nested, nested)
def test_different_values_differ(a, b):
    same = a == b and repr(a) == repr(b)  # 1 == 1.0 == True, -0.0 == 0.0: not the same
    if not same:
        assert fingerprint(a) != fingerprint(b)


def test_what_counts_in_a_dataclass_and_an_array():
    base = fingerprint(_point())
    assert fingerprint(_point()) == base
    assert fingerprint(_point(m=0.25)) != base
    assert fingerprint(_Other("a", np.array([1.0, 2.0, 3.0]), 0.5)) != base  # the type counts
    a = np.arange(6.0)
    assert fingerprint(a) != fingerprint(a.reshape(2, 3))  # the shape counts
    assert fingerprint(a) != fingerprint(a.astype(np.float32))  # the dtype counts
    assert fingerprint(a.reshape(2, 3).T) == fingerprint(np.ascontiguousarray(a.reshape(2, 3).T))
    assert fingerprint({"a": 1, "b": 2}) == fingerprint({"b": 2, "a": 1})  # no order in a dict
    assert fingerprint(("a", "b")) != fingerprint(("b", "a"))  # a tuple's order counts
    assert fingerprint(Path("x/y.csv")) != fingerprint("x/y.csv")
    assert fingerprint({1, 2}) == fingerprint(frozenset({2, 1}))


def test_an_unknown_type_is_refused_wherever_it_is_nested():
    class Opaque:
        pass

    with pytest.raises(TypeError, match="Opaque"):
        fingerprint({"a": [1, (2, Opaque())]})
    with pytest.raises(TypeError, match="objects"):
        fingerprint(np.array([object()]))
