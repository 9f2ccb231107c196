"""What a measurement says about the CAD: a Bayesian update of the mass budget that stays honest
when the spacecraft is not what its CAD says.

After the suspension test the measured CoG (with its covariance) and the weighed mass rarely
match the CAD. The CAD states how uncertain each item is (:mod:`cadcog.spacecraft.items`: a
relative mass change ``δ_I`` and a CoG shift ``s_I`` per item); this module asks which
explanation of the gap the data favour, and what the spacecraft's mass, CoG and inertia then
are, with their covariance.

**Observations.** ``y = (M_weighed, G_asm)``: the weighed spacecraft (without the measurement
equipment) and the CoG of the *assembly* (spacecraft + ME) that the hangs see,

    M(θ) = M_CAD + Σ m_I δ_I + m_u
    G(θ) = (S_CAD + Σ m_I (δ_I c_I + (1 + δ_I) s_I) + h + m_ME r_ME) / (M(θ) + m_ME)

with noise ``R``: the weighing's σ and the estimate's covariance plus the ME's CAD uncertainty
``(m_ME / M_total)² Σ_ME``. ``m_u`` and ``h = m_u p_u`` are an unmodelled mass and its moment
(prior: the mass ``N(μ_u, s_u²)``, its position uniform in a box, moment-matched), present in a
hypothesis that allows one.

**Hypotheses** (heavy tails as a mixture). A CAD is rarely wrong a little everywhere; more often
one thing is wrong by much. Besides ``H₀`` (every item within its stated σ; the user's
unmodelled mass in its region, if one is given) the update weighs:

- for each item ``I``, two: its mass σ (a part heavier than its data sheet), or its CoG σ (a
  CoG far from its model), ``ALTERNATIVE_SIGMA_FACTOR`` times wider; prior probability
  ``ALTERNATIVE_PRIOR_PROBABILITY`` per item, half each (at most
  ``MAX_ALTERNATIVES_PROBABILITY`` in all, shared, when there are many items; massless items
  are not weighed). These constants are :mod:`cadcog.spacecraft.explanations`'s;
- ``H_u``: an unmodelled mass anywhere in the spacecraft's bounding box (harness, fasteners,
  adhesive; replacing the user's region), prior ``0 ± UNMODELLED_SIGMA_FRACTION · M_CAD``,
  prior probability ``UNMODELLED_PRIOR_PROBABILITY``.

Each hypothesis is solved by Gauss-Newton on the exact (ratio) model, with the unmodelled mass
kept ≥ 0 (when the data want it negative it is fixed at 0 and the result says so); its
posterior covariance is the inverse Hessian there and its evidence the Gaussian marginal of the
model linearised at that point (exact for a linear model). Posterior probabilities
``P(H | y) ∝ P(H) p(y | H)``; the revised mass, CoG and inertia are the mixture's mean and
covariance (law of total variance), and each item's probability of being *the one that
changed* is the sum of its two hypotheses' posterior probabilities.

**Verdicts**, each a test of stated size :data:`LEVEL`:

- *differs*: ``χ² = rᵀ R⁻¹ r`` of the gap ``r = y − y_CAD`` against the measurement noise alone
  (4 dof; 10 with a measured tensor): the test tells the spacecraft from its CAD. Size 5 % on a
  spacecraft identical to its CAD.
- *consistent*: ``χ² = rᵀ (J P₀ Jᵀ + R)⁻¹ r`` under ``H₀`` (4 dof; 10): the gap is within the CAD's
  stated uncertainties. Size 5 % on spacecraft drawn from those uncertainties.
- *model rejected*: no hypothesis explains the gap at level 5 % (each one's prior-predictive
  χ²): the revised CoG is then the measurement's, with the measurement's covariance (never
  more confident than the data allow), and the revised mass the weighed one.

With no gap (the measurement equals the CAD's prediction) ``H₀`` is the most probable
explanation and the update moves nothing. Pure numpy; nothing here
imports the CAD layer.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.fittest import chi2_sf
from cadcog.mass.properties import MassProperties, combine
from cadcog.method.plumblines import compensate_me
from cadcog.spacecraft.explanations import (
    Hypothesis,
    Measurement,
    Model,
    Solution,
    UnmodelledPrior,
    hypotheses,
    mixture,
    numeric_jacobian,
    solve,
    unmodelled_from_region,
)
from cadcog.spacecraft.items import Item, items_from_bodies, linear_prior
from cadcog.spacecraft.update_result import LEVEL, Explanation, ItemChange, UpdateResult

FloatArray = npt.NDArray[np.float64]

__all__ = [
    "Explanation",
    "Item",
    "ItemChange",
    "Measurement",
    "UnmodelledPrior",
    "UpdateResult",
    "items_from_bodies",
    "recompensate",
    "unmodelled_from_region",
    "update_budget",
]

#: An unmodelled mass is placed (its position reported) only when it is this many σ above 0.
UNMODELLED_RESOLVED_SIGMAS = 2.0

#: Said whenever the gap is beyond the CAD's stated uncertainties.
INCONSISTENT_NOTE = (
    "The gap is larger than the CAD's stated uncertainties allow: the update weighs the "
    "explanations above (one item far off, an unmodelled mass) by how well each explains it; "
    "check the most probable one on the hardware before trusting the revised figures."
)

#: Said when no explanation fits.
REJECTED_NOTE = (
    "No explanation fits the gap (every hypothesis is rejected at 5 %): the revised CoG and "
    "mass are the measurement's, with the measurement's uncertainty; the CAD cannot be "
    "updated from this test (the inertia shown rests on the rejected explanations: do not use "
    "it). Look for a missing or misplaced part, or check the test."
)


def update_budget(
    items: Sequence[Item],
    fixed: MassProperties | None,
    measurement: Measurement,
    *,
    unmodelled: UnmodelledPrior | None = None,
    envelope_mm: tuple[npt.ArrayLike, npt.ArrayLike] | None = None,
    alternatives: bool = True,
) -> UpdateResult:
    """The revised mass budget given a measurement (module docstring).

    Parameters
    ----------
    items : sequence of Item
        The budget's uncertain items (:func:`cadcog.spacecraft.items.items_from_bodies`).
    fixed : MassProperties or None
        Everything without an uncertainty, combined.
    measurement : Measurement
    unmodelled : UnmodelledPrior, optional
        An unmodelled mass the user expects in a region (part of ``H₀``).
    envelope_mm : (lo, hi), optional
        The spacecraft's bounding box (mm): where ``H_u`` places an unmodelled mass. Without
        it, ``H_u`` is not weighed.
    alternatives : bool
        Weigh the alternative hypotheses (default). False: ``H₀`` alone, the plain Gaussian
        update under the CAD's stated uncertainties (confidently wrong when one item is far
        off: for comparison and tests).

    Raises
    ------
    ValueError
        With nothing uncertain to update, or a weighing that is not positive.
    """
    if not items and unmodelled is None and envelope_mm is None:
        raise ValueError("nothing to update: no item has a mass uncertainty and no unmodelled mass")
    if not measurement.mass_sigma_kg > 0:
        raise ValueError("the weighing needs a positive σ")
    env = None
    if envelope_mm is not None:
        env = (np.asarray(envelope_mm[0], float), np.asarray(envelope_mm[1], float))
    y = measurement.observed
    dof = len(y)
    null_model = Model(items, fixed, measurement, False)
    cad_mass = null_model.m0
    hyps = hypotheses(items, cad_mass, unmodelled, env)
    if not alternatives:
        hyps = [replace(hyps[0], prior_probability=1.0)]
    sols, dropped = _solutions(items, fixed, measurement, y, hyps)
    # Posterior probabilities of the hypotheses.
    logs = np.array([np.log(s.hypothesis.prior_probability) + s.log_evidence for s in sols])
    weights = np.exp(logs - logs.max())
    weights /= weights.sum()
    p_values = [chi2_sf(s.chi2, dof) for s in sols]
    # The verdicts.
    zero = np.zeros(null_model.size)
    r0 = y - null_model.predict(zero)
    differs_chi2 = float(r0 @ np.linalg.solve(null_model.noise, r0))
    model_rejected = max(p_values) < LEVEL
    mean_d, cov_d = _derived_mixture(sols, weights)
    cad = combine([i.properties for i in items] + ([fixed] if fixed is not None else []))
    cad_prior = linear_prior(items, fixed)
    measured_cog, measured_cov = recompensate(measurement)
    inertia, inertia_sigma = _inertia_with_sigma(mean_d[4:], np.diag(cov_d)[4:])
    if model_rejected:
        posterior = MassProperties(measurement.mass_kg, measured_cog, inertia, cad.volume_mm3)
        post_mass_sigma = measurement.mass_sigma_kg
        post_cog_cov = measured_cov
    else:
        posterior = MassProperties(float(mean_d[0]), mean_d[1:4], inertia, cad.volume_mm3)
        post_mass_sigma = float(np.sqrt(max(cov_d[0, 0], 0.0)))
        post_cog_cov = cov_d[1:4, 1:4]
    items_out = _item_changes(items, sols, weights)
    u_mass, u_sigma, u_cog, u_cov, u_negative, u_prob = _unmodelled_mixture(sols, weights)
    result = UpdateResult(
        cad=cad,
        cad_cog_cov_mm2=cad_prior.cog_cov_mm2,
        cad_mass_sigma_kg=cad_prior.mass_sigma_kg,
        measured_mass_kg=measurement.mass_kg,
        measured_mass_sigma_kg=measurement.mass_sigma_kg,
        measured_cog_mm=measured_cog,
        measured_cog_cov_mm2=measured_cov,
        posterior=posterior,
        posterior_mass_sigma_kg=post_mass_sigma,
        posterior_cog_cov_mm2=0.5 * (post_cog_cov + post_cog_cov.T),
        posterior_inertia_sigma_kg_mm2=inertia_sigma,
        items=items_out,
        explanations=_explanations(sols, weights, p_values, items_out),
        unmodelled_mass_kg=u_mass,
        unmodelled_mass_sigma_kg=u_sigma,
        unmodelled_cog_mm=u_cog,
        unmodelled_cog_cov_mm2=u_cov,
        unmodelled_negative=u_negative,
        unmodelled_probability=u_prob,
        differs_chi2=differs_chi2,
        differs_p_value=chi2_sf(differs_chi2, dof),
        chi2=sols[0].chi2,
        p_value=p_values[0],
        model_rejected=model_rejected,
        dof=dof,
    )
    notes = list(dropped)
    notes.extend(_wider_than_cad(result, sols, weights, measured_cov))
    if not items:
        notes.append(
            "no item states a mass uncertainty ([mass_uncertainty] in the materials file): "
            "the CAD is taken as exact, and only an unmodelled mass can explain a gap"
        )
    return replace(result, notes=tuple(notes))


def _derived_mixture(sols: Sequence[Any], weights: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The mass, CoG and inertia each hypothesis that matters (weight ≥ 1e-9) derives, with its
    covariance (first order), mixed by the hypotheses' posterior weights."""
    derived_means, derived_covs, used = [], [], []
    for s, w in zip(sols, weights, strict=True):
        if w < 1e-9:
            continue
        at = _unmodelled_position(s)
        f0 = s.model.derived(s.theta, at)
        jd = numeric_jacobian(
            lambda t, s=s, at=at: s.model.derived(t, at),
            s.theta,
            np.sqrt(np.maximum(np.diag(s.cov), 0.0)),
        )
        derived_means.append(f0)
        derived_covs.append(jd @ s.cov @ jd.T)
        used.append(w)
    return mixture(np.array(used), derived_means, derived_covs)


