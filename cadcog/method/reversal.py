"""Which reversal would help: the same point hung again with the sensor turned 180° on its mount.

A sensor turned on its mount reads ``−A + b`` where it read ``A + b`` (:func:`cadcog.rig.
inclinometer.sensor_readings`): the two readings of one point tell its zero offset ``b`` apart
from the angle, which no set of plain hangs does as directly. How much that is worth depends on
the set: it is the CoG's covariance of the joint fit (:func:`cadcog.method.sharedfit.fit_shared`)
at the nominal readings, with and without the turned hang, linearised (the fit at noise-free
readings converges to the truth and its covariance is the estimator's, ``cadcog estimate``'s).
The turned hang is a hang of its own (the object taken down and hung again), with its own play
and reading errors: what the re-hang does not reproduce limits what it tells.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.method import gls, sharedfit
from cadcog.method.wire import wire_shape_factor
from cadcog.rig.inclinometer import SHARED_SENSOR_PARAMETERS, InclinometerConfig, sensor_readings

FloatArray = npt.NDArray[np.float64]

#: A reversal is advised when it shrinks the CoG's linearised σ (√trace) by at least this
#: fraction: below it, another hang of the set is worth as much.
MIN_GAIN = 0.05


@dataclass(frozen=True)
class ReversalAdvice:
    """The best single reversal for a set of hangs, by the joint fit's linearised covariance.

    Attributes
    ----------
    point : str
        The point to hang again with the sensor turned.
    sigma_mm, sigma_with_mm : float
        The compensated CoG's σ (√trace of its covariance) without and with it.
    offset_sigma_deg, offset_sigma_with_deg : tuple of 2 floats
        The zero offsets' posterior σ (x, y) without and with it.
    advised : bool
        Whether the gain reaches :data:`MIN_GAIN`.
    """

    point: str
    sigma_mm: float
    sigma_with_mm: float
    offset_sigma_deg: tuple[float, float]
    offset_sigma_with_deg: tuple[float, float]
    advised: bool

    def to_dict(self) -> dict[str, Any]:
        return {
            "point": self.point,
            "sigma_mm": self.sigma_mm,
            "sigma_with_reversal_mm": self.sigma_with_mm,
            "offset_sigma_deg": list(self.offset_sigma_deg),
            "offset_sigma_with_reversal_deg": list(self.offset_sigma_with_deg),
            "advised": self.advised,
        }


def _nominal_verticals(
    points_mm: FloatArray, normals: FloatArray, cog_mm: FloatArray, wire: gls.WireTerm
) -> FloatArray:
    """Each hang's true vertical with the expected wire offset (a fixed point in θ)."""
    q = points_mm.copy()
    for _ in range(5):
        u = (q - cog_mm) / np.linalg.norm(q - cog_mm, axis=1, keepdims=True)
        shape = wire_shape_factor(np.sum(u * normals, axis=1), wire.model)
        q = points_mm + (wire.scale_mm * shape)[:, None] * normals
    return np.asarray((q - cog_mm) / np.linalg.norm(q - cog_mm, axis=1, keepdims=True))


def _fit(
    points_mm: FloatArray,
    normals: FloatArray,
    cog_mm: FloatArray,
    turned: npt.NDArray[np.bool_],
    errors: gls.LineErrors,
    wire: gls.WireTerm,
    prior: FloatArray,
    config: InclinometerConfig,
) -> sharedfit.SharedFit:
    u = _nominal_verticals(points_mm, normals, cog_mm, wire)
    x, y, top = sensor_readings(u, np.zeros(7), config, turned)
    return sharedfit.fit_shared(
        points_mm, x, y, top, normals, errors, wire, prior, config, sensor_turned=turned
    )


