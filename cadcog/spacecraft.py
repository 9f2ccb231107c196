"""A spacecraft from its CAD: set-up file, test planning, and comparison of a measured CoG.

The set-up file (``parts/cubesat_3u_setup.toml`` is the example) names the model (a STEP file
with a materials file, or a cadcog CubeSat spec), the measurement equipment (a rig's ME volumes,
placed on the spacecraft), the inclinometer and error model (the rig's), the candidate suspension
points (listed, or a grid on faces of the model's bounding box) and, optionally, the CubeSat
form factor.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from itertools import combinations
from math import comb
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog import bounds, gls, tolerances
from cadcog.envelope import CDS_COG_LIMITS_MM, check_envelope
from cadcog.errormodel import ErrorModel
from cadcog.errors import CadcogError
from cadcog.geometry import (
    FACES,
    axes_beyond_range,
    face_normal,
    face_normal_of_point,
    ideal_reading,
)
from cadcog.massprops import MassProperties
from cadcog.measurement import BodyBox, CogEstimate, MEData, estimate_cog
from cadcog.montecarlo import EstimatorOptions, Scenario, simulate
from cadcog.paramfile import TableReader, read_toml
from cadcog.readings import Suspension, id_problem
from cadcog.rig import MEVolume, Rig, me_cog_cov_mm2
from cadcog.rigfile import default_rig_path, load_rig

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class Candidate:
    id: str
    position_mm: FloatArray
    normal: FloatArray


@dataclass(frozen=True)
class Setup:
    name: str
    source: Path
    mass: MassProperties  # the spacecraft without ME, from CAD
    bbox_mm: tuple[FloatArray, FloatArray]
    me_volumes: tuple[MEVolume, ...]
    rig: Rig  # inclinometer, error model
    candidates: tuple[Candidate, ...]
    form_factor: str | None
    cog_limits_mm: FloatArray | None
    bodies: tuple[Any, ...]  # cadcog.cad.stepmass.BodyResult: mass, CoG, uncertainty item

    @property
    def geometric_center_mm(self) -> FloatArray:
        lo, hi = self.bbox_mm
        return np.asarray(0.5 * (lo + hi))

    @property
    def me_mass_kg(self) -> float:
        return sum(v.mass_kg for v in self.me_volumes)

    @property
    def me_cog_mm(self) -> FloatArray:
        m = np.array([v.mass_kg for v in self.me_volumes])
        c = np.array([v.center_mm for v in self.me_volumes])
        return np.asarray(m @ c / m.sum())

    @property
    def me_cog_cov_mm2(self) -> FloatArray:
        return me_cog_cov_mm2(self.me_volumes)

    def body(self) -> BodyBox:
        """The model's bounding box: the faces the suspension points sit on (bolt axes)."""
        lo, hi = self.bbox_mm
        return BodyBox(np.asarray(lo), np.asarray(hi), f"setup {self.source}")

    def me_data(self) -> MEData:
        """What ME compensation needs: the spacecraft's CAD mass and the placed ME."""
        return MEData(
            self.mass.mass_kg,
            self.me_mass_kg,
            self.me_cog_mm,
            self.me_cog_cov_mm2,
            f"setup {self.source}",
        )

    @property
    def assembly_cog_mm(self) -> FloatArray:
        m, me = self.mass.mass_kg, self.me_mass_kg
        return np.asarray((m * self.mass.cog_mm + me * self.me_cog_mm) / (m + me))

    def scenario(self, candidates: tuple[Candidate, ...] | None = None) -> Scenario:
        cands = self.candidates if candidates is None else candidates
        return Scenario(
            tuple(c.id for c in cands),
            np.array([c.position_mm for c in cands]),
            np.array([c.normal for c in cands]),
            self.mass.cog_mm,
            self.mass.mass_kg,
            self.me_mass_kg,
            self.me_cog_mm,
        )

    def error_model(self) -> ErrorModel:
        model = ErrorModel.from_rig(self.rig)
        return replace(
            model,
            me_masses_kg=tuple(v.mass_kg for v in self.me_volumes),
            me_edges_mm=tuple(v.cog_uncertainty_cube_mm for v in self.me_volumes),
        )


