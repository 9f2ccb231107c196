"""Distribution fits of CoG error norms: Rayleigh (the paper's), Maxwell, empirical quantiles.

The headline of a simulation is its empirical quantiles; the fits are shown beside them with
their KS distance, which says how much (or how little) they describe.

The norm of a 2-D isotropic normal error is Rayleigh; of a 3-D one, Maxwell (chi with 3 degrees
of freedom). The paper fitted a Rayleigh; a CoG error has three components, so the Maxwell is the
better-founded model, and heavy tails from near-collinear pairs fit neither: the KS statistics
say how well each fits. Because a few ill-conditioned pairs drag the maximum-likelihood scales
far into the tail, each law is also fitted robustly, by matching the sample median. (KS
p-values are not reported: with the parameter fitted on the same sample they would be biased.)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from cadcog.core.results import JsonResult

if TYPE_CHECKING:
    from cadcog.uncertainty.montecarlo import NormHistogram


@dataclass(frozen=True)
class NormFits(JsonResult):
    """Fits of error norms (mm)."""

    n: int
    rayleigh_sigma_mm: float
    maxwell_a_mm: float
    q50_mm: float
    q95_mm: float
    ks_rayleigh: float
    ks_maxwell: float
    rayleigh_sigma_median_mm: float
    maxwell_a_median_mm: float
    ks_rayleigh_median: float
    ks_maxwell_median: float

    def to_dict(self) -> dict[str, float | int]:
        return {
            "n_trials": self.n,
            "rayleigh_sigma_mm": self.rayleigh_sigma_mm,
            "maxwell_a_mm": self.maxwell_a_mm,
            "q50_mm": self.q50_mm,
            "q95_mm": self.q95_mm,
            "ks_rayleigh": self.ks_rayleigh,
            "ks_maxwell": self.ks_maxwell,
            "rayleigh_sigma_median_mm": self.rayleigh_sigma_median_mm,
            "maxwell_a_median_mm": self.maxwell_a_median_mm,
            "ks_rayleigh_median": self.ks_rayleigh_median,
            "ks_maxwell_median": self.ks_maxwell_median,
        }


#: Median of the unit Rayleigh law, √(2 ln 2), and of the unit Maxwell law (the root of its CDF at
#: 1/2; ``tests/uncertainty/test_fits.py`` checks both against scipy). Constants here keep
#: scipy.stats, a second to import, out of ``cadcog simulate``.
RAYLEIGH_MEDIAN = 1.1774100225154747
MAXWELL_MEDIAN = 1.5381722544550522


_ERF = np.frompyfunc(math.erf, 1, 1)


def _erf(x: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """``erf`` element-wise (math.erf: no scipy import, which costs half a second)."""
    return np.asarray(_ERF(np.asarray(x, dtype=float)), dtype=float)


def rayleigh_mle(norms_mm: npt.ArrayLike) -> float:
    """Maximum-likelihood Rayleigh scale: ``σ = √(Σ r² / 2n)``.

    Examples
    --------
    >>> rayleigh_mle([1.0, 1.0])
    0.7071067811865476
    """
    r = np.asarray(norms_mm, dtype=float)
    return float(np.sqrt(np.mean(r * r) / 2.0))


def maxwell_mle(norms_mm: npt.ArrayLike) -> float:
    """Maximum-likelihood Maxwell scale: ``a = √(Σ r² / 3n)``."""
    r = np.asarray(norms_mm, dtype=float)
    return float(np.sqrt(np.mean(r * r) / 3.0))


def rayleigh_cdf(r: npt.ArrayLike, sigma: float) -> npt.NDArray[np.float64]:
    """Rayleigh CDF, ``1 − exp(−r²/2σ²)`` (closed form: faster than scipy.stats)."""
    x = np.asarray(r, dtype=float) / sigma
    return np.asarray(-np.expm1(-0.5 * x * x))


def maxwell_cdf(r: npt.ArrayLike, a: float) -> npt.NDArray[np.float64]:
    """Maxwell CDF, ``erf(r/a√2) − √(2/π) (r/a) exp(−r²/2a²)``."""
    x = np.asarray(r, dtype=float) / a
    return np.asarray(_erf(x / np.sqrt(2.0)) - np.sqrt(2.0 / np.pi) * x * np.exp(-0.5 * x * x))


def ks_statistic(sorted_samples: npt.NDArray[np.float64], cdf_values: npt.ArrayLike) -> float:
    """One-sample Kolmogorov-Smirnov statistic from sorted samples and the model CDF at them."""
    n = sorted_samples.size
    f = np.asarray(cdf_values, dtype=float)
    i = np.arange(1, n + 1)
    return float(max(np.max(i / n - f), np.max(f - (i - 1) / n)))


def fit_norms(norms_mm: npt.ArrayLike) -> NormFits:
    """Rayleigh and Maxwell MLE fits, their KS statistics, and the empirical median and 95 %."""
    r = np.sort(np.asarray(norms_mm, dtype=float))
    if r.size < 2:
        raise ValueError("need at least two samples to fit")
    sigma = rayleigh_mle(r)
    a = maxwell_mle(r)
    q50 = float(np.quantile(r, 0.5))
    sigma_med = q50 / RAYLEIGH_MEDIAN
    a_med = q50 / MAXWELL_MEDIAN
    return NormFits(
        n=int(r.size),
        rayleigh_sigma_mm=sigma,
        maxwell_a_mm=a,
        q50_mm=q50,
        q95_mm=float(np.quantile(r, 0.95)),
        ks_rayleigh=ks_statistic(r, rayleigh_cdf(r, sigma)),
        ks_maxwell=ks_statistic(r, maxwell_cdf(r, a)),
        rayleigh_sigma_median_mm=sigma_med,
        maxwell_a_median_mm=a_med,
        ks_rayleigh_median=ks_statistic(r, rayleigh_cdf(r, sigma_med)),
        ks_maxwell_median=ks_statistic(r, maxwell_cdf(r, a_med)),
    )


def fit_histogram(hist: NormHistogram, norm_sumsq_mm2: float) -> NormFits:
    """:func:`fit_norms` from a streamed histogram and ``Σ r²``.

    The maximum-likelihood scales are exact (they need only ``Σ r²``); quantiles are within the
    histogram's relative bin width; KS distances are taken at the bin edges, so they can miss
    the supremum by at most the model CDF's rise inside one bin.
    """
    n = hist.n
    if n < 2:
        raise ValueError("need at least two samples to fit")
    sigma = float(np.sqrt(norm_sumsq_mm2 / n / 2.0))
    a = float(np.sqrt(norm_sumsq_mm2 / n / 3.0))
    q50 = hist.quantile(0.5)
    sigma_med = q50 / RAYLEIGH_MEDIAN
    a_med = q50 / MAXWELL_MEDIAN
    edges, emp = hist.cdf_at_edges()
    used = np.concatenate([[True], hist.counts[1:-1] > 0]) | np.concatenate(
        [hist.counts[1:-1] > 0, [True]]
    )
    e, f = edges[used], emp[used]

    def ks(cdf: npt.NDArray[np.float64]) -> float:
        return float(np.max(np.abs(f - cdf)))

    return NormFits(
        n=n,
        rayleigh_sigma_mm=sigma,
        maxwell_a_mm=a,
        q50_mm=q50,
        q95_mm=hist.quantile(0.95),
        ks_rayleigh=ks(rayleigh_cdf(e, sigma)),
        ks_maxwell=ks(maxwell_cdf(e, a)),
        rayleigh_sigma_median_mm=sigma_med,
        maxwell_a_median_mm=a_med,
        ks_rayleigh_median=ks(rayleigh_cdf(e, sigma_med)),
        ks_maxwell_median=ks(maxwell_cdf(e, a_med)),
    )
