"""Monte Carlo of the double-suspension method (docs/method.md §5), vectorised and streamed.

A trial is one group's estimate (a pair, or more points for the joint estimator) in one simulated
campaign. A campaign hangs the object once from every point some group uses: it draws the error
sources of :mod:`cadcog.method.errormodel` (one ME CoG error, each hang's play, wire offset and
reading errors), hangs the object physically (the true virtual suspension points and the true
assembly CoG give the true verticals) and reads the inclinometer with its errors. Each group then
estimates the CoG from the *nominal* points of its hangs with the estimator of ``cadcog
estimate`` (:mod:`cadcog.method.gls`), compensates the ME with its CAD CoG, and compares with the
true proof-mass CoG. A group's trials are independent (one per campaign); the groups of one
campaign share its hangs and its ME error, as the pairs of one lab campaign do.

Reproducibility: campaigns come in blocks of :data:`BLOCK_TRIALS`; block ``b`` draws from its own
generator seeded by ``SeedSequence(seed, spawn_key=(b,))``. Results are therefore identical
whatever the chunk size (blocks per vectorised batch) or the number of workers.
"""

from __future__ import annotations

import ctypes
import multiprocessing
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from itertools import combinations, pairwise
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.units import STANDARD_GRAVITY_M_S2
from cadcog.method.errormodel import ErrorModel, wire_shape_factor
from cadcog.method.gls import (
    PREPARED_ROWS,
    GLSBatch,
    LineErrors,
    PreparedLines,
    WireTerm,
    cog_only,
    combine_lines,
    plumb_gls,
    prepare_lines,
)
from cadcog.rig.geometry import FACES, face_normal, face_plane_mm, ideal_reading
from cadcog.rig.parameters import Rig

FloatArray = npt.NDArray[np.float64]

#: Trials per independently seeded block.
BLOCK_TRIALS = 4096

_ALLOCATOR_TUNED = False


def _init_worker() -> None:
    """Pool initializer: the allocator tuned, and Ctrl-C and SIGTERM left to the parent
    (:func:`cadcog.core.parallel.worker_signals`)."""
    from cadcog.core.parallel import worker_signals

    worker_signals()
    tune_allocator()


def tune_allocator() -> None:
    """Let glibc keep freed arrays in its heap instead of unmapping them (once per process).

    The kernels create many temporaries of 64 KiB to a few MiB. By default glibc serves each
    from a fresh ``mmap`` above 128 KiB (or trims the heap back) and the kernel zeroes its pages
    again: element-wise maths ran 4-6 times slower than with the arrays kept
    (``docs/performance.md``). Raising ``M_MMAP_THRESHOLD`` and ``M_TRIM_THRESHOLD`` keeps them;
    memory stays bounded by the batch size. Elsewhere than glibc this does nothing.
    """
    global _ALLOCATOR_TUNED
    if _ALLOCATOR_TUNED:
        return
    _ALLOCATOR_TUNED = True
    try:
        libc = ctypes.CDLL("libc.so.6")
        libc.mallopt(-3, 32 << 20)  # M_MMAP_THRESHOLD: 32 MiB
        libc.mallopt(-1, 128 << 20)  # M_TRIM_THRESHOLD: 128 MiB
    except (OSError, AttributeError):  # pragma: no cover - not glibc
        pass


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


def _measured_verticals(u_true: FloatArray, err_x: FloatArray, err_y: FloatArray) -> FloatArray:
    """Readings of the true verticals plus errors (degrees), back through eq. 2.

    ``u_true`` is component-first, shape (3, ...). ``sin(asin(u) + e)`` is evaluated as
    ``u cos e + √(1 − u²) sin e`` with ``cos e = √(1 − sin² e)`` (|e| < 90°), which avoids the
    arcsine and the cosine.
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
    sz = np.copysign(np.sqrt(np.maximum(1.0 - r2, 0.0)), u_true[2])
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
        Paper wire model: the offset of each hang along its bolt axis (mm). Elastica: the
        factor on λ, one per trial (the campaign's one wire).
    reading_deg : ndarray, shape (2, k, n)
        X and Y reading errors.
    """

    me_mm: FloatArray
    play_mm: FloatArray
    wire: FloatArray
    reading_deg: FloatArray


