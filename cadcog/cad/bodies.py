"""Each body of a STEP model integrated at unit density: a product's placement-free
integration, closure and box computed once for all its instances, then moved to each
placement (see :func:`cadcog.cad.stepmass.model_mass_properties`)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.TopAbs import TopAbs_SHELL
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS, TopoDS_Shape

from cadcog.cad.occt import face_area_mm2, placed, surface_properties, volume_properties
from cadcog.cad.overlaps import bounding_boxes
from cadcog.cad.stepmodel import StepBody
from cadcog.core.parallel import fork_map
from cadcog.core.units import areal_density_kg_m2_to_kg_mm2, density_kg_m3_to_kg_mm3
from cadcog.mass.properties import MassProperties

#: ``progress(description, total)`` returns a function called with the number of steps done.
ProgressFactory = Callable[[str, int], Callable[[int], None]]


def _closed(shape: TopoDS_Shape) -> bool:
    explorer = TopExp_Explorer(shape, TopAbs_SHELL)
    found = False
    while explorer.More():
        found = True
        if not BRep_Tool.IsClosed_s(TopoDS.Shell(explorer.Current())):
            return False
        explorer.Next()
    return found


def scaled_lengths(p: MassProperties, scale: float, dimension: int) -> MassProperties:
    """Properties of a body ``scale`` times larger (``dimension`` 3 for volumes, 2 areas)."""
    if scale == 1.0:
        return p
    k = scale**dimension
    return MassProperties(
        p.mass_kg * k, p.cog_mm * scale, p.inertia_kg_mm2 * k * scale**2, p.volume_mm3 * scale**3
    )


def with_mass_factor(p: MassProperties, factor: float) -> MassProperties:
    """The same geometry with its mass (and inertia) multiplied by ``factor``: a density."""
    return MassProperties(p.mass_kg * factor, p.cog_mm, p.inertia_kg_mm2 * factor, p.volume_mm3)


@dataclass
class Body:
    """Working state of one kept body."""

    step: StepBody
    props: MassProperties  # unit density (kg/mm³) or unit areal density (kg/mm²), mm
    box_lo: np.ndarray = field(default_factory=lambda: np.zeros(3))  # file frame and unit
    box_hi: np.ndarray = field(default_factory=lambda: np.zeros(3))
    material: str = ""
    source: str = ""
    density_kg_m3: float | None = None
    areal_density_kg_m2: float | None = None
    removed_mm3: float = 0.0
    surface_area_mm2: float | None = None  # mm² (after unit scaling); None: not asked for

    @property
    def density_kg_mm3(self) -> float:
        if self.step.kind == "solid":
            return density_kg_m3_to_kg_mm3(self.density_kg_m3 or 0.0)
        return areal_density_kg_m2_to_kg_mm2(self.areal_density_kg_m2 or 0.0)


@dataclass(frozen=True)
class _ProductCheck:
    """Placement-free results for one product's body, computed once for all its instances."""

    props: MassProperties  # unit density, the product's frame
    closed: bool
    box_lo: np.ndarray
    box_hi: np.ndarray
    face_area: float | None = None  # the file's unit squared; None: not asked for


def _check_product(body: StepBody, areas: bool = False) -> _ProductCheck:
    shape = body.local_shape
    if body.kind == "solid":
        props = volume_properties(shape)
        closed = _closed(shape)
        area = face_area_mm2(shape) if areas else None
    else:
        props, closed = surface_properties(shape), True
        area = props.mass_kg if areas else None  # unit areal density: the mass is the area
    lo, hi = bounding_boxes([shape])
    return _ProductCheck(props, closed, lo[0], hi[0], area)


def _check_product_with_area(body: StepBody) -> _ProductCheck:
    return _check_product(body, areas=True)


#: The eight corners of a box, as (hi?) flags per axis.
_CORNERS = np.array(list(np.ndindex(2, 2, 2)), dtype=bool)


