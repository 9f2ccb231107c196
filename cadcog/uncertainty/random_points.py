"""``cadcog simulate``: the paper's Monte Carlo over random suspension points, with fits.

Draws suspension points over the proof mass (:func:`cadcog.uncertainty.montecarlo.draw_points`),
forms the groups the chosen estimator uses (every pair, optionally screened by conditioning, or
groups of K points for the joint estimator), runs :func:`cadcog.uncertainty.montecarlo.simulate` and
fits the error norms (:mod:`cadcog.uncertainty.fits`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from itertools import combinations
from math import comb
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core import tolerances
from cadcog.core.results import JsonResult
from cadcog.method import gls
from cadcog.method.errormodel import ErrorModel
from cadcog.rig.geometry import angle_between_lines_deg
from cadcog.rig.parameters import Rig
from cadcog.uncertainty.fits import NormFits, fit_histogram
from cadcog.uncertainty.montecarlo import (
    EstimatorOptions,
    Scenario,
    SimulationResult,
    draw_points,
    simulate,
)

#: Largest number of K-point groups simulated for the joint estimator (random subset beyond).
MAX_GROUPS = 300


@dataclass(frozen=True)
class SimulationSettings:
    """What to simulate.

    Attributes
    ----------
    points : int
        Random suspension points (0: the rig's own points).
    trials_per_group : int
        Simulated campaigns (one trial of every group each).
    seed : int
    group_size : int
        2 for pairs; K > 2 for the joint estimate over K points.
    min_angle_deg : float
        Pair screening: pairs (or groups) whose best-conditioned pair of lines meets at less
        than this are not simulated.
    weighted, wire_correction, self_calibrate : bool
        The estimator (:class:`cadcog.uncertainty.montecarlo.EstimatorOptions`): by default the one
        ``cadcog estimate`` runs.
    screen_angle_deg : float
        The headline also gives the statistics of the groups conditioned at least this well:
        what ``cadcog estimate`` would accept without warning.
    """

    points: int = 25
    trials_per_group: int = 1000
    seed: int = 0
    group_size: int = 2
    min_angle_deg: float = 0.0
    weighted: bool = True
    wire_correction: bool = True
    self_calibrate: bool = False
    screen_angle_deg: float = tolerances.MIN_PAIR_ANGLE_DEG

    @property
    def options(self) -> EstimatorOptions:
        return EstimatorOptions(self.weighted, self.wire_correction, self.self_calibrate)


@dataclass(frozen=True, repr=False)  # JsonResult's one-line repr
class SimulationReport(JsonResult):
    """What ``cadcog simulate`` reports: the settings, the error model, the groups simulated,
    the streamed result (histograms by group) and the fits of the error norm."""

    settings: SimulationSettings
    scenario: Scenario
    model: ErrorModel
    groups: list[tuple[int, ...]]
    group_angle_deg: list[float]
    result: SimulationResult
    fits: NormFits
    #: Groups left out because they cannot determine the wire scale (self-calibration only).
    unidentifiable_groups: int = 0

    @property
    def q99_mm(self) -> float:
        """99th percentile of the CoG error norm over every group and trial (mm)."""
        return self.result.histogram.quantile(0.99)

    @property
    def screened(self) -> dict[str, Any]:
        """Statistics of the groups conditioned at least ``screen_angle_deg``."""
        s = self.settings
        n_groups = sum(a >= s.screen_angle_deg for a in self.group_angle_deg)
        hist = self.result.screened_histogram
        out: dict[str, Any] = {"min_angle_deg": s.screen_angle_deg, "n_groups": n_groups}
        if hist.n:
            out |= {
                "n_trials": hist.n,
                "q50_mm": hist.quantile(0.5),
                "q95_mm": hist.quantile(0.95),
                "q99_mm": hist.quantile(0.99),
            }
        return out

    def worst_groups(self, count: int = 5) -> list[dict[str, Any]]:
        """The ``count`` groups of points with the largest 95th-percentile error, worst first."""
        order = np.argsort(self.result.group_q95_mm)[::-1][:count]
        return [
            {
                "points": list(self.result.groups[i]),
                "q95_mm": self.result.group_q95_mm[i],
                "mean_mm": self.result.group_mean_mm[i],
                "angle_deg": self.group_angle_deg[i],
            }
            for i in order
        ]

    def to_dict(self) -> dict[str, Any]:
        s, f = self.settings, self.fits
        fits = f.to_dict()
        for key in ("n_trials", "q50_mm", "q95_mm"):
            fits.pop(key)
        return {
            "n_trials": f.n,
            "q50_mm": f.q50_mm,
            "q95_mm": f.q95_mm,
            "q99_mm": self.q99_mm,
            "quantile_rel_precision": self.result.histogram.REL_WIDTH,
            "screened": self.screened,
            "fits": {
                **fits,
                "note": "moment fits, with their KS distance as their quality; the headline is "
                "the quantiles",
            },
            "per_axis_bias_mm": self.result.axis_mean_mm.tolist(),
            "per_axis_std_mm": self.result.axis_std_mm.tolist(),
            "n_points": len(self.scenario.ids),
            "n_groups": len(self.groups),
            "groups_left_out_wire_unidentifiable": self.unidentifiable_groups,
            "group_size": s.group_size,
            "trials_per_group": s.trials_per_group,
            "seed": s.seed,
            "min_angle_deg": s.min_angle_deg,
            "error_model": self.model.describe(),
            "estimator": s.options.describe(),
            "points": {
                pid: p.tolist()
                for pid, p in zip(self.scenario.ids, self.scenario.points_mm, strict=True)
            },
            "worst_groups": self.worst_groups(),
        }


def _conditioning_deg(scenario: Scenario, group: tuple[int, ...]) -> float:
    """Largest angle between two of the group's plumb lines (the pair's angle for a pair)."""
    g = scenario.assembly_cog_mm
    return max(
        angle_between_lines_deg(scenario.points_mm[a] - g, scenario.points_mm[b] - g)
        for a, b in combinations(group, 2)
    )


def select_groups(
    scenario: Scenario, settings: SimulationSettings, rng: np.random.Generator
) -> tuple[list[tuple[int, ...]], list[float]]:
    """Groups of point indices to simulate, and each group's conditioning angle (degrees).

    For a pair this is the angle between its two plumb lines; for a larger group, the largest
    such angle among its pairs (the joint estimate is as good as its best-spread pair allows).
    """
    n = len(scenario.ids)
    k = settings.group_size
    if not 2 <= k <= n:
        raise ValueError(f"group size must be between 2 and the number of points ({n}), got {k}")
    if comb(n, k) <= MAX_GROUPS or k == 2:
        groups = list(combinations(range(n), k))
    else:
        seen: set[tuple[int, ...]] = set()
        while len(seen) < MAX_GROUPS:
            seen.add(tuple(sorted(rng.choice(n, size=k, replace=False).tolist())))
        groups = sorted(seen)
    angles = [_conditioning_deg(scenario, g) for g in groups]
    kept = [(g, a) for g, a in zip(groups, angles, strict=True) if a >= settings.min_angle_deg]
    if not kept:
        raise ValueError(f"no group is conditioned better than {settings.min_angle_deg:g}°")
    return [g for g, _ in kept], [a for _, a in kept]


def run_simulation(
    rig: Rig,
    settings: SimulationSettings,
    model: ErrorModel | None = None,
    *,
    workers: int = 1,
    progress: Callable[[int], None] | None = None,
    total: Callable[[int], None] | None = None,
) -> SimulationReport:
    """Monte Carlo of ``rig`` under ``settings``; the error model defaults to the rig's.

    ``progress`` is called with the trials finished after each batch; ``total``, once before
    the first, with the number of trials to run (groups × trials per group: a progress bar's
    total, known only once the groups are chosen).
    """
    model = model or ErrorModel.from_rig(rig)
    ss = np.random.SeedSequence(settings.seed)
    points_seed, groups_seed, trials_seed = ss.generate_state(3)
    if settings.points > 0:
        scenario = draw_points(rig, settings.points, np.random.default_rng(points_seed))
    else:
        scenario = Scenario.from_rig(rig)
    groups, angles = select_groups(scenario, settings, np.random.default_rng(groups_seed))
    left_out = 0
    if settings.self_calibrate:
        ok = wire_identifiable(scenario, model, groups)
        left_out = len(groups) - int(ok.sum())
        groups = [g for g, keep in zip(groups, ok, strict=True) if keep]
        angles = [a for a, keep in zip(angles, ok, strict=True) if keep]
        if not groups:
            raise ValueError(
                "no group of points lets the wire offset scale be estimated (their bolt axes "
                "are parallel or along their verticals): drop --self-calibrate-wire"
            )
    if total is not None:
        total(len(groups) * settings.trials_per_group)
    result = simulate(
        scenario,
        model,
        groups,
        settings.trials_per_group,
        int(trials_seed),
        settings.options,
        screened=[a >= settings.screen_angle_deg for a in angles],
        workers=workers,
        progress=progress,
    )
    fits = fit_histogram(result.histogram, result.norm_sumsq_mm2)
    return SimulationReport(settings, scenario, model, groups, angles, result, fits, left_out)


def wire_identifiable(
    scenario: Scenario, model: ErrorModel, groups: Sequence[tuple[int, ...]]
) -> npt.NDArray[np.bool_]:
    """Which groups of points determine the wire scale λ with the CoG (self-calibration).

    Judged on noise-free lines from each point to the CAD assembly CoG, by the test
    ``cadcog estimate --self-calibrate-wire`` applies to its readings
    (:func:`cadcog.method.gls.scale_identifiable`). Every point on one face fails it: the
    offsets then move the lines as a shift of the CoG would.
    """
    out = np.zeros(len(groups), dtype=bool)
    wire = gls.WireTerm.from_model(model, scenario.weight_n, estimate=True)
    errors = gls.LineErrors.from_model(model)
    g = scenario.assembly_cog_mm[:, None, None]
    for k in sorted({len(grp) for grp in groups}):
        rows = [i for i, grp in enumerate(groups) if len(grp) == k]
        idx = np.array([groups[i] for i in rows]).T  # (k, n): the groups of k points as trials
        p = np.moveaxis(scenario.points_mm[idx], -1, 0)  # (3, k, n)
        nrm = np.moveaxis(scenario.normals[idx], -1, 0)
        u = (p - g) / np.linalg.norm(p - g, axis=0)
        with np.errstate(divide="ignore", invalid="ignore"):
            batch = gls.plumb_gls(p, u, nrm, errors, wire)
        out[rows] = gls.scale_identifiable(batch)
    return out
