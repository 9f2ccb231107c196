"""From averaged readings to the compensated CoG with its uncertainty and diagnostics.

This is the library behind ``cadcog estimate``: readings → verticals (eq. 2) → plumb lines →
weighted joint estimate of the assembly CoG (METHOD.md §2) → ME compensation (eqs. 10, 16).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from cadcog import tolerances
from cadcog.errormodel import elastica_length_mm, wire_offset_mm
from cadcog.estimator import (
    POINT_SIGMA_MM,
    Compensation,
    JointEstimate,
    PlumbLine,
    compensate_me,
    weighted_estimate,
)
from cadcog.geometry import FloatArray, axes_beyond_range, face_normal_of_point
from cadcog.inclinometer import InclinometerConfig
from cadcog.readings import Suspension, suspension_verticals
from cadcog.rig import Rig


@dataclass(frozen=True)
class MEData:
    """What compensation needs: masses, the ME's CAD CoG and that CoG's covariance."""

    object_mass_kg: float
    me_mass_kg: float
    me_cog_mm: FloatArray
    me_cog_cov_mm2: FloatArray
    source: str

    @classmethod
    def from_rig(cls, rig: Rig) -> MEData:
        """Object = proof mass; ME mass, CoG and covariance from the rig's CAD model.

        The closed forms used here equal the B-rep ground truth to 1e-9 (``tests/cad``), and
        need no CAD kernel.
        """
        me = rig.analytic_me
        return cls(
            rig.proof_mass.mass_kg, me.mass_kg, me.cog_mm, rig.me_cog_cov_mm2, f"rig {rig.source}"
        )


def rig_point_sigma_mm(rig: Rig) -> float:
    """Per-axis suspension-point uncertainty implied by the rig's error model (mm).

    The play (uniform over ``play_mm``) and the spread of the wire offset (uniform over
    ``wire_offset_max_mm`` for the paper's model, ±``wire_stiffness_rel_uncertainty`` of λ for
    the elastica) added in quadrature: a deliberately isotropic, slightly conservative figure.
    """
    o = rig.error_options
    if o.wire_model == "paper":
        wire = o.wire_offset_max_mm
    else:
        wire = elastica_length_mm(o.wire_bending_stiffness_n_mm2, rig.weight_n) * (
            o.wire_stiffness_rel_uncertainty
        )
    return float(np.hypot(o.play_mm, wire) / np.sqrt(12.0))


def wire_corrections(rig: Rig, suspensions: Sequence[Suspension]) -> dict[str, FloatArray]:
    """Expected offset of each virtual suspension point along its bolt axis (mm, vectors).

    The paper's model: half of ``wire_offset_max_mm``. The elastica: ``Δ(θ) = λ/cos(θ/2)`` with
    θ between the bolt axis (the outward normal of the face the point sits on) and the measured
    vertical.
    """
    o = rig.error_options
    v = suspension_verticals(suspensions, rig.inclinometer).u
    lam = elastica_length_mm(o.wire_bending_stiffness_n_mm2, rig.weight_n)
    out = {}
    for s, u in zip(suspensions, v, strict=True):
        n = face_normal_of_point(s.position_mm, np.zeros(3), rig.proof_mass.size_mm)
        if o.wire_model == "paper":
            delta = 0.5 * o.wire_offset_max_mm
        else:
            theta_deg = float(np.rad2deg(np.arccos(np.clip(np.dot(u, n), -1.0, 1.0))))
            delta = float(wire_offset_mm(theta_deg, lam))
        out[s.id] = delta * n
    return out


@dataclass(frozen=True)
class CogEstimate:
    """Result of :func:`estimate_cog`."""

    suspensions: tuple[Suspension, ...]
    verticals: FloatArray
    joint: JointEstimate
    compensation: Compensation | None
    angle_sigma_deg: float
    point_sigma_mm: float
    n_normalized: int
    warnings: tuple[str, ...] = field(default=())

    @property
    def assembly_cog_mm(self) -> FloatArray:
        return self.joint.cog_mm

    @property
    def cog_mm(self) -> FloatArray:
        """Compensated CoG, or the assembly CoG when no ME data was given."""
        return self.assembly_cog_mm if self.compensation is None else self.compensation.cog_mm

    @property
    def cov_mm2(self) -> FloatArray:
        return self.joint.cov_mm2 if self.compensation is None else self.compensation.cov_mm2

    def to_dict(self) -> dict[str, Any]:
        """Plain-JSON form (keys documented in ``docs/estimate.md``)."""
        comp = self.compensation
        residuals = {r.id: r for r in self.joint.residuals}
        return {
            "assembly_cog_mm": self.assembly_cog_mm.tolist(),
            "assembly_cov_mm2": self.joint.cov_mm2.tolist(),
            "cog_mm": self.cog_mm.tolist(),
            "cov_mm2": self.cov_mm2.tolist(),
            "sigma_mm": np.sqrt(np.diag(self.cov_mm2)).tolist(),
            "compensation": (
                {"applied": False}
                if comp is None
                else {
                    "applied": True,
                    "object_mass_kg": comp.object_mass_kg,
                    "me_mass_kg": comp.me_mass_kg,
                    "me_cog_mm": comp.me_cog_mm.tolist(),
                }
            ),
            "suspensions": [
                {
                    "id": s.id,
                    "position_mm": list(s.position_mm),
                    "top_face_up": s.top_face_up,
                    "n_samples": s.n_samples,
                    "inc_x_deg": s.inc_x_deg,
                    "inc_y_deg": s.inc_y_deg,
                    "std_x_deg": s.std_x_deg,
                    "std_y_deg": s.std_y_deg,
                    "vertical": u.tolist(),
                    "residual_mm": residuals[s.id].distance_mm,
                    "residual_sigma": residuals[s.id].normalized,
                    "inconsistent": residuals[s.id].inconsistent,
                }
                for s, u in zip(self.suspensions, self.verticals, strict=True)
            ],
            "pairs": [p.to_dict() for p in self.joint.pairs],
            "skipped_pairs": [
                {"a": a, "b": b, "angle_deg": ang} for a, b, ang in self.joint.skipped_pairs
            ],
            "model": {
                "estimator": "weighted least squares over all plumb lines",
                "angle_sigma_deg": self.angle_sigma_deg,
                "point_sigma_mm": self.point_sigma_mm,
            },
            "n_normalized": self.n_normalized,
            "warnings": list(self.warnings),
        }


def estimate_cog(
    suspensions: Sequence[Suspension],
    config: InclinometerConfig | None = None,
    me: MEData | None = None,
    *,
    angle_sigma_deg: float | None = None,
    point_sigma_mm: float = POINT_SIGMA_MM,
    min_angle_deg: float = tolerances.MIN_PAIR_ANGLE_DEG,
    point_offsets_mm: Mapping[str, FloatArray] | None = None,
) -> CogEstimate:
    """Compensated CoG of an object from its averaged suspensions.

    Parameters
    ----------
    suspensions : sequence of Suspension
        At least two, with distinct ids.
    config : InclinometerConfig, optional
        Axis signs, range and default angular uncertainty (paper's rig if omitted).
    me : MEData, optional
        Without it the result is the assembly CoG and says so in its warnings.
    angle_sigma_deg : float, optional
        Per-axis reading uncertainty; default ``config.angle_sigma_deg``.
    point_sigma_mm : float
        Per-axis suspension-point uncertainty.
    min_angle_deg : float
        Pairs of plumb lines closer to parallel are left out of the pair diagnostics.
    point_offsets_mm : mapping of id → ndarray (3,), optional
        Corrections added to the suspension points (see :func:`wire_corrections`).

    Raises
    ------
    cadcog.errors.IllConditionedError
        If every pair of plumb lines is ill-conditioned.
    """
    cfg = config or InclinometerConfig()
    sigma_deg = cfg.angle_sigma_deg if angle_sigma_deg is None else angle_sigma_deg
    v = suspension_verticals(suspensions, cfg)
    warnings = []
    for s, normalized in zip(suspensions, v.normalized, strict=True):
        if normalized:
            warnings.append(
                f"suspension {s.id}: sin²X + sin²Y > 1 (X = {s.inc_x_deg:.3f}°, "
                f"Y = {s.inc_y_deg:.3f}°); the sines were normalised, the vertical is horizontal"
            )
        beyond = axes_beyond_range(s.inc_x_deg, s.inc_y_deg, cfg.range_deg)
        if beyond:
            warnings.append(
                f"suspension {s.id}: {', '.join(beyond)} beyond the inclinometer's "
                f"±{cfg.range_deg:g}° range; the reading may be saturated"
            )
    offsets = point_offsets_mm or {}
    lines = [
        PlumbLine(s.id, np.array(s.position_mm) + offsets.get(s.id, 0.0), u, 1.0)
        for s, u in zip(suspensions, v.u, strict=True)
    ]
    joint = weighted_estimate(
        lines, angle_sigma_deg=sigma_deg, point_sigma_mm=point_sigma_mm, min_angle_deg=min_angle_deg
    )
    for a, b, angle in joint.skipped_pairs:
        warnings.append(
            f"pair {a}-{b}: plumb lines meet at {angle:.2f}° (< {min_angle_deg:g}°), "
            "ill-conditioned; left out of the pair table"
        )
    for r in joint.residuals:
        if r.inconsistent:
            warnings.append(
                f"suspension {r.id}: its line passes {r.distance_mm:.2f} mm from the joint "
                f"estimate ({r.normalized:.1f} σ, p = {r.p_value:.2g}): "
                "inconsistent with the others"
            )
    comp = None
    if me is None:
        warnings.append(
            "no measurement-equipment data: cog_mm is the CoG of the assembly (object + ME), "
            "not compensated"
        )
    else:
        comp = compensate_me(
            joint.cog_mm,
            joint.cov_mm2,
            object_mass_kg=me.object_mass_kg,
            me_mass_kg=me.me_mass_kg,
            me_cog_mm=me.me_cog_mm,
            me_cog_cov_mm2=me.me_cog_cov_mm2,
        )
    return CogEstimate(
        tuple(suspensions),
        v.u,
        joint,
        comp,
        sigma_deg,
        point_sigma_mm,
        v.n_normalized,
        tuple(warnings),
    )
