"""What the ME compensation needs (masses, the ME's CAD CoG and its covariance), and the
bounds of a weighing."""

from __future__ import annotations

from dataclasses import dataclass, replace

from cadcog.core.errors import CadcogError
from cadcog.rig.geometry import FloatArray
from cadcog.rig.parameters import Rig

#: A weighed mass more than this factor from the model's (either way) is refused: a unit slip
#: (g for kg is 1000×) or another object; a CAD that is merely incomplete (a structure-only
#: model of a tenth of the spacecraft, whose gap ``update`` is there to find) passes.
WEIGHED_TO_MODEL = 100.0

#: A weighing's 1 σ below this fraction of the mass is refused (0.1 ppm: beyond any balance).
MIN_WEIGHING_SIGMA_REL = 1e-7


@dataclass(frozen=True)
class MEData:
    """What compensation needs: masses, the ME's CAD CoG and that CoG's covariance.

    ``object_mass_sigma_kg`` is the object mass's 1 σ (a weighing's, or the CAD's), propagated
    into the compensated CoG; ``object_mass_source`` says which ("rig", "CAD", "weighed").
    """

    object_mass_kg: float
    me_mass_kg: float
    me_cog_mm: FloatArray
    me_cog_cov_mm2: FloatArray
    source: str
    object_mass_sigma_kg: float = 0.0
    object_mass_source: str = "given"

    @classmethod
    def from_rig(cls, rig: Rig) -> MEData:
        """Object = proof mass; ME mass, CoG and covariance from the rig's CAD model.

        The closed forms used here equal the B-rep ground truth to 1e-9 (``tests/cad``), and
        need no CAD kernel.
        """
        me = rig.analytic_me
        return cls(
            rig.proof_mass.mass_kg,
            me.mass_kg,
            me.cog_mm,
            rig.me_cog_cov_mm2,
            f"rig {rig.source}",
            object_mass_source="rig",
        )

    def weighed(self, mass_kg: float, sigma_kg: float) -> MEData:
        """The same ME with the object's weighed mass and the weighing's 1 σ.

        Raises
        ------
        CadcogError
            A weighed mass beyond :data:`WEIGHED_TO_MODEL` times the model's either way (a
            weighing in g given as kg, or the wrong object), or a σ below
            :data:`MIN_WEIGHING_SIGMA_REL` of it (no scale resolves that; the update's
            matrices would be singular).
        """
        lo, hi = 1.0 / WEIGHED_TO_MODEL, WEIGHED_TO_MODEL
        if not (mass_kg > 0 and lo * self.object_mass_kg <= mass_kg <= hi * self.object_mass_kg):
            raise CadcogError(
                f"--weighed-mass-kg {mass_kg:g}: {mass_kg / self.object_mass_kg:.3g}× the "
                f"model's {self.object_mass_kg:.6g} kg ({self.source}); expected within "
                f"{lo:g}× to {hi:g}× of it (is the weighing in kg, and of this object?)"
            )
        if not sigma_kg >= MIN_WEIGHING_SIGMA_REL * mass_kg:
            raise CadcogError(
                f"--mass-sigma-kg {sigma_kg:g}: below {MIN_WEIGHING_SIGMA_REL:g} of the weighed "
                f"{mass_kg:g} kg; no scale resolves that"
            )
        return replace(
            self,
            object_mass_kg=mass_kg,
            object_mass_sigma_kg=sigma_kg,
            object_mass_source="weighed",
        )
