"""Which hangs determine the inertia tensor best: ``cadcog plan --for inertia`` (or ``both``).

For a set of hangs the prediction is the estimator's linearised covariance at the CAD
(:mod:`cadcog.dynamics.tensorfit`): each hang's usable modes (those its record can resolve) with
the relative model error (:attr:`~cadcog.dynamics.context.InertiaContext.frequency_model_rel`)
as their σ; the fit's own σ and what its halves disagree by come on top and are not known
before the swing (on the nonlinear study's 3U CubeSat the stated σ had a median of 7·10⁻⁴
against the air's 4·10⁻⁴), so where the frequencies dominate the plan's σ are on the low
side; each hang's pivot uncertainty in its own block; the wire length, top hinge, sensor
position, object mass and CoG shared by every hang. Generalised least squares with that
covariance ``C`` gives ``Cov p = (Jᵀ C⁻¹ J)⁻¹``; the ME's removal adds its own terms (ME CoGs and
own inertia, the mass and CoG through the parallel-axis terms), taken as independent of the rest
(a planning approximation). The CoG is taken independent of the pivots too, where the estimator
carries what the same hangs give both (:meth:`~cadcog.dynamics.context.InertiaContext.
hang_terms`): the plan's σ of the products of inertia are on the high side. Sets are grown
greedily from the best triple: the figure of merit is
the largest relative 1 σ of the three principal moments.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from itertools import combinations
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import DegenerateGeometryError
from cadcog.core.results import JsonResult
from cadcog.core.units import STANDARD_GRAVITY_M_S2
from cadcog.dynamics.context import InertiaContext
from cadcog.dynamics.hungbody import HangGeometry, hang_modes
from cadcog.dynamics.modalfit import UNRESOLVED_BINS
from cadcog.dynamics.result import principal_with_sigma
from cadcog.dynamics.tensorfit import compensate, direct_jacobian, entries, nuisances, tensor
from cadcog.mass.properties import combine

if TYPE_CHECKING:
    from cadcog.spacecraft.plan import Plan
    from cadcog.spacecraft.setup import Setup

FloatArray = npt.NDArray[np.float64]

#: Record length the prediction assumes (s): what decides which close modes are resolved.
PLAN_RECORD_S = 60.0

#: At most this many triples are screened exhaustively before growing.
MAX_TRIPLES = 20_000

#: The best triples of the screening that are judged on their principal moments.
SCREENED = 50


@dataclass(frozen=True)
class _HangInfo:
    jac: FloatArray  # (k, 6) ∂f/∂p
    local_cov: FloatArray  # (k, k) frequencies' and own exit's
    shared: FloatArray  # (k, s) ∂f/∂(shared nuisances)


@dataclass(frozen=True, repr=False)
class InertiaPlan(JsonResult):
    """The best set of each size for the inertia tensor, and the recommendation.

    Attributes
    ----------
    best_sets : tuple of dict
        ``points`` (ids), ``moments_sigma_rel`` (1 σ of each principal moment, relative,
        ascending moments), ``axes_sigma_deg`` and ``worst_moment_sigma_rel``.
    recommended : dict or None
        The smallest set within 10 % of the best figure, or None when no set determines the
        tensor.
    weighed : bool
        Whether the prediction assumes a weighing (1 g), or the CAD's mass uncertainty.
    """

    best_sets: tuple[dict[str, Any], ...]
    recommended: dict[str, Any] | None
    weighed: bool

    def to_dict(self) -> dict[str, Any]:
        return {
            "best_sets": list(self.best_sets),
            "recommended": self.recommended,
            "weighed": self.weighed,
            "assumptions": {
                "record_s": PLAN_RECORD_S,
                "merit": "largest relative 1-σ of the principal moments",
            },
        }


#: Where each shared nuisance sits in a plan's shared vector ``v`` (and its covariance): the
#: object's mass, the assembly's CoG, the wire's length, the top clamp's hinge, the sensor.
_MASS, _COG, _LENGTH, _HINGE, _SENSOR = 0, slice(1, 4), 4, 5, slice(6, 9)


def _shared_cov(
    context: InertiaContext, mass_sigma_kg: float, cog_cov_mm2: FloatArray, hinge_sigma_mm: float
) -> FloatArray:
    """The shared nuisances' covariance, laid out as ``_MASS`` … ``_SENSOR``, shape (9, 9)."""
    sw = context.swing
    cov = np.zeros((9, 9))
    cov[_MASS, _MASS] = mass_sigma_kg**2
    cov[_COG, _COG] = cog_cov_mm2
    cov[_LENGTH, _LENGTH] = sw.wire_length_sigma_mm**2
    cov[_HINGE, _HINGE] = hinge_sigma_mm**2
    cov[_SENSOR, _SENSOR] = sw.sensor_position_sigma_mm**2 * np.eye(3)
    return cov


