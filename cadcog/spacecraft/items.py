"""The CAD's uncertain items: what the mass budget, the CAD comparison and the update share.

A spacecraft's CAD is uncertain item by item. An *item* is a body, or an assembly whose bodies
vary together (the materials file's ``[mass_uncertainty]`` names it). Each item ``I`` of CAD mass
``m_I`` and CoG ``c_I`` has two independent uncertainties:

- its relative mass change ``δ_I ~ N(0, σ_I²)`` (``[mass_uncertainty]``);
- the shift ``s_I ~ N(0, diag(σc_I²))`` of its CoG (mm), from ``[cog_uncertainty]`` or, by
  default, ``σc_I,k = σ_I · spread_I,k``: the item's mass error is not spread as its CAD mass
  is, but sits anywhere in it, so its CoG moves by about its relative mass error times the
  spread of its mass along each axis (``spread_k = √(C_kk / m)``, ``C`` the second central
  moment, ``C = tr(J)/2 · 1 − J``; a uniform box of length L has spread ``L/√12``).

Everything else (bodies without a mass uncertainty) is fixed. The spacecraft then has mass and
mass moment

    M(θ) = M_CAD + Σ m_I δ_I
    S(θ) = S_CAD + Σ m_I (δ_I c_I + (1 + δ_I) s_I),    G = S / M

and, to first order in ``θ = (δ_1 … δ_N, s_1 … s_N)``, ``Var M = Σ (σ_I m_I)²`` and
``Cov G = Σ m_I² (σ_I² (c_I − G)(c_I − G)ᵀ + diag(σc_I²)) / M²``: :func:`linear_prior`. Pure
numpy; nothing here imports the CAD layer.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core import tolerances
from cadcog.mass.properties import MassProperties, combine

FloatArray = npt.NDArray[np.float64]

#: Default 1 σ of a weighing (kg): :data:`cadcog.core.tolerances.DEFAULT_WEIGHING_SIGMA_KG`.
DEFAULT_WEIGHING_SIGMA_KG = tolerances.DEFAULT_WEIGHING_SIGMA_KG

#: Where an item's CoG uncertainty comes from when no ``[cog_uncertainty]`` rule names it.
DEFAULT_COG_SOURCE = "default: mass uncertainty × spread of the item's mass"


def spread_mm(p: MassProperties) -> FloatArray:
    """Standard deviation of a body's mass along each axis about its CoG (mm), shape (3,).

    Examples
    --------
    >>> from cadcog.mass.properties import box_properties
    >>> spread_mm(box_properties([12.0, 6.0, 0.0], [0, 0, 0], mass_kg=1.0)).round(6).tolist()
    [3.464102, 1.732051, 0.0]
    """
    if not p.mass_kg > 0:
        return np.zeros(3)
    j = np.asarray(p.inertia_kg_mm2, dtype=float)
    second = 0.5 * np.trace(j) * np.eye(3) - j
    return np.asarray(np.sqrt(np.maximum(np.diag(second), 0.0) / p.mass_kg))


@dataclass(frozen=True)
class Item:
    """An uncertain item of the budget.

    Attributes
    ----------
    key : str
        The item's node path.
    properties : MassProperties
        Its CAD mass properties (its bodies combined).
    sigma_rel : float
        1-σ relative mass uncertainty.
    cog_sigma_mm : ndarray, shape (3,)
        1-σ uncertainty of its CoG along each model axis (mm).
    cog_source : str
        Where ``cog_sigma_mm`` comes from: a materials rule, or :data:`DEFAULT_COG_SOURCE`.
    """

    key: str
    properties: MassProperties
    sigma_rel: float
    cog_sigma_mm: FloatArray
    cog_source: str = DEFAULT_COG_SOURCE

    def __post_init__(self) -> None:
        sigma = np.broadcast_to(np.asarray(self.cog_sigma_mm, dtype=float), (3,)).copy()
        if not (self.sigma_rel >= 0 and np.all(sigma >= 0) and np.all(np.isfinite(sigma))):
            raise ValueError(f"item {self.key}: uncertainties must be finite and ≥ 0")
        object.__setattr__(self, "cog_sigma_mm", sigma)

    @classmethod
    def with_default_cog(cls, key: str, properties: MassProperties, sigma_rel: float) -> Item:
        """An item whose CoG uncertainty is the documented default (module docstring)."""
        return cls(key, properties, sigma_rel, sigma_rel * spread_mm(properties))


def items_from_bodies(bodies: Sequence[Any]) -> tuple[list[Item], MassProperties | None]:
    """The budget's uncertain items and the fixed rest.

    ``bodies`` carry ``properties``, ``sigma_rel``, ``item`` and optionally ``cog_sigma_mm``
    (``cadcog.cad.stepmass.BodyResult``). Bodies of one item are combined (they vary together;
    the first body's rules hold for the item); bodies without an uncertainty, or with zero mass
    and CoG uncertainty, are fixed.
    """
    groups: dict[str, list[Any]] = {}
    fixed = []
    for b in bodies:
        if b.sigma_rel is None:
            fixed.append(b.properties)
        else:
            groups.setdefault(b.item, []).append(b)
    items = []
    for key, members in groups.items():
        props = combine(b.properties for b in members)
        sigma = float(members[0].sigma_rel)
        rule = getattr(members[0], "cog_sigma_mm", None)
        if rule is None:
            item = Item.with_default_cog(key, props, sigma)
        else:
            item = Item(key, props, sigma, np.asarray(rule, float), "materials [cog_uncertainty]")
        if item.sigma_rel > 0 or np.any(item.cog_sigma_mm > 0):
            items.append(item)
        else:
            fixed.extend(b.properties for b in members)
    return items, (combine(fixed) if fixed else None)


@dataclass(frozen=True)
class LinearPrior:
    """The CAD's mass and CoG with their first-order uncertainty (module docstring).

    Attributes
    ----------
    mass_kg : float
    cog_mm : ndarray, shape (3,)
    jac_mass : ndarray, shape (n,)
        ``∂M/∂θ`` (kg per unit of each parameter).
    jac_cog : ndarray, shape (3, n)
        ``∂G/∂θ`` (mm per unit).
    prior_cov : ndarray, shape (n, n)
        Covariance of ``θ = (δ_1 … δ_N, s_1x, s_1y, s_1z, …, s_Nz)``.
    """

    mass_kg: float
    cog_mm: FloatArray
    jac_mass: FloatArray
    jac_cog: FloatArray
    prior_cov: FloatArray

    @property
    def mass_sigma_kg(self) -> float:
        return float(np.sqrt(self.jac_mass @ self.prior_cov @ self.jac_mass))

    @property
    def cog_cov_mm2(self) -> FloatArray:
        return np.asarray(self.jac_cog @ self.prior_cov @ self.jac_cog.T)

    @property
    def cog_mass_cov_mm_kg(self) -> FloatArray:
        """``Cov(G, M)`` (mm·kg), shape (3,)."""
        return np.asarray(self.jac_cog @ self.prior_cov @ self.jac_mass)


def parameter_prior_cov(
    items: Sequence[Item],
    mass_scale: npt.ArrayLike | None = None,
    cog_scale: npt.ArrayLike | None = None,
) -> FloatArray:
    """Covariance of ``θ = (δ…, s…)`` for ``items``, each item's mass and CoG σ optionally
    multiplied by ``mass_scale[I]``, ``cog_scale[I]`` (the update's alternative hypotheses),
    shape (4N, 4N), diagonal."""
    n = len(items)
    km = np.ones(n) if mass_scale is None else np.asarray(mass_scale, dtype=float)
    kc = np.ones(n) if cog_scale is None else np.asarray(cog_scale, dtype=float)
    mass = np.array([i.sigma_rel for i in items]) * km
    cog = np.array([i.cog_sigma_mm for i in items]).reshape(n, 3) * kc[:, None]
    return np.diag(np.concatenate([mass**2, (cog**2).ravel()]))


def linear_prior(items: Sequence[Item], fixed: MassProperties | None) -> LinearPrior:
    """The CAD's mass and CoG, their Jacobians in ``θ`` at ``θ = 0`` and ``θ``'s covariance.

    Examples
    --------
    Two 1 kg items 2 mm apart, one uncertain by 10 % in mass and 0 in CoG:

    >>> from cadcog.mass.properties import box_properties
    >>> a = Item("a", box_properties([1, 1, 1], [-1, 0, 0], mass_kg=1.0), 0.1, [0, 0, 0])
    >>> b = box_properties([1, 1, 1], [1, 0, 0], mass_kg=1.0)
    >>> p = linear_prior([a], b)
    >>> round(p.mass_sigma_kg, 6), round(float(p.cog_cov_mm2[0, 0]), 6)
    (0.1, 0.0025)
    """
    parts = [i.properties for i in items] + ([fixed] if fixed is not None else [])
    if not parts:
        raise ValueError("the CAD has no bodies")
    total = combine(parts)
    n = len(items)
    m = np.array([i.properties.mass_kg for i in items])
    c = np.array([i.properties.cog_mm for i in items]).reshape(n, 3)
    jm = np.concatenate([m, np.zeros(3 * n)])
    jg = np.zeros((3, 4 * n))
    jg[:, :n] = (m[:, None] * (c - total.cog_mm)).T / total.mass_kg
    for k in range(n):
        jg[:, n + 3 * k : n + 3 * k + 3] = np.eye(3) * m[k] / total.mass_kg
    return LinearPrior(total.mass_kg, total.cog_mm, jm, jg, parameter_prior_cov(items))
