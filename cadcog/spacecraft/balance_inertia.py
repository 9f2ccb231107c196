"""Inertia objectives for the least ballast: products of inertia within a limit (a
spin-balanced spacecraft), principal axes within an angle of the model's axes, each at its own
confidence.

With ballast ``m_i`` at ``p_i`` the spacecraft's tensor about its new CoG ``c'`` is, by the
parallel-axis theorem (tensor convention, ``J(r) = |r|² 1 − r rᵀ``),

    I' = I_G + M J(c − c') + Σ m_i J(p_i − c'),     c' = (M c + Σ m_i p_i) / (M + Σ m_i),

and its products ``P'_jk = −I'_jk`` (``+∫ x·y dm``). ``I_G``, ``M`` and ``c`` are uncertain
(their joint covariance: the CAD's items, or a test's mass and CoG with the CAD's tensor), and
``I'`` is carried to first order: ``∂I'/∂I_G`` is the entry itself, ``∂I'/∂M = J(c) − J(c')
− DJ(c')[c − c']`` and ``∂I'/∂c_k = M (DJ(c) − DJ(c'))[e_k]``, with ``DJ(r)[δ] = 2 (r·δ) 1 −
δ rᵀ − r δᵀ`` (the ballast exact; ``tests/spacecraft/test_balance_inertia.py`` checks them
against finite differences).

The objectives, each a set of one-sided conditions met with probability at least the
objectives' confidence ``P_I`` by a union bound (``z = Φ̄⁻¹((1 − P_I)/K)`` over all ``K``):

- ``max_product_kg_mm2 = L``: ``±P'_jk + z σ(P'_jk) ≤ L`` for the three products (six);
- ``max_axis_angle_deg = θ``: each pair's principal rotation ``½ atan(2 |P'_jk| /
  |I'_jj − I'_kk|)`` at most ``θ`` (first order in the products: the angle by which the
  principal axes of that pair turn about the third axis): ``±2 P'_jk − tan(2θ) |I'_jj −
  I'_kk| + z σ ≤ 0`` (six).

They are quadratic in the masses (the products about a CoG that moves with them), so the
programme is not convex: :func:`least_ballast_with_inertia` starts from the CoG's least
ballast (a proven lower bound for this problem too: it has fewer conditions) and, when that
misses an objective, runs a local search (SLSQP, the CoG's faces and the objectives as
smooth conditions) from several deterministic starts, keeping the lightest answer that meets
every condition when evaluated again directly. The answer is called the least only when it
is within :data:`cadcog.spacecraft.balance.PROVEN_RTOL` of the CoG's bound; otherwise it is the
best found, with that bound.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import CadcogError
from cadcog.spacecraft.balance import PROVEN_RTOL, least_ballast, with_ballast
from cadcog.spacecraft.balance_result import BalanceResult
from cadcog.spacecraft.ballast_programme import FACES6, norm_isf
from cadcog.spacecraft.ballast_spec import BallastSpec, UncertainMass

FloatArray = npt.NDArray[np.float64]

#: The tensor entries' order (the tensor's own entries: ``xy = −∫ x·y dm``).
ENTRY_ORDER = ("xx", "yy", "zz", "xy", "xz", "yz")
#: The pairs of axes whose product and principal rotation are bounded, with their entry index.
PAIRS = ((0, 1, 3), (0, 2, 4), (1, 2, 5))

#: An angle objective is a first-order rotation of a pair of principal axes: below 45°.
MAX_AXIS_ANGLE_DEG = 45.0

#: Local searches: deterministic starts (the CoG's answer, scaled copies, seeded draws) and
#: each search's iteration cap.
SEARCH_STARTS = 12
SEARCH_MAX_ITERATIONS = 300
#: A location given less than this fraction of the answer's scale gets none (SLSQP leaves
#: dust of 1e-9 of it); the answer is checked again without it.
DUST_RTOL = 1e-6
#: A condition counts as met, evaluated directly, within this fraction of its own scale.
CONDITION_RTOL = 1e-7


@dataclass(frozen=True)
class InertiaPrior:
    """The spacecraft's tensor about its own CoG and its uncertainty.

    Attributes
    ----------
    inertia_kg_mm2 : ndarray, shape (3, 3)
        About the CoG, model axes, tensor convention.
    entries_cov : ndarray, shape (6, 6)
        Covariance of its entries (:data:`ENTRY_ORDER`).
    cross_cov : ndarray, shape (6, 4)
        Covariance of the entries with ``(M, cx, cy, cz)`` (zero for a test's mass and CoG,
        measured apart from the CAD's tensor).
    source : str
    """

    inertia_kg_mm2: FloatArray
    entries_cov: FloatArray
    cross_cov: FloatArray
    source: str

    @classmethod
    def from_joint(cls, mean: FloatArray, cov: FloatArray, source: str = "CAD") -> InertiaPrior:
        """From :func:`cadcog.spacecraft.explanations.cad_joint_prior`'s mean and covariance."""
        e = np.asarray(mean, dtype=float)[4:]
        return cls(_tensor(e), np.asarray(cov[4:, 4:]), np.asarray(cov[4:, :4]), source)

    def joint_cov(self, state: UncertainMass) -> FloatArray:
        """The covariance of ``(M, c, entries)`` with ``state``'s mass and CoG."""
        out = np.zeros((10, 10))
        out[0, 0] = state.mass_sigma_kg**2
        out[1:4, 0] = out[0, 1:4] = state.cog_mass_cov_mm_kg
        out[1:4, 1:4] = state.cog_cov_mm2
        out[4:, :4] = self.cross_cov
        out[:4, 4:] = self.cross_cov.T
        out[4:, 4:] = self.entries_cov
        return out


@dataclass(frozen=True)
class InertiaObjectives:
    """What the ballast must do to the tensor too: the largest product of inertia (kg·mm²)
    and the largest principal rotation (degrees), either or both, at ``confidence``."""

    max_product_kg_mm2: float | None = None
    max_axis_angle_deg: float | None = None
    confidence: float = 0.95

    def __post_init__(self) -> None:
        if self.max_product_kg_mm2 is None and self.max_axis_angle_deg is None:
            raise CadcogError("inertia objectives: give a product limit or an axis angle")
        if self.max_product_kg_mm2 is not None and not self.max_product_kg_mm2 > 0:
            raise CadcogError(
                f"--max-product-kg-mm2 {self.max_product_kg_mm2!r}: expected a positive limit"
            )
        a = self.max_axis_angle_deg
        if a is not None and not 0.0 < a < MAX_AXIS_ANGLE_DEG:
            raise CadcogError(
                f"--max-axis-angle-deg {a!r}: expected an angle above 0 and below "
                f"{MAX_AXIS_ANGLE_DEG:g}° (a first-order rotation of a pair of principal axes)"
            )
        if not 0.0 < self.confidence < 1.0:
            raise CadcogError(
                f"--inertia-confidence {self.confidence!r}: expected a probability in (0, 1)"
            )

    @property
    def count(self) -> int:
        """One-sided conditions: six per objective given."""
        return 6 * ((self.max_product_kg_mm2 is not None) + (self.max_axis_angle_deg is not None))

    @property
    def quantile(self) -> float:
        """``z`` of each condition (the union bound over :attr:`count`)."""
        return float(norm_isf((1.0 - self.confidence) / self.count))


def _tensor(e: npt.ArrayLike) -> FloatArray:
    xx, yy, zz, xy, xz, yz = np.asarray(e, dtype=float)
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def _entries(t: FloatArray) -> FloatArray:
    return np.array([t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[0, 2], t[1, 2]])


def _j(r: FloatArray) -> FloatArray:
    """A unit mass's tensor at ``r``: ``|r|² 1 − r rᵀ``."""
    return np.asarray(float(r @ r) * np.eye(3) - np.outer(r, r))


def _dj(r: FloatArray, d: FloatArray) -> FloatArray:
    """The derivative of :func:`_j` at ``r`` along ``d``."""
    return np.asarray(2.0 * float(r @ d) * np.eye(3) - np.outer(d, r) - np.outer(r, d))


def inertia_with_ballast(
    state: UncertainMass,
    prior: InertiaPrior,
    positions_mm: FloatArray,
    masses_kg: npt.ArrayLike,
) -> tuple[FloatArray, FloatArray]:
    """The tensor about the new CoG with ballast, and the covariance of its entries.

    Returns
    -------
    inertia_kg_mm2 : ndarray, shape (3, 3)
    cov : ndarray, shape (6, 6)
        Of its entries (:data:`ENTRY_ORDER`), to first order (module docstring).
    """
    inertia, grad = tensor_and_gradient(
        state.mass_kg, state.cog_mm, prior.inertia_kg_mm2, positions_mm, masses_kg
    )
    cov = grad @ prior.joint_cov(state) @ grad.T
    return inertia, np.asarray((cov + cov.T) / 2.0)


def tensor_and_gradient(
    mass_kg: float,
    cog_mm: npt.ArrayLike,
    inertia_kg_mm2: npt.ArrayLike,
    positions_mm: npt.ArrayLike,
    masses_kg: npt.ArrayLike,
) -> tuple[FloatArray, FloatArray]:
    """The tensor about the CoG with ballast, and its entries' gradient with respect to
    ``(M, cx, cy, cz, entries of I_G)``, shape (6, 10) (module docstring).

    Examples
    --------
    One unit mass 10 mm out in x and y from a point mass of 1 kg at the origin: about their
    CoG at (5, 5, 0), ``P_xy = M m / (M + m) · 100 = 50`` kg·mm² (the tensor's entry −50).

    >>> t, g = tensor_and_gradient(1.0, [0, 0, 0], np.zeros((3, 3)), [[10.0, 10.0, 0]], [1.0])
    >>> float(t[0, 1]), g.shape
    (-50.0, (6, 10))
    """
    m = np.asarray(masses_kg, dtype=float)
    p = np.asarray(positions_mm, dtype=float).reshape(-1, 3)
    c = np.asarray(cog_mm, dtype=float)
    total = mass_kg + float(m.sum())
    new = (mass_kg * c + m @ p) / total
    inertia = np.asarray(inertia_kg_mm2, dtype=float) + mass_kg * _j(c - new)
    for mi, pi in zip(m, p, strict=True):
        if mi != 0.0:
            inertia = inertia + mi * _j(pi - new)
    grad = np.zeros((6, 10))
    grad[:, 0] = _entries(_j(c) - _j(new) - _dj(new, c - new))
    for k in range(3):
        e = np.zeros(3)
        e[k] = 1.0
        grad[:, 1 + k] = mass_kg * _entries(_dj(c, e) - _dj(new, e))
    grad[:, 4:] = np.eye(6)
    return inertia, grad


def conditions(
    objectives: InertiaObjectives,
    state: UncertainMass,
    prior: InertiaPrior,
    positions_mm: FloatArray,
    masses_kg: npt.ArrayLike,
) -> tuple[FloatArray, FloatArray]:
    """Each one-sided condition's value (met when ≤ 0) and its scale (the limit it is
    measured against), for these masses (module docstring)."""
    inertia, cov = inertia_with_ballast(state, prior, positions_mm, masses_kg)
    z = objectives.quantile
    values: list[float] = []
    scales: list[float] = []
    for j, k, e in PAIRS:
        g = np.zeros(6)
        g[e] = -1.0  # P = −I_jk
        product = -inertia[j, k]
        if objectives.max_product_kg_mm2 is not None:
            sd = float(np.sqrt(max(float(g @ cov @ g), 0.0)))
            limit = objectives.max_product_kg_mm2
            values += [product + z * sd - limit, -product + z * sd - limit]
            scales += [limit, limit]
        if objectives.max_axis_angle_deg is not None:
            t = float(np.tan(np.deg2rad(2.0 * objectives.max_axis_angle_deg)))
            gap = inertia[j, j] - inertia[k, k]
            s = 1.0 if gap >= 0 else -1.0
            for sign in (1.0, -1.0):
                h = np.zeros(6)
                h[e] = -2.0 * sign
                h[j] -= t * s
                h[k] += t * s
                sd = float(np.sqrt(max(float(h @ cov @ h), 0.0)))
                values.append(2.0 * sign * product - t * abs(gap) + z * sd)
                scales.append(max(t * abs(gap), 2.0 * abs(product), 1e-12))
    return np.array(values), np.array(scales)


def figures(
    objectives: InertiaObjectives,
    state: UncertainMass,
    prior: InertiaPrior,
    positions_mm: FloatArray,
    masses_kg: npt.ArrayLike,
) -> dict[str, Any]:
    """The tensor's figures with these masses, for the result: the tensor and its σ, the
    products (``+∫ x·y dm``) and σ, each pair's principal rotation, each principal axis's
    angle from its nearest model axis, and whether every condition is met."""
    inertia, cov = inertia_with_ballast(state, prior, positions_mm, masses_kg)
    values, scales = conditions(objectives, state, prior, positions_mm, masses_kg)
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    products = {f"P{'xyz'[j]}{'xyz'[k]}": -float(inertia[j, k]) for j, k, _ in PAIRS}
    products_sd = {f"P{'xyz'[j]}{'xyz'[k]}": float(sd[e]) for j, k, e in PAIRS}
    rotation = {
        f"{'xyz'[j]}{'xyz'[k]}": float(
            np.rad2deg(
                0.5 * np.arctan2(2.0 * abs(inertia[j, k]), abs(inertia[j, j] - inertia[k, k]))
            )
        )
        for j, k, _ in PAIRS
    }
    _, axes = np.linalg.eigh(inertia)
    off = [
        float(np.rad2deg(np.arccos(min(1.0, float(np.max(np.abs(axes[:, i]))))))) for i in range(3)
    ]
    return {
        "inertia_kg_mm2": inertia.tolist(),
        "inertia_sigma_kg_mm2": _tensor(sd).tolist(),
        "products_kg_mm2": products,
        "products_sigma_kg_mm2": products_sd,
        "pair_rotation_deg": rotation,
        "principal_axes_off_model_axes_deg": off,
        "met": bool(np.all(values <= CONDITION_RTOL * scales)),
    }


def least_ballast_with_inertia(
    state: UncertainMass,
    prior: InertiaPrior,
    spec: BallastSpec,
    geometric_center_mm: npt.ArrayLike,
    limits_mm: npt.ArrayLike,
    confidence: float,
    objectives: InertiaObjectives,
) -> BalanceResult:
    """The least ballast that meets the CoG envelope (as :func:`least_ballast`) and the
    inertia objectives (module docstring); the result's ``inertia`` holds the tensor's
    figures before and after, the objectives and how the answer was found.

    Raises
    ------
    CadcogError
        When the spacecraft's tensor has no prior (none given).
    """
    base = least_ballast(state, spec, geometric_center_mm, limits_mm, confidence)
    positions = np.array([p.position_mm for p in spec.points], dtype=float).reshape(-1, 3)
    zero = np.zeros(len(spec.points))
    info: dict[str, Any] = {
        "objectives": {
            "max_product_kg_mm2": objectives.max_product_kg_mm2,
            "max_axis_angle_deg": objectives.max_axis_angle_deg,
            "confidence": objectives.confidence,
            "conditions": objectives.count,
            "quantile": objectives.quantile,
        },
        "tensor_source": prior.source,
        "before": figures(objectives, state, prior, positions, zero),
    }
    if not base.feasible:
        info |= {"after": None, "search": "none: the CoG envelope alone cannot be met"}
        return replace(base, inertia=info)
    lower = base.bound_kg if base.bound_kg is not None else base.total_ballast_kg
    at_cog = figures(objectives, state, prior, positions, base.masses_kg)
    info["with_cog_ballast"] = at_cog
    if at_cog["met"]:
        info |= {"after": at_cog, "search": "the CoG's least ballast meets them"}
        return replace(base, inertia=info)
    if spec.sizes_kg is not None:
        info |= {"after": None, "search": "none: pieces (sizes_kg) are checked, not searched"}
        note = (
            "the least pieces for the CoG miss the inertia objectives, and with pieces they are "
            "checked, not searched: remove sizes_kg from the ballast file for a continuous "
            "search, then choose pieces near it"
        )
        return _infeasible(base, info, note)
    found = _search(state, prior, spec, positions, base, objectives)
    if found is None:
        info |= {"after": None, "search": f"local searches from {SEARCH_STARTS} starts"}
        note = (
            f"no ballast found that meets the inertia objectives as well as the CoG envelope "
            f"(local searches from {SEARCH_STARTS} starts; the problem is not convex): the "
            "locations cannot move the products enough, or a limit is too tight"
        )
        return _infeasible(base, info, note, *_too_uncertain(objectives, info["before"]))
    return _with_masses(base, state, prior, spec, positions, found, lower, objectives, info)


def _too_uncertain(objectives: InertiaObjectives, before: dict[str, Any]) -> list[str]:
    """Notes for the products whose own uncertainty exceeds the limit (ballast, exact, barely
    changes it: measure the tensor, or state the masses more tightly)."""
    limit = objectives.max_product_kg_mm2
    if limit is None:
        return []
    z = objectives.quantile
    return [
        f"{name}'s own uncertainty (1σ {sd:.4g} kg·mm², {z:.3g} σ = {z * sd:.4g}) exceeds the "
        f"limit {limit:g} kg·mm²: ballast cannot meet it; measure the tensor (cadcog inertia) "
        "or state the masses more tightly"
        for name, sd in before["products_sigma_kg_mm2"].items()
        if z * sd >= limit
    ]


def _face_values(
    state: UncertainMass,
    positions: FloatArray,
    masses: FloatArray,
    centre: FloatArray,
    limits: FloatArray,
    z: FloatArray,
) -> FloatArray:
    """The CoG's six faces at these masses, each relative to its half-width (met when ≤ 0):
    ``(±(c' − o) + z σ' − L) / L``."""
    _, _, cog, cov = with_ballast(state, positions, masses)
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    return np.array(
        [
            (sign * (cog[k] - centre[k]) + z[f] * sd[k] - limits[k]) / limits[k]
            for f, (k, sign) in enumerate(FACES6)
        ]
    )


def _search(
    state: UncertainMass,
    prior: InertiaPrior,
    spec: BallastSpec,
    positions: FloatArray,
    base: BalanceResult,
    objectives: InertiaObjectives,
) -> FloatArray | None:
    """The lightest ballast the local searches find meeting every condition, or None."""
    from scipy.optimize import minimize

    n = len(spec.points)
    centre, limits, z = base.geometric_center_mm, base.limits_mm, base.face_quantiles
    cap = spec.max_total_mass_kg
    upper = np.array(
        [
            p.max_mass_kg if p.max_mass_kg is not None else (cap or 10.0 * state.mass_kg)
            for p in spec.points
        ]
    )

    def inertia_part(x: FloatArray) -> FloatArray:
        v, s = conditions(objectives, state, prior, positions, x)
        return -v / s

    def faces_part(x: FloatArray) -> FloatArray:
        return -_face_values(state, positions, x, centre, limits, z)

    cons = [{"type": "ineq", "fun": inertia_part}, {"type": "ineq", "fun": faces_part}]
    if cap is not None:
        cons.append({"type": "ineq", "fun": lambda x: (cap - float(np.sum(x))) / cap})
    scale = max(base.total_ballast_kg, 1e-3 * state.mass_kg)
    rng = np.random.default_rng(0)
    starts = [base.masses_kg, 2.0 * base.masses_kg, np.full(n, scale / n)]
    while len(starts) < SEARCH_STARTS:
        starts.append(rng.uniform(0.0, 2.0 * scale, n))
    best: FloatArray | None = None
    for x0 in starts:
        sol = minimize(
            lambda x: float(np.sum(x)) / scale,
            np.clip(x0, 0.0, upper),
            jac=lambda x: np.ones_like(x) / scale,
            method="SLSQP",
            bounds=list(zip(np.zeros(n), upper, strict=True)),
            constraints=cons,
            options={"maxiter": SEARCH_MAX_ITERATIONS, "ftol": 1e-12},
        )
        x = np.clip(np.asarray(sol.x, dtype=float), 0.0, upper)
        x[x < DUST_RTOL * scale] = 0.0  # a solver's dust, not a ballast (checked again below)
        if not _meets(state, prior, positions, x, centre, limits, z, objectives, cap):
            continue
        if best is None or x.sum() < best.sum():
            best = x
    return best


def _meets(
    state: UncertainMass,
    prior: InertiaPrior,
    positions: FloatArray,
    x: FloatArray,
    centre: FloatArray,
    limits: FloatArray,
    z: FloatArray,
    objectives: InertiaObjectives,
    cap: float | None,
) -> bool:
    """Every condition met, evaluated directly (not the solver's word)."""
    v, s = conditions(objectives, state, prior, positions, x)
    faces = _face_values(state, positions, x, centre, limits, z)
    ok = bool(np.all(v <= CONDITION_RTOL * s)) and bool(np.all(faces <= CONDITION_RTOL))
    return ok and (cap is None or float(x.sum()) <= cap * (1.0 + CONDITION_RTOL))


def _infeasible(base: BalanceResult, info: dict[str, Any], *notes: str) -> BalanceResult:
    """No ballast meets both: the CoG's answer is not given as one."""
    zero = np.zeros_like(base.masses_kg)
    return replace(
        base,
        feasible=False,
        optimal=False,
        masses_kg=zero,
        counts=None,
        inertia=info,
        notes=(*base.notes, *notes),
        mass_kg=base.state.mass_kg,
        mass_sigma_kg=base.state.mass_sigma_kg,
        cog_mm=np.asarray(base.state.cog_mm),
        cog_cov_mm2=np.asarray(base.state.cog_cov_mm2),
        offset_mm=np.asarray(base.before["offset_mm"]),
        margin_mm=np.asarray(base.before["margin_mm"]),
        probability_inside=float(base.before["probability_inside"]),
    )


def _with_masses(
    base: BalanceResult,
    state: UncertainMass,
    prior: InertiaPrior,
    spec: BallastSpec,
    positions: FloatArray,
    masses: FloatArray,
    lower: float,
    objectives: InertiaObjectives,
    info: dict[str, Any],
) -> BalanceResult:
    """The result for the masses the search found: the CoG's figures at them (the faces'
    shares as the CoG's programme chose them), the CoG's bound, and optimal only at it."""
    from cadcog.spacecraft.balance import margins, probability_inside

    mass, sigma_m, cog, cov = with_ballast(state, positions, masses)
    centre, limits = base.geometric_center_mm, base.limits_mm
    offset = cog - centre
    margin, _ = margins(
        offset, np.sqrt(np.maximum(np.diag(cov), 0.0)), limits, 1.0 - base.confidence
    )
    total = float(masses.sum())
    optimal = total <= lower * (1.0 + PROVEN_RTOL) + 1e-15
    info |= {
        "after": figures(objectives, state, prior, positions, masses),
        "search": f"local searches from {SEARCH_STARTS} starts (SLSQP)",
        "cog_only_least_kg": base.total_ballast_kg,
    }
    note = (
        f"the inertia objectives need {total:.4g} kg where the CoG alone needs "
        f"{base.total_ballast_kg:.4g} kg; "
        + (
            "the answer is the least (it meets the CoG's proven bound)"
            if optimal
            else f"the programme is not convex: this is the lightest found, at least {lower:.4g} kg"
        )
    )
    return replace(
        base,
        masses_kg=masses,
        counts=None,
        optimal=bool(optimal),
        bound_kg=lower,
        mass_kg=mass,
        mass_sigma_kg=sigma_m,
        cog_mm=cog,
        cog_cov_mm2=cov,
        offset_mm=offset,
        margin_mm=margin,
        probability_inside=probability_inside(cog, cov, centre - limits, centre + limits),
        inertia=info,
        notes=(*base.notes, note),
    )
