"""What a measurement says about the CAD: a Bayesian update of the mass budget.

After the suspension test the measured CoG (with its covariance) and the weighed mass rarely match
the CAD. The mass budget already says how uncertain each item's mass is
(:mod:`cadcog.spacecraft.mass_budget`); this module finds the item masses, and optionally an
unmodelled mass (harness, fasteners, adhesive) somewhere in a region, that best explain the
measurement given those uncertainties, and what the spacecraft's mass, CoG and inertia then are,
with their covariance: the figures the attitude team should use.

Model. Unknowns ``θ = (δ_1 … δ_N, m_u, h)``: each uncertain item's relative mass change
(prior ``N(0, σ_I²)``), and, when a region is given, the unmodelled mass ``m_u`` and its mass
moment ``h = m_u p_u`` (prior: ``m_u ~ N(μ_u, s_u²)``, ``p_u`` uniform in the region, moment-
matched to a joint Gaussian). Bodies without an uncertainty are fixed. Observations ``y``: the
weighed mass of the spacecraft (without the measurement equipment) and the measured CoG of the
*assembly* (spacecraft + ME) that the suspensions see,

    M(θ) = M_CAD + Σ m_I δ_I + m_u
    G(θ) = (S_CAD + Σ m_I c_I δ_I + h + m_ME r_ME) / (M(θ) + m_ME)

with noise the weighing's σ and the estimate's covariance plus the ME's CAD uncertainty,
``(m_ME / M_total)² Σ_ME``. The posterior is found by Gauss-Newton on the exact (ratio) model;
its covariance is the inverse Hessian there (Laplace). Consistency: before updating, the CAD's
prediction is compared with the measurement, ``χ² = rᵀ (J P₀ Jᵀ + R)⁻¹ r`` with 4 degrees of
freedom; a small p-value says the gap is larger than the uncertainties allow.

With no discrepancy (the measurement equals the CAD's prediction) the update changes nothing.
Pure numpy; nothing here imports the CAD layer.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.results import JsonResult
from cadcog.mass.properties import MassProperties, combine

FloatArray = npt.NDArray[np.float64]

#: Gauss-Newton iterations; the model is nearly linear, so 3-4 reach round-off.
MAX_ITERATIONS = 20

#: Probability below which the CAD and the measurement disagree beyond their uncertainties.
CONSISTENCY_PROBABILITY = 0.05

#: Said whenever the CAD and the measurement disagree beyond their uncertainties.
INCONSISTENT_NOTE = (
    "The updated values assume the gap comes from the items' masses (and the unmodelled mass, "
    "if one is allowed) within their uncertainties; it does not: look for a missing or "
    "misplaced part, widen the uncertainties, allow an unmodelled mass in a region, or check "
    "the test, before using them."
)


@dataclass(frozen=True)
class Item:
    """An uncertain mass item of the budget: its CAD mass properties and 1-σ relative mass."""

    key: str
    properties: MassProperties
    sigma_rel: float


@dataclass(frozen=True)
class UnmodelledPrior:
    """An unmodelled mass somewhere in a box: prior mass mean and 1 σ (kg)."""

    lo_mm: FloatArray
    hi_mm: FloatArray
    mass_kg: float
    sigma_kg: float

    def __post_init__(self) -> None:
        lo, hi = np.asarray(self.lo_mm, dtype=float), np.asarray(self.hi_mm, dtype=float)
        if lo.shape != (3,) or hi.shape != (3,) or np.any(hi <= lo):
            raise ValueError(
                "the unmodelled mass region needs lo < hi on every axis, three values each "
                "(a box: the prior places the mass uniformly in it)"
            )
        if not (self.sigma_kg > 0 and self.mass_kg >= 0):
            raise ValueError("the unmodelled mass needs a positive σ and a mean ≥ 0")
        object.__setattr__(self, "lo_mm", lo)
        object.__setattr__(self, "hi_mm", hi)


@dataclass(frozen=True)
class Measurement:
    """What the test measured.

    Attributes
    ----------
    assembly_cog_mm, assembly_cov_mm2 : ndarray
        CoG of spacecraft + ME from the suspensions (``cadcog estimate``'s
        ``assembly_cog_mm``/``assembly_cov_mm2``).
    mass_kg, mass_sigma_kg : float
        The weighed spacecraft, without the ME.
    me_mass_kg : float
    me_cog_mm : ndarray, shape (3,)
    me_cog_cov_mm2 : ndarray, shape (3, 3)
        The ME's CAD CoG and its uncertainty.
    """

    assembly_cog_mm: FloatArray
    assembly_cov_mm2: FloatArray
    mass_kg: float
    mass_sigma_kg: float
    me_mass_kg: float
    me_cog_mm: FloatArray
    me_cog_cov_mm2: FloatArray = field(default_factory=lambda: np.zeros((3, 3)))


@dataclass(frozen=True)
class ItemChange(JsonResult):
    """How the update moved one item's mass."""

    key: str
    cad_mass_kg: float
    prior_sigma_rel: float
    delta_rel: float
    delta_sigma_rel: float

    @property
    def delta_kg(self) -> float:
        return self.cad_mass_kg * self.delta_rel

    @property
    def pull(self) -> float:
        """The change in prior sigmas: how much the data moved the item."""
        return self.delta_rel / self.prior_sigma_rel

    def to_dict(self) -> dict[str, Any]:
        return {
            "item": self.key,
            "cad_mass_kg": self.cad_mass_kg,
            "prior_sigma_rel": self.prior_sigma_rel,
            "delta_rel": self.delta_rel,
            "delta_sigma_rel": self.delta_sigma_rel,
            "delta_kg": self.delta_kg,
            "pull": self.pull,
        }


