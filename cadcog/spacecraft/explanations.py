"""The explanations ``cadcog update`` weighs: its observation model, each hypothesis's prior,
MAP, covariance and evidence (:mod:`cadcog.spacecraft.update` has the method and the result).

Parameters ``θ = (δ_1 … δ_N, s_1 … s_N[, m_u, h])``: each uncertain item's relative mass change
and CoG shift (:mod:`cadcog.spacecraft.items`) and, in a hypothesis that allows one, an
unmodelled mass and its moment. Pure numpy.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.mass.properties import MassProperties
from cadcog.spacecraft.items import Item, parameter_prior_cov

FloatArray = npt.NDArray[np.float64]

#: Gauss-Newton iterations at most (the CubeSat example converges in 4-6).
MAX_ITERATIONS = 30

#: Gauss-Newton stops when no parameter moves by more than this many prior σ.
GN_STEP_TOLERANCE = 1e-5

#: How much wider an item's mass and CoG σ are when it is the one that is wrong (``H_I``).
ALTERNATIVE_SIGMA_FACTOR = 10.0

#: Prior probability that a given item is wrong beyond its stated σ (``H_I``).
ALTERNATIVE_PRIOR_PROBABILITY = 0.02

#: Largest total prior probability of "one item is off" (many items share it: with more than
#: 15 items each gets less than :data:`ALTERNATIVE_PRIOR_PROBABILITY`).
MAX_ALTERNATIVES_PROBABILITY = 0.3

#: Prior probability of an unmodelled mass anywhere in the spacecraft (``H_u``).
UNMODELLED_PRIOR_PROBABILITY = 0.05

#: ``H_u``'s unmodelled mass prior 1 σ, as a fraction of the CAD mass.
UNMODELLED_SIGMA_FRACTION = 0.05


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

    @property
    def center_mm(self) -> FloatArray:
        return np.asarray(0.5 * (self.lo_mm + self.hi_mm))


def unmodelled_from_region(
    region_mm: Sequence[float] | None, mass_kg: float, sigma_kg: float | None
) -> UnmodelledPrior | None:
    """The unmodelled-mass prior of a box given by two opposite corners
    ``(x0, y0, z0, x1, y1, z1)`` (mm), its prior mean and 1 σ (kg); None without a box.

    Raises
    ------
    ValueError
        A box without a σ, a σ without a box, or a box flat along an axis.
    """
    if region_mm is None:
        if sigma_kg is not None:
            raise ValueError("an unmodelled mass σ needs a region (where the mass may be)")
        return None
    if sigma_kg is None:
        raise ValueError("an unmodelled mass region needs its prior 1 σ (kg)")
    r = np.asarray(region_mm, dtype=float)
    if r.shape != (6,) or not np.all(np.isfinite(r)):
        raise ValueError("expected six numbers X0,Y0,Z0,X1,Y1,Z1 (two opposite corners, mm)")
    flat = [axis for axis, lo, hi in zip("xyz", r[:3], r[3:], strict=True) if lo == hi]
    if flat:
        raise ValueError(
            f"the box has no extent along {', '.join(flat)} (X0,Y0,Z0,X1,Y1,Z1 are opposite "
            "corners; give where the mass may be)"
        )
    return UnmodelledPrior(np.minimum(r[:3], r[3:]), np.maximum(r[:3], r[3:]), mass_kg, sigma_kg)


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
    inertia_kg_mm2 : ndarray, shape (6,), optional
        The spacecraft's inertia tensor about its CoG measured from the swings
        (``cadcog inertia``), entries ``[xx, yy, zz, xy, xz, yz]`` (tensor convention).
    inertia_cov : ndarray, shape (6, 6), optional
        Its covariance (kg²·mm⁴). Taken as independent of the CoG and the weighing (an
        approximation: the tensor's estimate uses both).
    """

    assembly_cog_mm: FloatArray
    assembly_cov_mm2: FloatArray
    mass_kg: float
    mass_sigma_kg: float
    me_mass_kg: float
    me_cog_mm: FloatArray
    me_cog_cov_mm2: FloatArray = field(default_factory=lambda: np.zeros((3, 3)))
    inertia_kg_mm2: FloatArray | None = None
    inertia_cov: FloatArray | None = None

    @property
    def observed(self) -> FloatArray:
        """``y``: the weighed mass, the assembly CoG and, when measured, the six entries."""
        parts: list[FloatArray] = [np.array([self.mass_kg]), np.asarray(self.assembly_cog_mm)]
        if self.inertia_kg_mm2 is not None:
            parts.append(np.asarray(self.inertia_kg_mm2))
        return np.concatenate(parts)


