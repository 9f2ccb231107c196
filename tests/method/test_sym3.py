"""``cadcog.method.sym3``: the packed kernels against numpy's dense algebra, for any input, and
the in-order sums that make one trial's numbers independent of how many run with it."""

from __future__ import annotations

import functools
import operator

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from cadcog.method import sym3

finite = st.floats(-1e3, 1e3, allow_nan=False)


def _pack(full: np.ndarray) -> tuple[np.ndarray, ...]:
    return tuple(full[..., i, j] for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)))


@given(arrays(float, (3, 5), elements=finite), arrays(float, (3, 5), elements=finite))
def test_outer_matvec_and_dot_are_numpy_s(a, v):
    full = np.einsum("i...,j...->...ij", a, a)
    np.testing.assert_allclose(sym3.sym_to_full(sym3.sym_outer(a)), full, rtol=1e-15)
    m = _pack(full + np.eye(3))
    expected = np.einsum("...ij,j...->i...", full + np.eye(3), v)
    np.testing.assert_allclose(np.array(sym3.sym_matvec(m, v)), expected, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(sym3.dot3(a, v), np.einsum("i...,i...->...", a, v), rtol=1e-12,
                               atol=1e-9)  # fmt: skip


@given(arrays(float, (4, 3, 3), elements=st.floats(-1.0, 1.0)))
@settings(max_examples=50)
def test_inverse_and_determinant_are_numpy_s(b):
    full = b @ np.swapaxes(b, -1, -2) + 0.5 * np.eye(3)  # symmetric positive definite
    inv, det = sym3.sym_inv(_pack(full))
    np.testing.assert_allclose(sym3.sym_to_full(inv), np.linalg.inv(full), rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(det, np.linalg.det(full), rtol=1e-12)


@given(arrays(float, (3, 4), elements=st.floats(-1.0, 1.0)).filter(
    lambda u: np.all(np.linalg.norm(u, axis=0) > 1e-3)))  # fmt: skip
def test_the_projector_removes_its_axis(u):
    u = u / np.linalg.norm(u, axis=0)
    p = sym3.projector(u)
    np.testing.assert_allclose(np.array(sym3.sym_matvec(p, u)), 0.0, atol=1e-15)
    full = sym3.sym_to_full(p)
    np.testing.assert_allclose(full @ full, full, atol=1e-15)  # idempotent


@given(arrays(float, st.tuples(st.integers(1, 20), st.integers(1, 6)),
              elements=st.floats(-1e12, 1e12, allow_nan=False)))  # fmt: skip
def test_rows_add_in_order_whatever_the_number_of_columns(c):
    """Each column's sum is the left-to-right sum of its rows, to the bit: alone or among
    others (numpy's sum of a single column adds pairwise from nine rows on)."""
    total = sym3.rows_sum(c)
    for j in range(c.shape[1]):
        alone = sym3.rows_sum(c[:, j : j + 1])
        assert alone[0] == total[j]
        assert total[j] == functools.reduce(operator.add, c[:, j].tolist())


def test_a_lone_row_is_returned_as_is_and_lines_sum_each_component():
    row = np.arange(3.0)[None, :]
    assert np.shares_memory(sym3.rows_sum(row), row)  # no copy for one line
    x = (np.ones((4, 2)), 2 * np.ones((4, 2)))
    assert [s.tolist() for s in sym3.lines_sum(x)] == [[4.0, 4.0], [8.0, 8.0]]