def best_reversal(
    ids: Sequence[str],
    points_mm: npt.ArrayLike,
    normals: npt.ArrayLike,
    cog_mm: npt.ArrayLike,
    errors: gls.LineErrors,
    wire: gls.WireTerm,
    prior_sigma: npt.ArrayLike,
    config: InclinometerConfig | None = None,
    *,
    me_ratio: float = 0.0,
    me_sigma_mm: float = 0.0,
) -> ReversalAdvice | None:
    """The reversal of one of the set's points that shrinks the CoG's σ the most.

    Parameters
    ----------
    ids : sequence of str, length k
    points_mm, normals : array_like, shape (k, 3)
        The set's suspension points and bolt axes.
    cog_mm : array_like, shape (3,)
        The hung assembly's expected CoG.
    errors, wire : the estimator's line errors and wire term
    prior_sigma : array_like, shape (7,)
        The shared parameters' prior σ (:attr:`cadcog.method.errormodel.ErrorModel.
        shared_sensor_sigmas`).
    config : InclinometerConfig, optional
    me_ratio, me_sigma_mm : float
        ``m_ME/m`` and the ME's CoG σ per axis: the compensation (eq. 16) of both σ.

    Returns
    -------
    ReversalAdvice or None
        None when no zero offset is declared (a reversal cancels nothing then).

    Examples
    --------
    Three hangs of a 100 mm cube read by a sensor with a ±0.3° zero offset: turning it on one
    point's re-hang determines the offsets better and shrinks the CoG's σ.

    >>> p = np.array([[20.0, 50, 100], [100, 30, 80], [0, 60, 90]])
    >>> n = np.array([[0, 0, 1.0], [1, 0, 0], [-1, 0, 0]])
    >>> prior = [0.3 / 3**0.5] * 2 + [0.0] * 5
    >>> errors = gls.LineErrors(0.08, 0.0, np.radians(0.06) ** 2)
    >>> a = best_reversal(["A", "B", "C"], p, n, [50, 50, 40], errors, gls.WireTerm(), prior)
    >>> a.sigma_with_mm < a.sigma_mm, a.offset_sigma_with_deg[0] < a.offset_sigma_deg[0]
    (True, True)
    """
    prior = np.asarray(prior_sigma, dtype=float).reshape(7)
    if not np.any(prior[:2] > 0):
        return None
    cfg = config or InclinometerConfig()
    p = np.asarray(points_mm, dtype=float)
    n = np.asarray(normals, dtype=float)
    g = np.asarray(cog_mm, dtype=float)
    k = len(p)
    off = [SHARED_SENSOR_PARAMETERS.index(f"offset_{a}_deg") for a in "xy"]

    def sigma(fit: sharedfit.SharedFit) -> float:
        cov = (1.0 + me_ratio) ** 2 * fit.cov_mm2 + (me_ratio * me_sigma_mm) ** 2 * np.eye(3)
        return float(np.sqrt(np.trace(cov)))

    def reading_errors(rows: list[int]) -> gls.LineErrors:
        var = errors.reading_var_rad2
        if isinstance(var, np.ndarray) and var.ndim and var.shape[0] == k:
            return gls.LineErrors(
                errors.play_var_mm2, errors.axial_var_mm2, var[rows], errors.point_var_mm2
            )
        return errors

    base = _fit(p, n, g, np.zeros(k, dtype=bool), errors, wire, prior, cfg)
    best: tuple[float, int, sharedfit.SharedFit] | None = None
    for j in range(k):
        rows = [*range(k), j]
        turned = np.array([False] * k + [True])
        fit = _fit(p[rows], n[rows], g, turned, reading_errors(rows), wire, prior, cfg)
        s = sigma(fit)
        if best is None or s < best[0]:
            best = (s, j, fit)
    assert best is not None
    s_with, j, fit = best
    s0 = sigma(base)
    return ReversalAdvice(
        str(ids[j]),
        s0,
        s_with,
        (float(base.shared_sigma[off[0]]), float(base.shared_sigma[off[1]])),
        (float(fit.shared_sigma[off[0]]), float(fit.shared_sigma[off[1]])),
        bool(s_with < (1.0 - MIN_GAIN) * s0),
    )