#: ``derived``'s inertia entries (upper triangle xx, xy, xz, yy, yz, zz) in the order
#: ``[xx, yy, zz, xy, xz, yz]`` of a measured tensor.
_INERTIA_ORDER = [4, 7, 9, 5, 6, 8]


# --- the model ------------------------------------------------------------------------------------
class Model:
    """Observation model and its Jacobian (module docstring); ``θ = (δ, s, [m_u, h])``."""

    def __init__(
        self,
        items: Sequence[Item],
        fixed: MassProperties | None,
        meas: Measurement | None,
        with_unmodelled: bool,
        region_mm: tuple[FloatArray, FloatArray] | None = None,
    ) -> None:
        self.n = len(items)
        self.m = np.array([i.properties.mass_kg for i in items])
        self.c = np.array([i.properties.cog_mm for i in items]).reshape(-1, 3)
        self.j = np.array([i.properties.inertia_kg_mm2 for i in items]).reshape(-1, 3, 3)
        self.fixed = fixed
        self.m0 = float(self.m.sum()) + (fixed.mass_kg if fixed is not None else 0.0)
        s0 = self.m @ self.c if self.n else np.zeros(3)
        if fixed is not None:
            s0 = s0 + fixed.mass_kg * fixed.cog_mm
        self.s0 = np.asarray(s0, dtype=float)
        self.with_u = with_unmodelled
        self.region_mm = region_mm  # the box an unmodelled mass sits in (its prior's)
        self._meas = meas
        self.size = 4 * self.n + (4 if with_unmodelled else 0)
        if meas is None:  # the CAD alone (derived quantities only, no observation)
            return
        share = meas.me_mass_kg / (meas.mass_kg + meas.me_mass_kg)
        # Covariance of y's errors: the weighing's, and the assembly CoG's plus the ME's CAD
        # uncertainty at its share of the weighed assembly (the same for every θ).
        self.with_inertia = meas.inertia_kg_mm2 is not None
        n_obs = 10 if self.with_inertia else 4
        self.noise = np.zeros((n_obs, n_obs))
        self.noise[0, 0] = meas.mass_sigma_kg**2
        self.noise[1:4, 1:4] = meas.assembly_cov_mm2 + share**2 * meas.me_cog_cov_mm2
        if meas.inertia_cov is not None:
            self.noise[4:, 4:] = meas.inertia_cov
        self.noise_inv = np.linalg.inv(self.noise)
        self._rows = np.tile(np.arange(3), self.n)
        self._cols = self.n + np.arange(3 * self.n)

    def split(self, theta: FloatArray) -> tuple[FloatArray, FloatArray, float, FloatArray]:
        n = self.n
        d = theta[:n]
        s = theta[n : 4 * n].reshape(n, 3)
        if self.with_u:
            return d, s, float(theta[4 * n]), theta[4 * n + 1 : 4 * n + 4]
        return d, s, 0.0, np.zeros(3)

    def mass_moment(self, theta: FloatArray) -> tuple[float, FloatArray]:
        d, s, mu, h = self.split(theta)
        mass = self.m0 + float(self.m @ d) + mu
        moment = self.s0 + self.m @ (d[:, None] * self.c + (1.0 + d)[:, None] * s) + h
        return mass, np.asarray(moment)

    @property
    def meas(self) -> Measurement:
        """The observation (a model of the CAD alone has none: it only derives)."""
        if self._meas is None:
            raise ValueError("this model has no measurement: it only derives properties")
        return self._meas

    def predict(self, theta: FloatArray) -> FloatArray:
        mass, moment = self.mass_moment(theta)
        me = self.meas
        g = (moment + me.me_mass_kg * me.me_cog_mm) / (mass + me.me_mass_kg)
        if not self.with_inertia:
            return np.concatenate([[mass], g])
        return np.concatenate([[mass], g, self._inertia(theta[None, :])[0]])

    def _inertia(self, thetas: FloatArray) -> FloatArray:
        """The spacecraft's six entries about its CoG for rows of ``thetas`` (an unmodelled
        mass at its own position ``h / m_u``, held in its box: as ``m_u`` → 0, ``h / m_u``
        runs off to where the point's inertia ``|h|²/m_u`` is unbounded, and the fit with it;
        the prior puts the mass in the box)."""
        at = np.zeros(3)
        if self.with_u:
            _, _, mu, h = self.split(thetas[0])
            at = h / mu if mu > 0 else at
            if self.region_mm is not None:
                at = np.clip(at, *self.region_mm)
        return np.asarray(self.derived(thetas, at)[:, _INERTIA_ORDER])

    def jacobian(self, theta: FloatArray) -> FloatArray:
        """``∂(M, G_asm)/∂θ``, shape (4, size)."""
        d, s, _, _ = self.split(theta)
        mass, moment = self.mass_moment(theta)
        me = self.meas
        mt = mass + me.me_mass_kg
        g = (moment + me.me_mass_kg * me.me_cog_mm) / mt
        n = self.n
        dmass = np.zeros(self.size)
        dmom = np.zeros((3, self.size))
        dmass[:n] = self.m
        dmom[:, :n] = (self.m[:, None] * (self.c + s)).T
        dmom[self._rows, self._cols] = np.repeat(self.m * (1.0 + d), 3)
        if self.with_u:
            dmass[4 * n] = 1.0
            dmom[:, 4 * n + 1 :] = np.eye(3)
        jac = np.zeros((len(self.noise), self.size))
        jac[0] = dmass
        jac[1:4] = (dmom - np.outer(g, dmass)) / mt
        if self.with_inertia:
            # By central differences: δ relative (0.01), shifts and moments in mm (0.1).
            scale = np.full(self.size, 0.1)
            scale[:n] = 0.01
            if self.with_u:
                scale[4 * n] = 0.01 * max(self.m0, 1e-9)
            jac[4:] = numeric_jacobian(self._inertia, theta, scale)
        return jac

    def derived(self, theta: FloatArray, at_mm: FloatArray) -> FloatArray:
        """``(M, G, J_xx, J_xy, J_xz, J_yy, J_yz, J_zz)`` of the spacecraft (J about G) for
        each row of ``theta`` (shape (size,) or (B, size)), the unmodelled mass placed at
        ``at_mm`` for its inertia (its position's effect on the inertia's uncertainty is not
        counted)."""
        t = np.atleast_2d(theta)
        n = self.n
        d = t[:, :n]
        s = t[:, n : 4 * n].reshape(len(t), n, 3)
        mu = t[:, 4 * n] if self.with_u else np.zeros(len(t))
        h = t[:, 4 * n + 1 : 4 * n + 4] if self.with_u else np.zeros((len(t), 3))
        scale = 1.0 + d
        mass = self.m0 + d @ self.m + mu
        moment = self.s0 + (d * self.m) @ self.c + np.einsum("bn,bnk->bk", scale * self.m, s) + h
        g = moment / mass[:, None]
        mi = scale * self.m
        r = self.c + s - g[:, None, :]
        inertia = np.einsum("bn,nij->bij", scale, self.j) + _point_inertia(mi, r)
        if self.fixed is not None:
            f = self.fixed
            inertia = inertia + f.inertia_kg_mm2
            inertia = inertia + _point_inertia(
                np.full((len(t), 1), f.mass_kg), (f.cog_mm - g)[:, None, :]
            )
        if self.with_u:
            inertia = inertia + _point_inertia(
                np.maximum(mu, 0.0)[:, None], (at_mm - g)[:, None, :]
            )
        iu = np.triu_indices(3)
        out = np.concatenate([mass[:, None], g, inertia[:, iu[0], iu[1]]], axis=1)
        return out if np.ndim(theta) == 2 else out[0]


