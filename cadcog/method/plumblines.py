"""The double-suspension estimator (docs/method.md §2-3).

Each suspension gives a plumb line in the body frame: through the suspension point ``p``, along
the upward vertical ``u``; the CoG lies on it, below ``p``. Two lines give the CoG as the
midpoint of their shortest segment (eq. 8); N ≥ 2 lines give it as the weighted least-squares
point of all lines, with a covariance. The measurement equipment is then compensated (eq. 10)
with its error propagated (eq. 16).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from itertools import combinations

import numpy as np
import numpy.typing as npt

from cadcog.core import tolerances
from cadcog.core.errors import DegenerateGeometryError, IllConditionedError
from cadcog.core.fittest import FitTest, chi2_sf
from cadcog.core.results import JsonResult
from cadcog.method import gls, sym3
from cadcog.rig.geometry import angle_between_lines_deg, ideal_reading

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class PlumbLine:
    """A suspension's plumb line.

    Attributes
    ----------
    id : str
        Suspension point id.
    point_mm : ndarray, shape (3,)
        Suspension point (where the wire leaves the object), body frame, mm.
    vertical : ndarray, shape (3,)
        Upward unit vertical, body components.
    sigma_mm : float
        Standard deviation of the line's lateral position near the CoG, per lateral axis (mm);
        sets its weight in :func:`joint_estimate`.
    """

    id: str
    point_mm: FloatArray
    vertical: FloatArray
    sigma_mm: float = 1.0

    def __post_init__(self) -> None:
        p = np.array(self.point_mm, dtype=float)
        u = np.array(self.vertical, dtype=float)
        if p.shape != (3,) or u.shape != (3,):
            raise ValueError("point_mm and vertical must have shape (3,)")
        norm = np.linalg.norm(u)
        if not norm > 0:
            raise ValueError(f"suspension {self.id}: zero vertical")
        if not self.sigma_mm > 0:
            raise ValueError(f"suspension {self.id}: sigma_mm must be positive")
        object.__setattr__(self, "point_mm", p)
        object.__setattr__(self, "vertical", u / norm)

    def distance_mm(self, x_mm: npt.ArrayLike) -> float:
        """Distance of a point from the line."""
        d = np.asarray(x_mm, dtype=float) - self.point_mm
        return float(np.linalg.norm(d - np.dot(d, self.vertical) * self.vertical))


@dataclass(frozen=True)
class PairEstimate(JsonResult):
    """Closest approach of two plumb lines (eq. 8).

    Attributes
    ----------
    a, b : str
        Ids of the two suspensions.
    foot_a_mm, foot_b_mm : ndarray, shape (3,)
        Feet of the shortest segment on each line.
    midpoint_mm : ndarray, shape (3,)
        The estimate: midpoint of the shortest segment.
    gap_mm : float
        Length of the shortest segment (0 if the lines meet).
    angle_deg : float
        Acute angle between the lines.
    """

    a: str
    b: str
    foot_a_mm: FloatArray
    foot_b_mm: FloatArray
    midpoint_mm: FloatArray
    gap_mm: float
    angle_deg: float

    def to_dict(self) -> dict[str, object]:
        return {
            "a": self.a,
            "b": self.b,
            "midpoint_mm": self.midpoint_mm.tolist(),
            "gap_mm": self.gap_mm,
            "angle_deg": self.angle_deg,
        }


def pair_estimate(
    line_a: PlumbLine,
    line_b: PlumbLine,
    min_angle_deg: float = tolerances.MIN_PAIR_ANGLE_DEG,
) -> PairEstimate:
    """Midpoint of the shortest segment between two plumb lines (eqs. 6-8).

    With ``n = u_a × u_b`` and ``d = p_b − p_a``: ``t_a = ((d × u_b)·n)/|n|²``,
    ``t_b = ((d × u_a)·n)/|n|²``, feet ``p_a + t_a u_a`` and ``p_b + t_b u_b``.

    Raises
    ------
    IllConditionedError
        If the lines meet at less than ``min_angle_deg`` (parallel or nearly so).

    Examples
    --------
    >>> a = PlumbLine("A", [0, 0, 10], [0, 0, 1])
    >>> b = PlumbLine("B", [10, 0, 10], [1, 0, 1])
    >>> e = pair_estimate(a, b)
    >>> e.midpoint_mm.tolist(), round(e.gap_mm, 12), round(e.angle_deg, 9)
    ([0.0, 0.0, 0.0], 0.0, 45.0)
    """
    angle = angle_between_lines_deg(line_a.vertical, line_b.vertical)
    if angle < min_angle_deg:
        raise IllConditionedError(
            f"suspensions {line_a.id} and {line_b.id}: their plumb lines meet at {angle:.3g}°, "
            f"below {min_angle_deg:g}°; the points and the CoG are nearly collinear, so the "
            "intersection is ill-conditioned"
        )
    ua, ub = line_a.vertical, line_b.vertical
    n = np.cross(ua, ub)
    n2 = float(np.dot(n, n))
    if n2 == 0.0:
        raise IllConditionedError(
            f"suspensions {line_a.id} and {line_b.id}: their plumb lines are parallel, "
            "ill-conditioned: they have no closest point"
        )
    d = line_b.point_mm - line_a.point_mm
    ta = float(np.dot(np.cross(d, ub), n)) / n2
    tb = float(np.dot(np.cross(d, ua), n)) / n2
    fa = line_a.point_mm + ta * ua
    fb = line_b.point_mm + tb * ub
    return PairEstimate(
        line_a.id, line_b.id, fa, fb, 0.5 * (fa + fb), float(np.linalg.norm(fb - fa)), angle
    )


@dataclass(frozen=True)
class LineResidual:
    """How well one suspension's line agrees with the others.

    Attributes
    ----------
    id : str
    distance_mm : float
        Distance of the line (through its virtual suspension point) from the joint estimate.
    normalized : float
        Square root of the leave-one-out χ² statistic (in "sigmas").
    p_value : float
        Tail probability of that statistic.
    inconsistent : bool
        ``p_value`` below the outlier probability.
    """

    id: str
    distance_mm: float
    normalized: float
    p_value: float
    inconsistent: bool


@dataclass(frozen=True)
class WireScale:
    """The wire offset scale λ the estimate used or found.

    Attributes
    ----------
    scale_mm : float
        λ (the paper's model: the mean offset along each bolt axis; the elastica: the scale of
        Δ(θ) = λ/cos(θ/2)).
    sigma_mm : float
        Its standard deviation (0 for a known scale).
    estimated : bool
        True when the lines estimated it (self-calibration).
    prior_mm : float
        What the error model expects.
    """

    scale_mm: float
    sigma_mm: float
    estimated: bool
    prior_mm: float


@dataclass(frozen=True)
class JointEstimate:
    """Generalised least-squares point of N ≥ 2 plumb lines.

    Attributes
    ----------
    cog_mm : ndarray, shape (3,)
    cov_mm2 : ndarray, shape (3, 3)
        Covariance from the lines' lateral covariances (and the wire scale's, if uncertain).
    residuals : tuple of LineResidual
    pairs : tuple of PairEstimate
        Every well-conditioned pair's closest approach (diagnostics).
    skipped_pairs : tuple of (str, str, float)
        Pairs below the angle threshold: ids and angle (degrees).
    chi2, dof : float, int
        ``Σ rᵢᵀ Wᵢ rᵢ`` at the estimate and its degrees of freedom (2N − 3, one fewer when λ is
        estimated): the whole campaign's consistency.
    wire : WireScale, optional
    point_gain : ndarray, shape (4, N, 3), optional
        ``∂(G, λ)/∂pᵢ``: how the CoG (rows 0-2) and λ (row 3; 0 when λ is known) follow each
        line's assumed suspension point (:func:`cadcog.method.gls.point_gain`); with
        :attr:`cog_scale_cov_mm2`, what the CoG's error shares with the pivots' (the swing's
        moment arms, :meth:`cadcog.dynamics.context.InertiaContext.hang_terms`).
    cog_scale_cov_mm2 : ndarray, shape (3,), optional
        Covariance of the CoG with λ (0 when λ is known).
    point_cov_mm2 : ndarray, shape (N, 3, 3), optional
        Each line's suspension-point covariance as the fit took it (the play, or an override):
        what :attr:`point_gain` carries into the CoG.
    """

    cog_mm: FloatArray
    cov_mm2: FloatArray
    residuals: tuple[LineResidual, ...]
    pairs: tuple[PairEstimate, ...]
    skipped_pairs: tuple[tuple[str, str, float], ...]
    chi2: float = 0.0
    dof: int = 0
    wire: WireScale | None = None
    point_gain: FloatArray | None = None
    cog_scale_cov_mm2: FloatArray | None = None
    point_cov_mm2: FloatArray | None = None

    @property
    def chi2_p_value(self) -> float:
        return FitTest(self.chi2, self.dof).p


def least_squares_point(
    points_mm: npt.ArrayLike, verticals: npt.ArrayLike, weights: npt.ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Point minimising ``Σ w_i · dist(x, line_i)²`` and the normal matrix ``Σ w_i P_i``.

    ``x = (Σ w_i P_i)⁻¹ Σ w_i P_i p_i`` with ``P_i = I − u_i u_iᵀ`` (docs/method.md §2).

    Parameters
    ----------
    points_mm : array_like, shape (n, 3)
    verticals : array_like, shape (n, 3)
        Unit directions.
    weights : array_like, shape (n,)

    Raises
    ------
    DegenerateGeometryError
        If all lines are parallel (singular normal matrix).
    """
    p = np.asarray(points_mm, dtype=float)
    u = np.asarray(verticals, dtype=float)
    w = np.asarray(weights, dtype=float)
    proj = np.eye(3)[None, :, :] - u[:, :, None] * u[:, None, :]
    a = np.einsum("n,nij->ij", w, proj)
    b = np.einsum("n,nij,nj->i", w, proj, p)
    _check_normal_matrix(a)
    return np.linalg.solve(a, b), a