def estimate_for_setup(
    setup: Setup,
    suspensions: Sequence[Suspension],
    *,
    wire_correction: bool = True,
    self_calibrate: bool = False,
    angle_sigma_deg: float | None = None,
    point_sigma_mm: float | None = None,
    min_angle_deg: float = tolerances.MIN_PAIR_ANGLE_DEG,
) -> CogEstimate:
    """The spacecraft's compensated CoG from its suspensions, as ``cadcog estimate --setup``
    computes it: the set-up's inclinometer, error model, bolt axes and measurement equipment."""
    return estimate_cog(
        suspensions,
        setup.rig.inclinometer,
        setup.me_data(),
        model=setup.error_model(),
        body=setup.body(),
        wire_correction=wire_correction,
        self_calibrate=self_calibrate,
        angle_sigma_deg=angle_sigma_deg,
        point_sigma_mm=point_sigma_mm,
        min_angle_deg=min_angle_deg,
    )


def load_setup(path: str | Path) -> Setup:
    """Read a set-up file, compute the model's mass properties and the candidates."""
    p = Path(path)
    base = p.parent
    root = TableReader(read_toml(p), p)
    name = root.identifier("name")
    from cadcog.cad.modelfile import load_model

    massprops = load_model(root, base)
    form = None
    if root.has("form_factor"):
        form = root.string("form_factor", choices=list(CDS_COG_LIMITS_MM))
    limits = None
    if root.has("cog_limits_mm"):
        limits = np.array(root.vector("cog_limits_mm", positive=True))
    elif form is not None:
        limits = np.array(CDS_COG_LIMITS_MM[form])
    lo, hi = massprops.bbox_mm

    me_t = root.table("measurement_equipment")
    rig = load_rig(base / me_t.string("rig")) if me_t.has("rig") else load_rig(default_rig_path())
    target = np.array(me_t.vector("base_center_mm"))
    me_t.finish()
    rig_base = np.array([*rig.analytic_me.cog_mm[:2], rig.proof_mass.size_mm[2]])
    shift = target - rig_base
    volumes = tuple(
        replace(v, center_mm=_triple(np.asarray(v.center_mm) + shift)) for v in rig.me_volumes
    )

    cand_t = root.table("candidates")
    cands: list[Candidate] = []
    if cand_t.has("faces"):
        faces_value = cand_t.strings("faces", choices=list(FACES))
        spacing = cand_t.number("spacing_mm", positive=True)
        margin = cand_t.number("margin_mm", nonnegative=True)
        count = sum(_grid_size(f, lo, hi, spacing, margin) for f in faces_value)
        if count > bounds.MAX_CANDIDATES:
            raise cand_t.error(
                "spacing_mm",
                f"{spacing:g} mm gives {count} candidate points on {', '.join(faces_value)}; "
                f"at most {bounds.MAX_CANDIDATES} (every pair is screened): use a wider spacing",
            )
        for f in faces_value:
            cands.extend(_grid(f, lo, hi, spacing, margin))
    if cand_t.has("points"):
        for t in cand_t.tables("points"):
            pos = np.array(t.vector("position_mm"))
            try:
                normal = face_normal_of_point(pos, lo, hi)
            except ValueError:
                raise t.error(
                    "position_mm",
                    f"{pos.tolist()} is inside the model's bounding box: a "
                    "suspension point must be on its surface",
                ) from None
            pid = t.string("id")
            problem = id_problem(pid)
            if problem is not None:
                raise t.error("id", f"{pid!r}: {problem}")
            if any(c.id == pid for c in cands):
                raise t.error("id", f"duplicate candidate id {pid!r}")
            cands.append(Candidate(pid, pos, normal))
            t.finish()
    cand_t.finish()
    root.finish()
    if len(cands) < 2:
        raise CadcogError(f"{p}: fewer than two candidate suspension points")
    return Setup(
        name,
        p,
        massprops.total,
        (lo, hi),
        volumes,
        rig,
        tuple(cands),
        form,
        limits,
        tuple(massprops.bodies),
    )


def _triple(v: FloatArray) -> tuple[float, float, float]:
    return float(v[0]), float(v[1]), float(v[2])


