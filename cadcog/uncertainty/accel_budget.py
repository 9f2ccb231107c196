"""What an accelerometer (a phone, an ADXL355, an MPU-6050) will give, said before the test:
``cadcog budget`` and ``cadcog plan`` for ``device = "accelerometer"``.

The prediction is the estimator's own covariance at the readings the CAD predicts (a
linearisation): the hangs' ideal readings are those of a sensor without error hanging the CAD's
assembly, and :func:`cadcog.method.sharedfit.fit_shared` is run on them with the set-up's
declared figures, exactly as ``cadcog estimate`` runs on real readings. Its covariance is what
the estimate will state; ``benchmarks/study_phone_logs.py`` checks on an independent model of
the logs that the stated covariance covers the truth (docs/bench.md). Without self-calibration,
the shared errors are not estimated: their declared spread goes through the estimate's
sensitivity ``∂G/∂θ`` into the CoG, on top of the lines' own covariance.

A hang's reading error in the prediction is the declared ``accuracy_g`` (uniform ±) alone: the
noise of a mean of 10 s of samples is a few tens of µg for the three parts in the docs, against
an ``accuracy_g`` of 1 mg.

The 95 % error is the 95th percentile of ``|e|`` for ``e ~ N(0, C)`` (:func:`q95_mm`). Which hangs
to make: from the best pair, the hang (a candidate point, or the reversal of one already in
the set: the same point with the sensor turned 180° on its mount) that lowers it most is added,
one at a time (:func:`grow`); at each step the :data:`SCREEN_KEEP` candidates best without
the shared errors are the ones compared with them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from itertools import combinations
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import DegenerateGeometryError
from cadcog.core.results import JsonResult
from cadcog.method import gls, sharedfit
from cadcog.method.errormodel import ErrorModel
from cadcog.method.wire import wire_shape_factor
from cadcog.rig.accelerometer import ACCEL_SHARED_PARAMETERS, accel_readings
from cadcog.rig.inclinometer import InclinometerConfig

FloatArray = npt.NDArray[np.float64]

#: Draws of the normal the 95 % error is the percentile of (fixed seed: the same answer).
Q95_DRAWS = 40_000
#: A hang's suffix for the reversal of a point (as in ``--points``).
REVERSAL = "~"
#: Candidates kept at each step after a first screening without the shared errors (their
#: joint fit costs a dozen finite differences a step).
SCREEN_KEEP = 8


def q95_mm(cov_mm2: npt.ArrayLike, seed: int = 0) -> float:
    """The 95th percentile of ``|e|`` for ``e ~ N(0, cov)`` (mm).

    Examples
    --------
    >>> round(q95_mm(np.eye(3)), 1)  # √(χ²₃ 95 %) = 2.80
    2.8
    """
    c = np.asarray(cov_mm2, dtype=float)
    w, v = np.linalg.eigh(c)
    z = np.random.default_rng(seed).standard_normal((Q95_DRAWS, 3)) * np.sqrt(np.maximum(w, 0.0))
    return float(np.quantile(np.linalg.norm(z @ v.T, axis=1), 0.95))


@dataclass(frozen=True)
class Hangs:
    """Candidate hangs: ids, wire exits, bolt axes, the CAD's assembly CoG, and the weight on
    the wire (N: a stiff wire's offset depends on it)."""

    ids: tuple[str, ...]
    points_mm: FloatArray
    normals: FloatArray
    cog_mm: FloatArray
    weight_n: float

    def of(self, chosen: Sequence[str]) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Points, normals and the turned flags of hangs ``chosen`` (``ID~``: a reversal)."""
        rows = [self.ids.index(h.rstrip(REVERSAL)) for h in chosen]
        turned = np.array([h.endswith(REVERSAL) for h in chosen])
        return self.points_mm[rows], self.normals[rows], turned


@dataclass(frozen=True)
class Prediction:
    """The covariance the estimate will state for a set of hangs, with and without calibrating
    the sensor's shared errors, and their 95 % errors (mm)."""

    hangs: tuple[str, ...]
    cov_mm2: FloatArray
    cov_uncalibrated_mm2: FloatArray
    q95_mm: float
    q95_uncalibrated_mm: float
    calibrated: tuple[str, ...]

    def to_dict(self) -> dict[str, Any]:
        return {
            "hangs": list(self.hangs),
            "q95_mm": self.q95_mm,
            "q95_without_self_calibration_mm": self.q95_uncalibrated_mm,
            "sigma_mm": np.sqrt(np.diag(self.cov_mm2)).tolist(),
            "calibrated_by_hangs": list(self.calibrated),
        }


def _fit(
    hangs: Hangs,
    chosen: Sequence[str],
    cfg: InclinometerConfig,
    model: ErrorModel,
    prior: FloatArray,
    shared: FloatArray | None = None,
) -> sharedfit.SharedFit:
    p, n, turned = hangs.of(chosen)
    wire = gls.WireTerm.from_model(model, hangs.weight_n)
    # The CAD's lines: through the expected virtual points (the wire's shape at each hang's
    # angle, as the estimator places them), at the assembly's CoG.
    u = (p - hangs.cog_mm) / np.linalg.norm(p - hangs.cog_mm, axis=1)[:, None]
    for _ in range(4):  # the shape depends on the vertical: a fixed point, reached in a few
        shape = (
            np.ones(len(p))
            if wire.model == "paper"
            else wire_shape_factor(np.einsum("ij,ij->i", u, n), wire.model)
        )
        q = p + (wire.scale_mm * shape)[:, None] * n
        u = (q - hangs.cog_mm) / np.linalg.norm(q - hangs.cog_mm, axis=1)[:, None]
    acc = accel_readings(
        u, np.zeros(len(ACCEL_SHARED_PARAMETERS)) if shared is None else shared, cfg.axes, turned
    )
    var = np.full(len(p), cfg.accuracy_g**2 / 3.0)
    scatter = wire_scatter(model, hangs.weight_n)
    errors = gls.LineErrors(model.play_var_mm2, scatter, var, isotropic_reading=True)
    zeros = np.zeros(len(p))
    return sharedfit.fit_shared(
        p, zeros, zeros, np.ones(len(p), bool), n, errors, wire, prior, cfg,
        list(chosen), sensor_turned=turned, acc_g=acc, norm_var_g2=var, verdicts=False,
    )  # fmt: skip


def wire_scatter(model: ErrorModel, weight_n: float) -> float:
    """The wire offset's per-hang scatter along the bolt axis (mm²)."""
    return float(model.wire_prior(weight_n).scatter_var_mm2)


def predict(
    hangs: Hangs,
    chosen: Sequence[str],
    cfg: InclinometerConfig,
    model: ErrorModel,
    *,
    uncalibrated: bool = True,
) -> Prediction:
    """The estimate's covariance for ``chosen`` (ids of ``hangs``, ``ID~`` a reversal), and
    (``uncalibrated``) what it would be without calibrating the shared errors (NaN if not).

    Raises
    ------
    DegenerateGeometryError
        If the hangs do not determine the CoG.
    """
    prior = model.shared_sensor_sigmas
    fit = _fit(hangs, chosen, cfg, model, prior)
    names = sharedfit.shared_parameter_names(cfg)
    calibrated = tuple(nm for nm, c in zip(names, fit.calibrated, strict=True) if c)
    if not uncalibrated:
        nan = np.full((3, 3), np.nan)
        return Prediction(tuple(chosen), fit.cov_mm2, nan, q95_mm(fit.cov_mm2), np.nan, calibrated)
    # Without self-calibration: θ taken as 0 (a tiny prior), its declared spread propagated
    # through the estimate's sensitivity to it, column by column.
    known = np.where(prior > 0, prior * 1e-6, 0.0)
    base = _fit(hangs, chosen, cfg, model, known)
    jac = np.zeros((3, len(prior)))
    for j in np.flatnonzero(prior > 0):
        h = np.zeros(len(prior))
        h[j] = prior[j] * 1e-2
        jac[:, j] = (_fit(hangs, chosen, cfg, model, known, h).cog_mm - base.cog_mm) / h[j]
    uncal = base.cov_mm2 + jac @ np.diag(prior**2) @ jac.T
    return Prediction(
        tuple(chosen), fit.cov_mm2, uncal, q95_mm(fit.cov_mm2), q95_mm(uncal), calibrated
    )


def grow(
    hangs: Hangs,
    cfg: InclinometerConfig,
    model: ErrorModel,
    *,
    max_hangs: int = 8,
    reversals: bool = True,
) -> list[Prediction]:
    """The best set of each size from 2 to ``max_hangs``: the best pair, then the hang that
    lowers the 95 % error most, added one at a time (a reversal of a point in the set counts as
    a hang)."""
    best = _best(hangs, [(a, b) for a, b in combinations(hangs.ids, 2)], cfg, model)
    if best is None:
        raise DegenerateGeometryError("no pair of these points determines the CoG")
    out = [predict(hangs, best.hangs, cfg, model)]
    while len(out[-1].hangs) < max_hangs:
        current = out[-1].hangs
        options = [i for i in hangs.ids if i not in current]
        if reversals:
            options += [h + REVERSAL for h in current if not h.endswith(REVERSAL)]
            options = [o for o in options if o not in current]
        chosen = _best(hangs, [(*current, o) for o in options], cfg, model)
        if chosen is None:
            break
        out.append(predict(hangs, chosen.hangs, cfg, model))
    return out


def _best(
    hangs: Hangs, sets: list[tuple[str, ...]], cfg: InclinometerConfig, model: ErrorModel
) -> Prediction | None:
    """The set of ``sets`` with the smallest predicted 95 % error: the :data:`SCREEN_KEEP` best
    without the shared errors (the trace of the lines' covariance alone), then compared with
    them."""
    lines_only = replace(model, sources=tuple(x for x in model.sources if x != "inclinometer"))
    screened = []
    for chosen in sets:
        try:
            fit = _fit(hangs, chosen, cfg, lines_only, np.zeros(len(model.shared_sensor_sigmas)))
        except DegenerateGeometryError:
            continue
        screened.append((float(np.trace(fit.cov_mm2)), chosen))
    screened.sort(key=lambda x: x[0])
    best: Prediction | None = None
    for _, chosen in screened[:SCREEN_KEEP]:
        try:
            pr = predict(hangs, chosen, cfg, model, uncalibrated=False)
        except DegenerateGeometryError:
            continue
        if best is None or pr.q95_mm < best.q95_mm:
            best = pr
    return best


@dataclass(frozen=True, repr=False)
class AccelBudget(JsonResult):
    """An accelerometer's budget: the prediction for every hang of the rig, and the best set of
    each size with the first that meets the target."""

    all_hangs: Prediction
    sizes: tuple[Prediction, ...]
    target_mm: float | None
    model: dict[str, Any]

    @property
    def meets(self) -> Prediction | None:
        """The smallest set whose 95 % error is within the target (None: none, or no target)."""
        if self.target_mm is None:
            return None
        return next((s for s in self.sizes if s.q95_mm <= self.target_mm), None)

    def to_dict(self) -> dict[str, Any]:
        meets = self.meets
        return {
            "device": "accelerometer",
            "all_points": self.all_hangs.to_dict(),
            "best_sets": [s.to_dict() for s in self.sizes],
            "target_mm": self.target_mm,
            "smallest_set_within_target": None if meets is None else list(meets.hangs),
            "model": self.model,
        }


def accelerometer_budget(
    hangs: Hangs,
    cfg: InclinometerConfig,
    model: ErrorModel,
    *,
    target_mm: float | None = None,
    max_hangs: int = 8,
) -> AccelBudget:
    """:class:`AccelBudget` of ``hangs`` read by ``cfg``'s accelerometer."""
    if not model.accelerometer:
        raise ValueError("an accelerometer's budget needs an accelerometer's error model")
    every = predict(hangs, hangs.ids, cfg, model)
    sizes = grow(hangs, cfg, model, max_hangs=max_hangs)
    described = {
        **model.describe(),
        "axes": list(cfg.axes),
        "accuracy_g": cfg.accuracy_g,
        "cross_axis_rel": cfg.cross_axis_rel,
    }
    return AccelBudget(every, tuple(sizes), target_mm, described)
