"""Plumb lines with what every hang of a test shares: the sensor's offsets, sensitivities and
mounting estimated jointly with the CoG (and the wire scale), within their declared figures.

One sensor is read on every hang, so its zero offsets ``b``, sensitivity errors ``s`` and
mounting rotation ``r`` (:data:`cadcog.rig.inclinometer.SHARED_SENSOR_PARAMETERS`, defined by
:func:`cadcog.rig.inclinometer.sensor_readings`) are the same on every hang and do not average
out. The hangs' lines then meet only once those are corrected: hang ``i``'s upward vertical is
``uᵢ(θ)`` (:func:`cadcog.rig.inclinometer.corrected_verticals` of its readings), its line passes
through ``qᵢ = pᵢ + λ fᵢ nᵢ``, and the estimate minimises

    Σ rᵢᵀ Wᵢ rᵢ + Σⱼ θⱼ²/σⱼ² (+ (λ − λ₀)²/σ_λ²),     rᵢ = (I − uᵢuᵢᵀ)(G − qᵢ),

over the CoG ``G``, the shared parameters ``θ`` (those with a declared figure: its prior σ from
:attr:`cadcog.method.errormodel.ErrorModel.shared_sensor_sigmas`) and ``λ`` when it is
uncertain, by Gauss-Newton (``∂rᵢ/∂θ = −Lᵢ ∂uᵢ/∂θ`` on the plane ⊥ ``uᵢ``, ``Lᵢ = uᵢ·(G − qᵢ)``),
with ``Wᵢ`` the per-hang lateral weights of :func:`cadcog.method.gls.line_weights` at the
current distances. The covariance is the inverse of the normal matrix: the CoG's is marginal
over ``θ`` and ``λ``. Where the hangs identify a parameter its posterior σ falls below its
prior's (:attr:`SharedFit.calibrated`); where they do not, the prior carries it into the CoG's
covariance. With no shared figure and a known wire scale this is
:func:`cadcog.method.gls.plumb_gls` iterated to its fixed point.

The consistency check is :func:`cadcog.method.plumblines.line_consistency`'s, generalised: each
line against the joint estimate of the others (shared parameters included; the one-step
leave-one-out update of the joint estimate), a χ²₂ statistic with the others' covariance
propagated, the worst significant line set aside at a time
(:func:`cadcog.method.plumblines.flag_lines`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
import numpy.typing as npt

from cadcog.core import tolerances
from cadcog.core.errors import DegenerateGeometryError
from cadcog.method import gls, sym3
from cadcog.method.plumblines import LineResidual, PlumbLine, flag_lines
from cadcog.method.wire import wire_shape_factor
from cadcog.rig.accelerometer import ACCEL_SHARED_PARAMETERS, accel_norms, accel_verticals
from cadcog.rig.inclinometer import (
    SHARED_SENSOR_PARAMETERS,
    InclinometerConfig,
    corrected_verticals,
)

FloatArray = npt.NDArray[np.float64]


def shared_parameter_names(config: InclinometerConfig) -> tuple[str, ...]:
    """The shared parameters of ``config``'s sensor, in the order of every vector of them."""
    return ACCEL_SHARED_PARAMETERS if config.accelerometer else SHARED_SENSOR_PARAMETERS


#: Gauss-Newton iterations at most; the step is below :data:`STEP_TOL_MM` in 3-5 on every
#: tested campaign (the problem is nearly linear: θ is a fraction of a degree).
MAX_ITERATIONS = 30
#: Convergence: the CoG moves less than this (mm) and θ less than 10⁻⁶ of its prior σ.
STEP_TOL_MM = 1e-9
#: Finite-difference step of ∂u/∂θ, as a fraction of each parameter's prior σ (central
#: differences: the error is ~(step)² of the curvature, far below the readings' noise).
JACOBIAN_STEP = 1e-3
#: A parameter counts as calibrated by the hangs when its posterior σ is below this fraction
#: of its prior σ (the hangs then carry at least 75 % of what is known of it).
CALIBRATED_FRACTION = 0.5


