"""Component-first 3-vectors and packed symmetric 3 × 3 matrices, element-wise over any
trailing axes: what the vectorised estimators (:mod:`cadcog.method.gls`,
:mod:`cadcog.method.sharedbatch`) compute with.

Vectors have shape (3, ...), symmetric matrices are packed as (6, ...) in the order xx, yy, zz,
xy, xz, yz (an array, or a tuple of arrays: the kernels only index the first axis). Sums over
lines add contiguous rows in order (:func:`rows_sum`), so one trial and a million give the same
numbers.

Examples
--------
>>> import numpy as np
>>> m = sym_outer(np.array([1.0, 2.0, 3.0]))
>>> sym_to_full(m).tolist()
[[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [3.0, 6.0, 9.0]]
>>> [float(c) for c in sym_matvec(projector(np.array([0.0, 0.0, 1.0])), np.array([1.0, 2.0, 3.0]))]
[1.0, 2.0, 0.0]
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]

#: Component-first vectors (3, ...) or packed matrices (6, ...): an array, or its components.
Comp = FloatArray | Sequence[FloatArray]
Vec = tuple[FloatArray, ...]
Sym = tuple[FloatArray, ...]


def sym_outer(a: Comp) -> Sym:
    """``a aᵀ`` packed, for component-first ``a`` of shape (3, ...)."""
    return (a[0] * a[0], a[1] * a[1], a[2] * a[2], a[0] * a[1], a[0] * a[2], a[1] * a[2])


def sym_matvec(m: Comp, v: Comp) -> Vec:
    """``M v`` for packed ``M`` (6, ...) and ``v`` (3, ...)."""
    return (
        m[0] * v[0] + m[3] * v[1] + m[4] * v[2],
        m[3] * v[0] + m[1] * v[1] + m[5] * v[2],
        m[4] * v[0] + m[5] * v[1] + m[2] * v[2],
    )


def sym_inv(m: Comp) -> tuple[Sym, FloatArray]:
    """Inverse of packed symmetric matrices by the adjugate, and their determinants."""
    c00 = m[1] * m[2] - m[5] * m[5]
    c11 = m[0] * m[2] - m[4] * m[4]
    c22 = m[0] * m[1] - m[3] * m[3]
    c01 = m[4] * m[5] - m[3] * m[2]
    c02 = m[3] * m[5] - m[4] * m[1]
    c12 = m[3] * m[4] - m[0] * m[5]
    det = m[0] * c00 + m[3] * c01 + m[4] * c02
    r = 1.0 / det
    return (c00 * r, c11 * r, c22 * r, c01 * r, c02 * r, c12 * r), np.asarray(det)


def sym_to_full(m: Comp) -> FloatArray:
    """Packed (6, ...) → full (..., 3, 3)."""
    xx, yy, zz, xy, xz, yz = (np.asarray(c, dtype=float) for c in m)
    full = np.stack([np.stack([xx, xy, xz]), np.stack([xy, yy, yz]), np.stack([xz, yz, zz])])
    return np.asarray(np.moveaxis(full, (0, 1), (-2, -1)))


def dot3(a: Comp, b: Comp) -> FloatArray:
    """``a · b`` for component-first ``a``, ``b`` (3, ...)."""
    return np.asarray(a[0] * b[0] + a[1] * b[1] + a[2] * b[2])


def add_all(terms: Sequence[FloatArray] | FloatArray) -> FloatArray:
    """``terms[0] + terms[1] + …`` in order, into one new array (a lone term is returned as is);
    ``terms`` a sequence of arrays, or an array whose rows are added."""
    if len(terms) == 1:
        return np.asarray(terms[0])
    total = terms[0] + terms[1]
    for term in terms[2:]:
        total += term
    return np.asarray(total)


def rows_sum(c: FloatArray) -> FloatArray:
    """Sum over the first axis, row by row in order, whatever the trailing shape: a trial's sum
    is the same to the bit alone or among a million (numpy's ``c.sum(axis=0)`` adds in order
    when the rows hold many trials, but pairwise when they hold one, and differs in the last bit
    from nine rows on), without a reduction's overhead for the usual two or three lines."""
    return add_all(c)


def lines_sum(x: tuple[FloatArray, ...]) -> tuple[FloatArray, ...]:
    """Sum each component over the lines (its first axis)."""
    return tuple(rows_sum(c) for c in x)


def projector(u: Comp) -> Sym:
    """``I − u uᵀ`` packed, for unit ``u`` (3, ...)."""
    ux, uy, uz = u[0], u[1], u[2]
    return (1.0 - ux * ux, 1.0 - uy * uy, 1.0 - uz * uz, -ux * uy, -ux * uz, -uy * uz)
