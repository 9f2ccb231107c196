"""Test planning: which of a set-up's candidate suspension points to hang from.

:func:`plan_test` screens every usable set of candidates by the covariance the estimator predicts
for it, then simulates the best few; ``cadcog plan`` prints its :class:`Plan`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from itertools import chain, combinations
from math import comb
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core import numformat, tolerances
from cadcog.core.results import JsonResult
from cadcog.method import gls, sym3
from cadcog.method.errormodel import ErrorModel
from cadcog.method.reversal import ReversalAdvice, best_reversal
from cadcog.method.wire import wire_shape_factor
from cadcog.rig.geometry import axes_beyond_range, ideal_reading
from cadcog.spacecraft.setup import Candidate, FloatArray, Setup
from cadcog.uncertainty.montecarlo import EstimatorOptions, simulate


@dataclass(frozen=True)
class CandidateCheck:
    id: str
    inc_x_deg: float
    inc_y_deg: float
    usable: bool
    reason: str


@dataclass(frozen=True, repr=False)  # JsonResult's one-line repr
class Plan(JsonResult):
    """A test plan: every candidate checked (usable or why not), the pairs and the best sets
    with their predicted errors, and the recommended set (``None`` when nothing is usable).

    Attributes
    ----------
    checks : tuple of CandidateCheck
        Each candidate point: its nominal readings, whether it is usable and why not.
    pairs : tuple of dict
        Usable pairs, best first: ids ``a``, ``b``, ``angle_deg`` between their plumb lines and
        the linearised 95 % error ``linearised_q95_mm``.
    best_sets : tuple of dict
        The simulated finalists of each size: ``points`` (ids), ``q50_mm``, ``q95_mm``,
        ``mean_mm`` (Monte Carlo of the estimator) and ``linearised_q95_mm``.
    recommended : dict or None
        The set to hang from, as an entry of ``best_sets``.
    model : ErrorModel or None
        The error model the prediction assumed.
    trials : int
        Monte Carlo trials per finalist set.
    mass_kg : float
        The spacecraft's CAD mass (kg), without the measurement equipment.
    me_mass_kg : float
        The measurement equipment's mass (kg).
    warnings : tuple of str
        What the plan's user must know (an ME heavy against the object).
    reason : str
        Why nothing is recommended (empty when a set is).
    goal : str
        ``"cog"``, ``"inertia"`` or ``"both"`` (:func:`cadcog.runs.plan.run_plan`).
    inertia : InertiaPlan or None
        The hangs for the inertia tensor (:mod:`cadcog.dynamics.hangplan`), when planned.
    inertia_refused : str
        Why no set determines the tensor (``goal="both"``), else empty.
    cad_cog_mm : tuple of 3 floats
        The spacecraft's CAD CoG (mm).
    reversal : ReversalAdvice or None
        When the rig declares the sensor's zero offset: the point of the recommended set whose
        re-hang with the sensor turned 180° on its mount helps most, and by how much
        (:func:`cadcog.method.reversal.best_reversal`).
    """

    checks: tuple[CandidateCheck, ...]
    pairs: tuple[dict[str, Any], ...]
    best_sets: tuple[dict[str, Any], ...]
    recommended: dict[str, Any] | None
    model: ErrorModel | None = None
    trials: int = 0
    mass_kg: float = 0.0
    cad_cog_mm: tuple[float, float, float] = (0.0, 0.0, 0.0)
    me_mass_kg: float = 0.0
    warnings: tuple[str, ...] = ()
    reason: str = ""
    goal: str = "cog"
    inertia: Any = None
    inertia_refused: str = ""
    reversal: ReversalAdvice | None = None

    def to_dict(self) -> dict[str, Any]:
        return {
            "mass_kg": self.mass_kg,
            "cad_cog_mm": list(self.cad_cog_mm),
            "me_mass_kg": self.me_mass_kg,
            "me_share": self.me_mass_kg / self.mass_kg if self.mass_kg else 0.0,
            "candidates": [c.__dict__ for c in self.checks],
            "pairs": list(self.pairs),
            "best_sets": list(self.best_sets),
            "recommended": self.recommended,
            "reversal": None if self.reversal is None else self.reversal.to_dict(),
            "warnings": list(self.warnings),
            "reason": self.reason,
            "error_model": None if self.model is None else self.model.describe(),
            "estimator": EstimatorOptions().describe(),
            "prediction": f"Monte Carlo of the estimator of cadcog estimate, {self.trials} "
            "trials per finalist set; pairs and sets screened by their linearised covariance",
            **self._inertia_dict(),
        }

    def _inertia_dict(self) -> dict[str, Any]:
        if self.goal == "cog":
            return {}
        inertia = (
            self.inertia.to_dict()
            if self.inertia is not None
            else {"refused": self.inertia_refused}
        )
        return {"inertia": inertia, "goal": self.goal}


def check_candidate(setup: Setup, candidate: Candidate) -> CandidateCheck:
    """Whether a candidate can be hung from: the nominal readings (the ME on, the CAD's CoG)
    within the inclinometer's range, and the vertical at least
    :data:`~cadcog.core.tolerances.MIN_VERTICAL_ELEVATION_DEG` from its plane; why not. An
    accelerometer reads the whole vector: every candidate is usable."""
    rng_deg = setup.rig.inclinometer_range_deg
    r = ideal_reading(candidate.position_mm, setup.assembly_cog_mm)
    if setup.rig.inclinometer.accelerometer:
        return CandidateCheck(candidate.id, r.inc_x_deg, r.inc_y_deg, True, "")
    bad = axes_beyond_range(r.inc_x_deg, r.inc_y_deg, rng_deg)
    reason = f"{' and '.join(bad)} beyond the ±{rng_deg:g}° range" if bad else ""
    elevation = float(np.degrees(np.arcsin(min(1.0, abs(float(r.vertical[2]))))))
    if not bad and elevation < tolerances.MIN_VERTICAL_ELEVATION_DEG:
        bad, reason = (
            ["z"],
            (
                f"the vertical lies {elevation:.1f}° from the inclinometer's plane (below "
                f"{tolerances.MIN_VERTICAL_ELEVATION_DEG:g}°): its readings cannot be trusted"
            ),
        )
    return CandidateCheck(candidate.id, r.inc_x_deg, r.inc_y_deg, not bad, reason)


def _masses(setup: Setup) -> tuple[float, tuple[float, float, float], float]:
    c = setup.mass.cog_mm
    return setup.mass.mass_kg, (float(c[0]), float(c[1]), float(c[2])), setup.me_mass_kg


#: The ME's mass over the object's above which the plan warns: the compensation multiplies
#: every error of the hung assembly's CoG by ``1 + m_ME/m`` and the ME's own CoG error by
#: ``m_ME/m`` (eq. 16).
ME_HEAVY_RATIO = 0.5


def _warnings(setup: Setup, model: ErrorModel) -> tuple[str, ...]:
    ratio = setup.me_mass_kg / setup.mass.mass_kg
    if not ratio > ME_HEAVY_RATIO:
        return setup.notes
    return (
        *setup.notes,
        f"the measurement equipment ({numformat.mass(setup.me_mass_kg)}) weighs {ratio:.2f}× "
        f"the object ({numformat.mass(setup.mass.mass_kg)}): the compensation multiplies every "
        f"error of the hung assembly's CoG by {1 + ratio:.2f}, and the ME's own CoG uncertainty "
        f"({model.me_sigma_mm:.2g} mm per axis) adds {ratio * model.me_sigma_mm:.2g} mm; a "
        "lighter ME is the remedy",
    )


#: Sets per size that are simulated after the linearised screening.
PLAN_FINALISTS = 5

#: Largest number of sets of one size screened exhaustively (greedy growth beyond).
PLAN_MAX_SETS = 250_000

#: Fixed standard normal draws turning a covariance into a 95 % norm quantile for screening.
_SCREEN_DRAWS = 2000


def _linearised_q95(cov: FloatArray, z: FloatArray) -> FloatArray:
    """95 % quantile of |e| for e ~ N(0, C), for a stack of covariances C (m, 3, 3)."""
    eig = np.clip(np.linalg.eigvalsh(cov), 0.0, None)  # the norm depends only on these
    r = np.sqrt(eig @ (z * z).T)  # (m, draws)
    return np.asarray(np.quantile(r, 0.95, axis=1))


def _combinations(n: int, k: int) -> npt.NDArray[np.int64]:
    """Every ``k``-subset of ``range(n)`` in :func:`itertools.combinations` order, (C(n, k), k).

    Examples
    --------
    >>> _combinations(4, 3).tolist()
    [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]
    """
    flat = chain.from_iterable(combinations(range(n), k))
    return np.fromiter(flat, dtype=np.int64, count=comb(n, k) * k).reshape(-1, k)


def plan_test(
    setup: Setup,
    *,
    trials: int = 10_000,
    max_set: int = 4,
    seed: int = 0,
    min_angle_deg: float = tolerances.MIN_PAIR_ANGLE_DEG,
) -> Plan:
    """Check every candidate, screen every usable set of hangs, and recommend one.

    Every set of 2 to ``max_set`` usable candidates whose plumb lines meet at ``min_angle_deg`` or
    more is screened by the covariance the estimator predicts for it at the nominal readings
    (:func:`cadcog.method.gls.plumb_gls`, with the ME term of eq. 16), exhaustively while there are
    at most :data:`PLAN_MAX_SETS` sets of a size, growing the best set of the previous size beyond.
    The :data:`PLAN_FINALISTS` best sets of each size are then simulated (``trials`` trials of the
    same error model and estimator as ``cadcog campaign`` and ``cadcog estimate``); the
    recommendation is the set with the smallest simulated 95 % CoG error.
    """
    g = setup.assembly_cog_mm
    checks = [check_candidate(setup, c) for c in setup.candidates]
    usable = tuple(c for c, k in zip(setup.candidates, checks, strict=True) if k.usable)
    model = setup.error_model()
    model.require_angle_sensor("the Monte Carlo plan (cadcog.plan)")

    def nothing(reason: str) -> Plan:
        """The plan that recommends nothing, and why."""
        args = (model, trials, *_masses(setup), _warnings(setup, model), reason)
        return Plan(tuple(checks), (), (), None, *args)

    if len(usable) < 2:
        return nothing(
            f"{len(usable)} of {len(checks)} candidates usable, two at least are needed: add "
            "candidates, or move the ME so that the readings stay in range"
        )
    scenario = setup.scenario(usable)
    n = len(usable)
    screen = _Screen.of(scenario, model, g, seed)
    pair_idx = _combinations(n, 2)
    pair_idx = pair_idx[screen.conditioning(pair_idx) >= min_angle_deg]
    if not len(pair_idx):
        return nothing(
            f"no two usable candidates' plumb lines meet at {min_angle_deg:g}° or more (the "
            "object hangs the same way from each: the points lie in line with its CoG, or the ME "
            "outweighs it): add candidates far apart on other faces"
        )
    pair_q95 = screen.q95(pair_idx)
    pairs = sorted(
        (
            {
                "a": usable[a].id,
                "b": usable[b].id,
                "angle_deg": float(screen.angle[a, b]),
                "linearised_q95_mm": float(q),
            }
            for (a, b), q in zip(pair_idx, pair_q95, strict=True)
        ),
        key=lambda d: d["linearised_q95_mm"],
    )
    best_sets = _best_sets(
        screen, scenario, model, [c.id for c in usable], pair_idx, pair_q95,
        max_set=max_set, min_angle_deg=min_angle_deg, trials=trials, seed=seed,
    )  # fmt: skip
    recommended = min(best_sets, key=lambda s: float(s["q95_mm"]))
    chosen = [next(j for j, c in enumerate(usable) if c.id == pid) for pid in recommended["points"]]
    reversal = best_reversal(
        [usable[j].id for j in chosen],
        scenario.points_mm[chosen],
        scenario.normals[chosen],
        g,
        gls.LineErrors.from_model(model),
        screen.wire,
        model.shared_sensor_sigmas,
        setup.rig.inclinometer,
        me_ratio=screen.ratio,
        me_sigma_mm=model.me_sigma_mm,
    )
    warnings = _warnings(setup, model)
    lo, hi = setup.bbox_mm
    half = 0.5 * float(np.min(np.asarray(hi) - np.asarray(lo)))
    if float(recommended["q95_mm"]) > half:
        warnings += (
            f"the best test's predicted 95 % error, {float(recommended['q95_mm']):.3g} mm, "
            f"exceeds half the object's smallest extent ({half:.3g} mm): it cannot place the "
            "CoG within the object",
        )
    return Plan(
        tuple(checks),
        tuple(pairs),
        tuple(best_sets),
        recommended,
        model,
        trials,
        *_masses(setup),
        warnings,
        reversal=reversal,
    )


@dataclass(frozen=True)
class _Screen:
    """The screening of sets of usable candidates at the nominal readings: the angles between
    their plumb lines, and the covariance the estimator predicts for a set.

    At the nominal readings every line's weight is its own, whatever set it is in: the
    equal-weight pass of the estimator finds the CoG exactly, so each point's distance is
    known. One weight per candidate (``terms``), then every set is a sum."""

    angle: FloatArray  # (n, n) degrees between the candidates' plumb lines
    terms: gls.LineTerms
    wire: gls.WireTerm
    ratio: float  # the ME's mass over the object's
    me_sigma_mm: float
    z: FloatArray  # standard normal draws for the linearised 95 % error

    @classmethod
    def of(cls, scenario: Any, model: Any, cog_mm: FloatArray, seed: int) -> _Screen:
        n = len(scenario.points_mm)
        u_nom = np.array([(scenario.points_mm[i] - cog_mm) for i in range(n)])
        u_nom /= np.linalg.norm(u_nom, axis=1, keepdims=True)
        cos = np.clip(np.abs(u_nom @ u_nom.T), 0.0, 1.0)
        angle = np.degrees(np.arccos(cos))
        z = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(1,))).standard_normal(
            (_SCREEN_DRAWS, 3)
        )
        p_all = scenario.points_mm.T[:, :, None]
        n_all = scenario.normals.T[:, :, None]
        u_all = u_nom.T[:, :, None]
        wire = gls.WireTerm.from_model(model, scenario.weight_n)
        errors = gls.LineErrors.from_model(model)
        weights = gls.plumb_gls(p_all, u_all, n_all, errors, wire).weights
        shape_all = (
            np.ones(n)
            if wire.model == "paper"
            else wire_shape_factor(np.sum(u_nom * scenario.normals, axis=1), wire.model)
        )
        ratio = scenario.me_mass_kg / scenario.pm_mass_kg
        terms = gls.LineTerms.of_lines(p_all, n_all, shape_all[:, None], weights)
        return cls(angle, terms, wire, ratio, model.me_sigma_mm, z)

    def conditioning(self, groups: npt.NDArray[np.int64]) -> FloatArray:
        """Each set's widest angle between two of its plumb lines (degrees), shape (m,)."""
        best = np.zeros(len(groups))
        for a, b in combinations(range(groups.shape[1]), 2):
            best = np.maximum(best, self.angle[groups[:, a], groups[:, b]])
        return best

    def predicted(self, groups: npt.NDArray[np.int64]) -> FloatArray:
        """Compensated linearised covariances (m, 3, 3) of sets (m, k)."""
        cov = self.terms.take(groups.T).solve(self.wire)[1]  # the lines' terms, summed over k
        r = self.ratio
        return np.asarray(
            (1 + r) ** 2 * sym3.sym_to_full(cov) + r**2 * self.me_sigma_mm**2 * np.eye(3)
        )

    def q95(self, groups: npt.NDArray[np.int64]) -> FloatArray:
        """Each set's linearised 95 % CoG error (mm)."""
        return _linearised_q95(self.predicted(groups), self.z)


def _best_sets(
    screen: _Screen,
    scenario: Any,
    model: Any,
    ids: Sequence[str],
    pair_idx: npt.NDArray[np.int64],
    pair_q95: FloatArray,
    *,
    max_set: int,
    min_angle_deg: float,
    trials: int,
    seed: int,
) -> list[dict[str, Any]]:
    """The best set of each size from 2 to ``max_set``: every set while there are at most
    :data:`PLAN_MAX_SETS`, else the previous size's best grown by one point; the
    :data:`PLAN_FINALISTS` best by the linearised error simulated, the smallest simulated 95 %
    error kept."""
    n = len(ids)
    best_sets: list[dict[str, Any]] = []
    current = pair_idx[int(np.argmin(pair_q95))]
    for k in range(2, min(max_set, n) + 1):
        if k == 2:
            groups, lin = pair_idx, pair_q95
        else:
            if comb(n, k) <= PLAN_MAX_SETS:
                groups = _combinations(n, k)
            else:  # grow the best set of the previous size by one point
                groups = np.array(
                    [sorted((*current.tolist(), j)) for j in range(n) if j not in current]
                )
            groups = groups[screen.conditioning(groups) >= min_angle_deg]
            if not len(groups):
                break
            tr = np.trace(screen.predicted(groups), axis1=1, axis2=2)
            top = np.argsort(tr)[: 50 * PLAN_FINALISTS]
            groups = groups[top]
            lin = screen.q95(groups)
        finalists = groups[np.argsort(lin)[:PLAN_FINALISTS]]
        res = simulate(scenario, model, [tuple(f) for f in finalists], trials, seed + k)
        i = int(np.argmin(res.group_q95_mm))
        current = finalists[i]
        best_sets.append(
            {
                "points": [ids[j] for j in current],
                "q95_mm": res.group_q95_mm[i],
                "q50_mm": res.group_q50_mm[i],
                "mean_mm": res.group_mean_mm[i],
                "linearised_q95_mm": float(lin[np.argsort(lin)[i]]),
            }
        )
    return best_sets
