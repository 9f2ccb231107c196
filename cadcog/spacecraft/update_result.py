"""What :func:`cadcog.spacecraft.update.update_budget` returns: the revised mass, CoG and
inertia with their covariance, each explanation's posterior probability, each item's change and
the verdicts (its report is :mod:`cadcog.spacecraft.update_text`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.fittest import TEST_LEVEL
from cadcog.core.results import JsonResult
from cadcog.mass.inertia import TENSOR_CONVENTION
from cadcog.mass.properties import MassProperties

FloatArray = npt.NDArray[np.float64]

#: Size of every verdict (probability of a false alarm when its null holds).
LEVEL = TEST_LEVEL


@dataclass(frozen=True)
class ItemChange(JsonResult):
    """How the update moved one item (mixture over the hypotheses).

    ``probability`` is the posterior probability that this item is the one that is wrong
    beyond its stated σ (``H_I``).
    """

    key: str
    cad_mass_kg: float
    prior_sigma_rel: float
    delta_rel: float
    delta_sigma_rel: float
    prior_cog_sigma_mm: FloatArray
    cog_shift_mm: FloatArray
    cog_shift_sigma_mm: FloatArray
    probability: float

    @property
    def delta_kg(self) -> float:
        return self.cad_mass_kg * self.delta_rel

    @property
    def mass_sigma_kg(self) -> float:
        """The item's stated 1-σ mass (kg): how much it could move the mass and the CoG."""
        return self.cad_mass_kg * self.prior_sigma_rel

    @property
    def pull(self) -> float:
        """The mass change in prior sigmas: how much the data moved the item."""
        return self.delta_rel / self.prior_sigma_rel if self.prior_sigma_rel > 0 else 0.0

    def to_dict(self) -> dict[str, Any]:
        return {
            "item": self.key,
            "probability": self.probability,
            "cad_mass_kg": self.cad_mass_kg,
            "prior_sigma_rel": self.prior_sigma_rel,
            "delta_rel": self.delta_rel,
            "delta_sigma_rel": self.delta_sigma_rel,
            "delta_kg": self.delta_kg,
            "pull": self.pull,
            "prior_cog_sigma_mm": self.prior_cog_sigma_mm.tolist(),
            "cog_shift_mm": self.cog_shift_mm.tolist(),
            "cog_shift_sigma_mm": self.cog_shift_sigma_mm.tolist(),
        }


@dataclass(frozen=True)
class Explanation(JsonResult):
    """One hypothesis of the update: what it says, how probable it is given the data.

    ``label`` is ``"none"`` (every item within its stated σ), ``"KEY (mass)"`` or ``"KEY (CoG)"``
    (that item's mass or CoG is off beyond its σ; ``item`` is ``KEY``) or ``"unmodelled"`` (a
    mass anywhere in the spacecraft the CAD lacks).
    ``chi2``/``p_value``: its prior-predictive test (``dof``): does it explain the gap at all.
    """

    label: str
    description: str
    prior_probability: float
    probability: float
    chi2: float
    p_value: float
    unmodelled_negative: bool = False
    item: str = ""

    @property
    def cause(self) -> str:
        """What it blames: an item key, ``"unmodelled"`` or ``"none"``."""
        return self.item or self.label

    def to_dict(self) -> dict[str, Any]:
        return {
            "label": self.label,
            "cause": self.cause,
            "description": self.description,
            "prior_probability": self.prior_probability,
            "probability": self.probability,
            "chi2": self.chi2,
            "p_value": self.p_value,
            "unmodelled_wanted_negative": self.unmodelled_negative,
        }


