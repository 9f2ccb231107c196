"""The trial model of the Monte Carlo: a scenario, its error draws, one hang, one estimate.

:class:`Scenario` (the points, their bolt axes, the true CoG and the ME), the estimator's
options, the error draws of one batch of campaigns (:func:`draw_perturbations`), the physics of
one hang (:func:`hang`: the true vertical from the true virtual suspension point), the reading
of it, and the estimate of a group of hangs compensated for the ME (:func:`estimate_trials`,
:func:`group_errors`, :func:`propagate`). :mod:`cadcog.uncertainty.montecarlo` streams these
over many campaigns; :mod:`cadcog.uncertainty.error_budget` differentiates :func:`propagate`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.units import STANDARD_GRAVITY_M_S2
from cadcog.method.errormodel import ErrorModel
from cadcog.method.gls import GLSBatch, LineErrors, WireTerm, plumb_gls
from cadcog.method.preparedlines import cog_only
from cadcog.method.sharedbatch import fit_shared_cog, sensor_errors_deg
from cadcog.method.wire import wire_shape_factor
from cadcog.rig.parameters import Rig

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class Scenario:
    """The physical set-up: nominal suspension points and the true mass properties.

    Attributes
    ----------
    ids : tuple of str
    points_mm : ndarray, shape (n, 3)
        Nominal suspension points (where the wire leaves the object).
    normals : ndarray, shape (n, 3)
        Outward unit normals (bolt axes).
    pm_cog_mm : ndarray, shape (3,)
        True CoG of the object (proof mass), from the CAD ground truth.
    pm_mass_kg, me_mass_kg : float
    me_cog_mm : ndarray, shape (3,)
        CAD CoG of the measurement equipment.
    """

    ids: tuple[str, ...]
    points_mm: FloatArray
    normals: FloatArray
    pm_cog_mm: FloatArray
    pm_mass_kg: float
    me_mass_kg: float
    me_cog_mm: FloatArray

    @property
    def total_mass_kg(self) -> float:
        return self.pm_mass_kg + self.me_mass_kg

    @property
    def assembly_cog_mm(self) -> FloatArray:
        return np.asarray(
            (self.pm_mass_kg * self.pm_cog_mm + self.me_mass_kg * self.me_cog_mm)
            / self.total_mass_kg
        )

    @property
    def weight_n(self) -> float:
        return self.total_mass_kg * STANDARD_GRAVITY_M_S2

    @cached_property
    def tangents(self) -> tuple[FloatArray, FloatArray]:
        """Two unit vectors spanning each point's face plane, each of shape (n, 3)."""
        return _tangents(self.normals)

    def with_points(
        self, ids: Sequence[str], points_mm: npt.ArrayLike, normals: npt.ArrayLike
    ) -> Scenario:
        return Scenario(
            tuple(ids),
            np.asarray(points_mm, dtype=float),
            np.asarray(normals, dtype=float),
            self.pm_cog_mm,
            self.pm_mass_kg,
            self.me_mass_kg,
            self.me_cog_mm,
        )

    @classmethod
    def from_rig(cls, rig: Rig) -> Scenario:
        """The rig's own suspension points; masses and CoGs from its CAD closed forms."""
        pts = [rig.wire_exit_mm(p) for p in rig.suspension_points]
        return cls(
            tuple(p.id for p in rig.suspension_points),
            np.array(pts),
            np.array([p.normal for p in rig.suspension_points]),
            rig.analytic_proof_mass.cog_mm,
            rig.proof_mass.mass_kg,
            rig.analytic_me.mass_kg,
            rig.analytic_me.cog_mm,
        )


@dataclass(frozen=True)
class EstimatorOptions:
    """How the simulated user estimates: by default exactly as ``cadcog estimate`` does.

    Attributes
    ----------
    weighted : bool
        True: the generalised least squares of :func:`cadcog.method.gls.plumb_gls` with each line's
        covariance from the error model. False: equal weights (eq. 8 for a pair), the paper's.
    wire_correction : bool
        Move each nominal point along its bolt axis by the wire offset the model expects.
    self_calibrate : bool
        Estimate the wire offset scale λ with the CoG (three or more hangs).
    """

    weighted: bool = True
    wire_correction: bool = True
    self_calibrate: bool = False

    @classmethod
    def paper(cls) -> EstimatorOptions:
        """The paper's estimator: eq. 8 (equal weights), no wire correction."""
        return cls(weighted=False, wire_correction=False)

    def describe(self) -> dict[str, Any]:
        return {
            "estimator": "generalised least squares" if self.weighted else "equal weights (eq. 8)",
            "wire_correction": self.wire_correction,
            "wire_self_calibration": self.self_calibrate,
        }


