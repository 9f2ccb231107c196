"""The joint fit of :mod:`cadcog.method.sharedfit` over many simulated tests at once.

The Monte Carlo (``cadcog budget``, ``simulate``, ``plan``, ``validate``) draws one sensor per
simulated test when the rig declares the sensor's shared figures, and estimates each test as
``cadcog estimate`` does: the CoG jointly with the shared offsets, sensitivities and mounting
(and the wire scale λ when it is uncertain), by Gauss-Newton with their priors. This module is
that estimator vectorised over ``n`` tests of ``k`` hangs, component first like
:mod:`cadcog.method.gls` (vectors (3, k, n)), with what the simulated sensor does to a vertical
(:func:`sensor_errors_deg`).

The arithmetic is :func:`cadcog.method.sharedfit.fit_shared`'s: the same corrected verticals,
the same finite-difference step of ``∂u/∂θ``, the weights at the current distances, the same
priors and the same stopping rule. Each test stops when its own step is below the tolerance and
is not touched after: a test's estimate depends on its own readings only, never on which tests
share its batch (the Monte Carlo's results do not depend on the chunk size). The tests compare
it with :func:`~cadcog.method.sharedfit.fit_shared` test by test.

The device's axis signs are taken as +1: a shared error's distribution is symmetric, so the
signs change no statistic of the simulation.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import DegenerateGeometryError
from cadcog.method import gls, sym3
from cadcog.method.sharedfit import JACOBIAN_STEP, MAX_ITERATIONS, STEP_TOL_MM
from cadcog.method.wire import wire_shape_factor

FloatArray = npt.NDArray[np.float64]


def rotations(rotation_deg: FloatArray) -> FloatArray:
    """Rotation matrices (3, 3, n) of rotation vectors (3, n) in degrees (Rodrigues), element by
    element: :func:`cadcog.rig.inclinometer.rotation_matrix` of each column.

    Examples
    --------
    >>> r = rotations(np.array([[0.0, 0.0], [0.0, 0.0], [90.0, 0.0]]))
    >>> np.round(r[:, :, 0] @ [1.0, 0.0, 0.0], 12).tolist()
    [0.0, 1.0, 0.0]
    >>> bool(np.array_equal(r[:, :, 1], np.eye(3)))
    True
    """
    r = np.deg2rad(np.asarray(rotation_deg, dtype=float))
    angle = np.sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2])
    safe = np.where(angle > 0.0, angle, 1.0)
    kx, ky, kz = r[0] / safe, r[1] / safe, r[2] / safe
    s, c1 = np.sin(angle), 1.0 - np.cos(angle)
    return np.array(
        [
            [1.0 - c1 * (ky * ky + kz * kz), -s * kz + c1 * kx * ky, s * ky + c1 * kx * kz],
            [s * kz + c1 * kx * ky, 1.0 - c1 * (kx * kx + kz * kz), -s * kx + c1 * ky * kz],
            [-s * ky + c1 * kx * kz, s * kx + c1 * ky * kz, 1.0 - c1 * (kx * kx + ky * ky)],
        ]
    )


def turn(v: FloatArray, rot: FloatArray, *, transpose: bool = False) -> FloatArray:
    """``R v`` (or ``Rᵀ v``) for vectors (3, k, n) and one rotation (3, 3, n) per test."""
    r = rot.transpose(1, 0, 2) if transpose else rot
    return np.stack([r[i, 0] * v[0] + r[i, 1] * v[1] + r[i, 2] * v[2] for i in range(3)])


def sensor_errors_deg(u: FloatArray, shared: FloatArray) -> tuple[FloatArray, FloatArray]:
    """What a sensor with shared errors ``shared`` (7, n) adds to each channel's ideal angle of
    the upward verticals ``u`` (3, k, n), in degrees, and the verticals it sees.

    As :func:`cadcog.rig.inclinometer.sensor_readings` defines it: the sensor sees ``v = R u``
    and reports ``(1 + s) asin(v) + b``; the returned errors are ``s·asin(v) + b`` per channel,
    with ``v``: the caller adds them (and the per-hang errors) to ``asin(v)``.

    Returns
    -------
    errors : ndarray, shape (2, k, n)
    seen : ndarray, shape (3, k, n)
    """
    v = turn(u, rotations(shared[4:7]))
    ang = np.rad2deg(np.arcsin(np.clip(v[:2], -1.0, 1.0)))
    err = ang * shared[2:4, None, :] + shared[0:2, None, :]
    return np.asarray(err), v


def corrected(
    x_deg: FloatArray, y_deg: FloatArray, up: FloatArray, theta: FloatArray
) -> FloatArray:
    """Upward verticals (3, k, n) from readings (k, n) with the shared errors ``theta`` (7, n)
    removed: :func:`cadcog.rig.inclinometer.corrected_verticals` of every test (``up``: the
    sign of the z component, ±1)."""
    sx = np.sin(np.deg2rad((x_deg - theta[0]) / (1.0 + theta[2])))
    sy = np.sin(np.deg2rad((y_deg - theta[1]) / (1.0 + theta[3])))
    r2 = sx * sx + sy * sy
    over = r2 > 1.0
    if np.any(over):
        scale = np.where(over, 1.0 / np.sqrt(np.where(over, r2, 1.0)), 1.0)
        sx, sy = sx * scale, sy * scale
    sz = np.where(over, 0.0, up * np.sqrt(np.clip(1.0 - sx * sx - sy * sy, 0.0, None)))
    return turn(np.stack([sx, sy, sz]), rotations(theta[4:7]), transpose=True)


def _sym_apply(w: tuple[FloatArray, ...], d: FloatArray) -> FloatArray:
    """``W d`` for packed ``W`` (6, k, n) and columns ``d`` (3, m, k, n)."""
    return np.stack(
        [
            w[0] * d[0] + w[3] * d[1] + w[4] * d[2],
            w[3] * d[0] + w[1] * d[1] + w[5] * d[2],
            w[4] * d[0] + w[5] * d[1] + w[2] * d[2],
        ]
    )


def fit_shared_cog(
    points_mm: FloatArray,
    x_deg: FloatArray,
    y_deg: FloatArray,
    up: FloatArray,
    normals: FloatArray,
    errors: gls.LineErrors,
    wire: gls.WireTerm,
    prior_sigma: npt.ArrayLike,
) -> FloatArray:
    """The CoG (3, n) of :func:`cadcog.method.sharedfit.fit_shared` for each of ``n`` tests.

    Parameters
    ----------
    points_mm, normals : ndarray, shape (3, k, 1) or (3, k, n)
        Nominal suspension points and bolt axes.
    x_deg, y_deg : ndarray, shape (k, n)
        Each hang's readings, in the sensor's own axes.
    up : ndarray, shape (k, n)
        +1 where the top face is up, −1 where it is down.
    errors, wire : as for :func:`~cadcog.method.sharedfit.fit_shared`
    prior_sigma : array_like, shape (7,)

    Raises
    ------
    cadcog.core.errors.DegenerateGeometryError
        If the hangs of some test do not determine its CoG.
    """
    prior = np.asarray(prior_sigma, dtype=float).reshape(7)
    active = np.flatnonzero(prior > 0)
    with_lam = not wire.fixed
    k, n = x_deg.shape
    m = 3 + with_lam + len(active)
    lam_at = 3 if with_lam else None
    theta_at = 3 + with_lam
    prec = np.zeros(m)
    mean = np.zeros(m)
    if with_lam:
        prec[3] = 0.0 if wire.estimate else 1.0 / wire.scale_var_mm2
        mean[3] = wire.scale_mm
    prec[theta_at:] = 1.0 / prior[active] ** 2
    tol = np.concatenate([[STEP_TOL_MM] * 3, [1e-6] * with_lam, 1e-6 * prior[active]])
    steps = JACOBIAN_STEP * prior[active]

    def theta_of(x: FloatArray) -> FloatArray:
        th = np.zeros((7, x.shape[1]))
        th[active] = x[theta_at:]
        return th

    def verticals(x: FloatArray, sel: npt.NDArray[np.intp]) -> FloatArray:
        return corrected(x_deg[:, sel], y_deg[:, sel], up[:, sel], theta_of(x))

    def take(a: FloatArray, sel: npt.NDArray[np.intp]) -> FloatArray:
        return a if a.shape[-1] == 1 else a[..., sel]

    u0 = corrected(x_deg, y_deg, up, np.zeros((7, n)))
    x = np.zeros((m, n))
    x[:3] = gls.equal_weight_point(points_mm, u0)
    if with_lam:
        x[3] = wire.scale_mm
    todo = np.arange(n)
    for _ in range(MAX_ITERATIONS):
        if not len(todo):
            break
        xs = x[:, todo]
        p, nrm = take(points_mm, todo), take(normals, todo)
        u = verticals(xs, todo)
        lam = xs[3] if with_lam else wire.scale_mm
        shape = (
            np.ones(u.shape[1:])
            if wire.model == "paper"
            else wire_shape_factor(sym3.dot3(u, nrm), wire.model)
        )
        q = p + (lam * shape) * nrm
        d = xs[:3, None, :] - q
        dist2 = sym3.dot3(d, d)
        e1, e2, mm = gls.lateral_2d(u, nrm, dist2, errors)
        w = gls.assemble(e1, e2, *gls.inverse_2d(mm))
        along = sym3.dot3(u, d)
        proj = sym3.projector(u)
        cols = np.zeros((3, m, k, len(todo)))
        for a in range(3):
            cols[a, a] = 1.0
        if with_lam:
            cols[:, lam_at] = -(shape * nrm)
        for c, h in enumerate(steps):
            up_x, down_x = xs.copy(), xs.copy()
            up_x[theta_at + c] += h
            down_x[theta_at + c] -= h
            du = (verticals(up_x, todo) - verticals(down_x, todo)) / (2.0 * h)
            cols[:, theta_at + c] = -along * du
        design = _sym_apply(proj, cols)  # every column on the plane ⊥ uᵢ
        r = np.stack(sym3.sym_matvec(proj, d))
        wd = _sym_apply(w, design)  # (3, m, k, n)
        # Sums over the hangs row by row (sym3.rows_sum): numpy's reduction would add eight or
        # more hangs in another order for a lone campaign than in a batch.
        normal = np.empty((len(todo), m, m))
        for c in range(m):
            per_hang = np.sum(design[:, c][:, None] * wd, axis=0)  # (m, k, n)
            normal[:, c, :] = sym3.rows_sum(np.moveaxis(per_hang, 1, 0)).T
        grad = sym3.rows_sum(np.moveaxis(np.sum(wd * r[:, None], axis=0), 1, 0))
        grad = grad + prec[:, None] * (xs - mean[:, None])
        normal[:, np.arange(m), np.arange(m)] += prec
        try:
            step = -np.linalg.solve(normal, grad.T[:, :, None])[:, :, 0].T
        except np.linalg.LinAlgError:
            raise DegenerateGeometryError(
                "the suspensions do not determine the CoG with the shared sensor parameters "
                "(the plumb lines are parallel or nearly so)"
            ) from None
        x[:, todo] = xs + step
        done = np.all(np.abs(step) < tol[:, None], axis=0)
        todo = todo[~done]
    return np.asarray(x[:3])
