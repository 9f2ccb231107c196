"""What a Monte Carlo keeps: error norms binned in constant memory, and streamed summaries.

:class:`NormHistogram` counts error norms in log-spaced bins (quantiles and CDF in constant
memory); :class:`SimulationResult` gathers the histograms with per-axis and per-group summaries
as :func:`cadcog.uncertainty.montecarlo.simulate` streams its tasks.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]


class NormHistogram:
    """Counts of error norms in log-spaced bins: quantiles in constant memory.

    Bins are ``[LO·gʲ, LO·gʲ⁺¹)`` with ``g = 1 + REL_WIDTH``, from :data:`LO_MM` to
    :data:`HI_MM`, plus an underflow and an overflow bin. A quantile interpolated inside its
    bin is within ``REL_WIDTH`` (0.02 %) of the sample quantile, relative, whatever the number
    of trials; counts are integers, so the result does not depend on the order the trials are
    added in (chunks, workers).
    """

    REL_WIDTH = 2e-4
    LO_MM = 1e-6
    HI_MM = 1e6

    def __init__(self, counts: npt.NDArray[np.int64] | None = None) -> None:
        n = self.n_bins() + 2
        self.counts = np.zeros(n, dtype=np.int64) if counts is None else counts

    @classmethod
    def n_bins(cls) -> int:
        return int(np.ceil(np.log(cls.HI_MM / cls.LO_MM) / np.log1p(cls.REL_WIDTH)))

    @classmethod
    def edges_mm(cls) -> FloatArray:
        """The finite bin edges (n_bins + 1)."""
        return np.asarray(cls.LO_MM * np.exp(np.arange(cls.n_bins() + 1) * np.log1p(cls.REL_WIDTH)))

    def add(self, norms_mm: FloatArray) -> None:
        self.add_counts(self.count(norms_mm))

    def add_counts(self, counts: npt.NDArray[np.int64]) -> None:
        self.counts += counts

    #: Norms binned per pass of :meth:`count` (its temporaries stay under ~3 MB).
    COUNT_SLICE = 1 << 16

    @classmethod
    def count(cls, norms_mm: npt.ArrayLike) -> npt.NDArray[np.int64]:
        """Bin counts of ``norms_mm`` (add them to several histograms at the cost of one)."""
        x = np.asarray(norms_mm, dtype=float).ravel()
        nb = cls.n_bins()
        counts = np.zeros(nb + 2, dtype=np.int64)
        for lo in range(0, x.size, cls.COUNT_SLICE):
            part = x[lo : lo + cls.COUNT_SLICE]
            with np.errstate(divide="ignore"):
                j = np.floor(np.log(part * (1.0 / cls.LO_MM)) * (1.0 / np.log1p(cls.REL_WIDTH)))
            idx = np.clip(np.nan_to_num(j, nan=nb, neginf=-1.0), -1, nb) + 1
            counts += np.bincount(idx.astype(np.int64), minlength=nb + 2)
        return counts

    def merge(self, other: NormHistogram) -> None:
        self.counts += other.counts

    @property
    def n(self) -> int:
        return int(self.counts.sum())

    def quantile(self, q: float) -> float:
        """The ``q`` quantile (linear inside the bin holding it)."""
        n = self.n
        if n == 0:
            raise ValueError("empty histogram")
        target = q * n
        cum = np.cumsum(self.counts)
        j = int(np.searchsorted(cum, target, side="left"))
        j = min(max(j, 1), self.counts.size - 2)  # under/overflow: clamp to the range
        edges = self.edges_mm()
        lo, hi = edges[j - 1], edges[j]
        before = cum[j] - self.counts[j]
        frac = (target - before) / self.counts[j] if self.counts[j] else 0.0
        return float(lo + min(max(frac, 0.0), 1.0) * (hi - lo))

    def cdf_at_edges(self) -> tuple[FloatArray, FloatArray]:
        """Edges and the empirical CDF at them (fraction of norms below each edge)."""
        cum = np.cumsum(self.counts)[:-1] / max(self.n, 1)
        return self.edges_mm(), np.asarray(cum)

    def fraction_below(self, eps_mm: float) -> float:
        """Fraction of norms below ``eps_mm`` (to the bin: ``REL_WIDTH`` relative in ε)."""
        edges, cdf = self.cdf_at_edges()
        return float(np.interp(eps_mm, edges, cdf))


@dataclass
class SimulationResult:
    """Streamed results: histograms of the error norms, per-axis and per-group summaries.

    Attributes
    ----------
    histogram : NormHistogram
        |e| of every trial.
    screened_histogram : NormHistogram
        |e| of the trials of the groups marked as screened in (well-conditioned).
    n_trials : int
    axis_sum_mm, axis_sumsq_mm2 : ndarray, shape (3,)
        Sums of the error components and of their squares (group by group, in order).
    norm_sumsq_mm2 : float
        Σ |e|², for the moment fits.
    groups : list of tuple of str
    group_q50_mm, group_q95_mm, group_mean_mm : list of float
        Per group, exact (from that group's own trials).
    norms_mm : ndarray or None
        Every norm, groups in order, if asked for (``keep_norms``).
    """

    histogram: NormHistogram
    screened_histogram: NormHistogram
    n_trials: int = 0
    axis_sum_mm: FloatArray = field(default_factory=lambda: np.zeros(3))
    axis_sumsq_mm2: FloatArray = field(default_factory=lambda: np.zeros(3))
    norm_sumsq_mm2: float = 0.0
    groups: list[tuple[str, ...]] = field(default_factory=list)
    group_q50_mm: list[float] = field(default_factory=list)
    group_q95_mm: list[float] = field(default_factory=list)
    group_mean_mm: list[float] = field(default_factory=list)
    norms_mm: FloatArray | None = None

    @property
    def axis_mean_mm(self) -> FloatArray:
        return np.asarray(self.axis_sum_mm / self.n_trials)

    @property
    def axis_std_mm(self) -> FloatArray:
        n = self.n_trials
        var = (self.axis_sumsq_mm2 - self.axis_sum_mm**2 / n) / (n - 1)
        return np.asarray(np.sqrt(np.maximum(var, 0.0)))