def _tangents(normals: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Two unit vectors spanning each face plane; normals of shape (k, 3)."""
    helper = np.where(np.abs(normals[:, [0]]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])
    t1 = np.cross(normals, helper)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return t1, np.cross(normals, t1)


# The vectorised kernels below hold vectors as components first, shape (3, ...): each component
# is then a contiguous array, which makes the element-wise maths several times faster than on
# (..., 3) arrays.


def _dot(a: FloatArray, b: FloatArray) -> FloatArray:
    """Dot product of component-first arrays, shape (3, ...) → (...)."""
    return np.asarray(a[0] * b[0] + a[1] * b[1] + a[2] * b[2])


def _unit(v: FloatArray) -> FloatArray:
    return np.asarray(v / np.sqrt(_dot(v, v)))


def _measured_verticals(
    u_true: FloatArray, err_x: FloatArray, err_y: FloatArray, up: FloatArray | None = None
) -> FloatArray:
    """Readings of the true verticals plus errors (degrees), back through eq. 2.

    ``u_true`` is component-first, shape (3, ...). ``sin(asin(u) + e)`` is evaluated as
    ``u cos e + √(1 − u²) sin e`` with ``cos e = √(1 − sin² e)`` (|e| < 90°), which avoids the
    arcsine and the cosine. The z component takes the sign of ``up`` (default ``u_true``'s own):
    the top-face-up flag is the object's, when ``u_true`` is what a turned sensor sees.
    """
    ex = np.sin(np.deg2rad(err_x))
    ey = np.sin(np.deg2rad(err_y))
    ux, uy = u_true[0], u_true[1]
    sx = ux * np.sqrt(1.0 - ex * ex) + np.sqrt(np.maximum(1.0 - ux * ux, 0.0)) * ex
    sy = uy * np.sqrt(1.0 - ey * ey) + np.sqrt(np.maximum(1.0 - uy * uy, 0.0)) * ey
    r2 = sx * sx + sy * sy
    over = r2 > 1.0
    if np.any(over):  # the paper's normalisation, rare: only near the horizontal
        scale = np.where(over, 1.0 / np.sqrt(np.where(over, r2, 1.0)), 1.0)
        sx, sy = sx * scale, sy * scale
        r2 = np.where(over, 1.0, r2)
    sz = np.copysign(np.sqrt(np.maximum(1.0 - r2, 0.0)), u_true[2] if up is None else up)
    return np.stack([sx, sy, sz])


@dataclass(frozen=True)
class Perturbations:
    """Random draws of one batch of n campaigns (trials) of k hangs each.

    Attributes
    ----------
    me_mm : ndarray, shape (3, n)
        ME CoG error (component-first, like every array here).
    play_mm : ndarray, shape (2, k, n)
        Suspension-point play along the two face tangents.
    wire : ndarray, shape (k, n) or (1, n)
        Paper wire model: the offset of each hang along its bolt axis (mm). One wire: λ (mm),
        one per trial. Elastica: the factor on λ, one per trial (the campaign's one wire).
    reading_deg : ndarray, shape (2, k, n)
        X and Y reading errors of each hang.
    shared : ndarray, shape (7, n), optional
        The sensor's errors shared by the hangs of a campaign
        (:data:`cadcog.rig.inclinometer.SHARED_SENSOR_PARAMETERS`); None: none.
    """

    me_mm: FloatArray
    play_mm: FloatArray
    wire: FloatArray
    reading_deg: FloatArray
    shared: FloatArray | None = None


def draw_perturbations(
    model: ErrorModel, rng: np.random.Generator, n: int, k: int
) -> Perturbations:
    """Draw every enabled error source for ``n`` trials of ``k`` suspensions (others are 0).

    Draws are single precision (an error needs no more than 7 digits; it halves their cost).
    What is computed from them is double precision, but for the sine of a reading error and its
    cosine (:func:`_measured_verticals`), single precision like the error itself. The sensor's
    shared errors, when the model declares them, are drawn last (one sensor per campaign), so a
    model without them draws the same numbers as before they existed.
    """
    model.require_angle_sensor("the Monte Carlo")
    me = model.sample_me_errors(rng, n)
    play = model.sample_play(rng, n, k)
    wire = model.sample_wire(rng, n, k)
    reading = model.sample_reading_errors(rng, (2, k, n))
    shared = model.sample_shared_sensor(rng, n) if model.has_shared_sensor else None
    return Perturbations(me, play, wire, reading, shared)


def hang(
    scenario: Scenario, model: ErrorModel, group: Sequence[int], pert: Perturbations
) -> FloatArray:
    """True upward verticals when hanging from each point of ``group``: shape (3, k, n).

    The object hangs from the *true* virtual suspension point (nominal point + play + wire
    offset along the bolt axis) and its true assembly CoG (CAD + the ME's CoG error):
    :func:`true_pivots`.
    """
    pivots, g_true, _ = true_pivots(scenario, model, group, pert)
    return verticals(pivots, g_true)


def verticals(pivots_mm: FloatArray, cog_mm: FloatArray) -> FloatArray:
    """The upward verticals of hanging from ``pivots_mm`` (3, k, n) with the CoG at ``cog_mm``
    (3, 1, n), as :func:`true_pivots` gives them: unit vectors (3, k, n)."""
    return _unit(pivots_mm - cog_mm)


def true_pivots(
    scenario: Scenario, model: ErrorModel, group: Sequence[int], pert: Perturbations
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The drawn truth of hanging from each point of ``group``: the true virtual suspension
    points (3, k, n), the true assembly CoG (3, 1, n) and the wire's offset scale ``λ`` (1, n)
    the hangs share (0 for the paper's per-hang offsets)."""
    idx = np.asarray(group)
    ratio = scenario.me_mass_kg / scenario.total_mass_kg
    g_true = (scenario.assembly_cog_mm[:, None] + ratio * pert.me_mm)[:, None, :]  # (3, 1, n)
    p = scenario.points_mm[idx].T[:, :, None]  # (3, k, 1)
    nrm = scenario.normals[idx].T[:, :, None]
    t1, t2 = (t[idx].T[:, :, None] for t in scenario.tangents)
    q = p + pert.play_mm[0] * t1 + pert.play_mm[1] * t2  # (3, k, n)
    lam = np.zeros((1, q.shape[2]))
    if model.wire_model == "paper":
        delta = pert.wire
    elif "wire_offset" in model.sources:
        lam = (
            pert.wire
            if model.wire_model == "one-wire"
            else model.wire_length_mm(scenario.weight_n) * pert.wire
        )
        delta = lam * np.ones(q.shape[1:])
        for _ in range(3):  # θ depends on the offset only weakly: a fixed point converges
            u0 = _unit(q + delta * nrm - g_true)
            delta = lam * wire_shape_factor(_dot(u0, nrm), "elastica")
    else:
        delta = np.zeros(q.shape[1:])
    return q + delta * nrm, g_true, np.asarray(lam, dtype=float)


def estimate_trials(
    scenario: Scenario,
    model: ErrorModel,
    group: Sequence[int],
    pert: Perturbations,
    options: EstimatorOptions = EstimatorOptions(),
) -> GLSBatch:
    """The user's estimate of the assembly CoG in every trial, from nominal points and readings.

    Deterministic: the physics (:func:`hang`), the readings with their errors, and the same
    estimator as ``cadcog estimate`` (:func:`cadcog.method.gls.plumb_gls`) on the nominal points.
    The per-hang estimator with its covariances: a model with the sensor's shared errors is
    estimated by :func:`group_errors` (the joint fit gives the CoG only here).

    Raises
    ------
    ValueError
        If ``model`` declares shared sensor errors.
    """
    if model.has_shared_sensor:
        raise ValueError(
            "estimate_trials is the per-hang estimator: a model with shared sensor errors is "
            "estimated by group_errors"
        )
    idx = np.asarray(group)
    p = scenario.points_mm[idx].T[:, :, None]  # (3, k, 1)
    nrm = scenario.normals[idx].T[:, :, None]
    u_true = hang(scenario, model, group, pert)
    u = _measured_verticals(u_true, pert.reading_deg[0], pert.reading_deg[1])
    wire = WireTerm.from_model(
        model,
        scenario.weight_n,
        correct=options.wire_correction,
        estimate=options.self_calibrate,
    )
    return plumb_gls(p, u, nrm, LineErrors.from_model(model), wire, weighted=options.weighted)


def compensated_errors(scenario: Scenario, assembly_cog_mm: FloatArray) -> FloatArray:
    """Errors (mm), shape (n, 3), of the ME-compensated CoG (eq. 10) of estimates (3, n)."""
    r_pm = (
        scenario.total_mass_kg * assembly_cog_mm.T - scenario.me_mass_kg * scenario.me_cog_mm
    ) / (scenario.pm_mass_kg)
    return np.asarray(r_pm - scenario.pm_cog_mm)


def measured_verticals(
    scenario: Scenario, model: ErrorModel, group: Sequence[int], pert: Perturbations
) -> FloatArray:
    """What the inclinometer reads hanging from each point of ``group``: unit verticals (3, k, n).

    The physics (:func:`hang`) and the reading errors of ``pert`` back through eq. 2. With shared
    sensor errors the sensor sees each vertical turned by its mounting and adds its offsets and
    sensitivity errors (:func:`cadcog.method.sharedbatch.sensor_errors_deg`) to each hang's
    errors; what is returned is then eq. 2 of the readings as the device reports them (not
    corrected: the estimator does that), its z sign the object's.
    """
    u_true = hang(scenario, model, group, pert)
    if pert.shared is None or not np.any(pert.shared):
        return _measured_verticals(u_true, pert.reading_deg[0], pert.reading_deg[1])
    err, seen = sensor_errors_deg(u_true, np.asarray(pert.shared, dtype=float))
    return _measured_verticals(
        seen, pert.reading_deg[0] + err[0], pert.reading_deg[1] + err[1], up=u_true[2]
    )


def group_errors(
    scenario: Scenario,
    model: ErrorModel,
    group: Sequence[int],
    u: FloatArray,
    options: EstimatorOptions = EstimatorOptions(),
) -> FloatArray:
    """CoG errors (estimated − true, mm), shape (n, 3), of ``group``'s estimates from readings.

    The estimator of ``cadcog estimate`` on the nominal points and the measured verticals ``u``
    (3, k, n), through its CoG-only path :func:`cadcog.method.preparedlines.cog_only`, then the ME
    compensation with the ME's CAD CoG. When the model declares the sensor's shared errors,
    ``cadcog estimate`` fits them with the CoG, and so does this
    (:func:`cadcog.method.sharedbatch.fit_shared_cog` of the readings ``u`` gives back); the
    paper's equal-weight estimator (``options.weighted`` False) knows nothing of them.
    """
    idx = np.asarray(group)
    p = scenario.points_mm[idx].T[:, :, None]
    nrm = scenario.normals[idx].T[:, :, None]
    wire = WireTerm.from_model(
        model, scenario.weight_n, correct=options.wire_correction, estimate=options.self_calibrate
    )
    errors = LineErrors.from_model(model)
    if options.weighted and model.has_shared_sensor:
        x_deg = np.rad2deg(np.arcsin(np.clip(u[0], -1.0, 1.0)))
        y_deg = np.rad2deg(np.arcsin(np.clip(u[1], -1.0, 1.0)))
        up = np.where(np.signbit(u[2]), -1.0, 1.0)
        cog = fit_shared_cog(p, x_deg, y_deg, up, nrm, errors, wire, model.shared_sensor_sigmas)
    else:
        cog = cog_only(p, u, nrm, errors, wire, weighted=options.weighted)
    return compensated_errors(scenario, cog)


def propagate(
    scenario: Scenario,
    model: ErrorModel,
    group: Sequence[int],
    pert: Perturbations,
    options: EstimatorOptions = EstimatorOptions(),
) -> FloatArray:
    """CoG errors (estimated − true, mm), shape (n, 3), for given perturbations.

    Deterministic: :func:`measured_verticals` then :func:`group_errors` (what
    :func:`estimate_trials` does, through the estimator's CoG-only path).
    """
    u = measured_verticals(scenario, model, group, pert)
    return group_errors(scenario, model, group, u, options)


def simulate_block(
    scenario: Scenario,
    model: ErrorModel,
    group: Sequence[int],
    n: int,
    rng: np.random.Generator,
    options: EstimatorOptions = EstimatorOptions(),
) -> FloatArray:
    """CoG errors of ``n`` random trials suspending from ``group``; shape (n, 3)."""
    pert = draw_perturbations(model, rng, n, len(group))
    return propagate(scenario, model, group, pert, options)
