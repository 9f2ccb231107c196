"""Monte Carlo of the double-suspension method (METHOD.md §5), vectorised and streamed.

For a group of suspension points (a pair, or all points for the joint estimator) every trial
draws the error sources of :mod:`cadcog.errormodel`, hangs the object physically (the true
virtual suspension points and the true assembly CoG give the true verticals), reads the
inclinometer with its errors, estimates the CoG from the *nominal* points as a user would,
compensates the ME with its CAD CoG, and compares with the true proof-mass CoG.

Reproducibility: trials come in blocks of :data:`BLOCK_TRIALS`; block ``b`` of group ``g`` draws
from its own generator seeded by ``SeedSequence(seed, spawn_key=(g, b))``. Results are therefore
identical whatever the chunk size (blocks per vectorised batch) or the number of workers.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from functools import cached_property
from itertools import combinations
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.errormodel import STANDARD_GRAVITY_M_S2, ErrorModel, elastica_length_mm, wire_offset_mm
from cadcog.geometry import FACES, face_normal, face_plane_mm, ideal_reading
from cadcog.rig import Rig
from cadcog.units import rad_to_deg

FloatArray = npt.NDArray[np.float64]

#: Trials per independently seeded block.
BLOCK_TRIALS = 4096


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
    """How the simulated user estimates.

    Attributes
    ----------
    wire_correction : bool
        Move each nominal point along its bolt axis by the expected wire offset (the model's
        mean: half the paper's bound, or the elastica's Δ(θ) at the measured θ).
    """

    wire_correction: bool = False


def _tangents(normals: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Two unit vectors spanning each face plane; normals of shape (k, 3)."""
    helper = np.where(np.abs(normals[:, [0]]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])
    t1 = np.cross(normals, helper)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return t1, np.cross(normals, t1)


# The vectorised kernels below hold vectors as components first, shape (3, ...): each component
# is then a contiguous array, which makes the element-wise maths several times faster than on
# (..., 3) arrays.


