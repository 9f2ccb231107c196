"""The least ballast that puts the CoG inside its envelope with a stated confidence.

A spacecraft of mass ``M`` and CoG ``c`` (covariance ``Σ``, in the envelope's axes, the model's)
gets ballast masses ``m_i`` at allowed locations ``p_i``. Its new CoG is

    c' = (M c + Σ m_i p_i) / (M + Σ m_i),

and its uncertainty, the ballast's masses and positions taken as exact (weighed washers bolted
in drilled holes), ``σ'_k T = f_k M σ_k`` with ``T = M + Σ m_i``: ``f_k = 1`` when the mass
``M`` is exact (a weighing), and otherwise ``f_k`` carries the mass's own uncertainty (below),
so that σ' may even grow. The envelope is a box of half-widths ``L`` around the geometric centre
``o``. Each of its six faces ``f`` gets a miss budget ``β_f``, the CoG clearing it by ``z_f σ'``
with ``z_f = Φ̄⁻¹(β_f)``; when the budgets sum to ``1 - P``, the CoG is inside with probability
at least ``P`` (the union bound: the probability of any of six misses is at most the sum of
theirs):

    ±(c'_k - o_k) + z_f σ'_k ≤ L_k   for each face f (axis k, sign ±),   Σ_f Φ̄(z_f) ≤ 1 - P.

Multiplied by ``M + Σ m_i > 0`` each face is **linear in the masses and its quantile**:

    Σ_i m_i (±(p_ik - o_k) - L_k) + z_f σ'_k T ≤ L_k M ∓ M (c_k - o_k),

and the budget is convex (``Φ̄`` is, for ``z ≥ 0``), so the least total ballast, the budgets
chosen with it, is a convex programme; with discrete sizes (``m_i = Σ_j s_j n_ij``, whole
``n_ij``) a mixed-integer one. :mod:`cadcog.spacecraft.ballast_programme` brackets it with
HiGHS (:func:`scipy.optimize.milp`): a proven lower bound (tangents) and a feasible ballast
(chords), called the least when the two agree to :data:`PROVEN_RTOL` (``optimal``;
``bound_kg`` is the lower bound). Bonferroni's equal shares
(``z = Φ̄⁻¹((1 - P) / 6)`` on every face, ``allocate=False``) are one feasible choice among
them; choosing the shares lands the integrated probability (``probability_inside``) near ``P``
rather than at 0.99.

The mass's own uncertainty (a CAD's 5 % per item, correlated with its CoG) enters ``c'`` through
``∂c'/∂M = (c - c') / (M + m)``: the spread ``σ'_k T`` is evaluated at the ballast found and the
programme solved again until the spread assumed is the spread found (a fixed point, two or three
rounds; only then is the answer called the least). The result is then checked against the
envelope directly, not through the multiplied-out form.

With several configurations (the same ballast for each) every configuration has its own six
faces and its own budget: each is inside with probability at least ``P``.

When no ballast within the limits meets the envelope, the programme that minimises the total
shortfall (moment, kg·mm, over the faces, the shares chosen too) says which face is short and
by how much (at least that much: the relaxation's).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core import tolerances
from cadcog.core.errors import CadcogError
from cadcog.spacecraft.balance_result import BalanceResult
from cadcog.spacecraft.ballast_programme import (
    FACES6,
    Z_MAX,
    face_rows,
    norm_isf,
    norm_sf,
    solve_fixed,
    solve_joint,
)
from cadcog.spacecraft.ballast_programme import shortfall as face_shortfall
from cadcog.spacecraft.ballast_spec import BallastSpec, UncertainMass

FloatArray = npt.NDArray[np.float64]

#: Iterations of the spread ``σ' T`` (it settles in two or three), and the relative change
#: that settles it.
MAX_FACTOR_ITERATIONS = 20
SPREAD_RTOL = 1e-9
#: An exact CoG (no spread) this far beyond a face, relative to the half-width, is on it: the
#: arithmetic of a CoG the programme puts exactly on a face (the margin check uses the same).
EXACT_GAP_RTOL = 1e-9

#: A CoG axis with a smaller σ (mm) is exact in :func:`probability_inside` (a subnormal
#: variance would overflow the integral's inverse).
EXACT_SIGMA_MM = 1e-9

#: A ballast within this fraction (0.2 %) of the relaxation's proven lower bound is called the
#: least: the inner programme keeps 0.1 % of the budget in hand
#: (:data:`cadcog.spacecraft.ballast_programme.INNER_MARGIN`), which costs less than that.
PROVEN_RTOL = 2e-3


def face_quantile(confidence: float) -> float:
    """``z`` such that the CoG is inside the envelope with at least ``confidence`` when each
    face keeps ``z σ`` of margin (Bonferroni over six faces).

    Examples
    --------
    >>> round(face_quantile(0.95), 4)
    2.394
    """
    from scipy.special import ndtri  # scipy.stats.norm.ppf's own, without its import

    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence {confidence!r}: expected a probability in (0, 1)")
    return float(ndtri(1.0 - (1.0 - confidence) / 6.0))


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
    after = state.shifted(float(m.sum()), m @ p, np.zeros((3, 3)), state.source)
    return after.mass_kg, after.mass_sigma_kg, after.cog_mm, after.cog_cov_mm2


def probability_inside(
    cog_mm: npt.ArrayLike, cov_mm2: npt.ArrayLike, lo_mm: npt.ArrayLike, hi_mm: npt.ArrayLike
) -> float:
    """P(lo ≤ CoG ≤ hi) for a normal CoG (Genz's integration, a fixed seed: reproducible)."""
    from scipy.stats import multivariate_normal

    c = np.asarray(cog_mm, dtype=float)
    cov = np.asarray(cov_mm2, dtype=float)
    lo, hi = np.asarray(lo_mm, dtype=float), np.asarray(hi_mm, dtype=float)
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    exact = sd < EXACT_SIGMA_MM  # an exact axis: inside or not (on a face is in), the others
    if np.any(exact):  # by the integral
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


def _figures(
    state: UncertainMass,
    spec: BallastSpec,
    masses: FloatArray,
    centre: FloatArray,
    limits: FloatArray,
    alpha: float,
) -> tuple[float, float, FloatArray, FloatArray, FloatArray, FloatArray, float, FloatArray]:
    """Mass, its σ, CoG, covariance, offset, margin per axis (:func:`margins`), the joint
    probability inside and each face's miss probability, with these masses."""
    positions = np.array([p.position_mm for p in spec.points]).reshape(-1, 3)
    mass, sigma_m, cog, cov = with_ballast(state, positions, masses)
    offset = cog - centre
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    margin, miss = margins(offset, sd, limits, alpha)
    prob = probability_inside(cog, cov, centre - limits, centre + limits)
    return mass, sigma_m, cog, cov, offset, margin, prob, miss


def margins(
    offset_mm: FloatArray, sd_mm: FloatArray, limits_mm: FloatArray, alpha: float
) -> tuple[FloatArray, FloatArray]:
    """Per axis, how far the CoG may still move towards the nearer of its two faces with the
    union bound still met, the other faces' miss probabilities as they are (0 on a face that
    binds, negative when short); and each face's miss probability ``Φ̄(gap / σ)``.

    Examples
    --------
    A CoG 10 mm from a face, σ 2 mm, the other faces far: 10 - Φ̄⁻¹(0.05) × 2 = 6.71 mm.

    >>> m, q = margins(np.array([10.0, 0, 0]), np.array([2.0, 0, 0]), np.array([20.0] * 3), 0.05)
    >>> round(float(m[0]), 2), float(m[1]), float(m[2])
    (6.71, 20.0, 20.0)
    """
    gaps = np.array([limits_mm[k] - sign * offset_mm[k] for k, sign in FACES6])
    sd6 = np.array([sd_mm[k] for k, _ in FACES6])
    exact = sd6 < EXACT_SIGMA_MM
    # An exact CoG on its face (the programme puts it there) is inside: a gap of -4e-15 mm is
    # the arithmetic's, not a miss (which would leave the other faces no budget at all).
    touch = EXACT_GAP_RTOL * np.array([max(limits_mm[k], 1.0) for k, _ in FACES6])
    miss = np.where(exact, (gaps < -touch).astype(float), norm_sf(gaps / np.where(exact, 1.0, sd6)))
    rest = alpha - (miss.sum() - miss)  # what each face may spend, the others as they are
    z = np.where(rest > 0, norm_isf(np.clip(rest, 1e-300, 0.5)), Z_MAX)
    face = gaps - np.where(exact, 0.0, z * sd6)
    return np.minimum(face[0::2], face[1::2]), miss


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
    >>> from cadcog.spacecraft.ballast_spec import BallastPoint
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
    zero = np.zeros(len(spec.points))
    before = [_figures(st, spec, zero, centre, limits, alpha) for st in states]
    sd0 = [np.sqrt(np.maximum(np.diag(st.cog_cov_mm2), 0.0)) for st in states]
    run = _settle(states, spec, centre, limits, alpha, z_uniform, allocate, sd0)
    found, z, lower = run.found, run.z, run.lower
    shortfall: list[dict[str, Any]] = []
    if found is None:
        shortfall = face_shortfall(run.blocks, spec, alpha, [st.mass_kg for st in states], names)
        notes = _infeasible_notes(names, sd0, z_uniform, limits, bool(shortfall))
        masses, counts, optimal, bound = np.zeros(len(spec.points)), None, False, None
        z = np.full((len(states), 6), z_uniform)
    else:
        notes = []
        masses, counts = found.masses_kg, found.counts
        total = float(masses.sum())
        bound = found.bound_kg if lower is None else lower
        close = lower is None or total - lower <= PROVEN_RTOL * max(total, 1e-12) + 1e-15
        optimal = found.optimal and close and run.settled
    after = [_figures(st, spec, masses, centre, limits, alpha) for st in states]
    if found is not None:
        for name, fig in zip(names, after, strict=True):
            if np.any(fig[5] < -EXACT_GAP_RTOL * np.maximum(limits, 1.0)):
                raise CadcogError(
                    f"the ballast found leaves {name} a margin of {fig[5].tolist()} mm "
                    "(please report)"
                )
    mass, sigma_m, cog, cov, offset, margin, prob, _ = after[0]
    per_config = tuple(
        _configuration(name, fig, z[i], before[i], alpha)
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
        found is not None,
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
        _before(before[0], alpha),
        tuple(shortfall),
        tuple(notes),
        per_config,
    )


@dataclass(frozen=True)
class _Settled:
    """What :func:`_settle` ends with: the ballast found (None: none meets the envelope), each
    configuration's face quantiles and the proven lower bound (joint allocation), whether the
    spread assumed is the spread found, and the last face rows (for a shortfall)."""

    found: Any
    z: FloatArray
    lower: float | None
    settled: bool
    blocks: list[Any]


def _settle(
    states: Sequence[UncertainMass],
    spec: BallastSpec,
    centre: FloatArray,
    limits: FloatArray,
    alpha: float,
    z_uniform: float,
    allocate: bool,
    sd0: Sequence[FloatArray],
) -> _Settled:
    """Solve for the ballast with the CoG's spread (``σ T``) held, recompute the spread at the
    ballast found (its own mass counts), and repeat until the two agree: a fixed point, or a
    spread assumed that covers the spread found (safe), taken only upwards after
    :data:`MAX_FACTOR_ITERATIONS` tries so that it settles."""
    positions = np.array([p.position_mm for p in spec.points], dtype=float).reshape(-1, 3)
    uniform = np.full((len(states), 6), z_uniform)
    spread = np.array([st.mass_kg * sd for st, sd in zip(states, sd0, strict=True)])
    z, found, lower, settled = uniform, None, None, False
    for attempt in range(2 * MAX_FACTOR_ITERATIONS):
        blocks = [
            face_rows(st.mass_kg, st.cog_mm, spread[i], positions, centre, limits)
            for i, st in enumerate(states)
        ]
        z, lower = uniform, None
        if allocate:
            joint = solve_joint(blocks, spec, alpha, PROVEN_RTOL)
            if joint is None:
                found = None
                break
            z = uniform if joint[0] is None else joint[0]
            lower = joint[1]
        found = solve_fixed(blocks, z, spec)
        if found is None:
            break
        new = np.empty_like(spread)  # σ' T at the ballast found: the mass's own term included
        for i, st in enumerate(states):
            total, _, _, cov = with_ballast(st, positions, found.masses_kg)
            new[i] = np.sqrt(np.maximum(np.diag(cov), 0.0)) * total
        if np.allclose(new, spread, rtol=SPREAD_RTOL, atol=1e-12):
            settled = True  # a fixed point: the spread assumed is the spread found
            break
        if attempt + 1 < MAX_FACTOR_ITERATIONS:
            spread = new
        elif np.all(new <= spread * (1.0 + SPREAD_RTOL) + 1e-12):
            break  # not settled, but the spread assumed covers the spread found: safe
        else:
            spread = np.maximum(new, spread)  # only up from here: it settles, conservatively
    else:
        raise CadcogError("the ballast's uncertainty did not settle (please report)")
    return _Settled(found, z, lower, settled, blocks)


def _infeasible_notes(
    names: Sequence[str],
    sd0: Sequence[FloatArray],
    z_uniform: float,
    limits: FloatArray,
    short: bool,
) -> list[str]:
    """Why no ballast meets the envelope: an axis whose CoG uncertainty alone exceeds the
    half-width (ballast only dilutes it), or, with no face short (``short`` False), the
    pieces or the locations' limits."""
    notes = []
    for name, sd in zip(names, sd0, strict=True):
        where = f" ({name})" if len(names) > 1 else ""
        for k in np.flatnonzero(z_uniform * sd >= limits):
            notes.append(
                f"along {'xyz'[k]}{where} the CoG's own uncertainty (1σ {sd[k]:.3g} mm, "
                f"{z_uniform:.3g} σ = {z_uniform * sd[k]:.3g} mm) exceeds the half-width "
                f"{limits[k]:g} mm: ballast can only dilute it; measure the CoG (--readings) "
                "or state the masses more tightly"
            )
    if not short:
        notes.append(
            "continuous masses would meet the envelope: the sizes available, or the "
            "locations' limits in whole pieces, do not"
        )
    return notes


def _configuration(
    name: str, fig: tuple[Any, ...], z: FloatArray, before: tuple[Any, ...], alpha: float
) -> dict[str, Any]:
    """One other configuration's figures with the ballast, as the result's ``configurations``."""
    return {
        "name": name,
        "mass_kg": fig[0],
        "mass_sigma_kg": fig[1],
        "cog_mm": fig[2].tolist(),
        "cog_cov_mm2": fig[3].tolist(),
        "offset_mm": fig[4].tolist(),
        "margin_mm": fig[5].tolist(),
        "probability_inside": fig[6],
        "face_quantiles": z.tolist(),
        "before": _before(before, alpha),
    }


def _before(fig: tuple[Any, ...], alpha: float) -> dict[str, Any]:
    """The figures without ballast, as the result's ``before``; ``axes_without_budget``: the
    axes whose margin is negative only because the other axes' faces already miss with a
    probability of at least ``alpha`` (their margin is then taken at ``Z_MAX`` σ) while their
    own two faces miss with less."""
    b_mass, _, b_cog, b_cov, b_off, b_margin, b_prob, miss = fig
    own = [float(miss[2 * k] + miss[2 * k + 1]) for k in range(3)]
    others = [float(miss.sum()) - own[k] for k in range(3)]
    return {
        "mass_kg": b_mass,
        "cog_mm": b_cog.tolist(),
        "cog_cov_mm2": b_cov.tolist(),
        "offset_mm": b_off.tolist(),
        "margin_mm": b_margin.tolist(),
        "probability_inside": b_prob,
        "axes_without_budget": [
            "xyz"[k] for k in range(3) if others[k] >= alpha > own[k] and b_margin[k] < 0
        ],
    }
