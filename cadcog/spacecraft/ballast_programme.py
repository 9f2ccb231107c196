"""The ballast programmes (:mod:`cadcog.spacecraft.balance`): rows, the least total ballast with
each face's quantile fixed, and with the quantiles chosen too.

Each face ``f`` of each configuration's envelope is a row ``a_f · m + c_f z_f ≤ b_f`` (moments,
kg·mm): ``a_f`` the ballast's lever arms past the face, ``c_f = σ'_k T`` the CoG's spread times
the total mass, ``z_f`` the face's quantile. With the quantiles fixed the rows are linear in the
masses: a linear (or, with pieces, integer) programme. Choosing the quantiles too, under the
union bound ``Σ_f Φ̄(z_f) ≤ 1 − P`` (``Φ̄`` the normal's upper tail), keeps the rows linear in
``(m, z)`` and adds one convex constraint (``Φ̄`` is convex for ``z ≥ 0``). It is bracketed:
``Φ̄`` replaced by the maximum of its tangents (outer: a relaxation, its least total a proven
lower bound) and by its chords (inner: above ``Φ̄``, so its solutions meet the budget exactly),
points added where the two solutions stand until their totals agree; the inner solution's
quantiles are then fixed and the fixed-quantile programme solved: a feasible ballast, within a
proven distance of the least.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import CadcogError

FloatArray = npt.NDArray[np.float64]

#: The envelope's six faces, in the order of the rows: (axis, sign).
FACES6 = ((0, 1), (0, -1), (1, 1), (1, -1), (2, 1), (2, -1))

#: Seconds HiGHS may spend on one integer programme before the best solution and its proven
#: bound are reported instead of a proven optimum.
MILP_TIME_LIMIT_S = 60.0

#: A face's quantile is at most this (a miss of 1e-33: beyond it nothing changes).
Z_MAX = 12.0

#: Rounds of points added where the solutions stand.
MAX_CUT_ROUNDS = 40

#: The inner programme spends this fraction less than the budget: HiGHS meets a row to its
#: feasibility tolerance (1e-7), and the union bound must hold for the ballast as found, not
#: only as solved (5e-5 in hand at 95 %, where a row's tolerance moves a face's miss by ~1e-8).
INNER_MARGIN = 1e-3
INNER_MARGIN_ABS = 1e-6

#: A face is short when the least total shortfall leaves more than this on it (kg·mm).
SHORTFALL_KG_MM = 1e-9


def norm_sf(z: npt.ArrayLike) -> FloatArray:
    """The normal's upper tail ``Φ̄(z) = 1 - Φ(z)`` (scipy.stats.norm.sf's own ``ndtr(-z)``)."""
    from scipy.special import ndtr

    return np.asarray(ndtr(-np.asarray(z, dtype=float)), dtype=float)


def norm_isf(q: npt.ArrayLike) -> FloatArray:
    """``z`` with upper tail ``q`` (scipy.stats.norm.isf's own ``-ndtri(q)``)."""
    from scipy.special import ndtri

    return np.asarray(-ndtri(np.asarray(q, dtype=float)), dtype=float)


def norm_pdf(z: npt.ArrayLike) -> FloatArray:
    """The normal's density ``φ(z)`` (``-Φ̄'``)."""
    z = np.asarray(z, dtype=float)
    return np.asarray(np.exp(-(z**2) / 2.0) / np.sqrt(2.0 * np.pi), dtype=float)


@dataclass(frozen=True)
class Rows:
    """One configuration's six rows ``a m + c z ≤ b`` (kg·mm; ``a`` shape (6, n))."""

    a: FloatArray
    c: FloatArray
    b: FloatArray


def face_rows(
    mass_kg: float,
    cog_mm: FloatArray,
    spread_kg_mm: FloatArray,
    positions_mm: FloatArray,
    centre_mm: FloatArray,
    limits_mm: FloatArray,
) -> Rows:
    """The six faces' rows of a spacecraft (module docstring): ``±(c' - o) + z σ' ≤ L`` times
    ``T = M + Σ m``, with ``σ' T`` given per axis (``spread_kg_mm``: ``M σ`` when the mass is
    exact, whatever the ballast)."""
    a = np.empty((6, len(positions_mm)))
    c = np.empty(6)
    b = np.empty(6)
    for r, (k, sign) in enumerate(FACES6):
        a[r] = sign * (positions_mm[:, k] - centre_mm[k]) - limits_mm[k]
        c[r] = spread_kg_mm[k]
        b[r] = limits_mm[k] * mass_kg - sign * mass_kg * (cog_mm[k] - centre_mm[k])
    return Rows(a, c, b)


@dataclass(frozen=True)
class _Vars:
    """How the masses are made: ``m = E x`` (``x`` the masses, or counts of pieces)."""

    expand: FloatArray
    integrality: FloatArray
    upper: FloatArray
    caps: FloatArray
    total_cap: float

    @classmethod
    def of(cls, spec: Any) -> _Vars:
        n = len(spec.points)
        caps = np.array([np.inf if p.max_mass_kg is None else p.max_mass_kg for p in spec.points])
        total_cap = np.inf if spec.max_total_mass_kg is None else spec.max_total_mass_kg
        if spec.sizes_kg is None:
            return cls(np.eye(n), np.zeros(n), caps, caps, total_cap)
        sizes = np.asarray(spec.sizes_kg, dtype=float)
        expand = np.kron(np.eye(n), sizes[None, :])  # mass_i = Σ_j s_j n_ij
        upper = np.repeat(caps, len(sizes)) / np.tile(sizes, n)
        upper = np.floor(np.where(np.isfinite(upper), upper + 1e-9, np.inf))
        return cls(expand, np.ones(expand.shape[1]), upper, caps, total_cap)


def _milp(
    cost: FloatArray,
    a_ub: FloatArray,
    b_ub: FloatArray,
    lower: FloatArray,
    upper: FloatArray,
    integrality: FloatArray,
) -> Any:
    from scipy.optimize import Bounds, LinearConstraint, milp

    options: dict[str, Any] = {"disp": False}
    if integrality.any():
        options |= {"mip_rel_gap": 0.0, "time_limit": MILP_TIME_LIMIT_S}
    return milp(
        cost,
        constraints=[LinearConstraint(a_ub, -np.inf, b_ub)],
        integrality=integrality,
        bounds=Bounds(lower, upper),
        options=options,
    )


def _mass_rows(v: _Vars, width: int) -> tuple[FloatArray, FloatArray]:
    """Each location's cap and the total cap, as rows over ``width`` variables."""
    nx = v.expand.shape[1]
    capped = np.isfinite(v.caps)
    rows = [np.hstack([v.expand[capped], np.zeros((int(capped.sum()), width - nx))])]
    rhs = [v.caps[capped]]
    if np.isfinite(v.total_cap):
        rows.append(np.hstack([v.expand.sum(axis=0)[None, :], np.zeros((1, width - nx))]))
        rhs.append(np.array([v.total_cap]))
    return np.vstack(rows), np.concatenate(rhs)


@dataclass(frozen=True)
class Solution:
    """A ballast: masses (kg), counts of pieces (or None), proven least (or the bound)."""

    masses_kg: FloatArray
    counts: FloatArray | None
    optimal: bool
    bound_kg: float | None


def solve_fixed(blocks: Sequence[Rows], z: FloatArray, spec: Any) -> Solution | None:
    """The least total ballast with each face's quantile fixed (``z`` shape (S, 6)); None when
    no ballast within the limits meets every row. With pieces, among the equally light answers
    the one with the fewest pieces (a second integer programme)."""
    v = _Vars.of(spec)
    a = np.vstack([blk.a for blk in blocks]) @ v.expand
    b = np.concatenate([blk.b - blk.c * zs for blk, zs in zip(blocks, z, strict=True)])
    caps_a, caps_b = _mass_rows(v, v.expand.shape[1])
    res = _milp(
        v.expand.sum(axis=0),
        np.vstack([a, caps_a]),
        np.concatenate([b, caps_b]),
        np.zeros(v.expand.shape[1]),
        v.upper,
        v.integrality,
    )
    if res.status == 2 or res.x is None:
        return None
    if res.status not in (0, 1):
        raise CadcogError(f"the ballast programme failed: {res.message}")
    x = np.asarray(res.x)
    counts = None
    if spec.sizes_kg is not None:
        x = np.round(x)
        if res.status == 0:  # among the equally light, the fewest pieces
            least = float(v.expand.sum(axis=0) @ x)
            fewer = _milp(
                np.ones(len(x)),
                np.vstack([a, caps_a, v.expand.sum(axis=0)[None, :]]),
                np.concatenate([b, caps_b, [least * (1.0 + 1e-12) + 1e-15]]),
                np.zeros(len(x)),
                v.upper,
                v.integrality,
            )
            if fewer.status == 0 and fewer.x is not None:
                x = np.round(np.asarray(fewer.x))
        counts = x.reshape(len(spec.points), -1)
    optimal = res.status == 0
    bound = None if optimal else float(getattr(res, "mip_dual_bound", np.nan))
    return Solution(np.maximum(v.expand @ x, 0.0), counts, optimal, bound)


def _joint_matrices(
    blocks: Sequence[Rows],
    spec: Any,
    alpha: float,
    points: list[list[float]],
    inner: bool,
    slack: bool = False,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, int, int]:
    """A programme over ``(x, z, t[, v])``: face rows, each configuration's budget ``Σ t ≤
    α``, and ``t_f`` above ``Φ̄(z_f)``'s tangents at ``points`` (outer: a relaxation, a lower
    bound) or above its chords between consecutive ``points`` with ``z_f`` kept within them
    (inner: every solution meets the true budget); caps. ``slack`` adds ``v ≥ 0`` to every
    face row (the shortfall)."""
    v = _Vars.of(spec)
    nx, nf = v.expand.shape[1], 6 * len(blocks)
    width = nx + 2 * nf + (nf if slack else 0)
    rows, rhs = [], []
    a = np.vstack([blk.a for blk in blocks]) @ v.expand
    face = np.zeros((nf, width))
    face[:, :nx] = a
    face[np.arange(nf), nx + np.arange(nf)] = np.concatenate([blk.c for blk in blocks])
    if slack:
        face[np.arange(nf), nx + 2 * nf + np.arange(nf)] = -1.0
    rows.append(face)
    rhs.append(np.concatenate([blk.b for blk in blocks]))
    for s in range(len(blocks)):
        budget = np.zeros((1, width))
        budget[0, nx + nf + 6 * s : nx + nf + 6 * s + 6] = 1.0
        rows.append(budget)
        rhs.append(np.array([alpha]))
    z_lo, z_hi = np.zeros(nf), np.full(nf, Z_MAX)
    for f, pts in enumerate(points):
        zi = np.unique(np.asarray(pts, dtype=float))
        if inner:  # chords: t ≥ Φ̄(z_i) + s_i (z - z_i), z within [z_0, z_last]
            fi = norm_sf(zi)
            slope = np.diff(fi) / np.diff(zi)
            anchor, value = zi[:-1], fi[:-1]
            z_lo[f], z_hi[f] = zi[0], zi[-1]
        else:  # tangents: t ≥ Φ̄(z_i) - φ(z_i) (z - z_i)
            slope, anchor, value = -norm_pdf(zi), zi, norm_sf(zi)
        cut = np.zeros((len(anchor), width))
        cut[:, nx + f] = slope
        cut[:, nx + nf + f] = -1.0
        rows.append(cut)
        rhs.append(slope * anchor - value)
    caps_a, caps_b = _mass_rows(v, width)
    rows.append(caps_a)
    rhs.append(caps_b)
    lower = np.concatenate([np.zeros(nx), z_lo, np.zeros(nf), np.zeros(nf if slack else 0)])
    upper = np.concatenate([v.upper, z_hi, np.full(nf, alpha), np.full(nf if slack else 0, np.inf)])
    integrality = np.concatenate([v.integrality, np.zeros(width - nx)])
    return np.vstack(rows), np.concatenate(rhs), lower, upper, integrality, v.expand, nx, nf


def _initial_points(alpha: float, faces: int) -> list[list[float]]:
    """Points shared by every face: tails from the whole budget down to 1e-15."""
    tails = np.geomspace(alpha, 1e-15, 24)
    return [list(norm_isf(tails)) for _ in range(faces)]


def _run(
    blocks: Sequence[Rows], spec: Any, alpha: float, points: list[list[float]], inner: bool
) -> tuple[FloatArray, float] | None:
    """One programme (:func:`_joint_matrices`): its quantiles (S, 6) and least total, or None
    when it has no solution."""
    a, b, lo, hi, integ, expand, nx, nf = _joint_matrices(blocks, spec, alpha, points, inner)
    cost = np.concatenate([expand.sum(axis=0), np.zeros(2 * nf)])
    res = _milp(cost, a, b, lo, hi, integ)
    if res.status == 2 or res.x is None:
        return None
    if res.status not in (0, 1):
        raise CadcogError(f"the ballast programme failed: {res.message}")
    z = np.asarray(res.x[nx : nx + nf]).reshape(len(blocks), 6)
    value = float(res.fun) if res.status == 0 else float(getattr(res, "mip_dual_bound", 0.0))
    return z, value


def solve_joint(
    blocks: Sequence[Rows], spec: Any, alpha: float, rtol: float
) -> tuple[FloatArray | None, float] | None:
    """The quantiles (shape (S, 6)) of the least total ballast under each configuration's union
    bound, and a proven lower bound on that total (module docstring). The quantiles come from
    the inner programme (chords: they meet the budget exactly); the bound from the outer one
    (tangents); points are added where the solutions stand until the two agree to ``rtol``.
    Returns None when even the outer programme has no ballast within the limits; the
    quantiles are None when only the outer one has one."""
    nf = 6 * len(blocks)
    tangents = _initial_points(alpha, nf)
    chords = _initial_points(alpha, nf)
    best: FloatArray | None = None
    bound = 0.0
    for _ in range(MAX_CUT_ROUNDS):
        outer = _run(blocks, spec, alpha, tangents, inner=False)
        if outer is None:
            return None
        bound = outer[1]
        spend = alpha - max(alpha * INNER_MARGIN, INNER_MARGIN_ABS)
        inner = _run(blocks, spec, spend, chords, inner=True)
        if inner is not None:
            best = inner[0]
            if inner[1] - outer[1] <= rtol * max(inner[1], 1e-12) + 1e-15:
                return best, bound
        follow = outer[0] if inner is None else inner[0]
        for f, (zo, zi) in enumerate(zip(outer[0].ravel(), follow.ravel(), strict=True)):
            tangents[f].append(float(zo))
            chords[f].extend([float(zo), float(zi)])
    return best, bound


def shortfall(
    blocks: Sequence[Rows],
    spec: Any,
    alpha: float,
    masses_kg: Sequence[float],
    labels: Sequence[str],
) -> list[dict[str, Any]]:
    """The faces no ballast within the limits satisfies, even with the quantiles chosen: the
    least total shortfall (moment, kg·mm) over the relaxation with a slack on each face row
    (continuous masses). ``masses_kg``: each configuration's mass, for the CoG shift."""
    from scipy.optimize import linprog

    nf = 6 * len(blocks)
    points = _initial_points(alpha, nf)
    a, b, lo, hi, _, expand, nx, _ = _joint_matrices(blocks, spec, alpha, points, False, True)
    width = a.shape[1]
    cost = np.zeros(width)
    cost[nx + 2 * nf :] = 1.0
    res = linprog(cost, A_ub=a, b_ub=b, bounds=list(zip(lo, hi, strict=True)), method="highs")
    if res.status != 0:
        raise CadcogError(f"the ballast shortfall programme failed: {res.message}")
    masses = expand @ res.x[:nx]
    out = []
    for r, value in enumerate(res.x[nx + 2 * nf :]):
        k, sign = FACES6[r % 6]
        if value > SHORTFALL_KG_MM:
            row: dict[str, Any] = {
                "axis": "xyz"[k],
                "side": "+" if sign > 0 else "-",
                "moment_kg_mm": float(value),
                "cog_shift_mm": float(value / (masses_kg[r // 6] + masses.sum())),
            }
            if len(blocks) > 1:
                row["configuration"] = labels[r // 6]
            out.append(row)
    return out
