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

One concept a module: the trial model (scenario, error draws, one hang, one estimate) is
:mod:`cadcog.uncertainty.trials`, what a run keeps (histograms, streamed summaries)
:mod:`cadcog.uncertainty.histogram`; this module streams trials over campaigns, blocks, tasks
and workers (:func:`simulate`), and draws random suspension points (:func:`draw_points`). The
names of the other two stay importable from here.
"""

from __future__ import annotations

import ctypes
import multiprocessing
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from itertools import combinations, pairwise

import numpy as np
import numpy.typing as npt

from cadcog.method.errormodel import ErrorModel
from cadcog.method.gls import LineErrors, WireTerm
from cadcog.method.preparedlines import PREPARED_ROWS, PreparedLines, combine_lines, prepare_lines
from cadcog.rig.geometry import FACES, face_normal, face_plane_mm, ideal_reading
from cadcog.rig.parameters import Rig

# the trial model and the results have their own modules; their names stay importable here
from cadcog.uncertainty.histogram import NormHistogram, SimulationResult
from cadcog.uncertainty.trials import (  # noqa: F401
    EstimatorOptions,
    Perturbations,
    Scenario,
    _measured_verticals,
    _tangents,
    compensated_errors,
    draw_perturbations,
    estimate_trials,
    group_errors,
    hang,
    measured_verticals,
    propagate,
    simulate_block,
)

FloatArray = npt.NDArray[np.float64]

#: Trials per independently seeded block.
BLOCK_TRIALS = 4096

#: The estimator of ``cadcog estimate`` (frozen: safe as a default).
DEFAULT_OPTIONS = EstimatorOptions()

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
    """The draws of some hangs of the campaigns (the ME error, one wire and one sensor are
    shared)."""
    idx = np.asarray(cols)
    return Perturbations(
        pert.me_mm,
        pert.play_mm[:, idx],
        pert.wire[idx] if per_hang_wire else pert.wire,
        pert.reading_deg[:, idx],
        pert.shared,
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
    if not wire.fixed or (model.has_shared_sensor and options.weighted):
        # the wire scale or the sensor's shared errors are estimated: the full estimator,
        # group by group
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


#: Memory (bytes) of a chunk's prepared hangs (:class:`cadcog.method.preparedlines.PreparedLines`,
#: :data:`cadcog.method.preparedlines.PREPARED_ROWS` floats per campaign and hang): bounds the
#: chunk size.
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
    options: EstimatorOptions = DEFAULT_OPTIONS,
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
