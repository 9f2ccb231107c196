"""Generalised least squares of plumb lines, vectorised: the one estimator behind
``cadcog estimate`` and every Monte Carlo (``simulate``, ``plan``, ``validate``).

Hang ``i`` gives a plumb line through its virtual suspension point
``pᵢ + λ fᵢ nᵢ`` (the nominal point, raised along the bolt axis ``nᵢ`` by the wire offset, see
:class:`cadcog.method.errormodel.WirePrior`) along the measured upward vertical ``uᵢ``. Its lateral
position near the CoG, at distance ``Lᵢ`` from the point, errs with the 3 × 3, rank-2 covariance

    Sᵢ = Pᵢ Σ_point,ᵢ Pᵢ + Lᵢ² Σ_u,ᵢ,         Pᵢ = I − uᵢuᵢᵀ,

where ``Σ_point = σ_play² (I − nnᵀ) + σ_axial² nnᵀ`` (the play in the face plane, the wire
offset's scatter along the bolt axis) and ``Σ_u = σ_X² j_X j_Xᵀ + σ_Y² j_Y j_Yᵀ`` maps the
reading errors through eq. 2 (``j = ∂u/∂X``, ``∂u/∂Y``). With ``Wᵢ = Sᵢ⁺`` the estimate
minimises ``Σ rᵢᵀ Wᵢ rᵢ (+ (λ − λ₀)²/σ_λ²)`` over the CoG ``G`` (and the wire scale ``λ`` when
it is uncertain or self-calibrated), ``rᵢ = G − pᵢ − λ fᵢ nᵢ``; its covariance is the inverse of
the normal matrix. A first, equally weighted pass gives the distances ``Lᵢ``.

Arrays are component-first, like :mod:`cadcog.uncertainty.montecarlo`'s: vectors have shape (3, k,
n) for k lines of n trials (campaigns), symmetric 3 × 3 matrices are packed as (6, ...) in the order
xx, yy, zz, xy, xz, yz (an array, or a tuple of arrays: the kernels only index the first axis). Sums
over lines run over axis 1 of a vector, adding contiguous rows. Every operation is element-wise over
the trials, so one trial (``n = 1``, what ``cadcog estimate`` runs) and a million give the same
numbers.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from cadcog.core import tolerances
from cadcog.core.units import deg_to_rad
from cadcog.method.errormodel import ErrorModel
from cadcog.method.sym3 import (
    Comp,
    Sym,
    Vec,
    dot3,
    lines_sum,
    projector,
    rows_sum,
    sym_inv,
    sym_matvec,
    sym_outer,
)
from cadcog.method.wire import wire_shape_factor
from cadcog.rig.parameters import WireModel

FloatArray = npt.NDArray[np.float64]

#: Lateral variance added to every line (mm²) so that a model without any error source still
#: gives finite, equal weights. Far below any physical variance (play alone is ~0.08 mm²).
LATERAL_FLOOR_MM2 = 1e-9

#: Smallest |u_z| used in the reading Jacobian (eq. 2 is singular at the horizontal).
MIN_UZ = 1e-9


# --- the error model as the estimator sees it ----------------------------------------------------
@dataclass(frozen=True)
class LineErrors:
    """Variances the line covariances are built from.

    Attributes
    ----------
    play_var_mm2 : float
        Suspension point along each face tangent (the play).
    axial_var_mm2 : float
        Suspension point along the bolt axis (the wire offset's per-hang scatter).
    reading_var_rad2 : float or ndarray broadcastable to (k, n)
        Each axis of a hang's mean reading.
    point_var_mm2 : float, optional
        An isotropic point variance replacing the play and axial terms (a user override).
    isotropic_reading : bool
        False (an inclinometer): ``reading_var_rad2`` is each angle's, and the vertical's error
        follows ``∂u/∂X`` and ``∂u/∂Y``. True (an accelerometer, which reads the vector itself):
        it is the vertical's own variance along each direction ⊥ ``u``.
    """

    play_var_mm2: float
    axial_var_mm2: float
    reading_var_rad2: float | FloatArray
    point_var_mm2: float | None = None
    isotropic_reading: bool = False

    @classmethod
    def from_model(
        cls,
        model: ErrorModel,
        samples: npt.ArrayLike | None = None,
        *,
        angle_sigma_deg: float | None = None,
        point_sigma_mm: float | None = None,
    ) -> LineErrors:
        """The line errors of ``model``; ``samples`` per line, shape (k,) (default the model's).

        ``angle_sigma_deg`` and ``point_sigma_mm`` override the reading and point uncertainty.
        """
        if angle_sigma_deg is not None:
            reading: float | FloatArray = float(deg_to_rad(angle_sigma_deg)) ** 2
        elif samples is None:
            reading = model.reading_var_deg2() * float(deg_to_rad(1.0)) ** 2
        else:
            n = np.atleast_1d(np.asarray(samples, dtype=int))
            per_line = np.array([model.reading_var_deg2(int(s)) for s in n.ravel()])
            reading = per_line.reshape((*n.shape, 1)) * float(deg_to_rad(1.0)) ** 2
        return cls(
            model.play_var_mm2,
            model.wire_prior(1.0).scatter_var_mm2,
            reading,
            None if point_sigma_mm is None else point_sigma_mm**2,
        )

    def point_cov_mm2(self, normals: npt.ArrayLike) -> FloatArray:
        """Each suspension point's covariance as these errors take it, shape (k, 3, 3), for
        bolt axes ``normals`` (k, 3): ``σ_play² (I − nnᵀ) + σ_axial² nnᵀ``, or the override's
        ``σ² I``."""
        n = np.atleast_2d(np.asarray(normals, dtype=float))
        if self.point_var_mm2 is not None:
            return np.broadcast_to(self.point_var_mm2 * np.eye(3), (len(n), 3, 3)).copy()
        nn = n[:, :, None] * n[:, None, :]
        return np.asarray(self.play_var_mm2 * (np.eye(3) - nn) + self.axial_var_mm2 * nn)


@dataclass(frozen=True)
class WireTerm:
    """How the estimator treats the wire offset ``λ fᵢ`` along each bolt axis.

    Attributes
    ----------
    model : "paper" or "elastica"
        Sets the shape ``fᵢ`` (:func:`cadcog.method.wire.wire_shape_factor`).
    scale_mm : float
        ``λ₀``: the expected scale (0: no correction).
    scale_var_mm2 : float
        Its prior variance, shared by every hang: 0 for a known scale.
    estimate : bool
        Self-calibration: estimate λ from the data alone (the prior is dropped).
    """

    model: WireModel = "paper"
    scale_mm: float = 0.0
    scale_var_mm2: float = 0.0
    estimate: bool = False

    @property
    def fixed(self) -> bool:
        return not self.estimate and self.scale_var_mm2 == 0.0

    @classmethod
    def from_model(
        cls, model: ErrorModel, weight_n: float, *, correct: bool = True, estimate: bool = False
    ) -> WireTerm:
        """The model's wire prior; ``correct=False`` ignores the expected offset (the paper)."""
        if estimate and not correct:
            raise ValueError("self-calibration of the wire needs the wire correction")
        if not correct:
            return cls(model.wire_model)
        prior = model.wire_prior(weight_n)
        return cls(model.wire_model, prior.scale_mm, prior.scale_var_mm2, estimate)


@dataclass(frozen=True)
class GLSBatch:
    """Estimates of a batch of n trials of k lines.

    Attributes
    ----------
    cog_mm : ndarray, shape (3, n)
    cov_mm2 : ndarray, shape (6, n)
        Packed covariance of the CoG (λ marginalised when it is uncertain).
    scale_mm, scale_var_mm2 : ndarray, shape (n,)
        Wire scale λ and its variance (0 when λ is known).
    cov_cog_scale_mm2 : ndarray, shape (3, n)
        Covariance of the CoG with λ.
    scale_information : ndarray, shape (n,)
        What the lines alone say about λ, ``1/σ_λ²`` once the CoG is free (0: unidentifiable).
    points_mm : ndarray, shape (3, k, n)
        Virtual suspension points at the estimated λ.
    shape : ndarray, shape (k, n)
        ``fᵢ``.
    lateral_cov_mm2, weights : ndarray, shape (6, k, n)
        ``Sᵢ`` and ``Wᵢ = Sᵢ⁺``.
    """

    cog_mm: FloatArray
    cov_mm2: FloatArray
    scale_mm: FloatArray
    scale_var_mm2: FloatArray
    cov_cog_scale_mm2: FloatArray
    scale_information: FloatArray
    points_mm: FloatArray
    shape: FloatArray
    lateral_cov_mm2: FloatArray
    weights: FloatArray


# --- kernels -------------------------------------------------------------------------------------
def lateral_parts(
    u: Comp, normals: Comp, errors: LineErrors
) -> tuple[tuple[FloatArray, FloatArray], Vec, Vec, Vec]:
    """``Sᵢ`` in an orthonormal basis of the plane ⊥ ``u``, as ``m⁰ + L² mᴸ``.

    Returns ``((e₁ₓ, e₁_z), e₂, m⁰, mᴸ)`` with ``m = (m₁₁, m₁₂, m₂₂)``: ``L`` (the distance from
    the point to the CoG) enters only through the reading term, so the rest of a line's
    covariance is known before the CoG is. ``e₁ = (u_z, 0, −u_x)/ρ`` (ρ = √(u_x² + u_z²)) lies
    along ``∂u/∂X = cos X (1, 0, −u_x/u_z)`` and ``e₂ = u × e₁``; then
    ``∂u/∂X = (cos X ρ/u_z) e₁`` and ``∂u/∂Y = (cos Y/ρ)(u_x u_y/u_z, 1)`` in the basis, with
    ``cos² X = 1 − u_x²``. The point's covariance projects to ``c₁ I + (c₂ − c₁) m mᵀ``,
    ``m = (e₁·n, e₂·n)``.
    """
    ux, uy, uz = u[0], u[1], u[2]
    rho2 = np.maximum(ux * ux + uz * uz, 1e-24)
    rinv = 1.0 / np.sqrt(rho2)
    e1 = (uz * rinv, -ux * rinv)
    e2 = (-ux * uy * rinv, rho2 * rinv, -uy * uz * rinv)
    uz_safe = np.copysign(np.maximum(np.abs(uz), MIN_UZ), uz)
    var = errors.reading_var_rad2
    if errors.isotropic_reading:
        zero = np.zeros_like(rho2)
        m_iso = (zero + var, zero, zero + var)
        return _lateral_point(e1, e2, normals, errors, rho2, m_iso)
    hx = var * (1.0 - ux * ux) * rho2 / (uz_safe * uz_safe)
    hy = var * (1.0 - uy * uy) / rho2
    a1 = ux * uy / uz_safe
    ha = hy * a1
    m_l = (hx + ha * a1, ha, hy)
    return _lateral_point(e1, e2, normals, errors, rho2, m_l)


def _lateral_point(
    e1: tuple[FloatArray, FloatArray],
    e2: Vec,
    normals: Comp,
    errors: LineErrors,
    rho2: FloatArray,
    m_l: Vec,
) -> tuple[tuple[FloatArray, FloatArray], Vec, Vec, Vec]:
    """:func:`lateral_parts` once the reading's part ``mᴸ`` is known: the point's part ``m⁰``."""
    if errors.point_var_mm2 is not None:
        c1 = c2 = errors.point_var_mm2
    else:
        c1, c2 = errors.play_var_mm2, errors.axial_var_mm2
    base = c1 + LATERAL_FLOOR_MM2
    if c2 == c1:
        zero = np.zeros_like(rho2)
        return e1, e2, (zero + base, zero, zero + base), m_l
    m1 = e1[0] * normals[0] + e1[1] * normals[2]
    m2 = e2[0] * normals[0] + e2[1] * normals[1] + e2[2] * normals[2]
    d = c2 - c1
    dm1 = d * m1
    return e1, e2, (base + dm1 * m1, dm1 * m2, base + d * m2 * m2), m_l


def lateral_2d(
    u: Comp, normals: Comp, dist2_mm2: FloatArray, errors: LineErrors
) -> tuple[tuple[FloatArray, FloatArray], Vec, Vec]:
    """``(e₁, e₂, (m₁₁, m₁₂, m₂₂))`` of :func:`lateral_parts` at squared distances ``L²``."""
    e1, e2, m0, m_l = lateral_parts(u, normals, errors)
    return e1, e2, tuple(a + dist2_mm2 * b for a, b in zip(m0, m_l, strict=True))


def assemble(
    e1: tuple[FloatArray, FloatArray], e2: Vec, a: FloatArray, b: FloatArray, c: FloatArray
) -> Sym:
    """``a e₁e₁ᵀ + b (e₁e₂ᵀ + e₂e₁ᵀ) + c e₂e₂ᵀ`` packed; ``e₁`` has no y component and is given
    as ``(e₁ₓ, e₁_z)``."""
    t0 = a * e1[0] + b * e2[0]
    t2 = a * e1[1] + b * e2[2]
    s0 = b * e1[0] + c * e2[0]
    s1 = c * e2[1]
    s2 = b * e1[1] + c * e2[2]
    return (
        e1[0] * t0 + e2[0] * s0,
        e2[1] * s1,
        e1[1] * t2 + e2[2] * s2,
        e1[0] * b * e2[1] + e2[0] * s1,
        e1[0] * t2 + e2[0] * s2,
        e2[1] * s2,
    )


def inverse_2d(m: Vec) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``(a, b, c)`` of the inverse of ``[[m₁₁, m₁₂], [m₁₂, m₂₂]]``."""
    r = 1.0 / (m[0] * m[2] - m[1] * m[1])
    return m[2] * r, -m[1] * r, m[0] * r


def line_weights(u: Comp, normals: Comp, dist_mm: FloatArray, errors: LineErrors) -> Sym:
    """``Wᵢ = Sᵢ⁺``, packed (6, k, n): the inverse of ``Sᵢ`` on the plane ⊥ ``u``."""
    e1, e2, m = lateral_2d(u, normals, dist_mm * dist_mm, errors)
    return assemble(e1, e2, *inverse_2d(m))


@dataclass(frozen=True)
class LineTerms:
    """Each line's share of :func:`solve_lines`'s sums, before they are summed over the lines.

    A line's terms depend only on that line (its point, normal, shape factor and weight), so
    sets drawn from the same candidate lines can share them (``cadcog plan`` screens 10⁵ sets
    of 49 candidates): :meth:`of_lines` once, :meth:`take` for the sets, :meth:`summed`.

    Attributes
    ----------
    w : tuple of 6 arrays
        ``Wᵢ`` packed.
    wp : tuple of 3 arrays
        ``Wᵢ pᵢ``.
    swn : tuple of 3 arrays
        ``sᵢ Wᵢ nᵢ`` (``sᵢ`` the wire-shape factor).
    ssnwn : array
        ``sᵢ² nᵢ·Wᵢnᵢ``.
    snwp : array
        ``sᵢ nᵢ·Wᵢpᵢ``.
    """

    w: tuple[FloatArray, ...]
    wp: tuple[FloatArray, ...]
    swn: tuple[FloatArray, ...]
    ssnwn: FloatArray
    snwp: FloatArray

    @classmethod
    def of_lines(
        cls, points_mm: Comp, normals: Comp, shape: FloatArray, weights: Comp
    ) -> LineTerms:
        """The terms of lines (component-first arrays, the lines along the next axis)."""
        wp = sym_matvec(weights, points_mm)
        wn = sym_matvec(weights, normals)
        return cls(
            tuple(np.asarray(w) for w in weights),
            tuple(np.asarray(v) for v in wp),
            tuple(shape * w for w in wn),
            np.asarray(shape * shape * dot3(normals, wn)),
            np.asarray(shape * dot3(normals, wp)),
        )

    def take(self, index: npt.NDArray[np.int64]) -> LineTerms:
        """The terms of lines ``index`` (any shape) of lines held as shape (n,) or (n, 1)."""

        def at(a: FloatArray) -> FloatArray:
            return a[index] if a.ndim == 1 else a[index, 0]

        return LineTerms(
            tuple(at(a) for a in self.w),
            tuple(at(a) for a in self.wp),
            tuple(at(a) for a in self.swn),
            at(self.ssnwn),
            at(self.snwp),
        )

    def solve(
        self, wire: WireTerm
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
        """:func:`solve_lines` of these lines, summed over the first axis."""
        a = lines_sum(self.w)
        b = lines_sum(self.wp)
        ainv, _ = sym_inv(a)
        c = lines_sum(self.swn)
        ac = sym_matvec(ainv, c)
        d = self.ssnwn.sum(axis=0)
        info = np.maximum(d - dot3(c, ac), 0.0)  # what the lines say about λ once G is free
        x0 = sym_matvec(ainv, b)
        if wire.fixed:
            lam = np.full(info.shape, wire.scale_mm)
            x = np.stack([x0[i] + ac[i] * wire.scale_mm for i in range(3)])
            zero = np.zeros_like(lam)
            return x, np.stack(ainv), lam, zero, np.zeros_like(x), info
        prior = 0.0 if wire.estimate else 1.0 / wire.scale_var_mm2
        e = prior * wire.scale_mm - self.snwp.sum(axis=0)
        s = info + prior
        with np.errstate(divide="ignore", invalid="ignore"):
            var = 1.0 / s
            lam = (e + dot3(c, x0)) * var
            x = np.stack([x0[i] + ac[i] * lam for i in range(3)])
            cov = np.stack([m + o * var for m, o in zip(ainv, sym_outer(ac), strict=True)])
            cxl = np.stack([ac[i] * var for i in range(3)])
        return x, cov, lam, var, cxl, info


def solve_lines(
    points_mm: Comp,
    u: Comp,
    normals: Comp,
    shape: FloatArray,
    weights: Comp,
    wire: WireTerm,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Weighted least-squares CoG (and λ) of lines with given weights, summed over axis 1.

    Returns ``(cog (3, n), cov (6, n), λ (n,), var λ (n,), cov(cog, λ) (3, n), information on
    λ (n,))``. (``u`` is not needed once the weights are known: kept for the callers' symmetry.)
    """
    return LineTerms.of_lines(points_mm, normals, shape, weights).solve(wire)


def scale_identifiable(batch: GLSBatch) -> npt.NDArray[np.bool_]:
    """Whether each trial's lines determine the wire scale λ (self-calibration), shape (n,).

    The information the lines give on λ once the CoG is free, against what they would give if
    every offset moved its line sideways, must exceed
    :data:`cadcog.core.tolerances.WIRE_IDENTIFIABILITY`: it does not when the bolt axes lie
    along their verticals, or when the CoG absorbs the offsets (every point on one face, whose
    offsets all move the lines alike).
    """
    w = np.asarray(batch.weights)
    return wire_scale_identified(batch.scale_information, batch.shape, w[0] + w[1] + w[2])


def wire_scale_identified(
    information: npt.ArrayLike, shape: npt.ArrayLike, weight_traces: npt.ArrayLike
) -> npt.NDArray[np.bool_]:
    """The criterion of :func:`scale_identifiable`, from its parts: the information on λ
    (1/mm²), each line's wire shape ``fᵢ`` and the trace of its weight ``Wᵢ``, lines along the
    first axis."""
    ref = (np.asarray(shape) ** 2 * np.asarray(weight_traces)).sum(axis=0) / 2.0
    return np.asarray(np.asarray(information) > tolerances.WIRE_IDENTIFIABILITY * ref)


def equal_weight_point(points_mm: Comp, u: Comp) -> FloatArray:
    """Least-squares point of lines with equal weights ``Pᵢ`` (eq. 8 for a pair): (3, n)."""
    a = lines_sum(projector(u))
    uq = dot3(u, points_mm)
    b = tuple(rows_sum(points_mm[i] - uq * u[i]) for i in range(3))
    ainv, _ = sym_inv(a)
    return np.stack(sym_matvec(ainv, b))


def plumb_gls(
    points_mm: FloatArray,
    u: FloatArray,
    normals: FloatArray,
    errors: LineErrors,
    wire: WireTerm,
    *,
    weighted: bool = True,
) -> GLSBatch:
    """The estimator: CoG (and λ) of n trials of k plumb lines, with covariances.

    Parameters
    ----------
    points_mm : ndarray, shape (3, k, n or 1)
        Nominal suspension points (where the wire leaves the object).
    u : ndarray, shape (3, k, n)
        Measured unit upward verticals.
    normals : ndarray, shape (3, k, n or 1)
        Bolt axes (outward normals of the faces the points sit on).
    errors : LineErrors
    wire : WireTerm
    weighted : bool
        False: every line weighs ``Pᵢ`` (equal-weight least squares: eq. 8 for a pair), the
        paper's estimator; the covariance is then that of unit lateral errors.

    Examples
    --------
    Two noise-free plumb lines through the origin, from points 100 mm away:

    >>> p = np.array([[0.0, 0.0, 100.0], [60.0, 0.0, 80.0]]).T[:, :, None]  # (3, k=2, n=1)
    >>> u = p / 100.0
    >>> n = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]).T[:, :, None]
    >>> b = plumb_gls(p, u, n, LineErrors(0.08, 0.08, 1e-6), WireTerm())
    >>> np.round(b.cog_mm[:, 0], 9).tolist()
    [0.0, 0.0, 0.0]
    >>> from cadcog.method.sym3 import sym_to_full
    >>> bool(np.all(np.linalg.eigvalsh(sym_to_full(b.cov_mm2[:, 0])) > 0))
    True
    """
    shape = (
        np.ones(u.shape[1:])
        if wire.model == "paper"
        else wire_shape_factor(dot3(u, normals), wire.model)
    )
    q0 = points_mm + (wire.scale_mm * shape) * normals if wire.scale_mm else points_mm
    if not weighted:
        proj = projector(u)
        equal = solve_lines(q0, u, normals, shape, proj, WireTerm(wire.model))
        x, cov = equal[0], equal[1]
        lam = equal[2] + wire.scale_mm
        return GLSBatch(
            x, cov, lam, equal[3], equal[4], equal[5], np.asarray(q0), shape, np.stack(proj),
            np.stack(proj),
        )  # fmt: skip
    diff = equal_weight_point(q0, u)[:, None, :] - q0
    e1, e2, m = lateral_2d(u, normals, dot3(diff, diff), errors)
    lateral = assemble(e1, e2, *m)
    w = assemble(e1, e2, *inverse_2d(m))
    x, cov, lam, var, cxl, info = solve_lines(points_mm, u, normals, shape, w, wire)
    pts = points_mm + (lam * shape) * normals
    return GLSBatch(
        x, cov, lam, var, cxl, info, np.asarray(pts), shape, np.stack(lateral), np.stack(w)
    )


def point_gain(
    cov: FloatArray, design: FloatArray, weights: FloatArray, with_scale: bool
) -> FloatArray:
    """How the fitted CoG and λ follow each line's assumed point, shape (4, k, 3): rows G's
    x, y, z and λ (0 when λ is not an unknown, ``with_scale`` False).

    At a weighted least-squares solution of residuals ``rᵢ = Pᵢ(G − pᵢ − λ fᵢ nᵢ)`` (and any
    other unknowns θ), moving the point ``pᵢ`` the estimate assumed by ``δpᵢ`` moves the
    unknowns by ``C Dᵢᵀ Wᵢ δpᵢ`` (implicit function theorem, the weights held: ``∂rᵢ/∂pᵢ =
    −Pᵢ`` and ``Wᵢ Pᵢ = Wᵢ``), ``C`` the unknowns' covariance (the inverse normal matrix,
    priors included) and ``Dᵢ = ∂rᵢ/∂x`` the design. A hang's play moves its line, and the
    CoG the lines meet at follows part of it: the CoG's error and the pivots' are correlated,
    which is what the swing's moment arms ``pᵢ − G`` see (:mod:`cadcog.dynamics.context`).

    Parameters
    ----------
    cov : ndarray, shape (m, m)
        The unknowns' covariance, G first, then λ (with ``with_scale``), then any others.
    design : ndarray, shape (k, 3, m)
    weights : ndarray, shape (k, 3, 3)
    with_scale : bool

    Examples
    --------
    Two perpendicular lines, equal weights: line 1 (along z) alone fixes G's x, so its
    point moves G's x fully; y is fixed by both lines, so half of it; z not at all:

    >>> u = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
    >>> proj = np.eye(3) - u[:, :, None] * u[:, None, :]
    >>> cov = np.linalg.inv(proj.sum(axis=0))
    >>> g = point_gain(cov, proj, proj, with_scale=False)
    >>> g[:3, 0].round(3).tolist()  # rows: G's x, y, z; columns: line 1's point's x, y, z
    [[1.0, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 0.0]]
    """
    rows = 3 + with_scale
    gain = np.zeros((4, design.shape[0], 3))
    gain[:rows] = np.einsum("rm,kam,kab->rkb", cov[:rows], design, weights)
    return gain


def line_design(
    u: FloatArray,
    normals: FloatArray,
    shape: FloatArray,
    with_scale: bool,
    extra: FloatArray | None = None,
) -> FloatArray:
    """``Dᵢ = Pᵢ [I, −fᵢnᵢ, Eᵢ]``: the design of the lines' residuals ``Pᵢ(G − qᵢ)`` over G,
    λ (its column with ``with_scale``) and any further unknowns whose ``∂(G − qᵢ)/∂θ`` is
    ``extra`` (k, 3, e), every column projected on the plane ⊥ ``uᵢ``; shape (k, 3, m).
    ``u``, ``normals`` (k, 3), ``shape`` (k,)."""
    proj = np.eye(3) - u[:, :, None] * u[:, None, :]
    cols = [np.broadcast_to(np.eye(3), proj.shape)]
    if with_scale:
        cols.append(-(shape[:, None] * normals)[:, :, None])
    if extra is not None:
        cols.append(extra)
    return np.asarray(np.einsum("kij,kjm->kim", proj, np.concatenate(cols, axis=2)))