def _check_normal_matrix(a: FloatArray) -> None:
    eig = np.linalg.eigvalsh(a)
    if eig[0] <= 1e-12 * eig[-1]:
        raise DegenerateGeometryError("the plumb lines are all parallel: no common point")


def pair_diagnostics(
    lines: Sequence[PlumbLine], min_angle_deg: float = tolerances.MIN_PAIR_ANGLE_DEG
) -> tuple[list[PairEstimate], list[tuple[str, str, float]]]:
    """Every pair's closest approach, and the pairs below ``min_angle_deg``.

    Raises
    ------
    ValueError
        With fewer than two lines or duplicate ids.
    IllConditionedError
        If every pair of lines is below ``min_angle_deg``.
    """
    if len(lines) < 2:
        raise ValueError(f"need at least two suspensions, got {len(lines)}")
    ids = [ln.id for ln in lines]
    if len(set(ids)) != len(ids):
        raise ValueError(f"duplicate suspension ids in {ids}")
    pairs, skipped = [], []
    for a, b in combinations(lines, 2):
        try:
            pairs.append(pair_estimate(a, b, min_angle_deg))
        except IllConditionedError:
            skipped.append((a.id, b.id, angle_between_lines_deg(a.vertical, b.vertical)))
    if not pairs:
        worst = max(s[2] for s in skipped)
        if worst >= tolerances.MIN_PAIR_ANGLE_DEG:  # the hangs are fine: the threshold is not
            raise IllConditionedError(
                f"every pair of plumb lines meets at less than the --min-angle-deg of "
                f"{min_angle_deg:g}° (largest {worst:.3g}°): lower it (default "
                f"{tolerances.MIN_PAIR_ANGLE_DEG:g}°)"
            )
        raise IllConditionedError(
            f"every pair of plumb lines meets at less than {min_angle_deg:g}° (largest "
            f"{worst:.3g}°): the suspension points and the CoG are nearly collinear; "
            "suspend from points that spread around the CoG"
        )
    return pairs, skipped


