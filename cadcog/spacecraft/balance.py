"""The least ballast that puts the CoG inside its envelope with a stated confidence.

A spacecraft of mass ``M`` and CoG ``c`` (covariance ``Σ``, in the envelope's axes, the model's)
gets ballast masses ``m_i`` at allowed locations ``p_i``. Its new CoG is

    c' = (M c + Σ m_i p_i) / (M + Σ m_i),

and its uncertainty, the ballast's masses and positions taken as exact (weighed washers bolted
in drilled holes), ``σ'_k = f_k M σ_k / (M + Σ m_i)``, where ``f_k = 1`` when the mass is exact
and ``f_k`` carries the mass's own uncertainty otherwise (below). The envelope is a box of
half-widths ``L`` around the geometric centre ``o``. The CoG lies inside it with probability at
least ``P`` when each of its six faces is missed with probability at most ``(1 - P) / 6``
(Bonferroni: the union of six events is at most the sum of their probabilities), that is when

    ±(c'_k - o_k) + z σ'_k ≤ L_k   for each axis k and sign,   z = Φ⁻¹(1 - (1 - P) / 6).

Multiplied by ``M + Σ m_i > 0`` each is **linear in the masses**:

    Σ_i m_i (±(p_ik - o_k) - L_k) ≤ L_k M ∓ M (c_k - o_k) - z f_k M σ_k,

so the least total ballast is a linear programme (continuous masses) or, with discrete sizes
(``m_i = Σ_j s_j n_ij``, ``n_ij`` whole numbers), a mixed-integer one; both are solved exactly
by HiGHS through :func:`scipy.optimize.milp` (the integer one to a zero gap, or its proven bound
when the time limit stops it).

The mass's own uncertainty (a CAD's 5 % per item, correlated with its CoG) enters ``c'`` through
``∂c'/∂M = (c - c') / (M + m)``: ``f_k`` is the ratio of the full first-order σ'_k to the
exact-mass one, evaluated at the solution and the programme solved again until ``f`` settles
(it moves by parts per million: the term is second order in the CoG shift). The result is then
checked against the envelope directly, not through the multiplied-out form.

Bonferroni's equal shares are wasteful when one face binds and the others are far: the faces
that do not bind then give their share away. Each face ``f`` keeps a miss budget ``β_f``
(``Σ β_f = 1 - P``, ``z_f = Φ⁻¹(1 - β_f)``); after a solution, a face whose miss probability is
below a tenth of its budget keeps twice that probability, and the faces that bind share the
rest; the programme is solved again, and the new solution kept when it needs less ballast.
Every solution satisfies its six constraints with budgets summing to ``1 - P``, so the union
bound holds for each: the CoG is inside with probability at least ``P`` (the reported
``probability_inside``, integrated, is typically ``P`` to ``P + 0.01``).

When no ballast within the limits meets the envelope, the programme that minimises the total
shortfall (moment, kg·mm, over the six faces) says which face is short and by how much.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core import tolerances
from cadcog.core.errors import CadcogError
from cadcog.core.results import JsonResult

FloatArray = npt.NDArray[np.float64]

#: The envelope's six faces, in the order of the programme's rows: (axis, sign).
FACES6 = ((0, 1), (0, -1), (1, 1), (1, -1), (2, 1), (2, -1))

#: Seconds HiGHS may spend on an integer programme before the best solution and its proven
#: bound are reported instead of a proven optimum.
MILP_TIME_LIMIT_S = 60.0

#: Iterations of the mass-uncertainty factor ``f`` (it settles in two or three).
MAX_FACTOR_ITERATIONS = 20

#: Rounds of giving the miss budget of the faces that do not bind to those that do.
MAX_ALLOCATIONS = 8

#: A face is short when the least total shortfall leaves more than this on it (kg·mm).
SHORTFALL_KG_MM = 1e-9


@dataclass(frozen=True)
class BallastPoint:
    """An allowed ballast location: its id, position (mm) and most mass it takes (kg)."""

    id: str
    position_mm: FloatArray
    max_mass_kg: float | None = None


@dataclass(frozen=True)
class BallastSpec:
    """The allowed locations, the discrete sizes available (kg; None: any mass), the most
    ballast in all (kg) and where the spec came from."""

    points: tuple[BallastPoint, ...]
    sizes_kg: tuple[float, ...] | None = None
    max_total_mass_kg: float | None = None
    source: str = ""


@dataclass(frozen=True)
class UncertainMass:
    """What is balanced: a mass and CoG with their first-order uncertainty.

    Attributes
    ----------
    mass_kg, mass_sigma_kg : float
    cog_mm : ndarray, shape (3,)
    cog_cov_mm2 : ndarray, shape (3, 3)
    cog_mass_cov_mm_kg : ndarray, shape (3,)
        ``Cov(c, M)``: zero for a weighed mass.
    source : str
        What the figures are (``"CAD"``, ``"update"`` ...).
    """

    mass_kg: float
    mass_sigma_kg: float
    cog_mm: FloatArray
    cog_cov_mm2: FloatArray
    cog_mass_cov_mm_kg: FloatArray
    source: str

    def shifted(
        self,
        mass_kg: float,
        moment_kg_mm: npt.ArrayLike,
        moment_cov_kg2_mm2: npt.ArrayLike,
        source: str,
    ) -> UncertainMass:
        """The same spacecraft with a change of mass and first moment (a configuration's,
        with its own covariance, taken as independent of these figures): ``G' = (M G + ΔS) /
        (M + ΔM)`` to first order.

        Examples
        --------
        >>> s = UncertainMass(2.0, 0.0, np.zeros(3), np.eye(3), np.zeros(3), "test")
        >>> t = s.shifted(0.0, [20.0, 0, 0], np.zeros((3, 3)), "moved")
        >>> t.cog_mm.tolist(), np.diag(t.cog_cov_mm2).tolist()
        ([10.0, 0.0, 0.0], [1.0, 1.0, 1.0])
        """
        total = self.mass_kg + mass_kg
        if not total > 0:
            raise CadcogError(f"{source}: no mass left ({total:g} kg)")
        cog = (self.mass_kg * self.cog_mm + np.asarray(moment_kg_mm, dtype=float)) / total
        jc = self.mass_kg / total
        jm = (self.cog_mm - cog) / total
        s = self.cog_mass_cov_mm_kg
        cov = (
            jc**2 * self.cog_cov_mm2
            + jc * (np.outer(s, jm) + np.outer(jm, s))
            + self.mass_sigma_kg**2 * np.outer(jm, jm)
            + np.asarray(moment_cov_kg2_mm2, dtype=float) / total**2
        )
        return UncertainMass(total, self.mass_sigma_kg, cog, cov, jc * s, source)


def face_quantile(confidence: float) -> float:
    """``z`` such that the CoG is inside the envelope with at least ``confidence`` when each
    face keeps ``z σ`` of margin (Bonferroni over six faces).

    Examples
    --------
    >>> round(face_quantile(0.95), 4)
    2.394
    """
    from scipy.stats import norm

    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence {confidence!r}: expected a probability in (0, 1)")
    return float(norm.ppf(1.0 - (1.0 - confidence) / 6.0))


def with_ballast(
    state: UncertainMass, positions_mm: npt.ArrayLike, masses_kg: npt.ArrayLike
) -> tuple[float, float, FloatArray, FloatArray]:
    """Mass, its σ, CoG and CoG covariance with ballast added (first order, ballast exact).

    Examples
    --------
    >>> s = UncertainMass(1.0, 0.0, np.zeros(3), np.eye(3), np.zeros(3), "")
    >>> m, sm, c, cov = with_ballast(s, [[10.0, 0, 0]], [1.0])
    >>> m, c.tolist(), np.diag(cov).tolist()
    (2.0, [5.0, 0.0, 0.0], [0.25, 0.25, 0.25])
    """
    p = np.asarray(positions_mm, dtype=float).reshape(-1, 3)
    m = np.asarray(masses_kg, dtype=float).reshape(-1)
    total = state.mass_kg + float(m.sum())
    cog = (state.mass_kg * state.cog_mm + m @ p) / total
    jc = state.mass_kg / total  # ∂c'/∂c = jc·I
    jm = (state.cog_mm - cog) / total  # ∂c'/∂M
    s = state.cog_mass_cov_mm_kg
    cov = (
        jc**2 * state.cog_cov_mm2
        + jc * (np.outer(s, jm) + np.outer(jm, s))
        + state.mass_sigma_kg**2 * np.outer(jm, jm)
    )
    return total, state.mass_sigma_kg, cog, cov


def probability_inside(
    cog_mm: npt.ArrayLike, cov_mm2: npt.ArrayLike, lo_mm: npt.ArrayLike, hi_mm: npt.ArrayLike
) -> float:
    """P(lo ≤ CoG ≤ hi) for a normal CoG (Genz's integration, a fixed seed: reproducible)."""
    from scipy.stats import multivariate_normal

    c = np.asarray(cog_mm, dtype=float)
    cov = np.asarray(cov_mm2, dtype=float)
    lo, hi = np.asarray(lo_mm, dtype=float), np.asarray(hi_mm, dtype=float)
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    if np.any(sd == 0.0):  # an exact axis: inside or not (on a face is in), the others by
        exact = sd == 0.0  # the integral
        tol = tolerances.ON_SURFACE_MM
        if np.any((c[exact] < lo[exact] - tol) | (c[exact] > hi[exact] + tol)):
            return 0.0
        keep = ~exact
        if not keep.any():
            return 1.0
        c, cov, lo, hi = c[keep], cov[np.ix_(keep, keep)], lo[keep], hi[keep]
    p = multivariate_normal.cdf(
        hi,
        mean=c,
        cov=cov,
        allow_singular=True,
        abseps=1e-7,
        releps=1e-7,
        lower_limit=lo,
        rng=np.random.default_rng(0),
    )
    return float(min(max(p, 0.0), 1.0))


@dataclass(frozen=True, repr=False)
class BalanceResult(JsonResult):
    """The least ballast, or why there is none (:func:`least_ballast`).

    Attributes
    ----------
    feasible : bool
    masses_kg : ndarray, shape (n,)
        Ballast at each location (zeros when infeasible).
    counts : ndarray, shape (n, J) or None
        With discrete sizes: how many of each size at each location.
    optimal : bool
        The total is proven least (an integer programme stopped by its time limit: False,
        ``bound_kg`` then says how much less could exist at most).
    mass_kg : float
        The mass after ballast (kg).
    mass_sigma_kg : float
        Its 1 σ (kg; the ballast is exact).
    cog_mm : ndarray, shape (3,)
        The CoG after ballast (mm).
    cog_cov_mm2 : ndarray, shape (3, 3)
        Its covariance (mm²).
    offset_mm : ndarray, shape (3,)
        CoG minus the geometric centre (mm).
    margin_mm : ndarray, shape (3,)
        ``L - |offset| - z σ`` per axis, ``z`` the quantile of the face the CoG leans to: the
        margin at the confidence (negative: short).
    probability_inside : float
        The joint probability that the CoG lies inside the envelope (normal CoG, integrated).
    before : dict
        The same figures without ballast.
    shortfall : list of dict
        Infeasible: each face short (``axis``, ``side``, ``moment_kg_mm``, ``cog_shift_mm``;
        ``configuration`` with several).
    notes : tuple of str
    configurations : tuple of dict
        With other configurations: each one's figures with the same ballast (``name``,
        ``mass_kg``, ``cog_mm``, ``cog_cov_mm2``, ``offset_mm``, ``margin_mm``,
        ``probability_inside``, ``face_quantiles``, ``before``).
    """

    spec: BallastSpec
    state: UncertainMass
    geometric_center_mm: FloatArray
    limits_mm: FloatArray
    confidence: float
    face_quantiles: FloatArray
    feasible: bool
    masses_kg: FloatArray
    counts: FloatArray | None
    optimal: bool
    bound_kg: float | None
    mass_kg: float
    mass_sigma_kg: float
    cog_mm: FloatArray
    cog_cov_mm2: FloatArray
    offset_mm: FloatArray
    margin_mm: FloatArray
    probability_inside: float
    before: dict[str, Any]
    shortfall: tuple[dict[str, Any], ...]
    notes: tuple[str, ...] = ()
    configurations: tuple[dict[str, Any], ...] = ()

    @property
    def total_ballast_kg(self) -> float:
        """All the ballast (kg)."""
        return float(self.masses_kg.sum())

    def budget(self) -> list[dict[str, Any]]:
        """The mass budget with the ballast: the spacecraft, each location used, the total."""
        rows: list[dict[str, Any]] = [
            {
                "name": f"spacecraft ({self.state.source})",
                "mass_kg": self.state.mass_kg,
                "mass_sigma_kg": self.state.mass_sigma_kg,
                "cog_mm": np.asarray(self.state.cog_mm).tolist(),
            }
        ]
        for pt, m in zip(self.spec.points, self.masses_kg, strict=True):
            if m > 0.0:
                rows.append(
                    {
                        "name": f"ballast {pt.id}",
                        "mass_kg": float(m),
                        "mass_sigma_kg": 0.0,
                        "cog_mm": np.asarray(pt.position_mm).tolist(),
                    }
                )
        rows.append(
            {
                "name": "total",
                "mass_kg": self.mass_kg,
                "mass_sigma_kg": self.mass_sigma_kg,
                "cog_mm": self.cog_mm.tolist(),
            }
        )
        return rows

    def to_dict(self) -> dict[str, Any]:
        ballast = []
        for k, (pt, m) in enumerate(zip(self.spec.points, self.masses_kg, strict=True)):
            if m <= 0.0:
                continue
            row: dict[str, Any] = {
                "id": pt.id,
                "mass_kg": float(m),
                "position_mm": np.asarray(pt.position_mm).tolist(),
            }
            if self.counts is not None and self.spec.sizes_kg is not None:
                row["pieces"] = [
                    {"size_kg": s, "count": int(n)}
                    for s, n in zip(self.spec.sizes_kg, self.counts[k], strict=True)
                    if n > 0
                ]
            ballast.append(row)
        return {
            "feasible": self.feasible,
            "optimal": self.optimal,
            "bound_kg": self.bound_kg,
            "confidence": self.confidence,
            "face_quantiles": self.face_quantiles.tolist(),
            "face_miss_budget": norm_sf(self.face_quantiles).tolist(),
            "ballast": ballast,
            "total_ballast_kg": self.total_ballast_kg,
            "mass_kg": self.mass_kg,
            "mass_sigma_kg": self.mass_sigma_kg,
            "cog_mm": self.cog_mm.tolist(),
            "cog_cov_mm2": self.cog_cov_mm2.tolist(),
            "geometric_center_mm": self.geometric_center_mm.tolist(),
            "limits_mm": self.limits_mm.tolist(),
            "offset_mm": self.offset_mm.tolist(),
            "margin_mm": self.margin_mm.tolist(),
            "probability_inside": self.probability_inside,
            "before": self.before,
            "shortfall": list(self.shortfall),
            "budget": self.budget(),
            "source": self.state.source,
            "ballast_file": self.spec.source,
            "notes": list(self.notes),
            "configurations": list(self.configurations),
        }


def _figures(
    state: UncertainMass,
    spec: BallastSpec,
    masses: FloatArray,
    centre: FloatArray,
    limits: FloatArray,
    z6: FloatArray,
) -> tuple[float, float, FloatArray, FloatArray, FloatArray, FloatArray, float, FloatArray]:
    """Mass, its σ, CoG, covariance, offset, margin per axis (at the nearer face's quantile),
    the joint probability inside and each face's miss probability, with these masses."""
    from scipy.stats import norm

    positions = np.array([p.position_mm for p in spec.points]).reshape(-1, 3)
    mass, sigma_m, cog, cov = with_ballast(state, positions, masses)
    offset = cog - centre
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    near = np.where(offset >= 0, z6[0::2], z6[1::2])  # the face the CoG leans to
    margin = limits - np.abs(offset) - near * sd
    prob = probability_inside(cog, cov, centre - limits, centre + limits)
    miss = np.empty(6)
    for r, (k, sign) in enumerate(FACES6):
        gap = limits[k] - sign * offset[k]
        miss[r] = float(norm.sf(gap / sd[k])) if sd[k] > 0 else float(gap < 0)
    return mass, sigma_m, cog, cov, offset, margin, prob, miss


def _rows(
    state: UncertainMass,
    positions: FloatArray,
    centre: FloatArray,
    limits: FloatArray,
    z6: FloatArray,
    factor: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """The six faces' rows ``A m ≤ b`` (module docstring), kg·mm."""
    big_m = state.mass_kg
    sd = np.sqrt(np.maximum(np.diag(state.cog_cov_mm2), 0.0))
    a = np.empty((6, len(positions)))
    b = np.empty(6)
    for r, (k, sign) in enumerate(FACES6):
        a[r] = sign * (positions[:, k] - centre[k]) - limits[k]
        b[r] = (
            limits[k] * big_m
            - sign * big_m * (state.cog_mm[k] - centre[k])
            - z6[r] * factor[k] * big_m * sd[k]
        )
    return a, b


def _solve(
    a: FloatArray,
    b: FloatArray,
    spec: BallastSpec,
) -> tuple[str, FloatArray, FloatArray | None, bool, float | None]:
    """Least total ballast under ``A m ≤ b``: ("ok"|"infeasible", masses, counts, optimal,
    bound)."""
    from scipy.optimize import Bounds, LinearConstraint, milp

    n = len(spec.points)
    caps = np.array([np.inf if p.max_mass_kg is None else p.max_mass_kg for p in spec.points])
    total_cap = np.inf if spec.max_total_mass_kg is None else spec.max_total_mass_kg
    if spec.sizes_kg is None:
        expand = np.eye(n)  # variables: the masses
        integrality = np.zeros(n)
        upper = caps
    else:
        sizes = np.asarray(spec.sizes_kg, dtype=float)
        expand = np.kron(np.eye(n), sizes[None, :])  # mass_i = Σ_j s_j n_ij
        integrality = np.ones(expand.shape[1])
        upper = np.repeat(caps, len(sizes)) / np.tile(sizes, n)
        upper = np.floor(np.where(np.isfinite(upper), upper + 1e-9, np.inf))
    cons = [LinearConstraint(a @ expand, -np.inf, b)]
    cons.append(LinearConstraint(expand, -np.inf, caps))
    if np.isfinite(total_cap):
        cons.append(LinearConstraint(expand.sum(axis=0)[None, :], -np.inf, total_cap))
    cost = expand.sum(axis=0)
    options: dict[str, Any] = {"disp": False}
    if spec.sizes_kg is not None:
        options |= {"mip_rel_gap": 0.0, "time_limit": MILP_TIME_LIMIT_S}
    res = milp(
        cost,
        constraints=cons,
        integrality=integrality,
        bounds=Bounds(np.zeros(expand.shape[1]), upper),
        options=options,
    )
    if res.status == 2 or res.x is None:  # infeasible (or stopped before any solution)
        return "infeasible", np.zeros(n), None, False, None
    if res.status not in (0, 1):
        raise CadcogError(f"the ballast programme failed: {res.message}")
    x = np.asarray(res.x)
    counts = None
    if spec.sizes_kg is not None:
        x = np.round(x)
        counts = x.reshape(n, -1)
    masses = expand @ x
    optimal = res.status == 0
    bound = None
    if not optimal:
        bound = float(getattr(res, "mip_dual_bound", np.nan))
    return "ok", np.maximum(masses, 0.0), counts, optimal, bound


def _shortfall(
    a: FloatArray, b: FloatArray, spec: BallastSpec, total_mass_kg: float, labels: Sequence[str]
) -> list[dict[str, Any]]:
    """The faces no ballast within the limits satisfies: the least total shortfall (``labels``:
    the configuration of each block of six rows)."""
    from scipy.optimize import linprog

    n, rows_n = len(spec.points), len(b)
    caps = [(0.0, None if p.max_mass_kg is None else p.max_mass_kg) for p in spec.points]
    a_ub = np.hstack([a, -np.eye(rows_n)])
    rows, rhs = [a_ub], [b]
    if spec.max_total_mass_kg is not None:
        rows.append(np.hstack([np.ones((1, n)), np.zeros((1, rows_n))]))
        rhs.append(np.array([spec.max_total_mass_kg]))
    res = linprog(
        np.r_[np.zeros(n), np.ones(rows_n)],
        A_ub=np.vstack(rows),
        b_ub=np.concatenate(rhs),
        bounds=caps + [(0.0, None)] * rows_n,
        method="highs",
    )
    if res.status != 0:
        raise CadcogError(f"the ballast shortfall programme failed: {res.message}")
    masses, short = res.x[:n], res.x[n:]
    out = []
    for r, v in enumerate(short):
        k, sign = FACES6[r % 6]
        if v > SHORTFALL_KG_MM:
            row: dict[str, Any] = {
                "axis": "xyz"[k],
                "side": "+" if sign > 0 else "-",
                "moment_kg_mm": float(v),
                "cog_shift_mm": float(v / (total_mass_kg + masses.sum())),
            }
            if len(b) > 6:
                row["configuration"] = labels[r // 6]
            out.append(row)
    return out


def norm_sf(z: npt.ArrayLike) -> FloatArray:
    """The normal's upper tail ``1 - Φ(z)``."""
    from scipy.stats import norm

    return np.asarray(norm.sf(z), dtype=float)


def norm_isf(q: npt.ArrayLike) -> FloatArray:
    """``z`` with upper tail ``q``."""
    from scipy.stats import norm

    return np.asarray(norm.isf(q), dtype=float)


def _solve_at(
    states: Sequence[UncertainMass],
    spec: BallastSpec,
    positions: FloatArray,
    centre: FloatArray,
    limits: FloatArray,
    z: FloatArray,
) -> tuple[str, FloatArray, FloatArray | None, bool, float | None, FloatArray]:
    """The least ballast that every state's six faces allow, each face at its quantile
    ``z[s, f]``, the mass-uncertainty factors iterated until the σ assumed covers the σ found
    (module docstring)."""
    factor = np.ones((len(states), 3))
    sd0 = [np.sqrt(np.maximum(np.diag(st.cog_cov_mm2), 0.0)) for st in states]
    for _ in range(MAX_FACTOR_ITERATIONS):
        blocks = [
            _rows(st, positions, centre, limits, z[i], factor[i]) for i, st in enumerate(states)
        ]
        a = np.vstack([blk[0] for blk in blocks])
        b = np.concatenate([blk[1] for blk in blocks])
        status, masses, counts, optimal, bound = _solve(a, b, spec)
        if status != "ok":
            return status, masses, counts, optimal, bound, factor
        new = np.ones_like(factor)
        for i, st in enumerate(states):
            total, _, _, cov = with_ballast(st, positions, masses)
            sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
            exact_sd = st.mass_kg * sd0[i] / total
            new[i] = np.where(exact_sd > 0, sd / np.where(exact_sd > 0, exact_sd, 1.0), 1.0)
        if np.all(new <= factor * (1.0 + 1e-12)):  # the σ assumed covers the σ found
            return status, masses, counts, optimal, bound, factor
        factor = np.maximum(new, factor)  # only up: the factors settle
    raise CadcogError("the ballast's uncertainty factor did not settle (please report)")


def least_ballast(
    state: UncertainMass,
    spec: BallastSpec,
    geometric_center_mm: npt.ArrayLike,
    limits_mm: npt.ArrayLike,
    confidence: float = 0.95,
    *,
    allocate: bool = True,
    configurations: Sequence[tuple[str, UncertainMass]] = (),
) -> BalanceResult:
    """The least total ballast at the allowed locations that puts the CoG inside the envelope
    with at least ``confidence`` (module docstring), in ``state`` and in every configuration.

    Parameters
    ----------
    state : UncertainMass
        The spacecraft as it is (CAD, or measured and updated).
    spec : BallastSpec
        The allowed locations, sizes and limits.
    geometric_center_mm, limits_mm : array_like, shape (3,)
        The envelope: its centre and half-widths (mm, model axes).
    confidence : float
        In (0, 1): each configuration's CoG inside with at least this probability.
    allocate : bool
        Give the miss budget of the faces that do not bind to those that do (default); False
        keeps Bonferroni's equal shares (``z`` of :func:`face_quantile` on every face).
    configurations : sequence of (str, UncertainMass)
        Other configurations the same ballast must satisfy (the ballast does not move with
        them: it sits on the bus), by name.

    Returns
    -------
    BalanceResult
        The masses, the new figures and margins (``state``'s; ``configurations`` each); with
        ``feasible`` False, ``shortfall`` when no ballast within the limits meets the envelope.

    Examples
    --------
    A 1 kg body 10 mm off centre in x, a 20 mm envelope, exact figures, ballast allowed 50 mm
    the other way: the least mass brings the CoG exactly to the limit; here
    none (10 mm is inside), and with an 8 mm limit ``(10 - 50 m) / (1 + m) = 8``, ``m = 2/58 kg``:

    >>> state = UncertainMass(1.0, 0.0, np.array([10.0, 0, 0]), np.zeros((3, 3)), np.zeros(3), "")
    >>> spec = BallastSpec((BallastPoint("w", np.array([-50.0, 0, 0])),))
    >>> least_ballast(state, spec, np.zeros(3), [20.0, 20, 20]).total_ballast_kg
    0.0
    >>> r = least_ballast(state, spec, np.zeros(3), [8.0, 20, 20])
    >>> round(r.total_ballast_kg, 12) == round(2 / 58, 12), round(float(r.cog_mm[0]), 9)
    (True, 8.0)
    """
    if not spec.points:
        raise CadcogError("no ballast location given")
    alpha = 1.0 - confidence
    z_uniform = face_quantile(confidence)
    centre = np.asarray(geometric_center_mm, dtype=float)
    limits = np.asarray(limits_mm, dtype=float)
    if limits.shape != (3,) or np.any(limits <= 0):
        raise CadcogError(f"envelope half-widths {limits.tolist()}: expected three positive mm")
    names = [state.source, *(name for name, _ in configurations)]
    if len(set(names[1:])) != len(names) - 1:
        raise CadcogError(f"configurations {names[1:]}: a name is given twice")
    states = [state, *(st for _, st in configurations)]
    positions = np.array([p.position_mm for p in spec.points], dtype=float).reshape(-1, 3)
    zero = np.zeros(len(spec.points))
    z = np.full((len(states), 6), z_uniform)
    before = [_figures(st, spec, zero, centre, limits, z[i]) for i, st in enumerate(states)]
    status, masses, counts, optimal, bound, factor = _solve_at(
        states, spec, positions, centre, limits, z
    )
    for _ in range(MAX_ALLOCATIONS if allocate else 0):  # idle faces give their budget away
        if status != "ok":
            break
        z_new = z.copy()
        for i, st in enumerate(states):
            miss = _figures(st, spec, masses, centre, limits, z[i])[7]
            budget = norm_sf(z[i])
            idle = miss < budget / 10.0
            if idle.any() and not idle.all():
                new_budget = budget.copy()
                new_budget[idle] = np.maximum(2.0 * miss[idle], alpha * 1e-9)
                new_budget[~idle] = (alpha - new_budget[idle].sum()) / (~idle).sum()
                z_new[i] = norm_isf(new_budget)
        if np.array_equal(z_new, z):
            break
        trial = _solve_at(states, spec, positions, centre, limits, z_new)
        if trial[0] != "ok" or trial[1].sum() >= masses.sum() * (1.0 - 1e-9):
            break
        z = z_new
        status, masses, counts, optimal, bound, factor = trial
    notes: list[str] = []
    shortfall: list[dict[str, Any]] = []
    if status != "ok":
        blocks = [
            _rows(st, positions, centre, limits, z[i], factor[i]) for i, st in enumerate(states)
        ]
        a = np.vstack([blk[0] for blk in blocks])
        b = np.concatenate([blk[1] for blk in blocks])
        shortfall = _shortfall(a, b, spec, state.mass_kg, names)
        for name, st in zip(names, states, strict=True):
            sd0 = np.sqrt(np.maximum(np.diag(st.cog_cov_mm2), 0.0))
            where = f" ({name})" if len(states) > 1 else ""
            for k in np.flatnonzero(z_uniform * sd0 >= limits):
                notes.append(
                    f"along {'xyz'[k]}{where} the CoG's own uncertainty (1σ {sd0[k]:.3g} mm, "
                    f"{z_uniform:.3g} σ = {z_uniform * sd0[k]:.3g} mm) exceeds the half-width "
                    f"{limits[k]:g} mm: ballast can only dilute it; measure the CoG (--readings) "
                    "or state the masses more tightly"
                )
        if not shortfall and spec.sizes_kg is not None:
            notes.append(
                "continuous masses would meet the envelope: the sizes available, or the "
                "locations' limits in whole pieces, do not"
            )
        masses = np.zeros(len(positions))
        counts = None
        optimal = False
    after = [_figures(st, spec, masses, centre, limits, z[i]) for i, st in enumerate(states)]
    if status == "ok":
        for name, fig in zip(names, after, strict=True):
            if np.any(fig[5] < -1e-9 * np.maximum(limits, 1.0)):
                raise CadcogError(
                    f"the ballast found leaves {name} a margin of {fig[5].tolist()} mm "
                    "(please report)"
                )
    mass, sigma_m, cog, cov, offset, margin, prob, _ = after[0]
    per_config = tuple(
        {
            "name": name,
            "mass_kg": fig[0],
            "mass_sigma_kg": fig[1],
            "cog_mm": fig[2].tolist(),
            "cog_cov_mm2": fig[3].tolist(),
            "offset_mm": fig[4].tolist(),
            "margin_mm": fig[5].tolist(),
            "probability_inside": fig[6],
            "face_quantiles": z[i].tolist(),
            "before": _before(before[i]),
        }
        for i, (name, fig) in enumerate(zip(names, after, strict=True))
        if i > 0
    )
    return BalanceResult(
        spec,
        state,
        centre,
        limits,
        float(confidence),
        z[0],
        status == "ok",
        masses,
        counts,
        bool(optimal),
        bound,
        mass,
        sigma_m,
        cog,
        cov,
        offset,
        margin,
        prob,
        _before(before[0]),
        tuple(shortfall),
        tuple(notes),
        per_config,
    )


def _before(fig: tuple[Any, ...]) -> dict[str, Any]:
    """The figures without ballast, as the result's ``before``."""
    b_mass, _, b_cog, b_cov, b_off, b_margin, b_prob, _ = fig
    return {
        "mass_kg": b_mass,
        "cog_mm": b_cog.tolist(),
        "cog_cov_mm2": b_cov.tolist(),
        "offset_mm": b_off.tolist(),
        "margin_mm": b_margin.tolist(),
        "probability_inside": b_prob,
    }