@dataclass(frozen=True)
class SharedFit:
    """The joint estimate of :func:`fit_shared`.

    Attributes
    ----------
    cog_mm : ndarray, shape (3,)
    cov_mm2 : ndarray, shape (3, 3)
        The CoG's covariance, marginal over the shared parameters and λ.
    scale_mm, scale_sigma_mm : float
        The wire scale λ and its σ (0 when it is known).
    shared : ndarray, shape (7,) or (15,)
        The shared sensor parameters' estimates (0 where no figure is declared).
    shared_sigma : ndarray, shape (7,) or (15,)
        Their posterior σ (0 where no figure is declared).
    prior_sigma : ndarray, shape (7,) or (15,) (an accelerometer: :func:`shared_parameter_names`)
    verticals : ndarray, shape (k, 3)
        Each hang's vertical with the shared errors removed.
    points_mm : ndarray, shape (k, 3)
        Virtual suspension points at the estimated λ.
    chi2, dof : float, int
        ``Σ rᵢᵀWᵢrᵢ`` plus the priors' terms at the estimate, and ``2k − 3`` (one fewer when λ
        is self-calibrated): the priors are observations of their own.
    residuals : tuple of LineResidual
    scale_information : float
        What the lines say about λ once everything else is free (1/mm²; 0: nothing).
    scale_identified : bool
        Whether that determines λ (:func:`cadcog.method.gls.wire_scale_identified`): what
        self-calibrating the wire needs. False when λ is not an unknown.
    point_gain : ndarray, shape (4, k, 3)
        ``∂(G, λ)/∂pᵢ``: how the CoG and λ follow each hang's assumed point
        (:func:`cadcog.method.gls.point_gain`; λ's row 0 when λ is known).
    cog_scale_cov_mm2 : ndarray, shape (3,)
        The CoG's covariance with λ (0 when λ is known).
    """

    cog_mm: FloatArray
    cov_mm2: FloatArray
    scale_mm: float
    scale_sigma_mm: float
    shared: FloatArray
    shared_sigma: FloatArray
    prior_sigma: FloatArray
    verticals: FloatArray
    points_mm: FloatArray
    chi2: float
    dof: int
    residuals: tuple[LineResidual, ...]
    scale_information: float
    scale_identified: bool
    point_gain: FloatArray
    cog_scale_cov_mm2: FloatArray

    @property
    def calibrated(self) -> npt.NDArray[np.bool_]:
        """Which shared parameters the hangs determined (posterior σ below
        :data:`CALIBRATED_FRACTION` of the prior's), shape (7,) or (15,)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = self.shared_sigma / self.prior_sigma
        return np.asarray((self.prior_sigma > 0) & (ratio < CALIBRATED_FRACTION))

    def to_dict(self) -> dict[str, object]:
        """Each declared shared parameter: estimate, σ, prior σ, whether the hangs calibrated it."""
        out: dict[str, object] = {}
        accel = len(self.prior_sigma) == len(ACCEL_SHARED_PARAMETERS)
        names = ACCEL_SHARED_PARAMETERS if accel else SHARED_SENSOR_PARAMETERS
        for j, name in enumerate(names):
            if self.prior_sigma[j] > 0:
                out[name] = {
                    "estimate": float(self.shared[j]),
                    "sigma": float(self.shared_sigma[j]),
                    "prior_sigma": float(self.prior_sigma[j]),
                    "calibrated_by_hangs": bool(self.calibrated[j]),
                }
        return out


@dataclass(frozen=True)
class _Lines:
    """One test's hangs as :func:`fit_shared` takes them."""

    p: FloatArray  # (k, 3) nominal points
    x_deg: FloatArray  # (k,)
    y_deg: FloatArray
    top: npt.NDArray[np.bool_]
    n: FloatArray  # (k, 3) bolt axes
    errors: gls.LineErrors
    wire: gls.WireTerm
    prior_sigma: FloatArray  # (7,), or (9,) for an accelerometer
    config: InclinometerConfig
    turned: npt.NDArray[np.bool_]  # (k,) read with the sensor turned 180° on its mount
    acc: FloatArray | None = None  # (k, 3) an accelerometer's mean readings (g)
    norm_var: FloatArray | None = None  # (k,) variance of each one's gravity norm (g²)

    def take(self, rows: Sequence[int]) -> _Lines:
        idx = np.asarray(rows)
        reading = self.errors.reading_var_rad2
        if isinstance(reading, np.ndarray) and reading.ndim and reading.shape[0] == len(self.p):
            errors = replace(self.errors, reading_var_rad2=reading[idx])
        else:
            errors = self.errors
        return _Lines(
            self.p[idx], self.x_deg[idx], self.y_deg[idx], self.top[idx], self.n[idx], errors,
            self.wire, self.prior_sigma, self.config, self.turned[idx],
            None if self.acc is None else self.acc[idx],
            None if self.norm_var is None else self.norm_var[idx],
        )  # fmt: skip