@dataclass(frozen=True)
class _Hangs:
    """The model of every candidate hang at the CAD: its modes as a function of the tensor's
    entries ``p``, the shared nuisances ``v`` and its pivot."""

    context: InertiaContext
    me_mass_kg: float
    p0: FloatArray  # the assembly's entries at the CAD
    v0: FloatArray  # the shared nuisances at their nominal values
    scale: float  # the tensor's trace: the entries' finite-difference step is 1e-6 of it

    def modes_hz(self, p: FloatArray, v: FloatArray, exit_mm: FloatArray) -> FloatArray:
        ctx = self.context
        geo = HangGeometry(
            exit_mm, v[_SENSOR], max(v[_LENGTH], 0.0), max(v[_HINGE], 0.0), *ctx.signs
        )
        return hang_modes(
            tensor(p), v[_MASS] + self.me_mass_kg, v[_COG], geo, with_shapes=False
        ).frequencies_hz

    def info(
        self, exit_mm: FloatArray, exit_cov: FloatArray, shared_cov: FloatArray
    ) -> _HangInfo | None:
        """One hang's usable body modes (those a :data:`PLAN_RECORD_S` record resolves), their
        derivatives and own covariance; None when it has none."""
        p0, v0 = self.p0, self.v0
        f0 = self.modes_hz(p0, v0, exit_mm)
        gaps = np.diff(f0)
        close = np.zeros(len(f0), dtype=bool)
        close[:-1] |= gaps < UNRESOLVED_BINS / PLAN_RECORD_S
        close[1:] |= gaps < UNRESOLVED_BINS / PLAN_RECORD_S
        keep = ~close
        keep[: len(f0) - 2] = False  # the body modes only (as the estimator uses them)
        if not keep.any():
            return None

        def derivative(h: float, dp: Any = 0.0, dv: Any = 0.0, de: Any = 0.0) -> FloatArray:
            """Central difference of the kept modes along a step of the entries (``dp``),
            the shared nuisances (``dv``) or the pivot (``de``) of size ``h``."""
            plus = self.modes_hz(p0 + dp, v0 + dv, exit_mm + de)
            minus = self.modes_hz(p0 - dp, v0 - dv, exit_mm - de)
            return (plus - minus)[keep] / (2 * h)

        jac = np.zeros((int(keep.sum()), 6))
        for j in range(6):
            jac[:, j] = derivative(1e-6 * self.scale, dp=1e-6 * self.scale * np.eye(6)[j])
        shared = np.zeros((int(keep.sum()), 9))
        sig = np.sqrt(np.diag(shared_cov))
        for i in range(6):  # the sensor's position (_SENSOR) moves no frequency, only shapes
            if sig[i] != 0:
                shared[:, i] = derivative(0.1 * sig[i], dv=0.1 * sig[i] * np.eye(9)[i])
        d_exit = np.zeros((int(keep.sum()), 3))
        for a in range(3):
            d_exit[:, a] = derivative(0.05, de=0.05 * np.eye(3)[a])
        local = (
            np.diag((f0[keep] * self.context.frequency_model_rel) ** 2)
            + d_exit @ exit_cov @ d_exit.T
        )
        return _HangInfo(jac, local, shared)


def _set_cov(
    infos: Sequence[_HangInfo | None],
    group: Sequence[int],
    shared_cov: FloatArray,
    removal_cov: FloatArray,
) -> FloatArray | None:
    """The object's entries' covariance from hangs ``group`` (the GLS of their frequencies,
    plus the ME's removal ``removal_cov``); None when they do not determine the tensor."""
    hs = [infos[i] for i in group]
    if any(h is None for h in hs):
        return None
    hh = [h for h in hs if h is not None]
    jac = np.vstack([h.jac for h in hh])
    if jac.shape[0] < 6:
        return None
    n = jac.shape[0]
    c = np.zeros((n, n))
    at = 0
    for h in hh:
        k = len(h.local_cov)
        c[at : at + k, at : at + k] = h.local_cov
        at += k
    m = np.vstack([h.shared for h in hh])
    c += m @ shared_cov @ m.T
    try:
        cov = np.linalg.inv(jac.T @ np.linalg.solve(c, jac))
    except np.linalg.LinAlgError:
        return None
    if not np.all(np.isfinite(cov)) or np.min(np.linalg.eigvalsh(cov)) < 0:
        return None
    return np.asarray(cov + removal_cov)


