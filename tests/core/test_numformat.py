"""The one number-formatting module: significant figures survive, units fit, no ``-0``."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cadcog.core import numformat as nf


@pytest.mark.parametrize("digits", [1, 2, 4, 6])
def test_sig_keeps_the_asked_relative_precision_over_twenty_decades(digits):
    rng = np.random.default_rng(22)
    values = 10.0 ** rng.uniform(-5.9, 11.9, 400) * rng.choice([-1.0, 1.0], 400)
    for v in values:
        text = nf.sig(v, digits)
        back = float(text)
        # rounded to `digits` figures: within half a unit of the last figure
        assert abs(back - v) <= 0.5 * 10 ** (math.floor(math.log10(abs(v))) - digits + 1) * 1.0001
        assert "e" not in text  # plain decimals in this range


def test_sig_never_prints_negative_zero_and_drops_trailing_zeros():
    assert nf.sig(-1e-30) == "-1.000e-30"  # below the plain range: an exponent, sign kept
    assert nf.sig(-0.0) == "0" and nf.sig(2.50) == "2.5" and nf.sig(100.0) == "100"
    assert nf.fixed(-0.0004, 2) == "0.00"


def test_units_switch_at_one_kilogram_and_one_kg_mm2():
    assert nf.mass(0.999) == "999 g" and nf.mass(1.0) == "1 kg"
    assert nf.inertia(0.5) == "500 g·mm²" and nf.inertia(1.5) == "1.5 kg·mm²"
    # a column shares the unit of its largest entry
    assert nf.mass_unit([0.001, 2.0]) == nf.KILOGRAM
    assert nf.in_unit(0.00003, nf.mass_unit([0.00003])) == "0.03"


def test_share_is_never_zero_for_a_positive_fraction():
    for f in (1e-7, 3e-5, 0.004, 0.02, 0.5):
        text = nf.share(f)
        assert float(text.rstrip(" %")) > 0
        assert float(text.rstrip(" %")) == pytest.approx(100 * f, rel=0.05)
