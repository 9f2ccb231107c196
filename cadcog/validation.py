"""Experimental verification as a Bernoulli process (METHOD.md §6, eqs. 14-15), made rigorous.

Each measured pair of suspensions gives a compensated CoG whose error norm ``|e|`` is a trial;
success is ``|e| < ε``. The simulated CDF ``F(ε)`` predicts the success probability, the
campaign estimates it by ``p̂ = k/n`` (eq. 15). Eq. 14 asks that the two agree; here "agree"
means ``F(ε)`` lies inside the 95 % Clopper-Pearson interval of ``p̂``. A one-sample KS test of
the measured norms against the simulated CDF completes the check.

Caveat, stated in every report: the n = N(N−1)/2 pairs of N hangs share hangs, so their errors
are not independent; the binomial interval (and the KS p-value) treat them as if they were, as
the paper does. They are indicative, not exact.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from itertools import combinations
from typing import Any

import numpy as np
import numpy.typing as npt
from scipy import stats

from cadcog.errormodel import ErrorModel
from cadcog.errors import IllConditionedError
from cadcog.estimator import PlumbLine, compensate_me, pair_estimate
from cadcog.geometry import face_normal_of_point
from cadcog.inclinometer import InclinometerConfig
from cadcog.montecarlo import Scenario, simulate
from cadcog.readings import Suspension, suspension_verticals
from cadcog.rig import Rig

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
    alpha = 1.0 - confidence
    lo = 0.0 if k == 0 else float(stats.beta.ppf(alpha / 2, k, n - k + 1))
    hi = 1.0 if k == n else float(stats.beta.ppf(1 - alpha / 2, k + 1, n - k))
    return lo, hi


@dataclass(frozen=True)
class WindowCheck:
    """One row of the validation table (the paper's Table 2, with an interval)."""

    eps_mm: float
    F: float
    k: int
    n: int
    p_hat: float
    ci_low: float
    ci_high: float

    @property
    def consistent(self) -> bool:
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
            "consistent": self.consistent,
        }


@dataclass(frozen=True)
class Validation:
    windows: tuple[WindowCheck, ...]
    measured_norms_mm: FloatArray
    pairs: tuple[tuple[str, str], ...]
    ks_statistic: float
    ks_p_value: float

    @property
    def consistent(self) -> bool:
        return all(w.consistent for w in self.windows)

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
            "intervals and the KS p-value treat them as independent (as the paper does)",
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

    ks = stats.kstest(measured, sim_cdf)
    labels = tuple(pairs) if pairs else tuple((str(i), "") for i in range(n))
    return Validation(tuple(rows), measured, labels, float(ks.statistic), float(ks.pvalue))


def pair_errors(
    suspensions: Sequence[Suspension],
    config: InclinometerConfig,
    *,
    true_cog_mm: npt.ArrayLike,
    object_mass_kg: float,
    me_mass_kg: float,
    me_cog_mm: npt.ArrayLike,
) -> tuple[list[tuple[str, str]], FloatArray]:
    """Every pair's compensated eq. 8 estimate against the true CoG: labels and error norms.

    Pairs whose lines are parallel (no intersection at all) are skipped.
    """
    v = suspension_verticals(suspensions, config).u
    lines = [
        PlumbLine(s.id, np.array(s.position_mm), u) for s, u in zip(suspensions, v, strict=True)
    ]
    labels, norms = [], []
    for a, b in combinations(lines, 2):
        try:
            est = pair_estimate(a, b, min_angle_deg=0.0).midpoint_mm
        except IllConditionedError:
            continue
        comp = compensate_me(
            est,
            np.zeros((3, 3)),
            object_mass_kg=object_mass_kg,
            me_mass_kg=me_mass_kg,
            me_cog_mm=me_cog_mm,
        )
        labels.append((a.id, b.id))
        norms.append(float(np.linalg.norm(comp.cog_mm - np.asarray(true_cog_mm))))
    return labels, np.array(norms)


@dataclass(frozen=True)
class CampaignValidation:
    """A campaign checked against the Monte Carlo of the same rig and suspension points."""

    validation: Validation
    simulated_norms_mm: FloatArray
    trials_per_pair: int
    seed: int

    def to_dict(self) -> dict[str, Any]:
        sim = self.simulated_norms_mm
        return {
            **self.validation.to_dict(),
            "simulation": {
                "n_trials": int(sim.size),
                "trials_per_pair": self.trials_per_pair,
                "seed": self.seed,
                "q50_mm": float(np.quantile(sim, 0.5)),
                "q95_mm": float(np.quantile(sim, 0.95)),
            },
        }


def validate_campaign(
    rig: Rig,
    suspensions: Sequence[Suspension],
    windows_mm: Sequence[float] = DEFAULT_WINDOWS_MM,
    *,
    trials_per_pair: int = 20_000,
    seed: int = 0,
) -> CampaignValidation:
    """Measured pair errors of a campaign on ``rig`` against its simulated distribution.

    The true CoG is the rig's proof-mass CoG with its holes, from the closed forms of the CAD
    model (equal to the B-rep ground truth to 1e-9, ``tests/cad``); the simulation uses the rig's
    error model and the campaign's own suspension points (their faces inferred from their
    positions).
    """
    me = rig.analytic_me
    labels, measured = pair_errors(
        suspensions,
        rig.inclinometer,
        true_cog_mm=rig.analytic_proof_mass.cog_mm,
        object_mass_kg=rig.proof_mass.mass_kg,
        me_mass_kg=me.mass_kg,
        me_cog_mm=me.cog_mm,
    )
    if not labels:
        raise ValueError("no pair of suspensions has intersecting plumb lines")
    ids = [s.id for s in suspensions]
    points = np.array([s.position_mm for s in suspensions])
    normals = np.array(
        [face_normal_of_point(p, np.zeros(3), rig.proof_mass.size_mm) for p in points]
    )
    scenario = Scenario.from_rig(rig).with_points(ids, points, normals)
    index = {pid: i for i, pid in enumerate(ids)}
    groups = [(index[a], index[b]) for a, b in labels]
    sim = simulate(scenario, ErrorModel.from_rig(rig), groups, trials_per_pair, seed)
    validation = check_against_simulation(measured, sim.norms_mm, windows_mm, labels)
    return CampaignValidation(validation, sim.norms_mm, trials_per_pair, seed)