@dataclass(frozen=True, repr=False)  # JsonResult's one-line repr
class UpdateResult(JsonResult):
    """The CAD before, the posterior after, and what explains the difference."""

    cad: MassProperties
    cad_cog_cov_mm2: FloatArray
    cad_mass_sigma_kg: float
    measured_mass_kg: float  # weighed
    measured_mass_sigma_kg: float
    measured_cog_mm: FloatArray  # the spacecraft's, compensated with the weighed mass
    measured_cog_cov_mm2: FloatArray
    posterior: MassProperties
    posterior_mass_sigma_kg: float
    posterior_cog_cov_mm2: FloatArray
    posterior_inertia_sigma_kg_mm2: FloatArray  # 1 σ of each tensor entry
    items: tuple[ItemChange, ...]
    unmodelled_mass_kg: float | None
    unmodelled_mass_sigma_kg: float | None
    unmodelled_cog_mm: FloatArray | None
    unmodelled_cog_cov_mm2: FloatArray | None
    chi2: float
    dof: int
    p_value: float
    iterations: int

    @property
    def consistent(self) -> bool:
        return self.p_value >= CONSISTENCY_PROBABILITY

    def unmodelled_summary(self) -> str:
        """``"147.7 ± 19.4 g at [14.5 ± 9.1, …] mm"``: the unmodelled mass and where it is
        (1 σ); empty without an unmodelled mass."""
        if self.unmodelled_mass_kg is None:
            return ""
        sigma_g = (self.unmodelled_mass_sigma_kg or 0.0) * 1e3
        text = f"{self.unmodelled_mass_kg * 1e3:.1f} ± {sigma_g:.1f} g"
        if self.unmodelled_cog_mm is not None and self.unmodelled_cog_cov_mm2 is not None:
            sd = np.sqrt(np.maximum(np.diag(self.unmodelled_cog_cov_mm2), 0.0))
            text += (
                " at ["
                + ", ".join(
                    f"{round(float(c), 1) + 0.0:.1f} ± {e:.1f}"
                    for c, e in zip(self.unmodelled_cog_mm, sd, strict=True)
                )
                + "] mm"
            )
        return text

    def ranked_items(self) -> list[ItemChange]:
        """Items by how far the data moved them (|pull|), largest first."""
        return sorted(self.items, key=lambda c: -abs(c.pull))

    def to_dict(self) -> dict[str, Any]:
        def props(p: MassProperties) -> dict[str, Any]:
            return {
                "mass_kg": p.mass_kg,
                "cog_mm": p.cog_mm.tolist(),
                "inertia_kg_mm2": p.inertia_kg_mm2.tolist(),
            }

        out: dict[str, Any] = {
            "cad": {
                **props(self.cad),
                "mass_sigma_kg": self.cad_mass_sigma_kg,
                "cog_cov_mm2": self.cad_cog_cov_mm2.tolist(),
            },
            "measured": {
                "mass_kg": self.measured_mass_kg,
                "mass_sigma_kg": self.measured_mass_sigma_kg,
                "cog_mm": self.measured_cog_mm.tolist(),
                "cog_cov_mm2": self.measured_cog_cov_mm2.tolist(),
            },
            "posterior": {
                **props(self.posterior),
                "mass_sigma_kg": self.posterior_mass_sigma_kg,
                "cog_cov_mm2": self.posterior_cog_cov_mm2.tolist(),
                "inertia_sigma_kg_mm2": self.posterior_inertia_sigma_kg_mm2.tolist(),
            },
            "items": [c.to_dict() for c in self.ranked_items()],
            "consistency": {
                "chi2": self.chi2,
                "dof": self.dof,
                "p_value": self.p_value,
                "consistent": self.consistent,
            },
            "iterations": self.iterations,
        }
        if self.unmodelled_mass_kg is not None:
            out["unmodelled"] = {
                "mass_kg": self.unmodelled_mass_kg,
                "mass_sigma_kg": self.unmodelled_mass_sigma_kg,
                "cog_mm": None
                if self.unmodelled_cog_mm is None
                else self.unmodelled_cog_mm.tolist(),
                "cog_cov_mm2": None
                if self.unmodelled_cog_cov_mm2 is None
                else self.unmodelled_cog_cov_mm2.tolist(),
            }
        return out


