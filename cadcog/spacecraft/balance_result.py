"""What :func:`cadcog.spacecraft.balance.least_ballast` returns: the least ballast or why there
is none, the figures before and after, the mass budget with the ballast."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.results import JsonResult
from cadcog.spacecraft.ballast_programme import norm_sf
from cadcog.spacecraft.ballast_spec import BallastSpec, UncertainMass

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True, repr=False)
class BalanceResult(JsonResult):
    """The least ballast, or why there is none (:func:`cadcog.spacecraft.balance.least_ballast`).

    Attributes
    ----------
    feasible : bool
    masses_kg : ndarray, shape (n,)
        Ballast at each location (zeros when infeasible).
    counts : ndarray, shape (n, J) or None
        With discrete sizes: how many of each size at each location.
    optimal : bool
        The total is within :data:`cadcog.spacecraft.balance.PROVEN_RTOL` of ``bound_kg``
        and the CoG's spread settled (False also when an integer programme was stopped by its
        time limit).
    bound_kg : float or None
        A proven lower bound on the least total ballast (kg).
    mass_kg : float
        The mass after ballast (kg).
    mass_sigma_kg : float
        Its 1 σ (kg; the ballast is exact).
    cog_mm : ndarray, shape (3,)
        The CoG after ballast (mm).
    cog_cov_mm2 : ndarray, shape (3, 3)
        Its covariance (mm²).
    offset_mm : ndarray, shape (3,)
        CoG minus the geometric centre (mm).
    margin_mm : ndarray, shape (3,)
        Per axis, how far the CoG may still move towards its nearer face with the confidence
        still met, the other faces as they are (:func:`cadcog.spacecraft.balance.margins`): 0
        on a face that binds, negative when short.
    probability_inside : float
        The joint probability that the CoG lies inside the envelope (normal CoG, integrated).
    before : dict
        The same figures without ballast.
    shortfall : list of dict
        Infeasible: each face short (``axis``, ``side``, ``moment_kg_mm``, ``cog_shift_mm``;
        ``configuration`` with several).
    notes : tuple of str
        What to know about the answer (a dilution, a unit, a form factor).
    configurations : tuple of dict
        With other configurations: each one's figures with the same ballast (``name``,
        ``mass_kg``, ``cog_mm``, ``cog_cov_mm2``, ``offset_mm``, ``margin_mm``,
        ``probability_inside``, ``face_quantiles``, ``before``).
    envelope_source : str
        Where the envelope's limits come from (a PocketQube's are provisional).
    inertia : dict or None
        With inertia objectives (:mod:`cadcog.spacecraft.balance_inertia`): the objectives,
        the tensor's figures ``before`` and ``after`` and how the answer was found.
    """

    spec: BallastSpec
    state: UncertainMass
    geometric_center_mm: FloatArray
    limits_mm: FloatArray
    confidence: float
    face_quantiles: FloatArray
    feasible: bool
    masses_kg: FloatArray
    counts: FloatArray | None
    optimal: bool
    bound_kg: float | None
    mass_kg: float
    mass_sigma_kg: float
    cog_mm: FloatArray
    cog_cov_mm2: FloatArray
    offset_mm: FloatArray
    margin_mm: FloatArray
    probability_inside: float
    before: dict[str, Any]
    shortfall: tuple[dict[str, Any], ...]
    notes: tuple[str, ...] = ()
    configurations: tuple[dict[str, Any], ...] = ()
    envelope_source: str = ""
    inertia: dict[str, Any] | None = None

    @property
    def total_ballast_kg(self) -> float:
        """All the ballast (kg)."""
        return float(self.masses_kg.sum())

    def budget(self) -> list[dict[str, Any]]:
        """The mass budget with the ballast: the spacecraft, each location used, the total."""
        rows: list[dict[str, Any]] = [
            {
                "name": f"spacecraft ({self.state.source})",
                "mass_kg": self.state.mass_kg,
                "mass_sigma_kg": self.state.mass_sigma_kg,
                "cog_mm": np.asarray(self.state.cog_mm).tolist(),
            }
        ]
        for pt, m in zip(self.spec.points, self.masses_kg, strict=True):
            if m > 0.0:
                rows.append(
                    {
                        "name": f"ballast {pt.id}",
                        "mass_kg": float(m),
                        "mass_sigma_kg": 0.0,
                        "cog_mm": np.asarray(pt.position_mm).tolist(),
                    }
                )
        rows.append(
            {
                "name": "total",
                "mass_kg": self.mass_kg,
                "mass_sigma_kg": self.mass_sigma_kg,
                "cog_mm": self.cog_mm.tolist(),
            }
        )
        return rows

    def to_dict(self) -> dict[str, Any]:
        ballast = []
        for k, (pt, m) in enumerate(zip(self.spec.points, self.masses_kg, strict=True)):
            if m <= 0.0:
                continue
            row: dict[str, Any] = {
                "id": pt.id,
                "mass_kg": float(m),
                "position_mm": np.asarray(pt.position_mm).tolist(),
            }
            if self.counts is not None and self.spec.sizes_kg is not None:
                row["pieces"] = [
                    {"size_kg": s, "count": int(n)}
                    for s, n in zip(self.spec.sizes_kg, self.counts[k], strict=True)
                    if n > 0
                ]
            ballast.append(row)
        return {
            "feasible": self.feasible,
            "optimal": self.optimal,
            "bound_kg": self.bound_kg,
            "confidence": self.confidence,
            "face_quantiles": self.face_quantiles.tolist(),
            "face_miss_budget": norm_sf(self.face_quantiles).tolist(),
            "ballast": ballast,
            "total_ballast_kg": self.total_ballast_kg,
            "mass_kg": self.mass_kg,
            "mass_sigma_kg": self.mass_sigma_kg,
            "cog_mm": self.cog_mm.tolist(),
            "cog_cov_mm2": self.cog_cov_mm2.tolist(),
            "geometric_center_mm": self.geometric_center_mm.tolist(),
            "limits_mm": self.limits_mm.tolist(),
            "envelope_source": self.envelope_source,
            "offset_mm": self.offset_mm.tolist(),
            "margin_mm": self.margin_mm.tolist(),
            "probability_inside": self.probability_inside,
            "before": self.before,
            "shortfall": list(self.shortfall),
            "budget": self.budget(),
            "source": self.state.source,
            "ballast_file": self.spec.source,
            "notes": list(self.notes),
            "configurations": {  # keyed by name, as massprops's
                c["name"]: {k: v for k, v in c.items() if k != "name"} for c in self.configurations
            },
            "inertia": self.inertia,
        }