def _cross(a: FloatArray, b: FloatArray) -> FloatArray:
    """Cross product of component-first arrays, shape (3, ...)."""
    return np.stack(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


def _dot(a: FloatArray, b: FloatArray) -> FloatArray:
    """Dot product of component-first arrays, shape (3, ...) → (...)."""
    return np.asarray(a[0] * b[0] + a[1] * b[1] + a[2] * b[2])


def _unit(v: FloatArray) -> FloatArray:
    return np.asarray(v / np.sqrt(_dot(v, v)))


def _measured_verticals(u_true: FloatArray, err_x: FloatArray, err_y: FloatArray) -> FloatArray:
    """Readings of the true verticals plus errors (degrees), back through eq. 2.

    ``u_true`` is component-first, shape (3, ...). ``sin(asin(u) + e)`` is evaluated as
    ``u cos e + √(1 − u²) sin e``, which avoids the arcsine.
    """
    ex = np.deg2rad(err_x)
    ey = np.deg2rad(err_y)
    ux, uy = u_true[0], u_true[1]
    sx = ux * np.cos(ex) + np.sqrt(np.maximum(1.0 - ux * ux, 0.0)) * np.sin(ex)
    sy = uy * np.cos(ey) + np.sqrt(np.maximum(1.0 - uy * uy, 0.0)) * np.sin(ey)
    r2 = sx * sx + sy * sy
    over = r2 > 1.0
    if np.any(over):  # the paper's normalisation, rare: only near the horizontal
        scale = np.where(over, 1.0 / np.sqrt(np.where(over, r2, 1.0)), 1.0)
        sx, sy = sx * scale, sy * scale
        r2 = np.where(over, 1.0, r2)
    sz = np.copysign(np.sqrt(np.maximum(1.0 - r2, 0.0)), u_true[2])
    return np.stack([sx, sy, sz])


def _pair_midpoints(p: FloatArray, u: FloatArray) -> FloatArray:
    """Eq. 8 for many pairs at once: p, u component-first, shape (3, n, 2) → (3, n)."""
    ua, ub = u[:, :, 0], u[:, :, 1]
    n = _cross(ua, ub)
    n2 = _dot(n, n)
    d = p[:, :, 1] - p[:, :, 0]
    ta = _dot(_cross(d, ub), n) / n2
    tb = _dot(_cross(d, ua), n) / n2
    return np.asarray(0.5 * (p[:, :, 0] + ta * ua + p[:, :, 1] + tb * ub))


def _lsq_points(p: FloatArray, u: FloatArray) -> FloatArray:
    """Equal-weight least-squares point of k lines per trial: p, u shape (3, n, k) → (3, n)."""
    pt = np.moveaxis(p, 0, -1)  # (n, k, 3)
    ut = np.moveaxis(u, 0, -1)
    proj = np.eye(3) - ut[..., :, None] * ut[..., None, :]
    a = proj.sum(axis=1)
    b = np.einsum("nkij,nkj->ni", proj, pt)
    return np.asarray(np.linalg.solve(a, b[..., None])[..., 0].T)


@dataclass(frozen=True)
class Perturbations:
    """Random draws of one batch of trials for a group of k suspensions.

    Attributes
    ----------
    me_mm : ndarray, shape (3, n)
        ME CoG error (component-first, like every array here).
    play_mm : ndarray, shape (2, n, k)
        Suspension-point play along the two face tangents.
    wire : ndarray, shape (n, k)
        Paper wire model: the offset along the bolt axis (mm). Elastica: the factor on λ.
    reading_deg : ndarray, shape (2, n, k)
        X and Y reading errors.
    """

    me_mm: FloatArray
    play_mm: FloatArray
    wire: FloatArray
    reading_deg: FloatArray


def draw_perturbations(
    model: ErrorModel, rng: np.random.Generator, n: int, k: int
) -> Perturbations:
    """Draw every enabled error source for ``n`` trials of ``k`` suspensions (others are 0)."""
    me = model.sample_me_errors(rng, n)
    if "point_play" in model.sources and model.play_mm > 0:
        h = 0.5 * model.play_mm
        play = rng.uniform(-h, h, (2, n, k))
    else:
        play = np.zeros((2, n, k))
    if "wire_offset" not in model.sources:
        wire = np.zeros((n, k)) if model.wire_model == "paper" else np.ones((n, k))
    elif model.wire_model == "paper":
        wire = rng.uniform(0.0, model.wire_offset_max_mm, (n, k))
    else:
        rel = model.wire_stiffness_rel_uncertainty
        wire = np.sqrt(1.0 + rng.uniform(-rel, rel, (n, k)))
    return Perturbations(me, play, wire, model.sample_reading_errors(rng, (2, n, k)))


def hang(
    scenario: Scenario, model: ErrorModel, group: Sequence[int], pert: Perturbations
) -> FloatArray:
    """True upward verticals when hanging from each point of ``group``: shape (3, n, k).

    The object hangs from the *true* virtual suspension point (nominal point + play + wire
    offset along the bolt axis) and its true assembly CoG (CAD + the ME's CoG error).
    """
    idx = np.asarray(group)
    ratio = scenario.me_mass_kg / scenario.total_mass_kg
    g_true = (scenario.assembly_cog_mm[:, None] + ratio * pert.me_mm)[:, :, None]  # (3, n, 1)
    p = scenario.points_mm[idx].T[:, None, :]  # (3, 1, k)
    nrm = scenario.normals[idx].T[:, None, :]
    t1, t2 = (t[idx].T[:, None, :] for t in scenario.tangents)
    q = p + pert.play_mm[0] * t1 + pert.play_mm[1] * t2  # (3, n, k)
    if model.wire_model == "paper":
        delta = pert.wire
    elif "wire_offset" in model.sources:
        lam = elastica_length_mm(model.wire_bending_stiffness_n_mm2, scenario.weight_n) * pert.wire
        delta = lam.copy()
        for _ in range(3):  # θ depends on the offset only weakly: a fixed point converges
            u0 = _unit(q + delta * nrm - g_true)
            theta = rad_to_deg(np.arccos(np.clip(_dot(u0, nrm), -1, 1)))
            delta = wire_offset_mm(theta, lam)
    else:
        delta = np.zeros(pert.wire.shape)
    return _unit(q + delta * nrm - g_true)


def propagate(
    scenario: Scenario,
    model: ErrorModel,
    group: Sequence[int],
    pert: Perturbations,
    options: EstimatorOptions = EstimatorOptions(),
) -> FloatArray:
    """CoG errors (estimated − true, mm), shape (n, 3), for given perturbations.

    Deterministic: the physics and the estimator, with no random draws. A group of two uses
    eq. 8; a larger group the equal-weight least-squares point of all its lines.
    """
    idx = np.asarray(group)
    p = scenario.points_mm[idx].T[:, None, :]  # (3, 1, k)
    nrm = scenario.normals[idx].T[:, None, :]
    lam_nominal = elastica_length_mm(model.wire_bending_stiffness_n_mm2, scenario.weight_n)
    u_true = hang(scenario, model, group, pert)
    u = _measured_verticals(u_true, pert.reading_deg[0], pert.reading_deg[1])
    p_est = np.broadcast_to(p, u.shape)
    if options.wire_correction and "wire_offset" in model.sources:
        if model.wire_model == "paper":
            p_est = p_est + 0.5 * model.wire_offset_max_mm * nrm
        else:
            theta = rad_to_deg(np.arccos(np.clip(_dot(u, nrm), -1, 1)))
            p_est = p_est + wire_offset_mm(theta, lam_nominal) * nrm
    r_est = _pair_midpoints(p_est, u) if len(idx) == 2 else _lsq_points(p_est, u)
    r_pm = (scenario.total_mass_kg * r_est.T - scenario.me_mass_kg * scenario.me_cog_mm) / (
        scenario.pm_mass_kg
    )
    return np.asarray(r_pm - scenario.pm_cog_mm)


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


@dataclass
class SimulationResult:
    """Streamed results: error norms of every trial, per-axis moments, per-group summaries.

    Attributes
    ----------
    norms_mm : ndarray, shape (n_trials,)
        |e| of every trial, groups in order.
    axis_sum_mm, axis_sumsq_mm2 : ndarray, shape (3,)
        Running sums of the error components and of their squares.
    groups : list of tuple of str
    group_q95_mm, group_mean_mm : list of float
    """

    norms_mm: FloatArray
    axis_sum_mm: FloatArray
    axis_sumsq_mm2: FloatArray
    groups: list[tuple[str, ...]] = field(default_factory=list)
    group_q95_mm: list[float] = field(default_factory=list)
    group_mean_mm: list[float] = field(default_factory=list)

    @property
    def n_trials(self) -> int:
        return int(self.norms_mm.size)

    @property
    def axis_mean_mm(self) -> FloatArray:
        return np.asarray(self.axis_sum_mm / self.n_trials)

    @property
    def axis_std_mm(self) -> FloatArray:
        n = self.n_trials
        var = (self.axis_sumsq_mm2 - self.axis_sum_mm**2 / n) / (n - 1)
        return np.asarray(np.sqrt(np.maximum(var, 0.0)))


def _run_group(
    args: tuple[Scenario, ErrorModel, EstimatorOptions, int, tuple[int, ...], int, int, int],
) -> tuple[FloatArray, FloatArray, FloatArray, float]:
    """Simulate one group: its norms, axis sums, axis sums of squares and 95 % quantile."""
    scenario, model, options, g, group, trials, seed, chunk_blocks = args
    n_blocks = -(-trials // BLOCK_TRIALS)
    norms = np.empty(trials)
    s1 = np.zeros(3)
    s2 = np.zeros(3)
    for start in range(0, n_blocks, chunk_blocks):
        blocks = range(start, min(start + chunk_blocks, n_blocks))
        errors = []
        for b in blocks:
            n = min(BLOCK_TRIALS, trials - b * BLOCK_TRIALS)
            rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(g, b)))
            errors.append(simulate_block(scenario, model, group, n, rng, options))
        e = np.concatenate(errors)
        lo = blocks[0] * BLOCK_TRIALS
        norms[lo : lo + len(e)] = np.sqrt(np.einsum("ij,ij->i", e, e))
        s1 += e.sum(axis=0)
        s2 += np.einsum("ij,ij->j", e, e)
    return norms, s1, s2, _quantile_of_sorted(np.sort(norms), 0.95)