def items_from_bodies(bodies: Sequence[Any]) -> tuple[list[Item], MassProperties | None]:
    """The budget's uncertain items and the fixed rest, from bodies that carry ``properties``,
    ``sigma_rel`` and ``item`` (``cadcog.cad.stepmass.BodyResult``): bodies of one item are
    combined (they vary together); bodies without an uncertainty are fixed."""
    groups: dict[str, list[Any]] = {}
    fixed = []
    for b in bodies:
        if b.sigma_rel is None:
            fixed.append(b.properties)
        else:
            groups.setdefault(b.item, []).append(b)
    items = [
        Item(key, combine(b.properties for b in members), members[0].sigma_rel)
        for key, members in groups.items()
        if members[0].sigma_rel > 0
    ]
    zero = [b.properties for members in groups.values() for b in members if b.sigma_rel == 0]
    rest = fixed + zero
    return items, (combine(rest) if rest else None)


class _Model:
    """Observation model and its Jacobian (see the module docstring)."""

    def __init__(
        self,
        items: Sequence[Item],
        fixed: MassProperties | None,
        meas: Measurement,
        unmodelled: UnmodelledPrior | None,
    ) -> None:
        self.m = np.array([i.properties.mass_kg for i in items])
        self.c = np.array([i.properties.cog_mm for i in items]).reshape(-1, 3)
        self.m0 = float(self.m.sum()) + (fixed.mass_kg if fixed is not None else 0.0)
        s0 = self.m @ self.c if len(items) else np.zeros(3)
        if fixed is not None:
            s0 = s0 + fixed.mass_kg * fixed.cog_mm
        self.s0 = np.asarray(s0, dtype=float)
        self.n = len(items)
        self.with_u = unmodelled is not None
        self.meas = meas

    @property
    def size(self) -> int:
        return self.n + (4 if self.with_u else 0)

    def split(self, theta: FloatArray) -> tuple[FloatArray, float, FloatArray]:
        d = theta[: self.n]
        if self.with_u:
            return d, float(theta[self.n]), theta[self.n + 1 : self.n + 4]
        return d, 0.0, np.zeros(3)

    def mass_moment(self, theta: FloatArray) -> tuple[float, FloatArray]:
        d, mu, h = self.split(theta)
        mass = self.m0 + float(self.m @ d) + mu
        moment = self.s0 + (self.m * d) @ self.c + h
        return mass, np.asarray(moment)

    def predict(self, theta: FloatArray) -> FloatArray:
        mass, moment = self.mass_moment(theta)
        me = self.meas
        g = (moment + me.me_mass_kg * me.me_cog_mm) / (mass + me.me_mass_kg)
        return np.concatenate([[mass], g])

    def jacobian(self, theta: FloatArray) -> FloatArray:
        mass, moment = self.mass_moment(theta)
        me = self.meas
        mt = mass + me.me_mass_kg
        g = (moment + me.me_mass_kg * me.me_cog_mm) / mt
        j = np.zeros((4, self.size))
        j[0, : self.n] = self.m
        j[1:, : self.n] = (self.m[:, None] * (self.c - g)).T / mt
        if self.with_u:
            j[0, self.n] = 1.0
            j[1:, self.n] = -g / mt
            j[1:, self.n + 1 :] = np.eye(3) / mt
        return j

    def noise(self, theta: FloatArray) -> FloatArray:
        mass, _ = self.mass_moment(theta)
        me = self.meas
        share = me.me_mass_kg / (mass + me.me_mass_kg)
        r = np.zeros((4, 4))
        r[0, 0] = me.mass_sigma_kg**2
        r[1:, 1:] = me.assembly_cov_mm2 + share**2 * me.me_cog_cov_mm2
        return r