def _global_box(
    check: _ProductCheck, body: StepBody, rigid: tuple[np.ndarray, np.ndarray] | None
) -> tuple[np.ndarray, np.ndarray]:
    """The body's axis-aligned box: its product's box moved, exact for axis-aligned rotations
    (any multiple of 90°); other rotations are boxed afresh, since a moved box is looser."""
    if rigid is not None:
        r, t = rigid
        a = np.abs(r)
        whole = np.round(a)
        if np.all(np.abs(a - whole) <= 1e-12 + 1e-5 * whole):  # np.isclose(a, whole, atol=1e-12)
            corners = np.where(_CORNERS, check.box_hi, check.box_lo)
            moved = corners @ r.T + t
            return moved.min(axis=0), moved.max(axis=0)
    lo, hi = bounding_boxes([body.shape])
    return lo[0], hi[0]


def integrate(
    kept: Sequence[StepBody],
    scale: float,
    progress: ProgressFactory | None,
    workers: int,
    areas: bool = False,
) -> tuple[list[Body], dict[str, Any]]:
    """Unit-density properties of every body (shared between instances), and the audit;
    ``areas``: each body's face area too (:func:`cadcog.cad.occt.face_area_mm2`)."""
    firsts: dict[str, StepBody] = {}
    for body in kept:
        firsts.setdefault(body.product_key, body)
    tick = progress("integrating bodies", len(firsts)) if progress else None
    checks = dict(
        zip(
            firsts,
            fork_map(
                _check_product_with_area if areas else _check_product,
                list(firsts.values()),
                workers=workers,
                progress=tick,
            ),
            strict=True,
        )
    )
    problems: list[str] = []
    empty: list[str] = []
    open_solids: list[str] = []
    made_solid: list[str] = []
    out: list[Body] = []
    for body in kept:
        check = checks[body.product_key]
        rigid = body.rigid
        if rigid is not None:
            placed_props = placed(check.props, *rigid)
        elif body.kind == "solid":
            placed_props = volume_properties(body.shape)
        else:
            placed_props = surface_properties(body.shape)
        props = scaled_lengths(placed_props, scale, 3 if body.kind == "solid" else 2)
        if body.kind == "solid":
            if not check.closed:
                open_solids.append(body.path)
            elif not props.volume_mm3 > 1e-9:
                empty.append(body.path)
            if body.made_from_shell:
                made_solid.append(body.path)
        lo, hi = _global_box(check, body, rigid)
        area = check.face_area
        if area is not None and rigid is None:  # a scaled or sheared placement changes it
            # a surface's area is its placed properties' mass (unit areal density), as when
            # rigid; only a solid needs its faces integrated again
            area = placed_props.mass_kg if body.kind == "surface" else face_area_mm2(body.shape)
        out.append(
            Body(
                body,
                props,
                box_lo=lo,
                box_hi=hi,
                surface_area_mm2=None if area is None else area * scale**2,
            )
        )
    if open_solids:
        problems.append(
            f"solids whose shells are not closed: {', '.join(open_solids[:10])}"
            f"{' ...' if len(open_solids) > 10 else ''}; fix them or --exclude them"
        )
    if empty:
        problems.append(
            f"zero or negative volume: {', '.join(empty[:10])}"
            f"{' ...' if len(empty) > 10 else ''} (degenerate or inside-out solids); --exclude "
            "them or fix the model"
        )
    return out, {"problems": problems, "made_solid": made_solid}


def _valid(shape: TopoDS_Shape) -> bool:
    return bool(BRepCheck_Analyzer(shape).IsValid())


def invalid_solids(bodies: Sequence[Body], products: set[str] | None, workers: int) -> list[str]:
    """Paths of the solids whose product OCCT's checker finds invalid, in file order.

    Only the products in ``products`` are checked (None: every one): the check costs about as
    much as the integration and changes no number, so it is kept for the solids that go
    through a boolean (where invalid topology can make OCCT fail or mislead) and for
    ``--strict``.
    """
    firsts: dict[str, TopoDS_Shape] = {}
    for b in bodies:
        if b.step.kind == "solid" and (products is None or b.step.product_key in products):
            firsts.setdefault(b.step.product_key, b.step.local_shape)
    valid = dict(zip(firsts, fork_map(_valid, list(firsts.values()), workers=workers), strict=True))
    return [b.step.path for b in bodies if not valid.get(b.step.product_key, True)]