def joint_estimate(
    lines: Sequence[PlumbLine],
    min_angle_deg: float = tolerances.MIN_PAIR_ANGLE_DEG,
    outlier_probability: float = tolerances.OUTLIER_PROBABILITY,
) -> JointEstimate:
    """CoG from N ≥ 2 plumb lines with isotropic lateral errors ``sigma_mm``.

    Weights are ``Pᵢ/σᵢ²``. With two lines of equal sigma the result is eq. 8's midpoint. The
    covariance is ``(Σ Pᵢ/σᵢ²)⁻¹``. Consistency is tested as in :func:`line_consistency`.
    :func:`cadcog.method.estimate.estimate_cog` uses the full generalised least squares instead.

    Raises
    ------
    ValueError
        With fewer than two lines or duplicate ids.
    IllConditionedError
        If every pair of lines is below ``min_angle_deg``.
    """
    pairs, skipped = pair_diagnostics(lines, min_angle_deg)
    p = np.array([ln.point_mm for ln in lines]).T[:, :, None]
    u = np.array([ln.vertical for ln in lines]).T[:, :, None]
    var = np.array([ln.sigma_mm**2 for ln in lines])[:, None]
    proj = np.stack(sym3.projector(u))
    lateral = proj * var
    weights = proj / var
    _check_normal_matrix(sym3.sym_to_full(weights.sum(axis=1))[0])
    zero = np.zeros_like(p)
    shape = np.ones(var.shape)
    x, cov, *_ = gls.solve_lines(p, u, zero, shape, weights, gls.WireTerm())
    residuals, chi2, dof = line_consistency(
        [ln.id for ln in lines], p, u, zero, shape, weights, lateral, gls.WireTerm(), x[:, 0],
        outlier_probability,
    )  # fmt: skip
    full = sym3.sym_to_full(cov[:, 0])
    return JointEstimate(x[:, 0], full, tuple(residuals), tuple(pairs), tuple(skipped), chi2, dof)