def _point_inertia(masses: FloatArray, r: FloatArray) -> FloatArray:
    """Inertia of point masses (B, n) at offsets ``r`` (B, n, 3): ``Σ m (|r|² 1 − r rᵀ)``,
    shape (B, 3, 3)."""
    r2 = np.einsum("bnk,bnk->bn", r, r)
    return np.asarray(
        np.einsum("bn,bn->b", masses, r2)[:, None, None] * np.eye(3)
        - np.einsum("bn,bnj,bnk->bjk", masses, r, r)
    )


@dataclass(frozen=True)
class Hypothesis:
    label: str
    description: str
    prior_probability: float
    mass_scale: FloatArray  # per-item factor on the mass σ
    cog_scale: FloatArray  # per-item factor on the CoG σ
    unmodelled: UnmodelledPrior | None
    item: str = ""  # the item this hypothesis says is off


@dataclass(frozen=True)
class Solution:
    hypothesis: Hypothesis
    model: Model
    theta: FloatArray
    cov: FloatArray
    log_evidence: float
    chi2: float
    negative: bool


def parameter_prior(
    items: Sequence[Item], hyp: Hypothesis | None, unmodelled: UnmodelledPrior | None
) -> tuple[FloatArray, FloatArray]:
    """Prior mean and covariance of ``θ``."""
    n = len(items)
    size = 4 * n + (4 if unmodelled is not None else 0)
    mean = np.zeros(size)
    cov = np.zeros((size, size))
    cov[: 4 * n, : 4 * n] = parameter_prior_cov(
        items,
        None if hyp is None else hyp.mass_scale,
        None if hyp is None else hyp.cog_scale,
    )
    if unmodelled is not None:
        u = unmodelled
        p_mean = u.center_mm
        p_cov = np.diag((u.hi_mm - u.lo_mm) ** 2 / 12.0)
        k = 4 * n
        mean[k] = u.mass_kg
        mean[k + 1 :] = u.mass_kg * p_mean
        cov[k, k] = u.sigma_kg**2
        cov[k, k + 1 :] = cov[k + 1 :, k] = u.sigma_kg**2 * p_mean
        cov[k + 1 :, k + 1 :] = (
            u.sigma_kg**2 * np.outer(p_mean, p_mean) + (u.mass_kg**2 + u.sigma_kg**2) * p_cov
        )
    return mean, cov