def _grid_counts(
    face: str, lo: FloatArray, hi: FloatArray, spacing: float, margin: float
) -> list[int]:
    axis, _ = FACES[face]
    return [max(int((hi[j] - lo[j] - 2 * margin) // spacing) + 1, 1) for j in range(3) if j != axis]


def _grid_size(face: str, lo: FloatArray, hi: FloatArray, spacing: float, margin: float) -> int:
    a, b = _grid_counts(face, lo, hi, spacing, margin)
    return a * b


def _grid(
    face: str, lo: FloatArray, hi: FloatArray, spacing: float, margin: float
) -> list[Candidate]:
    axis, sign = FACES[face]
    others = [j for j in range(3) if j != axis]
    axes = []
    for j, n in zip(others, _grid_counts(face, lo, hi, spacing, margin), strict=True):
        span = (n - 1) * spacing
        mid = 0.5 * (lo[j] + hi[j])
        axes.append(mid - span / 2 + spacing * np.arange(n))
    out = []
    for a in axes[0]:
        for b in axes[1]:
            pos = np.zeros(3)
            pos[axis] = hi[axis] if sign > 0 else lo[axis]
            pos[others[0]], pos[others[1]] = a, b
            out.append(Candidate(f"{face}_{a:g}_{b:g}", pos, face_normal(face)))
    return out


# --- planning -------------------------------------------------------------------------------------
@dataclass(frozen=True)
class CandidateCheck:
    id: str
    inc_x_deg: float
    inc_y_deg: float
    usable: bool
    reason: str


@dataclass(frozen=True)
class Plan:
    checks: tuple[CandidateCheck, ...]
    pairs: tuple[dict[str, Any], ...]
    best_sets: tuple[dict[str, Any], ...]
    recommended: dict[str, Any] | None
    model: ErrorModel | None = None
    trials: int = 0

    def to_dict(self) -> dict[str, Any]:
        return {
            "candidates": [c.__dict__ for c in self.checks],
            "pairs": list(self.pairs),
            "best_sets": list(self.best_sets),
            "recommended": self.recommended,
            "error_model": None if self.model is None else self.model.describe(),
            "estimator": EstimatorOptions().describe(),
            "prediction": f"Monte Carlo of the estimator of cadcog estimate, {self.trials} "
            "trials per finalist set; pairs and sets screened by their linearised covariance",
        }


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


def plan_test(
    setup: Setup,
    *,
    trials: int = 10_000,
    max_set: int = 4,
    seed: int = 0,
    min_angle_deg: float = tolerances.MIN_PAIR_ANGLE_DEG,
) -> Plan:
    """Check every candidate, screen every usable set of hangs, and recommend one.

    Every set of 2 to ``max_set`` usable candidates whose plumb lines meet at ``min_angle_deg``
    or more is screened by the covariance the estimator predicts for it at the nominal readings
    (:func:`cadcog.gls.plumb_gls`, with the ME term of eq. 16), exhaustively while there are at
    most :data:`PLAN_MAX_SETS` sets of a size, growing the best set of the previous size beyond.
    The :data:`PLAN_FINALISTS` best sets of each size are then simulated (``trials`` trials of
    the same error model and estimator as ``cadcog campaign`` and ``cadcog estimate``); the
    recommendation is the set with the smallest simulated 95 % CoG error.
    """
    g = setup.assembly_cog_mm
    rng_deg = setup.rig.inclinometer_range_deg
    checks = []
    for c in setup.candidates:
        r = ideal_reading(c.position_mm, g)
        bad = axes_beyond_range(r.inc_x_deg, r.inc_y_deg, rng_deg)
        reason = f"{' and '.join(bad)} beyond the ±{rng_deg:g}° range" if bad else ""
        checks.append(CandidateCheck(c.id, r.inc_x_deg, r.inc_y_deg, not bad, reason))
    usable = tuple(c for c, k in zip(setup.candidates, checks, strict=True) if k.usable)
    model = setup.error_model()
    if len(usable) < 2:
        return Plan(tuple(checks), (), (), None, model, trials)
    scenario = setup.scenario(usable)
    n = len(usable)
    u_nom = np.array([(scenario.points_mm[i] - g) for i in range(n)])
    u_nom /= np.linalg.norm(u_nom, axis=1, keepdims=True)
    cos = np.clip(np.abs(u_nom @ u_nom.T), 0.0, 1.0)
    angle = np.degrees(np.arccos(cos))
    z = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(1,))).standard_normal(
        (_SCREEN_DRAWS, 3)
    )

    def conditioning(groups: npt.NDArray[np.int64]) -> FloatArray:
        best = np.zeros(len(groups))
        for a, b in combinations(range(groups.shape[1]), 2):
            best = np.maximum(best, angle[groups[:, a], groups[:, b]])
        return best

    # At the nominal readings every line's weight is its own, whatever set it is in: the
    # equal-weight pass of the estimator finds the CoG exactly, so each point's distance is
    # known. One weight per candidate, then every set is a sum.
    p_all = scenario.points_mm.T[:, :, None]
    n_all = scenario.normals.T[:, :, None]
    u_all = u_nom.T[:, :, None]
    wire = gls.WireTerm.from_model(model, scenario.weight_n)
    weights = gls.plumb_gls(p_all, u_all, n_all, gls.LineErrors.from_model(model), wire).weights
    shape_all = (
        np.ones(n)
        if wire.model == "paper"
        else gls.wire_shape_factor(np.sum(u_nom * scenario.normals, axis=1), wire.model)
    )
    ratio = scenario.me_mass_kg / scenario.pm_mass_kg

    def predicted(groups: npt.NDArray[np.int64]) -> FloatArray:
        """Compensated linearised covariances (m, 3, 3) of sets (m, k)."""
        g_t = groups.T  # (k, m)
        cov = gls.solve_lines(
            p_all[:, g_t, 0],
            u_all[:, g_t, 0],
            n_all[:, g_t, 0],
            shape_all[g_t],
            weights[:, g_t, 0],
            wire,
        )[1]
        return np.asarray(
            (1 + ratio) ** 2 * gls.sym_to_full(cov) + ratio**2 * model.me_sigma_mm**2 * np.eye(3)
        )

    pair_idx = np.array(list(combinations(range(n), 2)))
    pair_idx = pair_idx[conditioning(pair_idx) >= min_angle_deg]
    if not len(pair_idx):
        return Plan(tuple(checks), (), (), None, model, trials)
    pair_q95 = _linearised_q95(predicted(pair_idx), z)
    pairs = sorted(
        (
            {
                "a": usable[a].id,
                "b": usable[b].id,
                "angle_deg": float(angle[a, b]),
                "linearised_q95_mm": float(q),
            }
            for (a, b), q in zip(pair_idx, pair_q95, strict=True)
        ),
        key=lambda d: d["linearised_q95_mm"],
    )
    best_sets: list[dict[str, Any]] = []
    current = pair_idx[int(np.argmin(pair_q95))]
    for k in range(2, min(max_set, n) + 1):
        if k == 2:
            groups, lin = pair_idx, pair_q95
        else:
            if comb(n, k) <= PLAN_MAX_SETS:
                groups = np.array(list(combinations(range(n), k)))
            else:  # grow the best set of the previous size by one point
                groups = np.array(
                    [sorted((*current.tolist(), j)) for j in range(n) if j not in current]
                )
            groups = groups[conditioning(groups) >= min_angle_deg]
            if not len(groups):
                break
            tr = np.trace(predicted(groups), axis1=1, axis2=2)
            top = np.argsort(tr)[: 50 * PLAN_FINALISTS]
            groups = groups[top]
            lin = _linearised_q95(predicted(groups), z)
        finalists = groups[np.argsort(lin)[:PLAN_FINALISTS]]
        res = simulate(scenario, model, [tuple(f) for f in finalists], trials, seed + k)
        i = int(np.argmin(res.group_q95_mm))
        current = finalists[i]
        best_sets.append(
            {
                "points": [usable[j].id for j in current],
                "q95_mm": res.group_q95_mm[i],
                "q50_mm": res.group_q50_mm[i],
                "mean_mm": res.group_mean_mm[i],
                "linearised_q95_mm": float(lin[np.argsort(lin)[i]]),
            }
        )
    recommended = min(best_sets, key=lambda s: float(s["q95_mm"]))
    return Plan(tuple(checks), tuple(pairs), tuple(best_sets), recommended, model, trials)


def compare_with_cad(setup: Setup, cog_mm: FloatArray, cov_mm2: FloatArray) -> dict[str, Any]:
    """Measured minus CAD CoG in mm and in sigmas, and the CubeSat envelope check."""
    diff = cog_mm - setup.mass.cog_mm
    sigma = np.sqrt(np.diag(cov_mm2))
    maha = float(np.sqrt(diff @ np.linalg.solve(cov_mm2, diff)))
    out: dict[str, Any] = {
        "cad_cog_mm": setup.mass.cog_mm.tolist(),
        "difference_mm": diff.tolist(),
        "difference_sigma": (diff / sigma).tolist(),
        "mahalanobis": maha,
    }
    if setup.cog_limits_mm is not None:
        out["cubesat"] = check_envelope(
            cog_mm,
            setup.geometric_center_mm,
            setup.cog_limits_mm,
            cov_mm2=cov_mm2,
            form_factor=setup.form_factor,
        ).to_dict()
    return out
