"""``cadcog/cli/_types.py``: the argument types and checks the commands share."""

from __future__ import annotations

import argparse
import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.cli._types import positive_triple, weighing_sigma_kg
from cadcog.core.errors import CadcogError
from cadcog.core.tolerances import DEFAULT_WEIGHING_SIGMA_KG

NUMBER = st.floats(allow_nan=True, allow_infinity=True, width=64)


@given(st.lists(NUMBER, min_size=1, max_size=4))
def test_a_triple_is_three_positive_finite_numbers_or_refused_quoting_the_text(values):
    text = ",".join(repr(v) for v in values)
    good = len(values) == 3 and all(math.isfinite(v) and v > 0 for v in values)
    if good:
        assert positive_triple(text) == tuple(values)
        return
    with pytest.raises(argparse.ArgumentTypeError, match="expected three positive numbers X,Y,Z"):
        positive_triple(text)


@pytest.mark.parametrize("text", ["20,20", "a,b,c", "", "1,2,3,4", "1;2;3", "0,1,1"])
def test_malformed_triples_are_refused(text):
    with pytest.raises(argparse.ArgumentTypeError, match=repr(text).replace("(", r"\(")):
        positive_triple(text)


def test_the_weighings_sigma_goes_with_a_weighing():
    assert weighing_sigma_kg(None, None) == DEFAULT_WEIGHING_SIGMA_KG
    assert weighing_sigma_kg(2.6, None) == DEFAULT_WEIGHING_SIGMA_KG
    assert weighing_sigma_kg(2.6, 0.005) == 0.005
    with pytest.raises(CadcogError, match="--mass-sigma-kg goes with --weighed-mass-kg"):
        weighing_sigma_kg(None, 0.005)