def _prior_root(p0: FloatArray, k: int) -> FloatArray:
    """``L`` with ``P₀ = L Lᵀ``, its zero-variance directions dropped (shape (size, rank)).

    The items' part of the prior (the first ``k`` parameters) is diagonal
    (:func:`cadcog.spacecraft.items.parameter_prior_cov`): its root is elementwise; only the
    unmodelled mass's 4 × 4 block is decomposed (no eigendecomposition of the whole prior, once
    per hypothesis).
    """
    size = len(p0)
    d = np.sqrt(np.clip(np.diag(p0)[:k], 0.0, None))
    w, v = np.linalg.eigh(0.5 * (p0[k:, k:] + p0[k:, k:].T)) if size > k else (d[:0], None)
    top = max(float(np.max(d * d, initial=0.0)), float(np.max(w, initial=0.0)), 1e-300)
    keep_d = d * d > 1e-30 * top
    cols = [np.eye(size)[:, :k][:, keep_d] * d[keep_d]]
    if v is not None:
        keep_w = w > 1e-30 * top
        block = np.zeros((size, int(keep_w.sum())))
        block[k:] = v[:, keep_w] * np.sqrt(w[keep_w])
        cols.append(block)
    return np.hstack(cols)


def _gauss_newton(
    model: Model,
    y: FloatArray,
    theta0: FloatArray,
    p0: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """MAP and its covariance (inverse Hessian) for a Gaussian prior, by Gauss-Newton in the
    prior's square-root coordinates ``θ = θ₀ + L z`` (``P₀ = L Lᵀ``; zero-variance directions
    stay at the prior)."""
    if not p0.size:  # nothing is uncertain: the prior is the answer
        return theta0, np.zeros((0, 0))
    root = _prior_root(p0, 4 * model.n)
    z = np.zeros(root.shape[1])
    r_inv = model.noise_inv
    for _ in range(MAX_ITERATIONS):
        theta = theta0 + root @ z
        jz = model.jacobian(theta) @ root
        y_pred = model.predict(theta)
        hessian = jz.T @ r_inv @ jz + np.eye(z.size)
        step = np.linalg.solve(hessian, jz.T @ r_inv @ (y - y_pred) - z)
        z = z + step
        if np.max(np.abs(step), initial=0.0) < GN_STEP_TOLERANCE:
            break
    theta = theta0 + root @ z
    jz = model.jacobian(theta) @ root
    hessian = jz.T @ r_inv @ jz + np.eye(z.size)
    cov = root @ np.linalg.inv(hessian) @ root.T
    return theta, 0.5 * (cov + cov.T)


def solve(
    items: Sequence[Item],
    fixed: MassProperties | None,
    meas: Measurement,
    y: FloatArray,
    hyp: Hypothesis,
) -> Solution:
    """MAP, covariance, evidence and prior-predictive χ² of one hypothesis (module docstring);
    an unmodelled mass the data want negative is held at 0."""
    unmodelled = hyp.unmodelled
    region = None if unmodelled is None else (unmodelled.lo_mm, unmodelled.hi_mm)
    model = Model(items, fixed, meas, unmodelled is not None, region)
    theta0, p0 = parameter_prior(items, hyp, unmodelled)
    j0 = model.jacobian(theta0)
    r0 = y - model.predict(theta0)
    chi2 = float(r0 @ np.linalg.solve(j0 @ p0 @ j0.T + model.noise, r0))
    theta, cov = _gauss_newton(model, y, theta0, p0)
    negative = bool(unmodelled is not None and theta[4 * model.n] < 0.0)
    if negative:  # held at zero: the hypothesis without an unmodelled mass
        model = Model(items, fixed, meas, False)
        theta0, p0 = parameter_prior(items, hyp, None)
        theta, cov = _gauss_newton(model, y, theta0, p0)
    # Evidence: the Gaussian marginal of the model linearised at the MAP.
    j = model.jacobian(theta)
    s = j @ p0 @ j.T + model.noise
    resid = y - model.predict(theta) - j @ (theta0 - theta)
    _, logdet = np.linalg.slogdet(2.0 * np.pi * s)
    log_evidence = -0.5 * (float(resid @ np.linalg.solve(s, resid)) + logdet)
    if negative:  # pad (m_u, h) = 0 with no spread, in the layout of the full model
        size = model.size
        theta = np.concatenate([theta, np.zeros(4)])
        full = np.zeros((size + 4, size + 4))
        full[:size, :size] = cov
        cov = full
        model = Model(items, fixed, meas, True, region)
    return Solution(hyp, model, theta, cov, log_evidence, chi2, negative)


def hypotheses(
    items: Sequence[Item],
    cad_mass_kg: float,
    unmodelled: UnmodelledPrior | None,
    envelope_mm: tuple[FloatArray, FloatArray] | None,
) -> list[Hypothesis]:
    n = len(items)
    ones = np.ones(n)
    k = ALTERNATIVE_SIGMA_FACTOR
    # A real export has dozens of items: "one item is off" keeps a total prior of at most
    # MAX_ALTERNATIVES_PROBABILITY, shared by the items that have mass.
    massive = [item for item in items if item.properties.mass_kg > 0]
    per_item = min(
        ALTERNATIVE_PRIOR_PROBABILITY, MAX_ALTERNATIVES_PROBABILITY / max(len(massive), 1)
    )
    half = per_item / 2.0
    alternatives: list[Hypothesis] = []
    for j, item in enumerate(items):
        if not item.properties.mass_kg > 0:
            continue  # a massless body cannot explain a gap
        wide = np.where(np.arange(n) == j, k, 1.0)
        alternatives.append(
            Hypothesis(
                f"{item.key} (mass)",
                f"{item.key}'s mass is off beyond its stated σ (×{k:g})",
                half,
                wide,
                ones,
                unmodelled,
                item.key,
            )
        )
        if np.any(item.cog_sigma_mm > 0):
            alternatives.append(
                Hypothesis(
                    f"{item.key} (CoG)",
                    f"{item.key}'s CoG is off beyond its stated σ (×{k:g})",
                    half,
                    ones,
                    wide,
                    unmodelled,
                    item.key,
                )
            )
    if envelope_mm is not None:
        lo, hi = (np.asarray(v, dtype=float) for v in envelope_mm)
        anywhere = UnmodelledPrior(
            lo,
            hi,
            unmodelled.mass_kg if unmodelled is not None else 0.0,
            max(UNMODELLED_SIGMA_FRACTION * cad_mass_kg, unmodelled.sigma_kg if unmodelled else 0),
        )
        alternatives.append(
            Hypothesis(
                "unmodelled",
                "an unmodelled mass anywhere in the spacecraft's bounding box"
                + (" (not in the given region)" if unmodelled is not None else ""),
                UNMODELLED_PRIOR_PROBABILITY,
                ones,
                ones,
                anywhere,
            )
        )
    null_prior = 1.0 - sum(h.prior_probability for h in alternatives)
    null = Hypothesis(
        "none",
        "every item within its stated σ"
        + (" and the unmodelled mass in the given region" if unmodelled is not None else ""),
        null_prior,
        ones,
        ones,
        unmodelled,
    )
    return [null, *alternatives]


def mixture(
    weights: FloatArray, means: Sequence[FloatArray], covs: Sequence[FloatArray]
) -> tuple[FloatArray, FloatArray]:
    """Mean and covariance of a Gaussian mixture (law of total variance)."""
    w = np.asarray(weights, dtype=float) / float(np.sum(weights))
    mu = np.asarray(means)
    mean = w @ mu
    spread = mu - mean
    cov = np.einsum("h,hij->ij", w, np.asarray(covs)) + np.einsum("h,hi,hj->ij", w, spread, spread)
    return np.asarray(mean), np.asarray(0.5 * (cov + cov.T))


def numeric_jacobian(f: Any, x: FloatArray, scale: FloatArray) -> FloatArray:
    """Central-difference Jacobian of ``f`` at ``x`` with steps 1e-4 of each scale; ``f``
    takes a batch of points (rows) and returns a batch of values. A parameter that cannot
    move (scale 0) has a zero column."""
    moving = np.flatnonzero(scale > 0)
    if not moving.size:  # nothing can move: every column is zero
        return np.zeros((np.atleast_2d(f(x[None, :])).shape[1], x.size))
    steps = 1e-4 * scale[moving]
    points = np.repeat(x[None, :], 2 * moving.size, axis=0)
    points[np.arange(moving.size), moving] += steps
    points[moving.size + np.arange(moving.size), moving] -= steps
    values = f(points)
    out = np.zeros((values.shape[1], x.size))
    out[:, moving] = ((values[: moving.size] - values[moving.size :]) / (2 * steps[:, None])).T
    return out


def cad_inertia_prior(items: Sequence[Item], fixed: MassProperties | None) -> FloatArray:
    """Covariance of the CAD tensor's entries ``[xx, yy, zz, xy, xz, yz]`` about its CoG
    (kg²·mm⁴) from the items' stated mass and CoG uncertainties, to first order."""
    return np.asarray(cad_joint_prior(items, fixed)[1][4:, 4:])


def cad_joint_prior(
    items: Sequence[Item], fixed: MassProperties | None
) -> tuple[FloatArray, FloatArray]:
    """The CAD's mass, CoG and tensor about its CoG, and their joint first-order covariance
    from the items' stated mass and CoG uncertainties.

    Returns
    -------
    mean : ndarray, shape (10,)
        ``(M, Gx, Gy, Gz, J_xx, J_yy, J_zz, J_xy, J_xz, J_yz)`` (kg, mm, kg·mm²; the tensor's
        own entries: ``J_xy = −∫ x·y dm``).
    cov : ndarray, shape (10, 10)
        Their covariance, in the same order.
    """
    model = Model(items, fixed, None, False)
    prior = parameter_prior_cov(items)
    theta = np.zeros(model.size)
    jac = numeric_jacobian(lambda t: model.derived(t, np.zeros(3)), theta, np.sqrt(np.diag(prior)))
    # derived's order: M, G (3), then the tensor's upper triangle xx, xy, xz, yy, yz, zz.
    order = [0, 1, 2, 3, 4, 7, 9, 5, 6, 8]
    j = jac[order]
    mean = model.derived(theta, np.zeros(3))[order]
    return np.asarray(mean, dtype=float), np.asarray(j @ prior @ j.T)