def draw_perturbations(
    model: ErrorModel, rng: np.random.Generator, n: int, k: int
) -> Perturbations:
    """Draw every enabled error source for ``n`` trials of ``k`` suspensions (others are 0).

    Draws are single precision (an error needs no more than 7 digits; it halves their cost).
    What is computed from them is double precision, but for the sine of a reading error and its
    cosine (:func:`_measured_verticals`), single precision like the error itself.
    """
    me = model.sample_me_errors(rng, n)
    play = model.sample_play(rng, n, k)
    wire = model.sample_wire(rng, n, k)
    return Perturbations(me, play, wire, model.sample_reading_errors(rng, (2, k, n)))


def hang(
    scenario: Scenario, model: ErrorModel, group: Sequence[int], pert: Perturbations
) -> FloatArray:
    """True upward verticals when hanging from each point of ``group``: shape (3, k, n).

    The object hangs from the *true* virtual suspension point (nominal point + play + wire
    offset along the bolt axis) and its true assembly CoG (CAD + the ME's CoG error).
    """
    idx = np.asarray(group)
    ratio = scenario.me_mass_kg / scenario.total_mass_kg
    g_true = (scenario.assembly_cog_mm[:, None] + ratio * pert.me_mm)[:, None, :]  # (3, 1, n)
    p = scenario.points_mm[idx].T[:, :, None]  # (3, k, 1)
    nrm = scenario.normals[idx].T[:, :, None]
    t1, t2 = (t[idx].T[:, :, None] for t in scenario.tangents)
    q = p + pert.play_mm[0] * t1 + pert.play_mm[1] * t2  # (3, k, n)
    if model.wire_model == "paper":
        delta = pert.wire
    elif "wire_offset" in model.sources:
        lam = model.wire_length_mm(scenario.weight_n) * pert.wire
        delta = lam * np.ones(q.shape[1:])
        for _ in range(3):  # θ depends on the offset only weakly: a fixed point converges
            u0 = _unit(q + delta * nrm - g_true)
            delta = lam * wire_shape_factor(_dot(u0, nrm), "elastica")
    else:
        delta = np.zeros(q.shape[1:])
    return _unit(q + delta * nrm - g_true)


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
    """
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

    The physics (:func:`hang`) and the reading errors of ``pert`` back through eq. 2.
    """
    u_true = hang(scenario, model, group, pert)
    return _measured_verticals(u_true, pert.reading_deg[0], pert.reading_deg[1])


def group_errors(
    scenario: Scenario,
    model: ErrorModel,
    group: Sequence[int],
    u: FloatArray,
    options: EstimatorOptions = EstimatorOptions(),
) -> FloatArray:
    """CoG errors (estimated − true, mm), shape (n, 3), of ``group``'s estimates from readings.

    The estimator of ``cadcog estimate`` on the nominal points and the measured verticals ``u``
    (3, k, n), through its CoG-only path :func:`cadcog.method.gls.cog_only`, then the ME
    compensation with the ME's CAD CoG.
    """
    idx = np.asarray(group)
    p = scenario.points_mm[idx].T[:, :, None]
    nrm = scenario.normals[idx].T[:, :, None]
    wire = WireTerm.from_model(
        model, scenario.weight_n, correct=options.wire_correction, estimate=options.self_calibrate
    )
    cog = cog_only(p, u, nrm, LineErrors.from_model(model), wire, weighted=options.weighted)
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


@dataclass(frozen=True)
class _Task:
    """Groups simulated by one worker call, over every campaign.

    Attributes
    ----------
    groups : tuple of tuple of int
        Their point indices.
    hangs : tuple of int
        The points every campaign hangs from (the union over *all* groups, sorted): each
        campaign draws the errors of all of them, so every task sees the same campaigns.
    """

    scenario: Scenario
    model: ErrorModel
    options: EstimatorOptions
    groups: tuple[tuple[int, ...], ...]
    screened: tuple[bool, ...]
    hangs: tuple[int, ...]
    trials: int
    seed: int
    chunk_blocks: int
    keep: bool


