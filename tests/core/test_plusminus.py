"""``cadcog.core.plusminus``: a value beside its σ, for any value and σ: σ to two figures, the
value to σ's last decimal, and what is written within half a unit of that decimal."""

from __future__ import annotations

import math

from hypothesis import assume, given
from hypothesis import strategies as st

from cadcog.core import numformat as nf
from cadcog.core.plusminus import SIGMA_FIGS, pm, signed

plain_sigma = st.floats(1e-3, 1e4)
values = st.floats(-1e6, 1e6, allow_nan=False)


def _decimals(text: str) -> int:
    return len(text.split(".", 1)[1]) if "." in text else 0


@given(values, plain_sigma)
def test_the_value_is_written_to_the_decimal_of_sigma_s_last_figure(value, sigma):
    assume(nf.PLAIN_MIN <= sigma < nf.PLAIN_MAX and abs(value) < nf.PLAIN_MAX)
    v_text, s_text = pm(value, sigma).split(" ± ")
    assert _decimals(v_text) == _decimals(s_text)
    digits = s_text.replace(".", "").lstrip("0")
    assert len(digits) == SIGMA_FIGS or float(s_text) >= 10 ** (SIGMA_FIGS - 1)
    half_unit = 0.5 * 10.0 ** -_decimals(s_text)
    assert abs(float(v_text) - value) <= half_unit * (1 + 1e-9) + 1e-9 * abs(value)
    assert abs(float(s_text) - sigma) <= max(half_unit, 0.05 * sigma) * (1 + 1e-9)
    assert not v_text.startswith("-0") or float(v_text) != 0.0


@given(values, plain_sigma, st.sampled_from([1.0, 1e3, 1e-3]))
def test_a_factor_is_the_unit_shown(value, sigma, factor):
    assume(nf.PLAIN_MIN <= sigma * factor < nf.PLAIN_MAX and abs(value * factor) < nf.PLAIN_MAX)
    assert pm(value, sigma, factor=factor) == pm(value * factor, sigma * factor)


@given(values, plain_sigma)
def test_the_sign_of_sigma_is_ignored(value, sigma):
    assert pm(value, sigma) == pm(value, -sigma)


@given(values, plain_sigma)
def test_signed_marks_a_positive_value_only(value, sigma):
    text = pm(value, sigma)
    marked = signed(text)
    shown = float(text.split(" ")[0])
    assert marked == ("+" + text if shown > 0 else text)
    assert not math.isnan(shown)