@dataclass(frozen=True, repr=False)  # JsonResult's one-line repr
class UpdateResult(JsonResult):
    """The CAD before, the revised figures after, and what explains the difference.

    Attributes
    ----------
    cad, cad_cog_cov_mm2, cad_mass_sigma_kg
        The CAD and its stated uncertainty (item masses and CoGs).
    measured_mass_kg, measured_mass_sigma_kg
        The weighing.
    measured_cog_mm, measured_cog_cov_mm2
        The spacecraft's CoG from the test, compensated with the weighed mass.
    posterior, posterior_mass_sigma_kg, posterior_cog_cov_mm2, posterior_inertia_sigma_kg_mm2
        The revised figures: the mixture over the explanations; when the model is rejected the
        mass and CoG are the measurement's (the inertia stays the mixture's, not to be used).
    items : tuple of ItemChange
    explanations : tuple of Explanation
        Most probable first.
    unmodelled_* :
        The unmodelled mass *if there is one* (the mixture over the hypotheses that hold one;
        None when none does): its mass, 1 σ, and, when it is resolved (more than
        :data:`UNMODELLED_RESOLVED_SIGMAS` σ above 0), its position and position covariance;
        ``unmodelled_negative`` when the data wanted it below zero (it is then held at 0);
        ``unmodelled_probability`` the probability that there is one (1 with a region given).
    differs_chi2, differs_p_value
        The gap against the measurement noise alone (``dof``: 4, or 10 with a measured tensor).
    chi2, p_value
        The gap against the CAD's stated uncertainties (``H₀``'s prior predictive, ``dof``).
    model_rejected : bool
        No hypothesis explains the gap: the revised CoG and mass are the measurement's.
    dof : int
        Observed numbers: the weighed mass and the assembly CoG (4), and the measured tensor's
        six entries when one was given (``cadcog update --swings``).
    """

    cad: MassProperties
    cad_cog_cov_mm2: FloatArray
    cad_mass_sigma_kg: float
    measured_mass_kg: float
    measured_mass_sigma_kg: float
    measured_cog_mm: FloatArray
    measured_cog_cov_mm2: FloatArray
    posterior: MassProperties
    posterior_mass_sigma_kg: float
    posterior_cog_cov_mm2: FloatArray
    posterior_inertia_sigma_kg_mm2: FloatArray
    items: tuple[ItemChange, ...]
    explanations: tuple[Explanation, ...]
    unmodelled_mass_kg: float | None
    unmodelled_mass_sigma_kg: float | None
    unmodelled_cog_mm: FloatArray | None
    unmodelled_cog_cov_mm2: FloatArray | None
    unmodelled_negative: bool
    unmodelled_probability: float
    differs_chi2: float
    differs_p_value: float
    chi2: float
    p_value: float
    model_rejected: bool
    dof: int = 4
    notes: tuple[str, ...] = ()

    @property
    def differs(self) -> bool:
        """The test tells the spacecraft from its CAD (beyond the measurement noise)."""
        return self.differs_p_value < LEVEL

    @property
    def consistent(self) -> bool:
        """The gap is within the CAD's stated uncertainties (``H₀`` not rejected)."""
        return self.p_value >= LEVEL

    def verdict_lines(self) -> list[str]:
        """The verdicts in words (the command and the HTML report print them)."""
        differs = (
            "the test tells the spacecraft from its CAD"
            if self.differs
            else "the test cannot tell the spacecraft from its CAD"
        )
        within = (
            "the gap is within the CAD's stated uncertainties"
            if self.consistent
            else "the gap is BEYOND the CAD's stated uncertainties"
        )
        lines = [
            f"measured vs CAD, against the measurement noise alone: χ² = {self.differs_chi2:.2f} "
            f"({self.dof} dof), p = {self.differs_p_value:.3g}: {differs}",
            f"measured vs CAD, with the CAD's uncertainties: χ² = {self.chi2:.2f} "
            f"({self.dof} dof), p = {self.p_value:.3g}: {within}",
        ]
        if self.model_rejected:
            lines.append("no explanation fits: the updated CoG and mass are the measurement's")
        return lines + [f"note: {n}" for n in self.notes]

    def ranked_items(self) -> list[ItemChange]:
        """The items as the table lists them.

        When the gap is beyond the CAD's stated uncertainties, by the probability of being the
        one that changed (to 0.01 %), then by the item's stated 1-σ mass, then by |pull|. When
        it is within them, no item is implicated (a washer's "it is off" is as probable as
        its prior, and the data make a heavy item's less so): by the stated 1-σ mass, what
        could move the mass and the CoG, then by probability. Never by file order.
        """

        def p(c: ItemChange) -> float:  # a NaN probability (a failed weighting) sorts last
            return float(c.probability) if np.isfinite(c.probability) else -1.0

        if self.consistent:
            return sorted(self.items, key=lambda c: (-c.mass_sigma_kg, -p(c)))
        return sorted(
            self.items,
            key=lambda c: (-round(p(c), 4), -c.mass_sigma_kg, -abs(c.pull)),
        )

    def to_dict(self) -> dict[str, Any]:
        def props(p: MassProperties) -> dict[str, Any]:
            return {
                "mass_kg": p.mass_kg,
                "cog_mm": p.cog_mm.tolist(),
                "inertia_kg_mm2": p.inertia_kg_mm2.tolist(),
                "inertia_about": "centre of gravity, model axes",
                "inertia_convention": TENSOR_CONVENTION,
            }

        out: dict[str, Any] = {
            "cad": {
                **props(self.cad),
                "mass_sigma_kg": self.cad_mass_sigma_kg,
                "cog_cov_mm2": self.cad_cog_cov_mm2.tolist(),
                "uncertainty": "items' mass and CoG uncertainties, first order",
            },
            "measured": {
                "mass_kg": self.measured_mass_kg,
                "mass_sigma_kg": self.measured_mass_sigma_kg,
                "cog_mm": self.measured_cog_mm.tolist(),
                "cog_cov_mm2": self.measured_cog_cov_mm2.tolist(),
            },
            "posterior": {
                **props(self.posterior),
                "mass_sigma_kg": self.posterior_mass_sigma_kg,
                "cog_cov_mm2": self.posterior_cog_cov_mm2.tolist(),
                "inertia_sigma_kg_mm2": self.posterior_inertia_sigma_kg_mm2.tolist(),
                "source": "measurement (model rejected)"
                if self.model_rejected
                else "mixture over the explanations",
            },
            "verdict": {
                "differs": self.differs,
                "differs_chi2": self.differs_chi2,
                "differs_p_value": self.differs_p_value,
                "consistent": self.consistent,
                "chi2": self.chi2,
                "p_value": self.p_value,
                "dof": self.dof,
                "model_rejected": self.model_rejected,
                "level": LEVEL,
            },
            "explanations": [e.to_dict() for e in self.explanations],
            "items": [c.to_dict() for c in self.ranked_items()],
            "notes": list(self.notes),
        }
        if self.unmodelled_mass_kg is not None:
            out["unmodelled"] = {
                "mass_kg": self.unmodelled_mass_kg,
                "mass_sigma_kg": self.unmodelled_mass_sigma_kg,
                "cog_mm": None
                if self.unmodelled_cog_mm is None
                else self.unmodelled_cog_mm.tolist(),
                "cog_cov_mm2": None
                if self.unmodelled_cog_cov_mm2 is None
                else self.unmodelled_cog_cov_mm2.tolist(),
                "wanted_negative": self.unmodelled_negative,
                "probability": self.unmodelled_probability,
                "given": "that there is an unmodelled mass",
            }
        return out