def _inertia_with_sigma(upper: FloatArray, upper_var: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The tensor (3, 3) from its upper triangle in row order (xx, xy, xz, yy, yz, zz) and each
    entry's σ from the triangle's variances."""
    iu = np.triu_indices(3)
    inertia = np.zeros((3, 3))
    inertia[iu] = upper
    inertia = inertia + np.triu(inertia, 1).T
    sigma = np.zeros((3, 3))
    sigma[iu] = np.sqrt(np.maximum(upper_var, 0.0))
    return inertia, np.maximum(sigma, sigma.T)


def _explanations(
    sols: Sequence[Any],
    weights: FloatArray,
    p_values: Sequence[float],
    items_out: Sequence[ItemChange],
) -> tuple[Explanation, ...]:
    """Each hypothesis with its prior and posterior probability and fit, most probable first;
    equally probable ones (to 0.01 %) by the item that can move the mass and the CoG most (its
    stated 1-σ mass), never a washer by file order."""
    weight_of = {c.key: c.mass_sigma_kg for c in items_out}
    return tuple(
        sorted(
            (
                Explanation(
                    s.hypothesis.label,
                    s.hypothesis.description,
                    s.hypothesis.prior_probability,
                    float(w),
                    s.chi2,
                    p,
                    s.negative,
                    s.hypothesis.item,
                )
                for s, w, p in zip(sols, weights, p_values, strict=True)
            ),
            key=lambda e: (-round(e.probability, 4), -weight_of.get(e.item, np.inf)),
        )
    )


def _wider_than_cad(
    result: UpdateResult, sols: Sequence[Any], weights: FloatArray, measured_cov: FloatArray
) -> list[str]:
    """A note when the updated CoG's σ exceeds the CAD's stated σ on an axis: the mixture keeps
    the explanations the test cannot rule out (an item off beyond its stated σ), which the
    CAD's own figure leaves out; a user would otherwise read it as the test making it worse."""
    cad = np.sqrt(np.maximum(np.diag(result.cad_cog_cov_mm2), 0.0))
    after = np.sqrt(np.maximum(np.diag(result.posterior_cog_cov_mm2), 0.0))
    wider = [k for k in range(3) if after[k] > cad[k] * (1.0 + 1e-3)]
    if not wider or result.model_rejected:
        return []
    prior_alt = 1.0 - float(sols[0].hypothesis.prior_probability)  # sols[0]: H₀
    post_alt = 1.0 - float(weights[0])
    measured = np.sqrt(np.maximum(np.diag(measured_cov), 0.0))
    axes = ", ".join(
        f"{'xyz'[k]} {cad[k]:.2g} → {after[k]:.2g} mm (the test's own {measured[k]:.2g})"
        for k in wider
    )
    return [
        f"the updated CoG's σ is wider than the CAD's stated σ ({axes}): the update keeps open "
        f"that an item is off beyond its stated σ (prior {prior_alt:.0%}, after the test "
        f"{post_alt:.0%}), which the CAD's figure leaves out and this test is too coarse to "
        "rule out; a test with a smaller σ would narrow it"
    ]


def _solutions(
    items: Sequence[Item],
    fixed: MassProperties | None,
    measurement: Measurement,
    y: FloatArray,
    hyps: Sequence[Hypothesis],
) -> tuple[list[Solution], list[str]]:
    """Each hypothesis solved; an alternative that is ill-posed (a singular system) is dropped
    with a note, the others' probabilities renormalised over what remains. ``H₀`` must solve."""
    sols, notes = [], []
    for h in hyps:
        try:
            sols.append(solve(items, fixed, measurement, y, h))
        except np.linalg.LinAlgError as exc:
            if not sols:  # H₀, the CAD as stated
                raise ValueError(
                    f"the CAD's own hypothesis cannot be solved ({exc}): the items' stated "
                    "uncertainties and the measurement leave a singular system"
                ) from None
            notes.append(f"explanation '{h.label}' dropped: ill-posed ({exc})")
    return sols, notes


def _unmodelled_position(s: Solution) -> FloatArray:
    """Where a solution places its unmodelled mass (its prior region's centre if none)."""
    if not s.model.with_u:
        return np.zeros(3)
    _, _, mu, h = s.model.split(s.theta)
    u = s.hypothesis.unmodelled
    assert u is not None
    if mu > 0:  # in its box: a barely resolved mass has a wild h / m
        return np.asarray(np.clip(h / mu, u.lo_mm, u.hi_mm))
    return u.center_mm


def _item_changes(
    items: Sequence[Item], sols: Sequence[Solution], weights: FloatArray
) -> tuple[ItemChange, ...]:
    n = len(items)
    out = []
    prob: dict[str, float] = {}
    for s, w in zip(sols, weights, strict=True):
        if s.hypothesis.item:
            prob[s.hypothesis.item] = prob.get(s.hypothesis.item, 0.0) + float(w)
    for k, item in enumerate(items):
        idx = [k, n + 3 * k, n + 3 * k + 1, n + 3 * k + 2]
        mean, cov = mixture(
            weights,
            [s.theta[idx] for s in sols],
            [s.cov[np.ix_(idx, idx)] for s in sols],
        )
        sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
        out.append(
            ItemChange(
                item.key,
                item.properties.mass_kg,
                item.sigma_rel,
                float(mean[0]),
                float(sd[0]),
                item.cog_sigma_mm,
                mean[1:],
                sd[1:],
                prob.get(item.key, 0.0),
            )
        )
    return tuple(out)


def _unmodelled_mixture(
    sols: Sequence[Solution], weights: FloatArray
) -> tuple[float | None, float | None, FloatArray | None, FloatArray | None, bool, float]:
    """The unmodelled mass given that there is one: its mixture over the hypotheses that hold
    one (weights renormalised), its position over those that place a positive mass, and the
    probability that there is one (the sum of their weights)."""
    held = [(s, float(w)) for s, w in zip(sols, weights, strict=True) if s.model.with_u]
    if not held or sum(w for _, w in held) <= 0:
        return None, None, None, None, False, 0.0
    means, covs, pos_w, pos_m, pos_c = [], [], [], [], []
    negative = False
    for s, w in held:
        k = 4 * s.model.n
        mu = float(s.theta[k])
        means.append(np.array([mu]))
        covs.append(s.cov[k : k + 1, k : k + 1])
        negative = negative or (s.negative and w > 0.5 * sum(v for _, v in held))
        if mu > 0:  # position c = h / m_u, by linear propagation from (m_u, h)
            h = s.theta[k + 1 : k + 4]
            jc = np.hstack([-h[:, None] / mu**2, np.eye(3) / mu])
            pos_w.append(w)
            pos_m.append(h / mu)
            pos_c.append(jc @ s.cov[k : k + 4, k : k + 4] @ jc.T)
    mean, cov = mixture(np.array([w for _, w in held]), means, covs)
    sigma = float(np.sqrt(max(cov[0, 0], 0.0)))
    cog = cog_cov = None
    if pos_w and sum(pos_w) > 0 and mean[0] > UNMODELLED_RESOLVED_SIGMAS * sigma:
        cog, cog_cov = mixture(np.array(pos_w), pos_m, pos_c)
    probability = float(sum(w for _, w in held))
    return float(mean[0]), sigma, cog, cog_cov, negative, probability


def recompensate(meas: Measurement) -> tuple[FloatArray, FloatArray]:
    """The spacecraft's CoG from the assembly CoG with the *weighed* mass (eqs. 10, 16), its
    covariance including the weighing's σ (:func:`cadcog.method.plumblines.compensate_me`)."""
    c = compensate_me(
        meas.assembly_cog_mm,
        meas.assembly_cov_mm2,
        object_mass_kg=meas.mass_kg,
        me_mass_kg=meas.me_mass_kg,
        me_cog_mm=meas.me_cog_mm,
        me_cog_cov_mm2=meas.me_cog_cov_mm2,
        object_mass_sigma_kg=meas.mass_sigma_kg,
    )
    return c.cog_mm, c.cov_mm2
