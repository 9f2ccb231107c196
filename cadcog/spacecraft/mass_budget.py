"""A mass budget: bodies rolled up by assembly node, with mass uncertainty and growth.

Every body carries its mass properties and, when the materials file gives them, a 1-σ relative
mass uncertainty and a mass growth allowance (MGA). Uncertainties belong to *items*: a body, or
an assembly whose bodies vary together (a rule naming ``battery_pack`` makes the pack one item).
Items are independent of each other. With ``ε_I`` the relative mass error of item ``I`` (std
``σ_I``), the rolled-up figures are, to first order:

- total mass variance ``Σ_I (σ_I m_I)²``, and the same per node over the part of each item it
  holds;
- CoG covariance ``Σ_I m_I² (σ_I² (c_I − G)(c_I − G)ᵀ + diag(σc_I²)) / M²`` (``c_I`` the item's
  CoG, ``G`` the total's): scaling an item's mass pulls the CoG towards or away from it, and the
  item's own CoG is uncertain by ``σc_I`` (``[cog_uncertainty]``, or by default its mass
  uncertainty times the spread of its mass: :mod:`cadcog.spacecraft.items`). The CoG is a
  ratio of sums, so this linearisation is exact only as σ → 0: sampling shows it within 3 % at
  item uncertainties up to 2 %, and about 5 % low when a dominant item is uncertain by 10 %
  (``tests/spacecraft/test_mass_budget.py``).

Growth allowances are a planning reserve, not an uncertainty: the *predicted* mass of a body is
``m (1 + MGA)`` (AIAA S-120A's current best estimate plus growth), reported beside the current
best estimate with the CoG of the predicted masses.

Pure numpy: nothing here imports the CAD layer.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
import numpy.typing as npt

from cadcog.core.results import JsonResult
from cadcog.mass.properties import (
    MassProperties,
    combine,
    parallel_axis_kg_mm2,
    radii_of_gyration_mm,
)
from cadcog.spacecraft.items import items_from_bodies, linear_prior

FloatArray = npt.NDArray[np.float64]


class BudgetLine(Protocol):
    """What the budget needs of a body (``cadcog.cad.stepmass.BodyResult`` has it).

    A line may also have ``surface_area_mm2`` (float or None): the area of its faces, summed
    per node when every line below the node has one (:func:`_area_of`).
    """

    @property
    def nodes(self) -> tuple[str, ...]: ...

    @property
    def properties(self) -> MassProperties: ...

    @property
    def sigma_rel(self) -> float | None: ...

    @property
    def item(self) -> str: ...

    @property
    def growth(self) -> float: ...


@dataclass(frozen=True)
class BudgetNode(JsonResult):
    """One node of the budget tree (an assembly, or a body at a leaf).

    Attributes
    ----------
    path : str
    name : str
    mass_kg : float
        Current best estimate.
    share : float
        Of the total mass.
    cog_mm : ndarray, shape (3,)
    n_bodies : int
    mass_sigma_kg : float or None
        1 σ, from the items inside the node; None if no body in it has an uncertainty.
    sigma_complete : bool
        Every body in the node has an uncertainty.
    predicted_mass_kg : float
        With growth allowances.
    children : tuple of BudgetNode
    inertia_kg_mm2 : ndarray, shape (3, 3)
        About the node's own CoG, model axes (tensor convention of :mod:`cadcog.mass.inertia`:
        off-diagonal entries ``−∫ x·y dm``).
    inertia_total_cog_kg_mm2 : ndarray, shape (3, 3)
        The node's inertia about the *total's* CoG, model axes (its contribution to the total).
    item_masses : tuple of (item, mass_kg, sigma_rel)
        The node's mass in each uncertainty item (not in the JSON): lets identical siblings be
        grouped with their exact rolled-up σ (:func:`budget_rows`).
    surface_area_mm2 : float or None
        Sum of its bodies' face areas (mm²; shared faces counted once per body), when every body
        has one (``massprops --surface-area``); else None, and not in the JSON.
    product : str
        The product the node places (the STEP's product name), when its lines say
        (``products``); copies of one part share it whatever their instance names.
    """

    path: str
    name: str
    mass_kg: float
    share: float
    cog_mm: FloatArray
    n_bodies: int
    mass_sigma_kg: float | None
    sigma_complete: bool
    predicted_mass_kg: float
    children: tuple[BudgetNode, ...]
    inertia_kg_mm2: FloatArray = field(default_factory=lambda: np.zeros((3, 3)))
    inertia_total_cog_kg_mm2: FloatArray = field(default_factory=lambda: np.zeros((3, 3)))
    item_masses: tuple[tuple[str, float, float], ...] = field(default=(), repr=False)
    surface_area_mm2: float | None = None
    product: str = ""

    @property
    def radii_of_gyration_mm(self) -> FloatArray:
        """``k = √(I / m)`` about the node's own CoG, model axes x, y, z (mm), shape (3,)."""
        return radii_of_gyration_mm(self.mass_kg, self.inertia_kg_mm2)

    def walk(self, max_depth: int | None = None, depth: int = 0) -> list[tuple[int, BudgetNode]]:
        """The node and its descendants, depth first, with their depth."""
        out = [(depth, self)]
        if max_depth is None or depth < max_depth:
            for c in self.children:
                out.extend(c.walk(max_depth, depth + 1))
        return out

    def to_dict(self) -> dict[str, Any]:
        out = {
            "path": self.path,
            "name": self.name,
            "mass_kg": self.mass_kg,
            "share": self.share,
            "cog_mm": self.cog_mm.tolist(),
            "n_bodies": self.n_bodies,
            "mass_sigma_kg": self.mass_sigma_kg,
            "sigma_complete": self.sigma_complete,
            "predicted_mass_kg": self.predicted_mass_kg,
            "inertia_kg_mm2": self.inertia_kg_mm2.tolist(),
            "inertia_about_total_cog_kg_mm2": self.inertia_total_cog_kg_mm2.tolist(),
            "radii_of_gyration_mm": self.radii_of_gyration_mm.tolist(),
        }
        if self.surface_area_mm2 is not None:
            out["surface_area_mm2"] = self.surface_area_mm2
        if self.product:
            out["product"] = self.product
        out["children"] = [c.to_dict() for c in self.children]
        return out


@dataclass(frozen=True, repr=False)  # JsonResult's one-line repr
class MassBudget(JsonResult):
    """The budget tree and the rolled-up totals.

    Attributes
    ----------
    root : BudgetNode
    mass_sigma_kg : float or None
        1-σ total mass uncertainty (None if no body has one).
    cog_cov_mm2 : ndarray, shape (3, 3) or None
        Covariance of the total CoG from the items' mass uncertainties.
    sigma_coverage : float
        Fraction of the mass whose uncertainty is given.
    predicted : MassProperties
        Every body at ``m (1 + MGA)``.
    n_items : int
        Independent uncertainty items.
    total_given : bool
        The total is a weighed mass the densities were scaled to (``--total-mass-kg``): its σ
        is 0 and the CoG's covariance is the items' given that total (the Gaussian
        conditioned on ``M``: ``Cov(G) − Cov(G, M) Cov(M, G) / Var(M)``).
    """

    root: BudgetNode
    mass_sigma_kg: float | None
    cog_cov_mm2: FloatArray | None
    sigma_coverage: float
    predicted: MassProperties
    n_items: int
    total_given: bool = False

    @property
    def growth_kg(self) -> float:
        """Mass growth allowance of the whole model (kg): predicted minus current mass."""
        return self.predicted.mass_kg - self.root.mass_kg

    def to_dict(self) -> dict[str, Any]:
        return {
            "mass_kg": self.root.mass_kg,
            "mass_sigma_kg": self.mass_sigma_kg,
            "cog_mm": self.root.cog_mm.tolist(),
            "cog_cov_mm2": None if self.cog_cov_mm2 is None else self.cog_cov_mm2.tolist(),
            "cog_sigma_mm": None
            if self.cog_cov_mm2 is None
            else np.sqrt(np.diag(self.cog_cov_mm2)).tolist(),
            "sigma_coverage": self.sigma_coverage,
            "n_uncertainty_items": self.n_items,
            "total_given": self.total_given,
            "growth_kg": self.growth_kg,
            "predicted_mass_kg": self.predicted.mass_kg,
            "predicted_cog_mm": self.predicted.cog_mm.tolist(),
            "tree": self.root.to_dict(),
        }


def _item_masses(lines: Sequence[BudgetLine]) -> tuple[tuple[str, float, float], ...]:
    """(item, mass in these lines, σ_rel) for every item with an uncertainty."""
    per_item: dict[str, tuple[float, float]] = {}
    for b in lines:
        if b.sigma_rel is not None:
            mass, sigma = per_item.get(b.item, (0.0, b.sigma_rel))
            per_item[b.item] = (mass + b.properties.mass_kg, sigma)
    return tuple((k, m, s) for k, (m, s) in per_item.items())


def _sigma_of(items: Sequence[tuple[str, float, float]]) -> float:
    """1-σ mass of item parts: ``√Σ_I (σ_I m_I)²`` with ``m_I`` summed per item first."""
    per_item: dict[str, tuple[float, float]] = {}
    for key, mass, sigma in items:
        m0, _ = per_item.get(key, (0.0, sigma))
        per_item[key] = (m0 + mass, sigma)
    return float(np.sqrt(sum((m * s) ** 2 for m, s in per_item.values())))


def _area_of(areas: Sequence[float | None]) -> float | None:
    """The sum of face areas (mm²), or None when any is unknown."""
    return None if any(a is None for a in areas) else float(sum(areas))  # type: ignore[arg-type]


def _node_sigma(lines: Sequence[BudgetLine]) -> tuple[float | None, bool]:
    items = _item_masses(lines)
    if not items:
        return None, False
    return _sigma_of(items), all(b.sigma_rel is not None for b in lines)


_Alone = dict[int, tuple[MassProperties, FloatArray]]


def _alone(lines: Sequence[BudgetLine], total_cog_mm: FloatArray) -> _Alone:
    """Each line as a node of its own, for all lines at once: ``combine([line])`` and its
    inertia about the total's CoG (``inertia_about``), by the same element-wise operations, so
    the same bits (most nodes of a large model are single bodies). Keyed by ``id(line)``; empty
    when a line has no positive mass (``combine`` then says why)."""
    m = np.array([b.properties.mass_kg for b in lines])
    if not np.all(m > 0.0):
        return {}
    c = np.array([b.properties.cog_mm for b in lines])
    cog = (m[:, None] * c) / m[:, None]
    own = np.array([b.properties.inertia_kg_mm2 for b in lines]) + parallel_axis_kg_mm2(m, cog - c)
    about = own + parallel_axis_kg_mm2(m, total_cog_mm - cog)
    return {
        id(b): (MassProperties(m[k], cog[k], own[k], b.properties.volume_mm3 + 0.0), about[k])
        for k, b in enumerate(lines)
    }


def _build(
    lines: Sequence[BudgetLine],
    depth: int,
    path: str,
    name: str,
    total_kg: float,
    total_cog_mm: FloatArray,
    alone: _Alone,
) -> BudgetNode:
    if len(lines) == 1 and id(lines[0]) in alone:
        here, about = alone[id(lines[0])]
    else:
        here = combine(b.properties for b in lines)
        about = here.inertia_about(total_cog_mm)
    groups: dict[str, list[BudgetLine]] = {}
    for b in lines:
        if len(b.nodes) > depth:
            groups.setdefault(b.nodes[depth], []).append(b)
    children = tuple(
        _build(
            group,
            depth + 1,
            f"{path}/{child}" if path else child,
            child,
            total_kg,
            total_cog_mm,
            alone,
        )
        for child, group in groups.items()
    )
    sigma, complete = _node_sigma(lines)
    predicted = sum(b.properties.mass_kg * (1.0 + b.growth) for b in lines)
    return BudgetNode(
        path,
        name,
        here.mass_kg,
        here.mass_kg / total_kg,
        here.cog_mm,
        len(lines),
        sigma,
        complete,
        predicted,
        children,
        here.inertia_kg_mm2,
        about,
        _item_masses(lines),
        _area_of([getattr(b, "surface_area_mm2", None) for b in lines]),
        _product_at(lines, depth - 1),
    )


def _product_at(lines: Sequence[BudgetLine], depth: int) -> str:
    """The product the node at ``depth`` of these lines places, if every line says the same."""
    if depth < 0:
        return ""
    found = {p[depth] if len(p := tuple(getattr(b, "products", ()))) > depth else "" for b in lines}
    return found.pop() if len(found) == 1 else ""


def mass_budget(
    lines: Sequence[BudgetLine], name: str = "total", *, total_given: bool = False
) -> MassBudget:
    """Roll ``lines`` up by assembly node, with uncertainties and growth (module docstring).
    With ``total_given`` the total mass is a weighing (:attr:`MassBudget.total_given`).

    Raises
    ------
    ValueError
        With no lines or no positive total mass.

    Examples
    --------
    >>> from cadcog.mass.properties import box_properties
    >>> from types import SimpleNamespace as L
    >>> a = L(nodes=("sat", "a"), properties=box_properties([1, 1, 1], [-1, 0, 0], mass_kg=1.0),
    ...       sigma_rel=0.1, item="sat/a", growth=0.0, cog_sigma_mm=(0.0, 0.0, 0.0))
    >>> b = L(nodes=("sat", "b"), properties=box_properties([1, 1, 1], [1, 0, 0], mass_kg=1.0),
    ...       sigma_rel=None, item="sat/b", growth=0.2)
    >>> budget = mass_budget([a, b])
    >>> round(budget.mass_sigma_kg, 6), round(float(budget.cog_cov_mm2[0, 0]), 6)
    (0.1, 0.0025)
    >>> budget.predicted.mass_kg, budget.sigma_coverage
    (2.2, 0.5)

    Weighed, the total fixes the one uncertain mass, and with it the CoG:

    >>> weighed = mass_budget([a, b], total_given=True)
    >>> weighed.mass_sigma_kg, round(float(weighed.cog_cov_mm2[0, 0]), 12)
    (0.0, 0.0)
    """
    if not lines:
        raise ValueError("a mass budget needs at least one body")
    total = combine(b.properties for b in lines)
    root = _build(lines, 0, "", name, total.mass_kg, total.cog_mm, _alone(lines, total.cog_mm))
    if len(root.children) == 1 and root.children[0].n_bodies == root.n_bodies:
        root = root.children[0]  # one top assembly: it is the root
    cov = None
    sigma = None
    keys = {b.item for b in lines if b.sigma_rel is not None}
    if keys:
        items, fixed = items_from_bodies(lines)
        if items:
            prior = linear_prior(items, fixed)
            cov, sigma = prior.cog_cov_mm2, prior.mass_sigma_kg
            if total_given and sigma > 0:
                c = prior.cog_mass_cov_mm_kg
                cov, sigma = cov - np.outer(c, c) / sigma**2, 0.0
                cov = (cov + cov.T) / 2.0
        else:
            cov, sigma = np.zeros((3, 3)), 0.0
    covered = sum(b.properties.mass_kg for b in lines if b.sigma_rel is not None)
    predicted = combine(
        MassProperties(
            b.properties.mass_kg * (1.0 + b.growth),
            b.properties.cog_mm,
            b.properties.inertia_kg_mm2 * (1.0 + b.growth),
            b.properties.volume_mm3,
        )
        for b in lines
    )
    return MassBudget(root, sigma, cov, covered / total.mass_kg, predicted, len(keys), total_given)


# --- the budget as people read it: identical parts grouped, sorted, small ones collapsed -------
#: Two sibling nodes are copies of one part when their base names (without an instance suffix
#: ``[n]`` or a body suffix ``#n``), body counts and masses agree to this relative difference.
IDENTICAL_MASS_RELATIVE = 1e-9

_INSTANCE_SUFFIX = re.compile(r"(\[\d+\]|#\d+)+$")


@dataclass(frozen=True)
class BudgetRow:
    """One row of a budget table: a node, a group of identical sibling nodes, or the sum of the
    siblings below the collapse share.

    Attributes
    ----------
    level : int
        Depth below the root (0 for the root).
    name : str
        The node's name; for a group, the base name without its instance suffix ``[n]``; for a
        collapsed row, ``"N others"``.
    count : int
        Identical copies grouped in the row (1 for a single node; the number of nodes folded into
        a collapsed row).
    unit_mass_kg : float or None
        Mass of one copy (None for a collapsed row).
    mass_kg : float
    share : float
        Of the total mass.
    mass_sigma_kg : float or None
        1 σ of the row's mass from the uncertainty items it holds.
    cog_mm : ndarray, shape (3,)
        The row's combined CoG.
    inertia_kg_mm2 : ndarray, shape (3, 3)
        The row's inertia about its own CoG, model axes (off-diagonal ``−∫ x·y dm``).
    path : str
        The (first) node's path; empty for a collapsed row.
    n_bodies : int
    collapsed : bool
        The row stands for siblings each below the collapse share.
    predicted_mass_kg : float
        With growth allowances.
    surface_area_mm2 : float or None
        Sum of the face areas of its bodies (mm²), when known.
    """

    level: int
    name: str
    count: int
    unit_mass_kg: float | None
    mass_kg: float
    share: float
    mass_sigma_kg: float | None
    cog_mm: FloatArray
    inertia_kg_mm2: FloatArray
    path: str
    n_bodies: int
    collapsed: bool = False
    predicted_mass_kg: float = 0.0
    surface_area_mm2: float | None = None

    @property
    def label(self) -> str:
        """``name``, ``name ×count`` for identical copies."""
        return f"{self.name} ×{self.count}" if self.count > 1 and not self.collapsed else self.name

    @property
    def radii_of_gyration_mm(self) -> FloatArray:
        """``√(I / m)`` about the row's CoG, model axes (mm), shape (3,)."""
        return radii_of_gyration_mm(self.mass_kg, self.inertia_kg_mm2)


def _merged(nodes: Sequence[BudgetNode], level: int, name: str, collapsed: bool) -> BudgetRow:
    props = combine(MassProperties(n.mass_kg, n.cog_mm, n.inertia_kg_mm2, 0.0) for n in nodes)
    items = [t for n in nodes for t in n.item_masses]
    sigma = _sigma_of(items) if items else None
    first = nodes[0]
    return BudgetRow(
        level,
        name,
        len(nodes),
        None if collapsed else first.mass_kg,
        props.mass_kg,
        sum(n.share for n in nodes),
        sigma,
        props.cog_mm,
        props.inertia_kg_mm2,
        "" if collapsed else first.path,
        sum(n.n_bodies for n in nodes),
        collapsed,
        sum(n.predicted_mass_kg for n in nodes),
        _area_of([n.surface_area_mm2 for n in nodes]),
    )


def _same_part(a: BudgetNode, b: BudgetNode) -> bool:
    same = (
        a.product == b.product
        if a.product and b.product
        else _INSTANCE_SUFFIX.sub("", a.name) == _INSTANCE_SUFFIX.sub("", b.name)
    )
    return (
        same
        and a.n_bodies == b.n_bodies
        and abs(a.mass_kg - b.mass_kg) <= IDENTICAL_MASS_RELATIVE * max(a.mass_kg, b.mass_kg)
    )


def _group_name(bunch: Sequence[BudgetNode]) -> str:
    """A group's name: the copies' base name when they share one, else their product's."""
    bases = {_INSTANCE_SUFFIX.sub("", n.name) for n in bunch}
    if len(bases) == 1:
        return bases.pop()
    return bunch[0].product or _INSTANCE_SUFFIX.sub("", bunch[0].name)


def budget_rows(
    root: BudgetNode,
    max_depth: int | None = None,
    *,
    collapse_below: float = 0.0,
    group: bool = True,
) -> list[BudgetRow]:
    """The budget tree as table rows: copies grouped, heaviest first, small siblings collapsed.

    Parameters
    ----------
    root : BudgetNode
    max_depth : int, optional
        Levels below the root shown (None: all).
    collapse_below : float
        Siblings each below this share of the total mass are summed into one ``N others`` row
        (only when there are two or more of them); 0 shows every node.
    group : bool
        Fold identical sibling nodes (the same product, or without products the same base name
        without ``[n]``; the same bodies and mass) into one ``name ×count`` row whose children
        are the first copy's; the row is named by the copies' base name, or by their product
        when their names differ (KiCad's R1, R2 ...; Inventor's part:1, part:2 ...).

    Examples
    --------
    >>> from types import SimpleNamespace as L
    >>> from cadcog.mass.properties import box_properties
    >>> def body(name, x, m):
    ...     return L(nodes=("sat", name), properties=box_properties([1, 1, 1], [x, 0, 0],
    ...              mass_kg=m), sigma_rel=None, item=name, growth=0.0)
    >>> lines = [body("screw[1]", 0, 0.001), body("pcb", 5, 0.5), body("screw[2]", 1, 0.001),
    ...          body("nut", 2, 0.0005), body("washer", 3, 0.0002)]
    >>> for r in budget_rows(mass_budget(lines).root, collapse_below=0.003):
    ...     print(r.level, r.label, round(r.mass_kg, 4), r.cog_mm[0].round(3))
    0 sat 0.5027 4.978
    1 pcb 0.5 5.0
    1 screw ×2 0.002 0.5
    1 2 others 0.0007 2.286
    """
    rows: list[BudgetRow] = []

    def visit(node: BudgetNode, level: int) -> None:
        if max_depth is not None and level >= max_depth:
            return
        bunches: list[list[BudgetNode]] = []
        for child in node.children:
            for bunch in bunches if group else []:
                if _same_part(bunch[0], child):
                    bunch.append(child)
                    break
            else:
                bunches.append([child])
        bunches.sort(key=lambda b: -sum(n.mass_kg for n in b))
        small = [b for b in bunches if sum(n.share for n in b) < collapse_below]
        if len(small) < 2:
            small = []
        for bunch in bunches:
            if any(bunch is s for s in small):
                continue
            base = _group_name(bunch) if len(bunch) > 1 else bunch[0].name
            rows.append(_merged(bunch, level + 1, base, collapsed=False))
            visit(bunch[0], level + 1)
        if small:
            folded = [n for b in small for n in b]
            rows.append(_merged(folded, level + 1, f"{len(folded)} others", collapsed=True))

    rows.append(_merged([root], 0, root.name, collapsed=False))
    visit(root, 0)
    return rows
