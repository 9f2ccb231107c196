"""A spacecraft from its CAD: set-up file, test planning, and comparison of a measured CoG.

The set-up file (``parts/cubesat_3u_setup.toml`` is the example) names the model (a STEP file
with a materials file, or a cadcog CubeSat spec), the measurement equipment (a rig's ME volumes,
placed on the spacecraft), the inclinometer and error model (the rig's), the candidate suspension
points (listed, or a grid on faces of the model's bounding box) and, optionally, the CubeSat
form factor.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from itertools import combinations
from math import comb
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog import tolerances
from cadcog.envelope import CDS_COG_LIMITS_MM, check_envelope
from cadcog.errormodel import ErrorModel
from cadcog.errors import CadcogError
from cadcog.geometry import (
    FACES,
    angle_between_lines_deg,
    axes_beyond_range,
    face_normal,
    face_normal_of_point,
    ideal_reading,
)
from cadcog.massprops import MassProperties
from cadcog.measurement import MEData
from cadcog.montecarlo import Scenario, simulate
from cadcog.paramfile import TableReader, read_toml
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
    solids: tuple[Any, ...]

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


def load_setup(path: str | Path) -> Setup:
    """Read a set-up file, compute the model's mass properties and the candidates."""
    p = Path(path)
    base = p.parent
    root = TableReader(read_toml(p), p)
    name = root.string("name")
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
            cands.append(Candidate(t.string("id"), pos, normal))
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


def _grid(
    face: str, lo: FloatArray, hi: FloatArray, spacing: float, margin: float
) -> list[Candidate]:
    axis, sign = FACES[face]
    others = [j for j in range(3) if j != axis]
    axes = []
    for j in others:
        n = max(int((hi[j] - lo[j] - 2 * margin) // spacing) + 1, 1)
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

    def to_dict(self) -> dict[str, Any]:
        return {
            "candidates": [c.__dict__ for c in self.checks],
            "pairs": list(self.pairs),
            "best_sets": list(self.best_sets),
            "recommended": self.recommended,
        }


def plan_test(
    setup: Setup,
    *,
    trials: int = 2000,
    max_set: int = 4,
    seed: int = 0,
    min_angle_deg: float = tolerances.MIN_PAIR_ANGLE_DEG,
) -> Plan:
    """Check every candidate, simulate every usable pair, and recommend a set of suspensions.

    The recommendation is the set (2 to ``max_set`` hangs, joint estimate) with the smallest
    simulated 95 % CoG error; sets are searched exhaustively while there are at most 300 per
    size, greedily beyond. Pairs and sets whose plumb lines all meet at less than
    ``min_angle_deg`` are ill-conditioned and not considered.
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
    if len(usable) < 2:
        return Plan(tuple(checks), (), (), None)
    scenario = setup.scenario(usable)
    model = setup.error_model()
    n = len(usable)
    u = [(scenario.points_mm[i] - g) for i in range(n)]

    def conditioning(group: tuple[int, ...]) -> float:
        return max(angle_between_lines_deg(u[a], u[b]) for a, b in combinations(group, 2))

    pair_idx = [pr for pr in combinations(range(n), 2) if conditioning(pr) >= min_angle_deg]
    if not pair_idx:
        return Plan(tuple(checks), (), (), None)
    sim = simulate(scenario, model, pair_idx, trials, seed)
    pairs = [
        {"a": usable[a].id, "b": usable[b].id, "angle_deg": conditioning((a, b)), "q95_mm": q95}
        for (a, b), q95 in zip(pair_idx, sim.group_q95_mm, strict=True)
    ]
    i = int(np.argmin(sim.group_q95_mm))
    current: tuple[int, ...] = pair_idx[i]
    best_sets: list[dict[str, Any]] = [
        {
            "points": [usable[j].id for j in current],
            "q95_mm": sim.group_q95_mm[i],
            "mean_mm": sim.group_mean_mm[i],
        }
    ]
    for k in range(3, min(max_set, n) + 1):
        if comb(n, k) <= 300:
            groups = list(combinations(range(n), k))
        else:  # grow the best set of the previous size by one point
            groups = [tuple(sorted((*current, j))) for j in range(n) if j not in current]
        groups = [grp for grp in groups if conditioning(grp) >= min_angle_deg]
        if not groups:
            break
        res = simulate(scenario, model, groups, trials, seed + k)
        i = int(np.argmin(res.group_q95_mm))
        current = groups[i]
        best_sets.append(
            {
                "points": [usable[j].id for j in current],
                "q95_mm": res.group_q95_mm[i],
                "mean_mm": res.group_mean_mm[i],
            }
        )
    recommended = min(best_sets, key=lambda s: float(s["q95_mm"]))
    return Plan(
        tuple(checks),
        tuple(sorted(pairs, key=lambda p: p["q95_mm"])),
        tuple(best_sets),
        recommended,
    )


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