def simulate(
    scenario: Scenario,
    model: ErrorModel,
    groups: Sequence[Sequence[int]],
    trials_per_group: int,
    seed: int,
    options: EstimatorOptions = EstimatorOptions(),
    *,
    chunk_blocks: int = 8,
    workers: int = 1,
    progress: Callable[[int], None] | None = None,
) -> SimulationResult:
    """Run ``trials_per_group`` trials for each group of suspension indices.

    Parameters
    ----------
    scenario, model, options
    groups : sequence of sequences of int
        Indices into ``scenario``'s points: pairs for eq. 8, or larger groups (joint estimate).
    trials_per_group : int
    seed : int
        Root seed; the results depend on it, not on ``chunk_blocks`` or ``workers``.
    chunk_blocks : int
        Blocks of :data:`BLOCK_TRIALS` trials processed per vectorised batch (memory ∝ this).
    workers : int
        Processes to spread the groups over.
    progress : callable, optional
        Called with the number of trials finished after each group.
    """
    if trials_per_group < 2:
        raise ValueError("trials_per_group must be at least 2")
    if seed < 0:
        raise ValueError("seed must be non-negative")
    jobs = [
        (scenario, model, options, g, tuple(group), trials_per_group, seed, chunk_blocks)
        for g, group in enumerate(groups)
    ]
    result = SimulationResult(np.empty(len(jobs) * trials_per_group), np.zeros(3), np.zeros(3))
    if workers > 1:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            outputs = pool.map(_run_group, jobs, chunksize=max(1, len(jobs) // (4 * workers)))
            _collect(result, scenario, jobs, outputs, trials_per_group, progress)
    else:
        _collect(result, scenario, jobs, map(_run_group, jobs), trials_per_group, progress)
    return result


def _collect(
    result: SimulationResult,
    scenario: Scenario,
    jobs: Sequence[tuple[Any, ...]],
    outputs: Iterable[tuple[FloatArray, FloatArray, FloatArray, float]],
    trials: int,
    progress: Callable[[int], None] | None,
) -> None:
    """Gather the workers' outputs, in group order, into ``result``."""
    for j, (norms, s1, s2, q95) in enumerate(outputs):
        result.norms_mm[j * trials : (j + 1) * trials] = norms
        result.axis_sum_mm += s1
        result.axis_sumsq_mm2 += s2
        result.groups.append(tuple(scenario.ids[i] for i in jobs[j][4]))
        result.group_q95_mm.append(q95)
        result.group_mean_mm.append(float(norms.mean()))
        if progress is not None:
            progress(trials)


def _quantile_of_sorted(x: FloatArray, q: float) -> float:
    """``np.quantile(x, q)`` (linear interpolation) for an already sorted array, faster."""
    pos = q * (x.size - 1)
    lo = int(np.floor(pos))
    hi = min(lo + 1, x.size - 1)
    return float(x[lo] + (pos - lo) * (x[hi] - x[lo]))


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