@dataclass(frozen=True)
class _State:
    """The unknowns at one iterate and what the lines give there."""

    x: FloatArray  # G (3), [λ], θ_active
    normal: FloatArray  # the normal matrix (m × m)
    chi2: float
    u: FloatArray  # (k, 3)
    q: FloatArray  # (k, 3)
    shape: FloatArray  # (k,)
    design: FloatArray  # (k, 3, m): ∂rᵢ/∂x
    weights: FloatArray  # (k, 3, 3)
    scale_information: float
    residuals: FloatArray  # (k, 3): rᵢ = (I − uᵢuᵢᵀ)(G − qᵢ)
    # An accelerometer's gravity norms |(aᵢ − b)/(1 + s)| − 1, their design ∂/∂x and weights
    # (zero-sized for an inclinometer).
    norm_residuals: FloatArray  # (k,)
    norm_design: FloatArray  # (k, m)
    norm_weights: FloatArray  # (k,)


def _layout(lines: _Lines) -> tuple[bool, npt.NDArray[np.intp]]:
    """Whether λ is an unknown, and which shared parameters are."""
    return (not lines.wire.fixed), np.flatnonzero(lines.prior_sigma > 0)


def _verticals(lines: _Lines, theta: FloatArray) -> FloatArray:
    if lines.acc is not None:
        return accel_verticals(lines.acc, theta, lines.config.axes, lines.turned).u
    return corrected_verticals(
        lines.x_deg, lines.y_deg, lines.top, theta, lines.config, lines.turned
    ).u