def line_consistency(
    ids: Sequence[str],
    points_mm: FloatArray,
    u: FloatArray,
    normals: FloatArray,
    shape: FloatArray,
    weights: FloatArray,
    lateral: FloatArray,
    wire: gls.WireTerm,
    cog_mm: FloatArray,
    outlier_probability: float = tolerances.OUTLIER_PROBABILITY,
) -> tuple[list[LineResidual], float, int]:
    """Per-line consistency, each line against the estimate from the *other* lines.

    Arrays are one trial in :mod:`cadcog.method.gls`'s layout (vectors (3, k, 1), packed matrices
    (6, k, 1), ``shape`` (k, 1)). A plain residual from the joint estimate hides an outlier,
    which drags the estimate towards itself; the leave-one-out residual does not. Line i's
    lateral residual ``rᵢ = Pᵢ(G₋ᵢ − pᵢ − λ₋ᵢ fᵢ nᵢ)`` has covariance
    ``Sᵢ + Pᵢ Jᵢ C₋ᵢ Jᵢᵀ Pᵢ`` (``Jᵢ = [I, −fᵢnᵢ]``, ``C₋ᵢ`` the others' covariance of G and
    λ) and gives a χ² statistic with 2 degrees of freedom. One outlier still biases every
    other line's leave-one-out estimate, so lines are flagged one at a time: the worst
    significant line is flagged and set aside, and the rest are tested again.

    With two lines there is no "other" estimate: the campaign's χ² (one degree of freedom) is
    tested and both lines share the verdict, since either may be at fault.

    Returns the residuals, the campaign's ``χ² = Σ rᵢᵀWᵢrᵢ (+ the λ prior's term)`` at the
    joint estimate, and its degrees of freedom.
    """
    k = len(ids)
    lam = _scale_at(points_mm, u, normals, shape, weights, wire)
    virtual = points_mm + lam * shape * normals
    chi2 = max(_chi2(virtual, weights, cog_mm), 0.0)
    if not wire.fixed and not wire.estimate:
        chi2 += (lam - wire.scale_mm) ** 2 / wire.scale_var_mm2
    dof = 2 * k - 3 - (1 if wire.estimate else 0)
    distances = [
        PlumbLine(i, virtual[:, j, 0], u[:, j, 0]).distance_mm(cog_mm) for j, i in enumerate(ids)
    ]

    def statistic(active: list[int], i: int) -> float:
        return _loo_statistic(points_mm, u, normals, shape, weights, lateral, wire, active, i)

    residuals = flag_lines(ids, distances, chi2, dof, statistic, outlier_probability)
    return residuals, chi2, dof