def _prior(
    items: Sequence[Item], unmodelled: UnmodelledPrior | None
) -> tuple[FloatArray, FloatArray]:
    n = len(items)
    size = n + (4 if unmodelled is not None else 0)
    mean = np.zeros(size)
    cov = np.zeros((size, size))
    cov[:n, :n] = np.diag([i.sigma_rel**2 for i in items])
    if unmodelled is not None:
        u = unmodelled
        p_mean = 0.5 * (u.lo_mm + u.hi_mm)
        p_cov = np.diag((u.hi_mm - u.lo_mm) ** 2 / 12.0)
        mean[n] = u.mass_kg
        mean[n + 1 :] = u.mass_kg * p_mean
        cov[n, n] = u.sigma_kg**2
        cov[n, n + 1 :] = cov[n + 1 :, n] = u.sigma_kg**2 * p_mean
        cov[n + 1 :, n + 1 :] = (
            u.sigma_kg**2 * np.outer(p_mean, p_mean) + (u.mass_kg**2 + u.sigma_kg**2) * p_cov
        )
    return mean, cov


def _inertia(
    theta: FloatArray,
    items: Sequence[Item],
    fixed: MassProperties | None,
    model: _Model,
) -> MassProperties:
    """Mass properties of the spacecraft for parameters ``theta`` (about its CoG)."""
    d, mu, h = model.split(theta)
    parts = [
        MassProperties(
            i.properties.mass_kg * (1 + dk),
            i.properties.cog_mm,
            i.properties.inertia_kg_mm2 * (1 + dk),
            i.properties.volume_mm3,
        )
        for i, dk in zip(items, d, strict=True)
    ]
    if fixed is not None:
        parts.append(fixed)
    if model.with_u and abs(mu) > 0:
        parts.append(MassProperties(mu, h / mu, np.zeros((3, 3)), 0.0))
    return combine(parts)


