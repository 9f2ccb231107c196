"""The result of a CoG estimate: the hung assembly's CoG and the compensated one, with their
covariances, each hang's diagnostics and the model used (the result apart from the fitting:
:mod:`cadcog.method.estimate`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from cadcog.core.results import JsonResult
from cadcog.method.plumblines import Compensation, JointEstimate
from cadcog.method.readings import Suspension
from cadcog.rig.geometry import FloatArray


@dataclass(frozen=True, repr=False)  # JsonResult's one-line repr
class CogEstimate(JsonResult):
    """Result of :func:`~cadcog.method.estimate.estimate_cog`.

    Attributes
    ----------
    suspensions : tuple of Suspension
        The averaged hangs, in file order.
    verticals : ndarray, shape (k, 3)
        Each hang's measured vertical in the body frame.
    joint : JointEstimate
        The joint estimate of the hung assembly over every hang: its CoG and covariance, the
        per-line residuals, the pairwise estimates, the wire offset scale.
    compensation : Compensation or None
        The ME compensation (eq. 10/16), None when no ME was given.
    model : dict
        The error model and estimator options used, as the JSON shows them.
    n_normalized : int
        Suspensions whose readings gave sin²X + sin²Y > 1 (noise near 90°): their sines were
        rescaled and the vertical's z component set to 0.
    warnings : tuple of str
        What the user should know (inconsistent hangs, poor conditioning).
    cad : dict or None
        For a spacecraft set-up: the comparison with its CAD CoG and CubeSat envelope
        (:func:`cadcog.spacecraft.compare.compare_with_cad`), as ``estimate --setup`` prints it.
    """

    suspensions: tuple[Suspension, ...]
    verticals: FloatArray
    joint: JointEstimate
    compensation: Compensation | None
    model: dict[str, Any]
    n_normalized: int
    warnings: tuple[str, ...] = field(default=())
    cad: dict[str, Any] | None = None

    @property
    def assembly_cog_mm(self) -> FloatArray:
        """CoG of the hung assembly, object and ME together (mm), before compensation."""
        return self.joint.cog_mm

    @property
    def cog_mm(self) -> FloatArray:
        """Compensated CoG, or the assembly CoG when no ME data was given."""
        return self.assembly_cog_mm if self.compensation is None else self.compensation.cog_mm

    @property
    def cov_mm2(self) -> FloatArray:
        """Covariance (mm², 3 × 3) of :attr:`cog_mm`, the ME's CAD uncertainty included."""
        return self.joint.cov_mm2 if self.compensation is None else self.compensation.cov_mm2

    def to_dict(self) -> dict[str, Any]:
        """Plain-JSON form (keys documented in ``docs/estimate.md``)."""
        comp = self.compensation
        residuals = {r.id: r for r in self.joint.residuals}
        wire = self.joint.wire
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
                    "object_mass_sigma_kg": comp.object_mass_sigma_kg,
                    "object_mass_source": comp.object_mass_source,
                    "me_mass_kg": comp.me_mass_kg,
                    "me_cog_mm": comp.me_cog_mm.tolist(),
                }
            ),
            "wire": None
            if wire is None
            else {
                "scale_mm": wire.scale_mm,
                "sigma_mm": wire.sigma_mm,
                "estimated": wire.estimated,
                "prior_mm": wire.prior_mm,
            },
            "consistency": {
                "chi2": self.joint.chi2,
                "dof": self.joint.dof,
                "p_value": self.joint.chi2_p_value,
            },
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
            "model": self.model,
            "n_normalized": self.n_normalized,
            "warnings": list(self.warnings),
            **({} if self.cad is None else {"cad": self.cad}),
        }