def _removal_cov(
    ctx: InertiaContext,
    p0: FloatArray,
    v0: FloatArray,
    mass_sigma_kg: float,
    cog_cov_mm2: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """The ME's removal, which does not depend on the set: the object's entries at the CAD and
    what the ME's CoGs and own inertia, the mass and the CoG add to their covariance."""
    nuis = nuisances(
        object_mass_kg=ctx.object_cad.mass_kg,
        object_mass_sigma_kg=mass_sigma_kg,
        cog_mm=v0[_COG],
        wire_length_mm=ctx.swing.wire_length_mm,
        wire_length_sigma_mm=0.0,
        top_hinge_mm=float(v0[_HINGE]),
        sensor_mm=ctx.sensor_mm,
        sensor_sigma_mm=0.0,
        exits_mm=np.zeros((0, 3)),
        geometry_cov_mm2=np.pad(np.asarray(cog_cov_mm2, dtype=float), (0, 1)),
        me_parts=ctx.me_parts,
        me_cog_sigma_mm=ctx.me_cog_sigma_mm,
        me_inertia_rel=ctx.swing.me_inertia_rel,
    )
    jc = direct_jacobian(lambda v: compensate(p0, nuis, v, ctx.me_parts)[0], nuis)
    return compensate(p0, nuis, nuis.values, ctx.me_parts)[0], jc @ nuis.cov @ jc.T


def plan_inertia(
    context: InertiaContext,
    candidates: Sequence[tuple[str, FloatArray]],
    *,
    cog_cov_mm2: FloatArray,
    mass_sigma_kg: float,
    weighed: bool,
    max_set: int = 8,
    start: Sequence[str] = (),
) -> InertiaPlan:
    """Screen sets of candidate hangs for the inertia tensor (module docstring).

    Parameters
    ----------
    context : InertiaContext
    candidates : sequence of (id, exit_mm)
        The usable suspension points.
    cog_cov_mm2 : ndarray, shape (3, 3)
        The assembly CoG's covariance the plumb lines will give (a planning figure).
    mass_sigma_kg : float
        1 σ of the object's mass (a weighing's, or the CAD's).
    weighed : bool
    max_set : int
    start : sequence of str
        Grow from these ids (the CoG's set, for a plan for both) instead of the best triple.
    """
    ctx = context
    truth = combine([ctx.object_cad, *ctx.me_parts])
    weight_n = truth.mass_kg * STANDARD_GRAVITY_M_S2
    hinge, hinge_sigma = ctx.top_hinge_mm(weight_n)
    shared_cov = _shared_cov(ctx, mass_sigma_kg, cog_cov_mm2, hinge_sigma)
    model = _Hangs(
        ctx,
        sum(x.mass_kg for x in ctx.me_parts),
        entries(truth.inertia_kg_mm2),
        np.concatenate(
            [
                [ctx.object_cad.mass_kg],
                truth.cog_mm,
                [ctx.swing.wire_length_mm, hinge],
                ctx.sensor_mm,
            ]
        ),
        float(np.trace(truth.inertia_kg_mm2)),
    )
    positions = np.array([c[1] for c in candidates], dtype=float).reshape(-1, 3)
    pivots, pivot_covs = ctx.pivots(positions, truth.cog_mm, weight_n)
    infos = [
        model.info(exit_mm, exit_cov, shared_cov)
        for exit_mm, exit_cov in zip(pivots, pivot_covs, strict=True)
    ]
    p_obj, removal = _removal_cov(ctx, model.p0, model.v0, mass_sigma_kg, cog_cov_mm2)
    closest = [np.inf]  # the smallest worst-moment σ of a set refused for exceeding the limit

    def screen(group: Sequence[int]) -> float:
        """A cheap figure for screening: the largest relative σ of the diagonal entries."""
        out = _set_cov(infos, group, shared_cov, removal)
        if out is None:
            return np.inf
        return float(np.max(np.sqrt(np.diag(out)[:3]) / p_obj[:3]))

    def evaluate(group: Sequence[int]) -> tuple[float, Any] | None:
        cov = _set_cov(infos, group, shared_cov, removal)
        if cov is None:
            return None
        pr = principal_with_sigma(p_obj, cov)
        rel = pr.moments_sigma_kg_mm2 / pr.moments_kg_mm2
        if not np.max(rel) <= MAX_MOMENT_SIGMA_REL:
            closest[0] = min(closest[0], float(np.max(rel)))
            return None
        return float(np.max(rel)), pr

    ids = [c[0] for c in candidates]
    best_sets = _grow(evaluate, screen, ids, max_set, start)
    if not best_sets:
        raise _nothing_determines(ctx, closest[0])
    best = min(s["worst_moment_sigma_rel"] for s in best_sets)
    recommended = next(s for s in best_sets if s["worst_moment_sigma_rel"] <= 1.1 * best)
    return InertiaPlan(tuple(best_sets), recommended, weighed)


def _grow(
    evaluate: Callable[[Sequence[int]], tuple[float, Any] | None],
    screen: Callable[[Sequence[int]], float],
    ids: Sequence[str],
    max_set: int,
    start: Sequence[str],
) -> list[dict[str, Any]]:
    """The best set of each size: the best triple (screened on the diagonal entries, the best
    :data:`SCREENED` judged on the principal moments), or ``start``, grown by one hang at a
    time."""
    n = len(ids)
    best_sets: list[dict[str, Any]] = []
    current: list[int] | None = None
    first = 3
    if start:
        current = [list(ids).index(i) for i in start]
        first = len(current) + 1
        r = evaluate(current)
        if r is not None:
            best_sets.append(_entry([ids[i] for i in current], *r))
    for size in range(first, min(max_set, n) + 1):
        pool: list[tuple[int, ...]]
        if size == 3 and not start:
            pool = list(combinations(range(n), 3))
            if len(pool) > MAX_TRIPLES:
                pool = pool[:: len(pool) // MAX_TRIPLES + 1]
            figures = np.array([screen(g) for g in pool])
            pool = [pool[i] for i in np.argsort(figures)[:SCREENED]]
        elif current is None:
            break
        else:
            pool = [tuple(sorted([*current, j])) for j in range(n) if j not in current]
        scored = [(r, g) for g in pool if (r := evaluate(g)) is not None]
        if not scored:
            continue
        (merit, pr), group = min(scored, key=lambda t: t[0][0])
        current = list(group)
        best_sets.append(_entry([ids[i] for i in group], merit, pr))
    return best_sets


def _nothing_determines(ctx: InertiaContext, closest: float) -> DegenerateGeometryError:
    """Why no set was planned: the best refused set's worst moment (``closest``, relative 1 σ;
    inf when no set determined the tensor at all) and, when the ME outweighs half the object,
    that its inertia is the remedy."""
    if np.isfinite(closest):
        heavy = sum(x.mass_kg for x in ctx.me_parts) / ctx.object_cad.mass_kg
        return DegenerateGeometryError(
            "no set of these candidates determines the inertia tensor usefully: the best "
            + (
                f"gives a principal moment only to ±{100 * closest:.0f} % at 1 σ"
                if closest < 10
                else "leaves a principal moment undetermined (1 σ above 1000 %)"
            )
            + f" (a plan needs ±{100 * MAX_MOMENT_SIGMA_REL:.0f} % or better)"
            + (
                f"; the measurement equipment weighs {heavy:.2f}× the object, and its "
                "inertia's uncertainty dominates: a lighter ME is the remedy"
                if heavy > 0.5
                else ""
            )
        )
    return DegenerateGeometryError(
        "no set of these candidates determines the inertia tensor (each hang gives two "
        "usable frequencies at most: three hangs whose plumb lines point in different "
        "directions are the least)"
    )


#: A set whose worst principal moment is known to worse than this (1 σ, relative) is not planned.
MAX_MOMENT_SIGMA_REL = 0.3


def _entry(points: list[str], merit: float, pr: Any) -> dict[str, Any]:
    return {
        "points": points,
        "worst_moment_sigma_rel": merit,
        "moments_sigma_rel": (pr.moments_sigma_kg_mm2 / pr.moments_kg_mm2).tolist(),
        "moments_kg_mm2": pr.moments_kg_mm2.tolist(),
        "axes_sigma_deg": pr.axes_sigma_deg.tolist(),
    }


def plan_inertia_for_setup(
    setup: Setup, cog_plan: Plan, *, weighed: bool = True, max_set: int = 8, both: bool = False
) -> InertiaPlan:
    """``cadcog plan --for inertia|both``: the set-up's usable candidates (from the CoG plan's
    checks), the CoG covariance of the CoG plan's recommended set (isotropic, from its 95 %
    error), a weighing of 1 g or the CAD's mass uncertainty."""
    from cadcog.dynamics.context import context_for_setup
    from cadcog.spacecraft.items import DEFAULT_WEIGHING_SIGMA_KG

    usable = {c.id for c in cog_plan.checks if c.usable}
    cands = [(c.id, np.asarray(c.position_mm, float)) for c in setup.candidates if c.id in usable]
    q95 = cog_plan.recommended["q95_mm"] if cog_plan.recommended is not None else 1.0
    cog_cov = (q95 / 2.8) ** 2 * np.eye(3)  # the 95 % radius of an isotropic 3-D normal ≈ 2.8 σ
    sigma = DEFAULT_WEIGHING_SIGMA_KG if weighed else setup.cad_prior().mass_sigma_kg
    start = cog_plan.recommended["points"] if both and cog_plan.recommended else ()
    return plan_inertia(
        context_for_setup(setup, np.zeros((6, 6))),
        cands,
        cog_cov_mm2=cog_cov,
        mass_sigma_kg=sigma,
        weighed=weighed,
        max_set=max_set,
        start=start,
    )