def update_budget(
    items: Sequence[Item],
    fixed: MassProperties | None,
    measurement: Measurement,
    *,
    unmodelled: UnmodelledPrior | None = None,
) -> UpdateResult:
    """The posterior mass budget given a measurement (module docstring).

    Parameters
    ----------
    items : sequence of Item
        The budget's uncertain items.
    fixed : MassProperties or None
        Everything without an uncertainty, combined.
    measurement : Measurement
    unmodelled : UnmodelledPrior, optional

    Raises
    ------
    ValueError
        With nothing uncertain to update, or a weighing or covariance that is not positive.
    """
    if not items and unmodelled is None:
        raise ValueError("nothing to update: no item has a mass uncertainty and no unmodelled mass")
    if not measurement.mass_sigma_kg > 0:
        raise ValueError("the weighing needs a positive σ")
    model = _Model(items, fixed, measurement, unmodelled)
    theta0, p0 = _prior(items, unmodelled)
    p0_inv = np.linalg.pinv(p0, hermitian=True)
    y = np.concatenate([[measurement.mass_kg], measurement.assembly_cog_mm])
    # Consistency of the CAD with the measurement, before updating.
    j0 = model.jacobian(theta0)
    r0 = y - model.predict(theta0)
    s = j0 @ p0 @ j0.T + model.noise(theta0)
    chi2 = float(r0 @ np.linalg.solve(s, r0))
    # Gauss-Newton for the MAP; the linear-Gaussian step from the prior is its first iterate.
    theta = theta0.copy()
    iterations = 0
    for iterations in range(1, MAX_ITERATIONS + 1):  # noqa: B007 - reported
        j = model.jacobian(theta)
        r_inv = np.linalg.inv(model.noise(theta))
        hessian = j.T @ r_inv @ j + p0_inv
        gradient = j.T @ r_inv @ (y - model.predict(theta)) - p0_inv @ (theta - theta0)
        step = np.linalg.solve(hessian, gradient)
        theta = theta + step
        if np.max(np.abs(step)) < 1e-12 * (1.0 + np.max(np.abs(theta))):
            break
    j = model.jacobian(theta)
    post_cov = np.linalg.inv(j.T @ np.linalg.inv(model.noise(theta)) @ j + p0_inv)
    post_cov = 0.5 * (post_cov + post_cov.T)
    cad = _inertia(np.zeros(model.size), items, fixed, model)  # the CAD: nothing changed
    posterior = _inertia(theta, items, fixed, model)

    # Covariances of derived quantities by linear propagation (central differences).
    def derived(t: FloatArray) -> FloatArray:
        p = _inertia(t, items, fixed, model)
        return np.concatenate([[p.mass_kg], p.cog_mm, p.inertia_kg_mm2[np.triu_indices(3)]])

    jd = _numeric_jacobian(derived, theta, np.sqrt(np.maximum(np.diag(post_cov), 0.0)))
    cov_d = jd @ post_cov @ jd.T
    # The CAD's own uncertainty: its items' (the unmodelled mass is not in the CAD).
    n = model.n
    jd0 = _numeric_jacobian(derived, np.zeros(model.size), np.sqrt(np.maximum(np.diag(p0), 0.0)))
    cov_d0 = jd0[:, :n] @ p0[:n, :n] @ jd0[:, :n].T
    inertia_sigma = np.zeros((3, 3))
    iu = np.triu_indices(3)
    inertia_sigma[iu] = np.sqrt(np.maximum(np.diag(cov_d)[4:], 0.0))
    inertia_sigma = np.maximum(inertia_sigma, inertia_sigma.T)
    changes = tuple(
        ItemChange(
            i.key,
            i.properties.mass_kg,
            i.sigma_rel,
            float(theta[k]),
            float(np.sqrt(max(post_cov[k, k], 0.0))),
        )
        for k, i in enumerate(items)
    )
    u_mass = u_sigma = None
    u_cog = u_cog_cov = None
    if unmodelled is not None:
        u_mass = float(theta[n])
        u_sigma = float(np.sqrt(max(post_cov[n, n], 0.0)))
        if abs(u_mass) > 0:  # c = h / m: its covariance by linear propagation from (m, h)
            h = theta[n + 1 : n + 4]
            u_cog = h / u_mass
            jc = np.hstack([-h[:, None] / u_mass**2, np.eye(3) / u_mass])
            u_cog_cov = jc @ post_cov[n : n + 4, n : n + 4] @ jc.T
    measured_cog, measured_cov = recompensate(measurement)
    return UpdateResult(
        cad,
        cov_d0[1:4, 1:4],
        float(np.sqrt(max(cov_d0[0, 0], 0.0))),
        measurement.mass_kg,
        measurement.mass_sigma_kg,
        measured_cog,
        measured_cov,
        posterior,
        float(np.sqrt(max(cov_d[0, 0], 0.0))),
        cov_d[1:4, 1:4],
        inertia_sigma,
        changes,
        u_mass,
        u_sigma,
        u_cog,
        u_cog_cov,
        chi2,
        4,
        float(_chi2_sf(chi2, 4)),
        iterations,
    )


def recompensate(meas: Measurement) -> tuple[FloatArray, FloatArray]:
    """The spacecraft's CoG from the assembly CoG with the *weighed* mass (eqs. 10, 16)."""
    ratio = meas.me_mass_kg / meas.mass_kg
    cog = (1.0 + ratio) * meas.assembly_cog_mm - ratio * meas.me_cog_mm
    cov = (1.0 + ratio) ** 2 * meas.assembly_cov_mm2 + ratio**2 * meas.me_cog_cov_mm2
    return np.asarray(cog), np.asarray(cov)


def _numeric_jacobian(f: Any, x: FloatArray, scale: FloatArray) -> FloatArray:
    """Central-difference Jacobian of ``f`` at ``x`` with steps 1e-4 of each scale."""
    f0 = f(x)
    out = np.zeros((f0.size, x.size))
    for k in range(x.size):
        h = 1e-4 * (scale[k] if scale[k] > 0 else 1.0)
        e = np.zeros(x.size)
        e[k] = h
        out[:, k] = (f(x + e) - f(x - e)) / (2 * h)
    return out


def _chi2_sf(x: float, df: int) -> float:
    """χ² survival function (scipy.stats imported here: a second at start-up otherwise)."""
    from scipy import stats

    return float(stats.chi2.sf(x, df=df))