_GroupSummary = tuple[FloatArray, FloatArray, float, float, float, float, FloatArray | None]


def campaign_perturbations(
    model: ErrorModel, n_hangs: int, trials: int, seed: int, block: int
) -> Perturbations:
    """Draws of block ``block`` of :data:`BLOCK_TRIALS` campaigns of ``n_hangs`` hangs each.

    The block draws from ``SeedSequence(seed, spawn_key=(block,))``: a campaign's draws depend on
    the seed and its index only.
    """
    n = min(BLOCK_TRIALS, trials - block * BLOCK_TRIALS)
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(block,)))
    return draw_perturbations(model, rng, n, n_hangs)


def _hangs_subset(pert: Perturbations, cols: Sequence[int], per_hang_wire: bool) -> Perturbations:
    """The draws of some hangs of the campaigns (the ME error and an elastica wire are shared)."""
    idx = np.asarray(cols)
    return Perturbations(
        pert.me_mm,
        pert.play_mm[:, idx],
        pert.wire[idx] if per_hang_wire else pert.wire,
        pert.reading_deg[:, idx],
    )


def _add_errors(
    j: int, lo: int, e: FloatArray, norms: FloatArray, s1: FloatArray, s2: FloatArray
) -> None:
    """Group ``j``'s errors (n, 3) of the campaigns from ``lo`` into its norms and sums.

    The norms element by element (not ``einsum``, whose order of summation depends on the
    number of rows): a campaign's norm is the same whatever chunk it was computed in.
    """
    sq = e * e
    norms[j, lo : lo + len(e)] = np.sqrt(sq[:, 0] + sq[:, 1] + sq[:, 2])
    s1[j] += e.sum(axis=0)
    s2[j] += sq.sum(axis=0)


def _estimate_slice(
    task: _Task,
    u: FloatArray,
    lo: int,
    used: Sequence[int],
    wire: WireTerm,
    errors: LineErrors,
    stats: tuple[FloatArray, FloatArray, FloatArray],
) -> None:
    """Every group's estimate from the readings ``u`` (3, len(used), n) of campaigns ``lo`` on."""
    sc, model, options = task.scenario, task.model, task.options
    col = {h: j for j, h in enumerate(used)}
    if not wire.fixed:  # the wire scale is estimated: the full estimator, group by group
        for j, group in enumerate(task.groups):
            e = group_errors(sc, model, group, u[:, [col[h] for h in group]], options)
            _add_errors(j, lo, e, *stats)
        return
    # Each hang's share of the estimator once (a few hangs at a time: the temporaries stay
    # small), then every group from its hangs' shares.
    prepared: list[PreparedLines] = []
    for h0 in range(0, len(used), PREPARE_HANGS):
        few = list(used[h0 : h0 + PREPARE_HANGS])
        part = prepare_lines(
            sc.points_mm[few].T[:, :, None], u[:, h0 : h0 + len(few)],
            sc.normals[few].T[:, :, None], errors, wire, weighted=options.weighted,
        )  # fmt: skip
        prepared += [part.take(i) for i in range(len(few))]
    for j, group in enumerate(task.groups):
        cog = combine_lines([prepared[col[h]] for h in group])[:, 0, :]
        _add_errors(j, lo, compensated_errors(sc, cog), *stats)


