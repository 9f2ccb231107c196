"""The one test of fit: the χ² tail's closed forms against scipy, and the verdict at the level."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import stats

from cadcog.core.fittest import CHI2_CLOSED_FORM_MAX_DOF, TEST_LEVEL, FitTest, chi2_sf


@given(st.integers(1, CHI2_CLOSED_FORM_MAX_DOF + 20), st.floats(0.0, 400.0))
def test_the_tail_is_scipy_s(dof, x):
    want = float(stats.chi2.sf(x, dof))
    assert chi2_sf(x, dof) == pytest.approx(want, rel=1e-9, abs=1e-300)


@pytest.mark.parametrize("dof", [1, 2, 6, 50, 150])
def test_the_verdict_turns_at_the_level(dof):
    edge = float(stats.chi2.isf(TEST_LEVEL, dof))
    assert FitTest(edge * (1 - 1e-9), dof).passes
    assert not FitTest(edge * (1 + 1e-9), dof).passes
    assert FitTest(edge, dof, level=0.01).passes  # a stricter level lets it through


def test_no_degree_of_freedom_tests_nothing():
    assert FitTest(1e9, 0).p == 1.0 and FitTest(1e9, 0).passes
    with pytest.raises(ValueError, match="at least one degree of freedom"):
        chi2_sf(1.0, 0)