def flag_lines(
    ids: Sequence[str],
    distances: Sequence[float],
    chi2: float,
    dof: int,
    statistic: Callable[[list[int], int], float],
    outlier_probability: float = tolerances.OUTLIER_PROBABILITY,
) -> list[LineResidual]:
    """Each line's verdict from its leave-one-out χ²₂ ``statistic(active, i)`` (line ``i``
    against the estimate of the other ``active`` lines): the worst significant line is flagged
    and set aside, and the rest are tested again. With two lines, or no degree of freedom, the
    campaign's ``chi2`` is tested and every line shares the verdict."""
    k = len(ids)
    if k == 2 or dof < 1:
        p_value = chi2_sf(chi2, dof) if dof > 0 else 1.0
        bad = p_value < outlier_probability
        return [
            LineResidual(i, d, float(np.sqrt(max(chi2, 0.0))), p_value, bad)
            for i, d in zip(ids, distances, strict=True)
        ]
    active = list(range(k))
    verdict: dict[int, tuple[float, float, bool]] = {}
    while True:
        current = {i: statistic(active, i) for i in active}
        worst = max(active, key=lambda i: current[i])
        p_worst = chi2_sf(current[worst], 2)
        if p_worst < outlier_probability and len(active) > 3:
            verdict[worst] = (current[worst], p_worst, True)
            active.remove(worst)
            continue
        for i in active:
            p_i = chi2_sf(current[i], 2)
            verdict[i] = (current[i], p_i, p_i < outlier_probability and i == worst)
        break
    return [
        LineResidual(ids[i], distances[i], float(np.sqrt(verdict[i][0])), *verdict[i][1:])
        for i in range(k)
    ]


def _scale_at(
    points_mm: FloatArray,
    u: FloatArray,
    normals: FloatArray,
    shape: FloatArray,
    weights: FloatArray,
    wire: gls.WireTerm,
) -> float:
    return float(gls.solve_lines(points_mm, u, normals, shape, weights, wire)[2][0])


def _chi2(virtual: FloatArray, weights: FloatArray, cog_mm: FloatArray) -> float:
    r = cog_mm[:, None, None] - virtual
    return float(np.sum(sym3.dot3(r, sym3.sym_matvec(weights, r))))


def _loo_statistic(
    points_mm: FloatArray,
    u: FloatArray,
    normals: FloatArray,
    shape: FloatArray,
    weights: FloatArray,
    lateral: FloatArray,
    wire: gls.WireTerm,
    active: list[int],
    i: int,
) -> float:
    """χ²₂ statistic of line ``i`` against the estimate of the other ``active`` lines."""
    o = [j for j in active if j != i]
    with np.errstate(divide="ignore", invalid="ignore"):  # parallel others: checked below
        x, cov, lam, var, cxl, _ = gls.solve_lines(
            points_mm[:, o], u[:, o], normals[:, o], shape[o], weights[:, o], wire
        )
    if not np.all(np.isfinite(x)) or (not wire.fixed and not np.isfinite(var[0])):
        return 0.0  # the others do not determine an estimate: nothing to test against
    n, f = normals[:, i, 0], float(shape[i, 0])
    ui = u[:, i, 0]
    proj = np.eye(3) - np.outer(ui, ui)
    r = proj @ (x[:, 0] - points_mm[:, i, 0] - lam[0] * f * n)
    c_g = sym3.sym_to_full(cov[:, 0])
    c_gl = cxl[:, 0]
    jcj = c_g - f * (np.outer(n, c_gl) + np.outer(c_gl, n)) + f * f * var[0] * np.outer(n, n)
    v = sym3.sym_to_full(lateral[:, i, 0]) + proj @ jcj @ proj
    w = np.linalg.inv(v + np.outer(ui, ui)) - np.outer(ui, ui)
    return float(r @ w @ r)