def _run_task(
    task: _Task,
) -> tuple[list[_GroupSummary], npt.NDArray[np.int64], npt.NDArray[np.int64]]:
    """Simulate a task's groups over every campaign; per-group summaries and the histograms.

    Campaigns come in chunks of ``chunk_blocks`` blocks: their draws for every hang of the
    simulation, the physics and readings of the hangs this task's groups use, then each
    group's estimate from those readings. Everything is element-wise over campaigns, so the
    chunking changes the speed, never the numbers.
    """
    sc, model, options = task.scenario, task.model, task.options
    used = sorted(set().union(*task.groups))
    pos = {h: j for j, h in enumerate(task.hangs)}
    per_hang_wire = model.wire_model == "paper"
    norms = np.empty((len(task.groups), task.trials))
    s1 = np.zeros((len(task.groups), 3))
    s2 = np.zeros((len(task.groups), 3))
    stats = (norms, s1, s2)
    n_blocks = -(-task.trials // BLOCK_TRIALS)
    # Chunks of at most chunk_blocks blocks, fewer if the prepared hangs would outgrow their
    # budget (then estimated in slices), and balanced (9 blocks in chunks of 5 and 4, not 8 and 1).
    fit = PREPARED_BYTES // (PREPARED_ROWS * 8 * len(used) * BLOCK_TRIALS)
    n_chunks = -(-n_blocks // max(1, min(task.chunk_blocks, fit)))
    per_chunk = -(-n_blocks // n_chunks)
    cols = [pos[h] for h in used]
    wire = WireTerm.from_model(
        model, sc.weight_n, correct=options.wire_correction, estimate=options.self_calibrate
    )
    errors = LineErrors.from_model(model)
    for start in range(0, n_blocks, per_chunk):
        lo = start * BLOCK_TRIALS
        hi = min((start + per_chunk) * BLOCK_TRIALS, task.trials)
        # The physics block by block (its temporaries stay small), the estimates by chunk.
        u = np.empty((3, len(used), hi - lo))
        for b in range(start, min(start + per_chunk, n_blocks)):
            pert = campaign_perturbations(model, len(task.hangs), task.trials, task.seed, b)
            at = b * BLOCK_TRIALS - lo
            sub = _hangs_subset(pert, cols, per_hang_wire)
            u[:, :, at : at + pert.me_mm.shape[1]] = measured_verticals(sc, model, used, sub)
        # The estimates in slices whose prepared hangs fit PREPARED_BYTES (less than a block
        # when the hangs are many).
        step = max(1, PREPARED_BYTES // (PREPARED_ROWS * 8 * len(used)))
        for a in range(0, hi - lo, step):
            _estimate_slice(task, u[:, :, a : a + step], lo + a, used, wire, errors, stats)
        del u
    scr = np.asarray(task.screened)
    if scr.all():  # the usual cases first: no copy of the norms
        counts = NormHistogram.count(norms)
        counts_s = counts.copy()
    elif not scr.any():
        counts = NormHistogram.count(norms)
        counts_s = np.zeros_like(counts)
    else:
        counts_s = NormHistogram.count(norms[scr])
        counts = counts_s + NormHistogram.count(norms[~scr])
    out: list[_GroupSummary] = []
    for j in range(len(task.groups)):
        q50, q95 = _exact_quantiles(norms[j], (0.5, 0.95))
        out.append(
            (
                s1[j],
                s2[j],
                float(np.sum(norms[j] * norms[j])),  # not np.dot: no BLAS threads
                q50,
                q95,
                float(norms[j].mean()),
                norms[j].copy() if task.keep else None,
            )
        )
    return out, counts, counts_s


#: Memory (bytes) of a chunk's prepared hangs (:class:`cadcog.method.gls.PreparedLines`,
#: :data:`cadcog.method.gls.PREPARED_ROWS` floats per campaign and hang): bounds the chunk size.
PREPARED_BYTES = 32 << 20

#: Hangs prepared per call: bounds the preparation's temporaries.
PREPARE_HANGS = 5

#: Norms (bytes) one task holds at most (for each group's exact quantiles): with many trials per
#: group, groups are spread over more tasks. A single group of more trials needs more.
TASK_NORM_BYTES = 32 << 20


def simulate(
    scenario: Scenario,
    model: ErrorModel,
    groups: Sequence[Sequence[int]],
    trials_per_group: int,
    seed: int,
    options: EstimatorOptions = EstimatorOptions(),
    *,
    screened: Sequence[bool] | None = None,
    keep_norms: bool = False,
    chunk_blocks: int = 8,
    workers: int = 1,
    progress: Callable[[int], None] | None = None,
) -> SimulationResult:
    """Simulate ``trials_per_group`` campaigns; estimate every group from each of them.

    A campaign hangs the object once from every point that some group uses, with its own
    draws of every error source (one ME CoG error, each hang's play, wire offset and reading
    errors); each group's estimate uses that campaign's hangs, as a group of hangs of one lab
    campaign would. A trial is one group's estimate in one campaign. Each group's trials are
    therefore independent (one per campaign) and its error has exactly the distribution of
    independent draws; the groups of one campaign share hangs, as at the bench.

    Parameters
    ----------
    scenario, model, options
    groups : sequence of sequences of int
        Indices into ``scenario``'s points: pairs, or larger groups (joint estimate).
    trials_per_group : int
        Simulated campaigns.
    seed : int
        Root seed; the results depend on it, not on ``chunk_blocks`` or ``workers``.
    screened : sequence of bool, optional
        Which groups count in :attr:`SimulationResult.screened_histogram` (default: all).
    keep_norms : bool
        Also keep every norm (8 bytes a trial).
    chunk_blocks : int
        Most blocks of :data:`BLOCK_TRIALS` campaigns simulated per vectorised batch (fewer when
        their prepared hangs would exceed :data:`PREPARED_BYTES`).
    workers : int
        Processes to spread the groups over.
    progress : callable, optional
        Called with the number of trials finished after each batch of groups.
    """
    if trials_per_group < 2:
        raise ValueError("trials_per_group must be at least 2")
    if seed < 0:
        raise ValueError("seed must be non-negative")
    if not groups:
        raise ValueError("no group to simulate")
    if chunk_blocks < 1:
        raise ValueError("chunk_blocks must be at least 1")
    if workers < 1:
        raise ValueError("workers must be at least 1")
    n_points = len(scenario.ids)
    tgroups = [tuple(int(i) for i in g) for g in groups]
    for g in tgroups:
        if len(g) < 2 or len(set(g)) != len(g) or not all(0 <= i < n_points for i in g):
            raise ValueError(
                f"group {g}: expected two or more distinct point indices in 0..{n_points - 1}"
            )
    flags = [True] * len(tgroups) if screened is None else [bool(f) for f in screened]
    if len(flags) != len(tgroups):
        raise ValueError(f"screened has {len(flags)} flags for {len(tgroups)} groups")
    hangs = tuple(sorted(set().union(*tgroups)))
    # Every task draws and prepares all the campaigns' hangs: as few tasks as the norms' memory
    # allows (TASK_NORM_BYTES a task), and two per worker when there are several, so that a
    # worker slowed by other load on the machine leaves work to the other.
    per_task = max(1, TASK_NORM_BYTES // (8 * trials_per_group))
    per_worker = 2 if workers > 1 else 1
    n_tasks = min(len(tgroups), max(per_worker * workers, -(-len(tgroups) // per_task)))
    bounds = np.linspace(0, len(tgroups), n_tasks + 1).astype(int)
    common = (hangs, trials_per_group, seed, chunk_blocks, keep_norms)
    tasks = [
        _Task(scenario, model, options, tuple(tgroups[lo:hi]), tuple(flags[lo:hi]), *common)
        for lo, hi in pairwise(bounds)
        if hi > lo
    ]
    result = SimulationResult(NormHistogram(), NormHistogram())
    kept: list[FloatArray] = []
    tune_allocator()
    if workers > 1:
        # multiprocessing's pool, not concurrent.futures': leaving its block terminates the
        # workers at once, so Ctrl-C or SIGTERM stops a long run in a moment instead of
        # waiting for every queued task.
        with multiprocessing.Pool(workers, initializer=_init_worker) as pool:
            outputs = pool.imap(_run_task, tasks, chunksize=1)
            _collect(result, scenario, tasks, outputs, kept, progress)
    else:
        _collect(result, scenario, tasks, map(_run_task, tasks), kept, progress)
    if keep_norms:
        result.norms_mm = np.concatenate(kept)
    return result


def _collect(
    result: SimulationResult,
    scenario: Scenario,
    tasks: Sequence[_Task],
    outputs: Iterable[tuple[list[_GroupSummary], npt.NDArray[np.int64], npt.NDArray[np.int64]]],
    kept: list[FloatArray],
    progress: Callable[[int], None] | None,
) -> None:
    """Gather the tasks' outputs, in group order, into ``result``."""
    for task, (summaries, counts, counts_s) in zip(tasks, outputs, strict=True):
        result.histogram.counts += counts
        result.screened_histogram.counts += counts_s
        for group, (s1, s2, ss, q50, q95, mean, norms) in zip(task.groups, summaries, strict=True):
            result.n_trials += task.trials
            result.axis_sum_mm += s1
            result.axis_sumsq_mm2 += s2
            result.norm_sumsq_mm2 += ss
            result.groups.append(tuple(scenario.ids[i] for i in group))
            result.group_q50_mm.append(q50)
            result.group_q95_mm.append(q95)
            result.group_mean_mm.append(mean)
            if norms is not None:
                kept.append(norms)
        if progress is not None:
            progress(task.trials * len(task.groups))


def _exact_quantiles(x: FloatArray, qs: Sequence[float]) -> list[float]:
    """``np.quantile(x, q)`` (linear interpolation) for each q, by partial sorting."""
    pos = [q * (x.size - 1) for q in qs]
    kth = sorted({min(int(np.floor(p)) + d, x.size - 1) for p in pos for d in (0, 1)})
    part = np.partition(x, kth)
    out = []
    for p in pos:
        lo = int(np.floor(p))
        hi = min(lo + 1, x.size - 1)
        out.append(float(part[lo] + (p - lo) * (part[hi] - part[lo])))
    return out


def all_pairs(n_points: int) -> list[tuple[int, int]]:
    return list(combinations(range(n_points), 2))


def draw_points(
    rig: Rig, n_points: int, rng: np.random.Generator, max_tries: int = 100_000
) -> Scenario:
    """Scenario with ``n_points`` suspension points uniform over the proof-mass surface.

    A candidate is kept if its hole fits on its face, it is off the ME footprint (on +z), it keeps
    the clearance of one hole diameter from the points already drawn, and hanging from it keeps
    both inclinometer axes within range.
    """
    base = Scenario.from_rig(rig)
    size = np.asarray(rig.proof_mass.size_mm)
    faces = list(FACES)
    areas = np.array([np.prod(np.delete(size, FACES[f][0])) for f in faces])
    r = rig.hole_radius_mm
    h = rig.holes.wire_exit_height_mm
    g = rig.analytic_assembly.cog_mm
    ids: list[str] = []
    pts: list[FloatArray] = []
    nrms: list[FloatArray] = []
    faces_used: list[str] = []
    for _ in range(max_tries):
        if len(pts) == n_points:
            break
        f = faces[rng.choice(len(faces), p=areas / areas.sum())]
        axis, _ = FACES[f]
        pos = rng.uniform(0.0, size)
        pos[axis] = face_plane_mm(f, size)
        other = [j for j in range(3) if j != axis]
        if np.any(pos[other] < r) or np.any(pos[other] > size[other] - r):
            continue
        if f == "+z" and any(
            np.all(pos[:2] + r > v.min_mm[:2]) and np.all(pos[:2] - r < v.max_mm[:2])
            for v in rig.me_volumes
        ):
            continue
        if any(
            fu == f and np.linalg.norm(pos - (pp - h * face_normal(fu))) < 2 * rig.holes.diameter_mm
            for fu, pp in zip(faces_used, pts, strict=True)
        ):
            continue
        exit_mm = pos + h * face_normal(f)
        if not ideal_reading(exit_mm, g).in_range(rig.inclinometer_range_deg):
            continue
        ids.append(f"R{len(pts) + 1}")
        pts.append(exit_mm)
        nrms.append(face_normal(f))
        faces_used.append(f)
    if len(pts) < n_points:
        raise ValueError(f"found only {len(pts)} admissible suspension points in {max_tries} tries")
    return base.with_points(ids, pts, nrms)
