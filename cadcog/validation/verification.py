"""Experimental verification (docs/method.md §6, eqs. 14-15), with a test of stated size.

Each measured pair of suspensions gives a compensated CoG whose error norm ``|e|`` is a trial;
success is ``|e| < ε``. The simulated CDF ``F(ε)`` predicts the success probability, the
campaign estimates it by ``p̂ = k/n`` (eq. 15): the paper's Table 2, kept window by window.

The n = N(N−1)/2 pairs of N hangs share hangs, so their errors are not independent, and a
binomial interval (or a KS p-value) that treats them as independent has a false-alarm rate far
above its nominal level. Here the null distribution of every campaign statistic comes from
simulating *whole campaigns* on the same suspension points with the same error model
(:func:`campaign_null`): each window's count k gets its null interval, and the campaign gets
one verdict, a Monte Carlo p-value of the line statistic ``T = Σᵢ rᵢᵀ Wᵢ rᵢ`` (each hang's
plumb line against the known CoG, weighted by its model covariance), whose false-alarm rate
is its stated level (``benchmarks/study_validation.py``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from itertools import combinations
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.results import JsonResult
from cadcog.method import gls, sym3
from cadcog.method.errormodel import ErrorModel
from cadcog.method.estimate import BodyBox
from cadcog.method.readings import Suspension, suspension_verticals
from cadcog.method.wire import wire_shape_factor
from cadcog.rig.parameters import Rig
from cadcog.uncertainty.montecarlo import (
    BLOCK_TRIALS,
    EstimatorOptions,
    Scenario,
    campaign_perturbations,
    compensated_errors,
    measured_verticals,
)

FloatArray = npt.NDArray[np.float64]

DEFAULT_WINDOWS_MM = (0.5, 1.0, 1.5, 2.0, 3.0)
CONFIDENCE = 0.95


def clopper_pearson(k: int, n: int, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """Exact (Clopper-Pearson) two-sided interval for a binomial proportion k/n.

    Examples
    --------
    >>> lo, hi = clopper_pearson(0, 10)
    >>> lo, round(hi, 4)
    (0.0, 0.3085)
    """
    if not 0 <= k <= n or n < 1:
        raise ValueError(f"need 0 <= k <= n and n >= 1, got k={k}, n={n}")
    # The beta quantiles by scipy.special's inverse regularised incomplete beta function:
    # the very value scipy.stats.beta.ppf returns (both Boost's ibeta_inv; equal to the bit,
    # tests/validation/test_verification.py), without scipy.stats' second of import.
    from scipy.special import betaincinv

    alpha = 1.0 - confidence
    lo = 0.0 if k == 0 else float(betaincinv(k, n - k + 1, alpha / 2))
    hi = 1.0 if k == n else float(betaincinv(k + 1, n - k, 1 - alpha / 2))
    return lo, hi


@dataclass(frozen=True)
class WindowCheck(JsonResult):
    """One row of the validation table (the paper's Table 2, with intervals).

    ``ci_low, ci_high`` is the Clopper-Pearson interval of ``p̂`` as if the pairs were
    independent (the paper's view). ``null_k_low, null_k_high`` is the central 95 % range of k
    over simulated whole campaigns, which accounts for the shared hangs; when given, it decides
    ``consistent``.
    """

    eps_mm: float
    F: float
    k: int
    n: int
    p_hat: float
    ci_low: float
    ci_high: float
    null_k_low: int | None = None
    null_k_high: int | None = None

    @property
    def consistent(self) -> bool:
        if self.null_k_low is not None and self.null_k_high is not None:
            return self.null_k_low <= self.k <= self.null_k_high
        return self.ci_low <= self.F <= self.ci_high

    def to_dict(self) -> dict[str, Any]:
        return {
            "eps_mm": self.eps_mm,
            "F": self.F,
            "k": self.k,
            "n": self.n,
            "p_hat": self.p_hat,
            "eq14_difference": self.p_hat - self.F,
            "ci_low": self.ci_low,
            "ci_high": self.ci_high,
            "null_k_low": self.null_k_low,
            "null_k_high": self.null_k_high,
            "consistent": self.consistent,
        }


@dataclass(frozen=True)
class Validation(JsonResult):
    windows: tuple[WindowCheck, ...]
    measured_norms_mm: FloatArray
    pairs: tuple[tuple[str, str], ...]
    ks_statistic: float
    ks_p_value: float

    @property
    def consistent(self) -> bool:
        """Every window consistent (against its null range of k when it has one)."""
        return all(w.consistent for w in self.windows)

    @property
    def consistent_cp(self) -> bool:
        """The paper's check: F(ε) inside every window's Clopper-Pearson interval."""
        return all(w.ci_low <= w.F <= w.ci_high for w in self.windows)

    def to_dict(self) -> dict[str, Any]:
        return {
            "windows": [w.to_dict() for w in self.windows],
            "consistent": self.consistent,
            "ks_statistic": self.ks_statistic,
            "ks_p_value": self.ks_p_value,
            "pairs": [
                {"a": a, "b": b, "error_mm": float(e)}
                for (a, b), e in zip(self.pairs, self.measured_norms_mm, strict=True)
            ],
            "caveat": "pairs share hangs, so their errors are not independent; the binomial "
            "intervals and the KS p-value treat them as independent (as the paper does): the "
            "null ranges of k and the campaign verdict do not",
        }


def check_against_simulation(
    measured_norms_mm: npt.ArrayLike,
    simulated_norms_mm: npt.ArrayLike,
    windows_mm: Sequence[float] = DEFAULT_WINDOWS_MM,
    pairs: Sequence[tuple[str, str]] = (),
) -> Validation:
    """Compare measured error norms with the simulated distribution, window by window.

    Parameters
    ----------
    measured_norms_mm : array_like, shape (n,)
    simulated_norms_mm : array_like
        The Monte Carlo sample of the same set-up.
    windows_mm : sequence of float
        Error windows ε.
    pairs : sequence of (str, str), optional
        Labels of the measured trials.
    """
    measured = np.asarray(measured_norms_mm, dtype=float)
    sim = np.sort(np.asarray(simulated_norms_mm, dtype=float))
    n = measured.size
    if n < 1:
        raise ValueError("no measured trials")
    rows = []
    for eps in windows_mm:
        if not eps > 0:
            raise ValueError(f"windows must be positive, got {eps}")
        f = float(np.searchsorted(sim, eps, side="left") / sim.size)
        k = int(np.count_nonzero(measured < eps))
        lo, hi = clopper_pearson(k, n)
        rows.append(WindowCheck(float(eps), f, k, n, k / n, lo, hi))

    def sim_cdf(x: FloatArray) -> FloatArray:
        return np.asarray(np.searchsorted(sim, x, side="right") / sim.size)

    from scipy import stats  # here, not at import: scipy.stats takes ~1 s to import

    ks = stats.kstest(measured, sim_cdf)
    ks_statistic, ks_p_value = float(ks.statistic), float(ks.pvalue)
    labels = tuple(pairs) if pairs else tuple((str(i), "") for i in range(n))
    return Validation(tuple(rows), measured, labels, ks_statistic, ks_p_value)


@dataclass(frozen=True)
class CampaignNull:
    """Statistics of simulated whole campaigns on one set of suspension points.

    Attributes
    ----------
    pair_norms_mm : ndarray, shape (n_campaigns, n_pairs)
        Every pair's compensated error norm (the pairs of :attr:`pairs`, in order).
    line_stat : ndarray, shape (n_campaigns,)
        ``T = Σᵢ rᵢᵀ Wᵢ rᵢ`` of each campaign (:func:`line_statistic`).
    pairs : tuple of (int, int)
    seed : int
    """

    pair_norms_mm: FloatArray
    line_stat: FloatArray
    pairs: tuple[tuple[int, int], ...]
    seed: int

    @property
    def n_campaigns(self) -> int:
        return int(self.line_stat.size)


def _pairs(k: int) -> tuple[tuple[int, int], ...]:
    return tuple(combinations(range(k), 2))


def line_statistic(
    scenario: Scenario,
    model: ErrorModel,
    u: FloatArray,
    options: EstimatorOptions = EstimatorOptions(),  # noqa: B008 - frozen dataclass
) -> FloatArray:
    """``T = Σᵢ rᵢᵀ Wᵢ rᵢ`` of campaigns with measured verticals ``u`` (3, k, n).

    ``rᵢ`` is the lateral miss of hang i's plumb line (through its nominal point, corrected for
    the expected wire offset as the estimator does) from the known assembly CoG; ``Wᵢ`` the
    inverse of its lateral covariance under ``model`` (:func:`cadcog.method.gls.line_weights`,
    at the point's distance from that CoG). Near χ² with 2k degrees of freedom when the model
    is right; its exact null distribution comes from :func:`campaign_null`.
    """
    p = scenario.points_mm.T[:, :, None]
    nrm = scenario.normals.T[:, :, None]
    wire = gls.WireTerm.from_model(model, scenario.weight_n, correct=options.wire_correction)
    if wire.model == "paper":
        shape = np.ones(u.shape[1:])
    else:
        shape = wire_shape_factor(sym3.dot3(u, nrm), wire.model)
    q = p + wire.scale_mm * shape * nrm
    g = scenario.assembly_cog_mm[:, None, None]
    diff = g - q
    dist = np.sqrt(sym3.dot3(diff, diff))
    prior = model.wire_prior(scenario.weight_n)
    # The wire scale's spread (elastica) is shared by the hangs; as a statistic of each line
    # alone it is counted in every line's axial variance.
    errors = gls.LineErrors.from_model(model)
    if prior.scale_var_mm2:
        errors = gls.LineErrors(
            errors.play_var_mm2,
            errors.axial_var_mm2 + prior.scale_var_mm2 * float(np.max(shape)) ** 2,
            errors.reading_var_rad2,
        )
    w = gls.line_weights(u, nrm, dist, errors)
    return np.asarray(sym3.dot3(diff, sym3.sym_matvec(w, diff)).sum(axis=0))


def _pair_errors(
    scenario: Scenario,
    model: ErrorModel,
    u: FloatArray,
    pairs: Sequence[tuple[int, int]],
    options: EstimatorOptions,
    samples: npt.ArrayLike | None = None,
) -> FloatArray:
    """Compensated error norms, shape (n, n_pairs), of each pair's estimate from ``u``."""
    p = scenario.points_mm.T[:, :, None]
    nrm = scenario.normals.T[:, :, None]
    errors = gls.LineErrors.from_model(model, samples)
    wire = gls.WireTerm.from_model(model, scenario.weight_n, correct=options.wire_correction)
    out = np.empty((u.shape[2], len(pairs)))
    for j, (a, b) in enumerate(pairs):
        idx = [a, b]
        lerr = errors
        if samples is not None:
            lerr = gls.LineErrors(
                errors.play_var_mm2,
                errors.axial_var_mm2,
                np.asarray(errors.reading_var_rad2)[idx],
                errors.point_var_mm2,
            )
        est = gls.plumb_gls(
            p[:, idx], u[:, idx], nrm[:, idx], lerr, wire, weighted=options.weighted
        )
        e = compensated_errors(scenario, est.cog_mm)
        out[:, j] = np.sqrt(np.einsum("ij,ij->i", e, e))
    return out


def campaign_null(
    scenario: Scenario,
    model: ErrorModel,
    n_campaigns: int = 2000,
    seed: int = 0,
    options: EstimatorOptions = EstimatorOptions(),  # noqa: B008 - frozen dataclass
) -> CampaignNull:
    """Simulate ``n_campaigns`` whole campaigns (every hang once) and their statistics.

    Block b of campaigns draws from ``SeedSequence(seed, spawn_key=(b,))``: the result does
    not depend on anything but the seed.
    """
    if n_campaigns < 20:
        raise ValueError(f"need at least 20 simulated campaigns, got {n_campaigns}")
    pairs = _pairs(len(scenario.ids))
    norms, stat = [], []
    hangs = range(len(scenario.ids))
    for b in range(-(-n_campaigns // BLOCK_TRIALS)):
        pert = campaign_perturbations(model, len(hangs), n_campaigns, seed, b)
        u = measured_verticals(scenario, model, hangs, pert)
        norms.append(_pair_errors(scenario, model, u, pairs, options))
        stat.append(line_statistic(scenario, model, u, options))
    return CampaignNull(np.concatenate(norms), np.concatenate(stat), pairs, seed)


@dataclass(frozen=True)
class CampaignVerdict(JsonResult):
    """The one campaign-level test: the line statistic against its simulated null."""

    statistic: float
    p_value: float
    level: float
    n_null: int

    @property
    def consistent(self) -> bool:
        """The campaign is consistent with the model at the false-alarm rate ``level``."""
        return self.p_value >= self.level

    def to_dict(self) -> dict[str, Any]:
        return {
            "statistic": "T = sum of each hang's squared, model-weighted miss of the known CoG",
            "T": self.statistic,
            "p_value": self.p_value,
            "level": self.level,
            "n_null_campaigns": self.n_null,
            "consistent": self.consistent,
        }


@dataclass(frozen=True, repr=False)  # JsonResult's one-line repr
class CampaignValidation(JsonResult):
    """A campaign checked against simulated campaigns on the same rig and suspension points."""

    validation: Validation
    verdict: CampaignVerdict
    null: CampaignNull
    model: ErrorModel

    @property
    def simulated_norms_mm(self) -> FloatArray:
        """The simulated pair errors, pooled (the F(ε) of the table)."""
        return np.asarray(self.null.pair_norms_mm.ravel())

    @property
    def consistent(self) -> bool:
        """The campaign verdict: consistent with the Monte Carlo's prediction."""
        return self.verdict.consistent

    def to_dict(self) -> dict[str, Any]:
        sim = self.simulated_norms_mm
        return {
            **self.validation.to_dict(),
            "windows_consistent": self.validation.consistent,
            "campaign": self.verdict.to_dict(),
            "consistent": self.verdict.consistent,
            "simulation": {
                "n_campaigns": self.null.n_campaigns,
                "n_pair_trials": int(sim.size),
                "seed": self.null.seed,
                "q50_mm": float(np.quantile(sim, 0.5)),
                "q95_mm": float(np.quantile(sim, 0.95)),
            },
            "error_model": self.model.describe(),
        }


def campaign_scenario(rig: Rig, suspensions: Sequence[Suspension]) -> Scenario:
    """The rig's masses with the campaign's own points (faces inferred from their positions)."""
    normals = BodyBox.of_rig(rig).normals(suspensions)
    points = np.array([s.position_mm for s in suspensions], dtype=float)
    return Scenario.from_rig(rig).with_points([s.id for s in suspensions], points, normals)


def validate_campaign(
    rig: Rig,
    suspensions: Sequence[Suspension],
    windows_mm: Sequence[float] = DEFAULT_WINDOWS_MM,
    *,
    n_campaigns: int = 2000,
    seed: int = 0,
    level: float = 0.05,
    model: ErrorModel | None = None,
    null: CampaignNull | None = None,
) -> CampaignValidation:
    """A campaign of known truth (the rig's proof mass) against simulated campaigns.

    The true CoG is the rig's proof-mass CoG with its holes, from the closed forms of the CAD
    model (equal to the B-rep ground truth to 1e-9, ``tests/cad``). The null campaigns use the
    rig's error model (with the campaign's number of samples) and the campaign's own points;
    pass ``null`` to reuse one (it must come from the same points and model).
    """
    if len(suspensions) < 3:
        raise ValueError(f"validation needs 3 or more suspensions, got {len(suspensions)}")
    if not 0 < level < 1:
        raise ValueError(f"level must be in (0, 1), got {level}")
    base = model or ErrorModel.from_rig(rig)
    samples = [s.n_samples for s in suspensions]
    mdl = replace(base, samples=round(float(np.mean(samples))))
    scenario = campaign_scenario(rig, suspensions)
    options = EstimatorOptions()
    u = suspension_verticals(suspensions, rig.inclinometer).u.T[:, :, None]
    pairs = _pairs(len(suspensions))
    measured = _pair_errors(scenario, mdl, u, pairs, options, samples)[0]
    stat = float(line_statistic(scenario, mdl, u, options)[0])
    if null is None:
        null = campaign_null(scenario, mdl, n_campaigns, seed, options)
    elif null.pairs != pairs:
        raise ValueError("the given null distribution is for another set of suspensions")
    p_value = (1.0 + np.count_nonzero(null.line_stat >= stat)) / (null.n_campaigns + 1.0)
    verdict = CampaignVerdict(stat, float(p_value), level, null.n_campaigns)
    labels = [(suspensions[a].id, suspensions[b].id) for a, b in pairs]
    validation = check_against_simulation(measured, null.pair_norms_mm.ravel(), windows_mm, labels)
    rows = []
    for w in validation.windows:
        k_null = np.count_nonzero(null.pair_norms_mm < w.eps_mm, axis=1)
        lo, hi = np.quantile(k_null, [0.025, 0.975], method="inverted_cdf")
        rows.append(replace(w, null_k_low=int(lo), null_k_high=int(hi)))
    validation = replace(validation, windows=tuple(rows))
    return CampaignValidation(validation, verdict, null, mdl)