def _norm_terms(
    lines: _Lines, theta: FloatArray, active: npt.NDArray[np.intp], m: int
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """An accelerometer's gravity-norm residuals, their design (k, m) over the unknowns and
    weights; empty for an inclinometer. The norms depend on θ only (the columns of G and λ are
    0), by central differences with the plumb lines' step."""
    if lines.acc is None or lines.norm_var is None:
        return np.zeros(0), np.zeros((0, m)), np.zeros(0)
    r = accel_norms(lines.acc, theta) - 1.0
    design = np.zeros((len(r), m))
    steps = JACOBIAN_STEP * lines.prior_sigma[active]
    first = m - len(active)
    for c, (j, h) in enumerate(zip(active, steps, strict=True)):
        up, down = theta.copy(), theta.copy()
        up[j] += h
        down[j] -= h
        design[:, first + c] = (accel_norms(lines.acc, up) - accel_norms(lines.acc, down)) / (
            2.0 * h
        )
    return r, design, 1.0 / lines.norm_var


def _evaluate(lines: _Lines, x: FloatArray, *, information: bool = False) -> _State:
    """Residuals, their design and weights, the normal matrix and χ² at ``x`` (and, with
    ``information``, what the lines alone say about λ)."""
    with_lam, active = _layout(lines)
    k = len(lines.p)
    g = x[:3]
    lam = x[3] if with_lam else lines.wire.scale_mm
    theta = np.zeros(len(lines.prior_sigma))
    theta[active] = x[3 + with_lam :]
    u = _verticals(lines, theta)
    shape = (
        np.ones(k)
        if lines.wire.model == "paper"
        else wire_shape_factor(np.einsum("ij,ij->i", u, lines.n), lines.wire.model)
    )
    q = lines.p + (lam * shape)[:, None] * lines.n
    d = g - q
    dist = np.linalg.norm(d, axis=1)
    packed = gls.line_weights(u.T[:, :, None], lines.n.T[:, :, None], dist[:, None], lines.errors)
    w = sym3.sym_to_full(np.stack([np.asarray(c)[:, 0] for c in packed]))  # (k, 3, 3)
    proj = np.eye(3) - u[:, :, None] * u[:, None, :]
    r = np.einsum("kij,kj->ki", proj, d)
    along = np.einsum("ki,ki->k", u, d)  # Lᵢ, signed
    du = np.empty((k, 3, len(active)))
    if len(active):
        steps = JACOBIAN_STEP * lines.prior_sigma[active]
        for c, (j, h) in enumerate(zip(active, steps, strict=True)):
            up, down = theta.copy(), theta.copy()
            up[j] += h
            down[j] -= h
            du[:, :, c] = (_verticals(lines, up) - _verticals(lines, down)) / (2.0 * h)
    # ∂(G − qᵢ)/∂x, every column on the plane ⊥ uᵢ, where the residual and the weights live
    # (a finite difference of a strongly corrected vertical is not exactly ⊥ uᵢ either)
    design = gls.line_design(u, lines.n, shape, with_lam, -along[:, None, None] * du)
    normal = np.einsum("kai,kab,kbj->ij", design, w, design)
    chi2 = float(np.einsum("ka,kab,kb->", r, w, r))
    nr, nd, nw = _norm_terms(lines, theta, active, design.shape[2])
    if len(nr):
        normal = normal + np.einsum("ki,k,kj->ij", nd, nw, nd)
        chi2 += float(np.sum(nw * nr * nr))
    info = 0.0
    if with_lam and information:
        # What the lines alone say about λ once G and θ are free (the prior left out).
        lam_col = 3
        rest = [i for i in range(normal.shape[0]) if i != lam_col]
        others = (
            normal[np.ix_(rest, rest)]
            + _prior_precision(lines, exclude_lam=True)[np.ix_(rest, rest)]
        )
        cross = normal[lam_col, rest]
        try:
            info = float(normal[lam_col, lam_col] - cross @ np.linalg.solve(others, cross))
        except np.linalg.LinAlgError:
            info = 0.0  # G is not determined without λ's prior: nothing said about λ alone
    return _State(x, normal, chi2, u, q, shape, design, w, max(info, 0.0), r, nr, nd, nw)


def _prior_precision(lines: _Lines, *, exclude_lam: bool = False) -> FloatArray:
    """The priors' precision on the unknowns (0 for G, and for λ when self-calibrated)."""
    with_lam, active = _layout(lines)
    diag = [0.0, 0.0, 0.0]
    if with_lam:
        est = lines.wire.estimate or exclude_lam
        diag.append(0.0 if est else 1.0 / lines.wire.scale_var_mm2)
    diag.extend(1.0 / lines.prior_sigma[active] ** 2)
    return np.diag(diag)


def _prior_mean(lines: _Lines) -> FloatArray:
    with_lam, active = _layout(lines)
    return np.array([0.0, 0.0, 0.0, *([lines.wire.scale_mm] if with_lam else []),
                     *np.zeros(len(active))])  # fmt: skip


def _solve(lines: _Lines, start: FloatArray) -> tuple[_State, FloatArray]:
    """Gauss-Newton from ``start``; the final state and the unknowns' covariance."""
    prec, mean = _prior_precision(lines), _prior_mean(lines)
    with_lam, active = _layout(lines)
    scale = np.concatenate([[1.0, 1.0, 1.0], [1.0] * with_lam, lines.prior_sigma[active]])
    x = start.copy()
    for _ in range(MAX_ITERATIONS):
        st = _evaluate(lines, x)
        grad = np.einsum("kai,kab,kb->i", st.design, st.weights, st.residuals) + prec @ (x - mean)
        grad += st.norm_design.T @ (st.norm_weights * st.norm_residuals)
        total = st.normal + prec
        try:
            step = -np.linalg.solve(total, grad)
        except np.linalg.LinAlgError:
            why = "the plumb lines are parallel or nearly so"
            if lines.wire.estimate:
                why += (
                    ", or a CoG shift absorbs the self-calibrated wire offsets (hang from "
                    "points on two faces or more, or drop --self-calibrate-wire)"
                )
            raise DegenerateGeometryError(
                "the suspensions do not determine the CoG with the shared sensor parameters "
                f"({why})"
            ) from None
        x = x + step
        if np.all(np.abs(step[:3]) < STEP_TOL_MM) and np.all(np.abs(step[3:]) < 1e-6 * scale[3:]):
            break
    st = _evaluate(lines, x, information=True)
    total = st.normal + prec
    cov = np.asarray(np.linalg.inv(total), dtype=float)
    dx = x - mean
    return replace(st, chi2=st.chi2 + float(dx @ prec @ dx)), cov


def _start(lines: _Lines) -> FloatArray:
    """The equal-weight point of the uncorrected lines, λ at its prior, θ = 0."""
    with_lam, active = _layout(lines)
    u = _verticals(lines, np.zeros(len(lines.prior_sigma)))
    g = gls.equal_weight_point(lines.p.T[:, :, None], u.T[:, :, None])[:, 0]
    return np.concatenate([g, [lines.wire.scale_mm] * with_lam, np.zeros(len(active))])


def _loo_statistic(state: _State, hessian: FloatArray, local: int) -> float:
    """χ²₂ of the ``local``-th line of ``state`` (the joint estimate of a set of lines, its
    Hessian ``hessian`` = normal matrix + priors) against the estimate of the others.

    One Gauss-Newton step from the joint estimate with the line's terms taken out (exact for
    the linearised problem, the usual leave-one-out update): ``H₋ᵢ = H − Mᵢᵀ Wᵢ Mᵢ``, the others'
    estimate ``x₋ᵢ = x + H₋ᵢ⁻¹ Mᵢᵀ Wᵢ rᵢ``, line ``i``'s residual there ``rᵢ + Mᵢ (x₋ᵢ − x)`` with
    covariance ``Sᵢ + Mᵢ H₋ᵢ⁻¹ Mᵢᵀ``.
    """
    u = state.u[local]
    uu = np.outer(u, u)
    m, w, r = state.design[local], state.weights[local], state.residuals[local]
    pull = m.T @ (w @ r)  # what the line pulls the joint estimate by
    if len(state.norm_residuals):  # the hang's gravity norm leaves with it
        dn, wn = state.norm_design[local], state.norm_weights[local]
        hessian = hessian - wn * np.outer(dn, dn)
        pull = pull + dn * (wn * state.norm_residuals[local])
    try:
        h_inv = np.linalg.inv(hessian - m.T @ w @ m)
    except np.linalg.LinAlgError:
        return 0.0  # the others do not determine an estimate: nothing to test against
    if not np.all(np.isfinite(h_inv)) or np.any(np.diag(h_inv) < 0):
        return 0.0
    r_other = r + m @ (h_inv @ pull)
    try:
        lateral = np.linalg.inv(w + uu) - uu
        v = lateral + m @ h_inv @ m.T
        wv = np.linalg.inv(v + uu) - uu
    except np.linalg.LinAlgError:
        return 0.0  # the others leave this line's residual undetermined: nothing to test
    return max(float(r_other @ wv @ r_other), 0.0)


def fit_shared(
    positions_mm: npt.ArrayLike,
    inc_x_deg: npt.ArrayLike,
    inc_y_deg: npt.ArrayLike,
    top_face_up: npt.ArrayLike,
    normals: npt.ArrayLike,
    errors: gls.LineErrors,
    wire: gls.WireTerm,
    prior_sigma: npt.ArrayLike,
    config: InclinometerConfig | None = None,
    ids: Sequence[str] | None = None,
    outlier_probability: float = tolerances.OUTLIER_PROBABILITY,
    sensor_turned: npt.ArrayLike | None = None,
    *,
    acc_g: npt.ArrayLike | None = None,
    norm_var_g2: npt.ArrayLike | None = None,
    verdicts: bool = True,
) -> SharedFit:
    """The CoG of one test's hangs with the shared sensor parameters (and λ) estimated jointly.

    Parameters
    ----------
    positions_mm : array_like, shape (k, 3)
        Nominal suspension points.
    inc_x_deg, inc_y_deg : array_like, shape (k,)
        Each hang's mean readings, as the device reports them.
    top_face_up : array_like of bool, shape (k,)
    normals : array_like, shape (k, 3)
        Bolt axes.
    errors : LineErrors
        The per-hang errors (play, wire scatter, the reading's own errors).
    wire : WireTerm
    prior_sigma : array_like, shape (7,) or (15,)
        Prior σ of each shared parameter (0: known to be 0, not estimated).
    config : InclinometerConfig, optional
    ids : sequence of str, optional
        Names of the hangs for the residuals (default their indices).
    outlier_probability : float
    sensor_turned : array_like of bool, shape (k,), optional
        Hangs read with the sensor turned 180° on its mount (reversals; default none): with
        the same point hung both ways, the zero offsets are determined.
    acc_g : array_like, shape (k, 3), optional
        An accelerometer's mean readings (g, its own axes; ``config.device`` must be
        ``"accelerometer"``): they replace the angles (pass zeros for those), the shared
        parameters are :data:`cadcog.rig.accelerometer.ACCEL_SHARED_PARAMETERS` (``prior_sigma``
        of shape (15,)), and each hang's gravity norm is a residual of its own
        (:func:`cadcog.rig.accelerometer.accel_norms`), with variance ``norm_var_g2`` (k,).
    verdicts : bool
        Each line's consistency verdict (default); False leaves :attr:`SharedFit.residuals`
        empty (a prediction at ideal readings needs none).

    Raises
    ------
    cadcog.core.errors.DegenerateGeometryError
        If the hangs do not determine the CoG. (Whether they determine λ is
        :attr:`SharedFit.scale_identified`.)

    Examples
    --------
    Five hangs of a 100 mm cube read by a sensor with every shared error; the hangs calibrate
    them, and the true CoG lies inside the estimate's 95 % ellipsoid:

    >>> from cadcog.rig.inclinometer import sensor_readings
    >>> g = np.array([50.0, 50.0, 40.0])
    >>> p = np.array([[20.0, 50, 100], [100, 30, 80], [70, 0, 70], [0, 60, 90], [80, 100, 60]])
    >>> n = np.array([[0, 0, 1.0], [1, 0, 0], [0, -1, 0], [-1, 0, 0], [0, 1, 0]])
    >>> u = (p - g) / np.linalg.norm(p - g, axis=1)[:, None]
    >>> x, y, top = sensor_readings(u, [0.3, -0.2, 0.01, 0, 0.4, -0.3, 0.2])
    >>> prior = [0.2, 0.2, 0.01, 0.01, 0.3, 0.3, 0.3]
    >>> fit = fit_shared(p, x, y, top, n, gls.LineErrors(1e-4, 1e-4, 1e-10), gls.WireTerm(), prior)
    >>> e = fit.cog_mm - g
    >>> bool(e @ np.linalg.solve(fit.cov_mm2, e) < 7.81), fit.calibrated.tolist()
    (True, [True, True, True, True, True, True, True])
    """
    p = np.atleast_2d(np.asarray(positions_mm, dtype=float))
    k = len(p)
    names = [str(j) for j in range(k)] if ids is None else list(ids)
    cfg = config or InclinometerConfig()
    if (acc_g is not None) != cfg.accelerometer or (acc_g is not None) != (norm_var_g2 is not None):
        raise ValueError("acc_g and norm_var_g2 go together, with an accelerometer's config")
    n_shared = len(shared_parameter_names(cfg))
    lines = _Lines(
        p,
        np.asarray(inc_x_deg, dtype=float).reshape(k),
        np.asarray(inc_y_deg, dtype=float).reshape(k),
        np.asarray(top_face_up, dtype=bool).reshape(k),
        np.atleast_2d(np.asarray(normals, dtype=float)),
        errors,
        wire,
        np.asarray(prior_sigma, dtype=float).reshape(n_shared),
        cfg,
        np.zeros(k, dtype=bool)
        if sensor_turned is None
        else np.asarray(sensor_turned, dtype=bool).reshape(k),
        None if acc_g is None else np.asarray(acc_g, dtype=float).reshape(k, 3),
        None if norm_var_g2 is None else np.asarray(norm_var_g2, dtype=float).reshape(k),
    )
    if np.any(lines.prior_sigma < 0):
        raise ValueError("prior σ of the shared sensor parameters must be non-negative")
    with_lam, active = _layout(lines)
    state, cov = _solve(lines, _start(lines))
    identified = with_lam and bool(
        gls.wire_scale_identified(
            state.scale_information, state.shape, np.trace(state.weights, axis1=1, axis2=2)
        )
    )
    shared = np.zeros(n_shared)
    shared_sigma = np.zeros(n_shared)
    off = 3 + with_lam
    shared[active] = state.x[off:]
    shared_sigma[active] = np.sqrt(np.diag(cov)[off:])
    # Each hang's gravity norm is one more observation.
    dof = 2 * k - 3 - (1 if wire.estimate else 0) + len(state.norm_residuals)
    residuals = _residuals(lines, state, names, dof, outlier_probability) if verdicts else []
    return SharedFit(
        state.x[:3].copy(),
        cov[:3, :3].copy(),
        float(state.x[3]) if with_lam else wire.scale_mm,
        float(np.sqrt(cov[3, 3])) if with_lam else 0.0,
        shared,
        shared_sigma,
        lines.prior_sigma.copy(),
        state.u,
        state.q,
        state.chi2,
        dof,
        tuple(residuals),
        state.scale_information,
        identified,
        gls.point_gain(cov, state.design, state.weights, with_lam),
        cov[:3, 3].copy() if with_lam else np.zeros(3),
    )


def _residuals(
    lines: _Lines, state: _State, ids: list[str], dof: int, outlier_probability: float
) -> list[LineResidual]:
    """Per-line verdicts, as :func:`cadcog.method.plumblines.line_consistency` gives them."""
    g = state.x[:3]
    distances = [PlumbLine(i, state.q[j], state.u[j]).distance_mm(g) for j, i in enumerate(ids)]

    solved: dict[tuple[int, ...], tuple[_State, FloatArray] | None] = {}

    def statistic(active: list[int], i: int) -> float:
        key = tuple(active)
        if key not in solved:  # the joint estimate of the lines still in, once per set
            sub = lines.take(active)
            try:
                st = state if len(active) == len(ids) else _solve(sub, state.x)[0]
                solved[key] = (st, st.normal + _prior_precision(sub))
            except DegenerateGeometryError:
                solved[key] = None
        found = solved[key]
        if found is None:
            return 0.0  # these lines do not determine an estimate: nothing to test against
        return _loo_statistic(found[0], found[1], active.index(i))

    return flag_lines(ids, distances, state.chi2, dof, statistic, outlier_probability)
