"""What ``cadcog balance`` balances and with what: the spacecraft's mass and CoG with their
first-order uncertainty (:class:`UncertainMass`), and the allowed ballast (:class:`BallastSpec`
of :class:`BallastPoint`; read from a ballast file by :mod:`cadcog.spacecraft.ballast_file`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import CadcogError

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class BallastPoint:
    """An allowed ballast location: its id, position (mm) and most mass it takes (kg)."""

    id: str
    position_mm: FloatArray
    max_mass_kg: float | None = None


@dataclass(frozen=True)
class BallastSpec:
    """The allowed locations, the discrete sizes available (kg; None: any mass), the most
    ballast in all (kg) and where the spec came from."""

    points: tuple[BallastPoint, ...]
    sizes_kg: tuple[float, ...] | None = None
    max_total_mass_kg: float | None = None
    source: str = ""


@dataclass(frozen=True)
class UncertainMass:
    """What is balanced: a mass and CoG with their first-order uncertainty.

    Attributes
    ----------
    mass_kg, mass_sigma_kg : float
    cog_mm : ndarray, shape (3,)
    cog_cov_mm2 : ndarray, shape (3, 3)
    cog_mass_cov_mm_kg : ndarray, shape (3,)
        ``Cov(c, M)``: zero for a weighed mass.
    source : str
        What the figures are (``"CAD"``, ``"update"`` ...).
    """

    mass_kg: float
    mass_sigma_kg: float
    cog_mm: FloatArray
    cog_cov_mm2: FloatArray
    cog_mass_cov_mm_kg: FloatArray
    source: str

    @classmethod
    def from_prior(cls, prior: Any, source: str = "CAD") -> UncertainMass:
        """The CAD's figures (:class:`cadcog.spacecraft.items.LinearPrior`: its mass, CoG and
        their first-order covariance)."""
        return cls(
            prior.mass_kg,
            prior.mass_sigma_kg,
            np.asarray(prior.cog_mm, dtype=float),
            np.asarray(prior.cog_cov_mm2, dtype=float),
            np.asarray(prior.cog_mass_cov_mm_kg, dtype=float),
            source,
        )

    def shifted(
        self,
        mass_kg: float,
        moment_kg_mm: npt.ArrayLike,
        moment_cov_kg2_mm2: npt.ArrayLike,
        source: str,
        *,
        mass_var_kg2: float = 0.0,
        moment_mass_cov_kg2_mm: npt.ArrayLike | None = None,
    ) -> UncertainMass:
        """The same spacecraft with a change of mass ``ΔM`` and first moment ``ΔS`` (ballast,
        exact; or a configuration's, with their covariance, taken as independent of these
        figures): ``G' = (M G + ΔS) / (M + ΔM)``, its covariance and ``Cov(G', M')`` to first
        order (``∂G'/∂G = M/T``, ``∂G'/∂M = (G - G')/T``, ``∂G'/∂ΔS = 1/T``, ``∂G'/∂ΔM =
        -G'/T``, ``T = M + ΔM``: the change's share ``ΔS - G' ΔM`` does not depend on where
        the origin is).

        Examples
        --------
        >>> s = UncertainMass(2.0, 0.0, np.zeros(3), np.eye(3), np.zeros(3), "test")
        >>> t = s.shifted(0.0, [20.0, 0, 0], np.zeros((3, 3)), "moved")
        >>> t.cog_mm.tolist(), np.diag(t.cog_cov_mm2).tolist()
        ([10.0, 0.0, 0.0], [1.0, 1.0, 1.0])
        """
        total = self.mass_kg + mass_kg
        if not total > 0:
            raise CadcogError(f"{source}: no mass left ({total:g} kg)")
        cog = (self.mass_kg * self.cog_mm + np.asarray(moment_kg_mm, dtype=float)) / total
        jc = self.mass_kg / total
        jm = (self.cog_mm - cog) / total
        s = self.cog_mass_cov_mm_kg
        cross = (
            np.zeros(3)
            if moment_mass_cov_kg2_mm is None
            else np.asarray(moment_mass_cov_kg2_mm, dtype=float)
        )
        change = (
            np.asarray(moment_cov_kg2_mm2, dtype=float)
            - np.outer(cross, cog)
            - np.outer(cog, cross)
            + mass_var_kg2 * np.outer(cog, cog)
        )  # Cov(ΔS - G' ΔM)
        cov = (
            jc**2 * self.cog_cov_mm2
            + jc * (np.outer(s, jm) + np.outer(jm, s))
            + self.mass_sigma_kg**2 * np.outer(jm, jm)
            + change / total**2
        )
        mass_sigma = float(np.sqrt(self.mass_sigma_kg**2 + mass_var_kg2))
        with_mass = jc * s + self.mass_sigma_kg**2 * jm + (cross - mass_var_kg2 * cog) / total
        return UncertainMass(total, mass_sigma, cog, cov, with_mass, source)