@dataclass(frozen=True)
class Compensation:
    """Object CoG from the assembly CoG by removing the ME (eqs. 10 and 16).

    ``cov_mm2`` includes the object mass's uncertainty (``object_mass_sigma_kg``, through
    ``mass_gradient_mm_kg`` = ``∂r_obj/∂m_obj``); ``cov_given_mass_mm2`` is the covariance with
    the object mass taken as exact.
    """

    cog_mm: FloatArray
    cov_mm2: FloatArray
    object_mass_kg: float
    me_mass_kg: float
    me_cog_mm: FloatArray
    object_mass_sigma_kg: float = 0.0
    mass_gradient_mm_kg: FloatArray = field(default_factory=lambda: np.zeros(3))
    cov_given_mass_mm2: FloatArray | None = None
    object_mass_source: str = "given"


def compensate_me(
    assembly_cog_mm: npt.ArrayLike,
    assembly_cov_mm2: npt.ArrayLike,
    *,
    object_mass_kg: float,
    me_mass_kg: float,
    me_cog_mm: npt.ArrayLike,
    me_cog_cov_mm2: npt.ArrayLike | None = None,
    object_mass_sigma_kg: float = 0.0,
    object_mass_source: str = "given",
) -> Compensation:
    """Remove the measurement equipment from an assembly CoG (eq. 10), propagating errors (eq. 16).

    ``r_obj = ((m_obj + m_ME) r_est − m_ME r_ME) / m_obj`` and
    ``cov_obj = (1 + m_ME/m_obj)² cov_est + (m_ME/m_obj)² cov_ME + σ_m² a aᵀ``, with
    ``a = ∂r_obj/∂m_obj = −(m_ME/m_obj²)(r_est − r_ME)`` and ``σ_m`` the object mass's 1 σ
    (a weighing's, or the CAD's: every kg the mass is off moves ``r_obj`` by ``a``).

    Examples
    --------
    >>> c = compensate_me([1.0, 0, 0], np.zeros((3, 3)), object_mass_kg=9.0, me_mass_kg=1.0,
    ...                   me_cog_mm=[10.0, 0, 0])
    >>> c.cog_mm.tolist()  # (10·1 − 1·10) / 9
    [0.0, 0.0, 0.0]
    >>> c = compensate_me([1.0, 0, 0], np.zeros((3, 3)), object_mass_kg=9.0, me_mass_kg=1.0,
    ...                   me_cog_mm=[10.0, 0, 0], object_mass_sigma_kg=0.9)
    >>> round(float(c.cov_mm2[0, 0]), 6)  # (0.9 · 1/81 · 9)²
    0.01
    """
    if not object_mass_kg > 0 or not me_mass_kg >= 0:
        raise ValueError("object mass must be positive and ME mass non-negative")
    if not object_mass_sigma_kg >= 0:
        raise ValueError("the object mass's σ must be ≥ 0")
    ratio = me_mass_kg / object_mass_kg
    r_est = np.asarray(assembly_cog_mm, dtype=float)
    r_me = np.asarray(me_cog_mm, dtype=float)
    cog = (1.0 + ratio) * r_est - ratio * r_me
    cov_me = np.zeros((3, 3)) if me_cog_cov_mm2 is None else np.asarray(me_cog_cov_mm2, float)
    cov = (1.0 + ratio) ** 2 * np.asarray(assembly_cov_mm2, dtype=float) + ratio**2 * cov_me
    gradient = -ratio / object_mass_kg * (r_est - r_me)
    total = cov + object_mass_sigma_kg**2 * np.outer(gradient, gradient)
    return Compensation(
        cog,
        total,
        object_mass_kg,
        me_mass_kg,
        r_me,
        object_mass_sigma_kg,
        gradient,
        cov,
        object_mass_source,
    )


def out_of_range(
    points_mm: dict[str, npt.ArrayLike], cog_mm: npt.ArrayLike, range_deg: float
) -> list[tuple[str, float, float]]:
    """Suspensions whose ideal readings leave ``±range_deg``: (id, X_deg, Y_deg) for each.

    Examples
    --------
    >>> out_of_range({"A": [0, 0, 10], "B": [10, 0, 1]}, [0, 0, 0], 60.0)
    [('B', 84.28940686250037, 0.0)]
    """
    bad = []
    for pid, p in points_mm.items():
        r = ideal_reading(p, cog_mm)
        if not r.in_range(range_deg):
            bad.append((pid, r.inc_x_deg, r.inc_y_deg))
    return bad
