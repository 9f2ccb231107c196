"""Lines prepared once and combined in groups: the Monte Carlo's fast path to the CoG
:func:`cadcog.method.gls.plumb_gls` estimates (:func:`cog_only`), for a known wire scale.

Every hang of the simulated campaigns is prepared once (:func:`prepare_lines`); a group of them
is then estimated without redoing the per-line work (:func:`combine_lines`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from cadcog.method import gls
from cadcog.method.sym3 import Comp, Sym, Vec, add_all, dot3, projector, sym_inv, sym_matvec
from cadcog.method.wire import wire_shape_factor

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class PreparedLines:
    """What the estimator needs of each line before it knows the others, for a known wire scale.

    A line's weight depends on the other lines only through its distance ``L`` to the CoG, and
    only through the reading term: its lateral covariance in the plane ⊥ ``u`` is
    ``M = M⁰ + L² Mᴸ`` (:func:`cadcog.method.gls.lateral_parts`), and since the adjugate of a
    2 × 2 matrix is linear, ``W = E adj(M) Eᵀ / det M = (W⁰ + L² W¹) / (d₀ + d₁ L² + d₂ L⁴)`` with
    ``W⁰ = E adj(M⁰) Eᵀ``, ``W¹ = E adj(Mᴸ) Eᵀ`` and ``E = [e₁ e₂]``. Built once per line by
    :func:`prepare_lines`; :func:`combine_lines` then estimates groups of them. The Monte Carlo
    prepares every hang of its simulated campaigns once and combines them group by group. Each
    attribute is a tuple of arrays of shape (k, n), or (k, 1) for what does not vary between
    trials.

    Attributes
    ----------
    q_mm : tuple of 3 arrays
        Virtual suspension points (the nominal ones moved by the expected wire offset).
    proj : tuple of 6 arrays
        ``Pᵢ = I − uᵢuᵢᵀ`` packed.
    proj_q_mm : tuple of 3 arrays
        ``Pᵢ qᵢ``.
    w0, w1 : tuple of 6 arrays
        ``W⁰`` (1/mm²) and ``W¹`` (1/rad²), packed.
    det : tuple of 3 arrays
        ``(d₀, d₁, d₂)``.
    w0_q, w1_q : tuple of 3 arrays
        ``W⁰ qᵢ`` and ``W¹ qᵢ``.
    weighted : bool
        False: only the equal-weight parts were prepared.
    """

    q_mm: Vec
    proj: Sym
    proj_q_mm: Vec
    w0: Sym
    w1: Sym
    det: Vec
    w0_q: Vec
    w1_q: Vec
    weighted: bool

    def take(self, rows: int | slice | npt.NDArray[np.intp]) -> PreparedLines:
        """Some of the lines: ``rows`` an index (a view, shape (1, n)), a slice (a view) or an
        array of indices (a copy, shape (len(rows), n))."""
        pick = slice(rows, rows + 1) if isinstance(rows, int) else rows
        parts = (self.q_mm, self.proj, self.proj_q_mm, self.w0, self.w1, self.det, self.w0_q,
                 self.w1_q)  # fmt: skip
        q, proj, proj_q, w0, w1, det, w0_q, w1_q = (tuple(c[pick] for c in p) for p in parts)
        return PreparedLines(q, proj, proj_q, w0, w1, det, w0_q, w1_q, self.weighted)


#: Arrays of one prepared line that may vary between trials (``q_mm`` does only with the
#: elastica wire): what a Monte Carlo chunk holds per hang and campaign, at most.
PREPARED_ROWS = 33


def prepare_lines(
    points_mm: Comp,
    u: Comp,
    normals: Comp,
    errors: gls.LineErrors,
    wire: gls.WireTerm,
    *,
    weighted: bool = True,
) -> PreparedLines:
    """The per-line parts of :func:`cog_only` for lines ``(3, k, n)`` and a known wire scale."""
    if not wire.fixed:
        raise ValueError("prepared lines need a known wire scale (no prior spread, no estimate)")
    if wire.scale_mm:
        shape = 1.0 if wire.model == "paper" else wire_shape_factor(dot3(u, normals), wire.model)
        q = tuple(points_mm[i] + (wire.scale_mm * shape) * normals[i] for i in range(3))
    else:
        q = tuple(points_mm[i] for i in range(3))
    uq = dot3(u, q)
    proj_q = tuple(q[i] - uq * u[i] for i in range(3))
    if not weighted:
        return PreparedLines(q, projector(u), proj_q, (), (), (), (), (), weighted)
    e1, e2, (a0, b0, c0), (a1, b1, c1) = gls.lateral_parts(u, normals, errors)
    w0 = gls.assemble(e1, e2, c0, -b0, a0)  # E adj(M⁰) Eᵀ
    w1 = gls.assemble(e1, e2, c1, -b1, a1)
    det = (a0 * c0 - b0 * b0, a0 * c1 + a1 * c0 - 2.0 * b0 * b1, a1 * c1 - b1 * b1)
    return PreparedLines(
        q, projector(u), proj_q, w0, w1, det, sym_matvec(w0, q), sym_matvec(w1, q), weighted
    )


def _sum_slots(slots: Sequence[Vec]) -> tuple[FloatArray, ...]:
    """Sum packed parts over the slots (element-wise: line by line)."""
    return tuple(add_all(parts) for parts in zip(*slots, strict=True))


def combine_lines(slots: Sequence[PreparedLines]) -> FloatArray:
    """CoGs of groups of prepared lines, as :func:`cog_only` estimates them: shape (3, m, n).

    ``slots`` holds two or more sets of m lines each (:meth:`PreparedLines.take`): group ``j`` is
    made of line ``j`` of every set.
    """
    if len(slots) < 2:
        raise ValueError("a group needs at least two lines")
    ainv, _ = sym_inv(_sum_slots([s.proj for s in slots]))
    g0 = sym_matvec(ainv, _sum_slots([s.proj_q_mm for s in slots]))
    if not slots[0].weighted:
        return np.stack(np.broadcast_arrays(*g0))
    weights, rhs = [], []
    for slot in slots:
        q = slot.q_mm
        diff = (g0[0] - q[0], g0[1] - q[1], g0[2] - q[2])
        l2 = dot3(diff, diff)
        d0, d1, d2 = slot.det
        r = 1.0 / (d0 + l2 * (d1 + l2 * d2))
        weights.append(tuple((w0 + l2 * w1) * r for w0, w1 in zip(slot.w0, slot.w1, strict=True)))
        rhs.append(tuple((a + l2 * b) * r for a, b in zip(slot.w0_q, slot.w1_q, strict=True)))
    ainv, _ = sym_inv(_sum_slots(weights))
    return np.stack(np.broadcast_arrays(*sym_matvec(ainv, _sum_slots(rhs))))


def cog_only(
    points_mm: FloatArray,
    u: FloatArray,
    normals: FloatArray,
    errors: gls.LineErrors,
    wire: gls.WireTerm,
    *,
    weighted: bool = True,
) -> FloatArray:
    """The CoG of :func:`cadcog.method.gls.plumb_gls` alone, (3, n): the Monte Carlo's fast path.

    For a known wire scale (the common case) the same equations without the covariances and λ
    (:func:`prepare_lines` then :func:`combine_lines`); otherwise it calls
    :func:`cadcog.method.gls.plumb_gls`.
    """
    if not wire.fixed:
        return gls.plumb_gls(points_mm, u, normals, errors, wire, weighted=weighted).cog_mm
    prepared = prepare_lines(points_mm, u, normals, errors, wire, weighted=weighted)
    slots = [prepared.take(i) for i in range(len(prepared.proj[0]))]
    return combine_lines(slots)[:, 0, :]
