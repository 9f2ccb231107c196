"""What :func:`cadcog.cad.stepread.read_step` finds in a STEP file: the model, its bodies with
their placements, names, paths and materials (the reader itself is
:mod:`cadcog.cad.stepread`)."""

from __future__ import annotations

import re
import unicodedata
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

from cadcog.cad.occt import FloatArray, rigid_transform

if TYPE_CHECKING:
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopoDS import TopoDS_Shape

_GENERATED_NAME = re.compile(r"^(=>\[[0-9:]*\]|NAUO\d*|\d+|)$")


@dataclass(frozen=True)
class XcafMaterial:
    """A material a STEP file attaches to a product (XCAF), with its density if usable.

    Attributes
    ----------
    name : str
    density_kg_m3 : float or None
        None when the file gives no density or one whose unit cannot be interpreted.
    raw : str
        The density as the file states it (value and unit name), for messages.
    """

    name: str
    density_kg_m3: float | None
    raw: str


@dataclass(frozen=True)
class Node:
    """One instance on the path from the root to a body.

    Attributes
    ----------
    name : str
        The unique name of this instance among its siblings (with ``[k]`` if needed).
    instance : str
        The instance name in the file ('' if none or generated).
    product : str
        The name of the product it places.
    """

    name: str
    instance: str
    product: str


@dataclass(frozen=True)
class StepBody:
    """A solid or a surface body of the model, at its global placement (mm).

    Attributes
    ----------
    nodes : tuple of Node
        The instances from the root to the body; the last node is the body's own (with
        ``#k`` when its part holds several solids).
    kind : "solid" or "surface"
    shape : TopoDS_Shape
        The body at its global placement (a solid, or a compound of faces).
    local_shape : TopoDS_Shape
        The same body in its product's own frame; bodies of one product share it.
    placement : TopLoc_Location
        Global placement: ``shape = local_shape.Moved(placement)``.
    product_key : str
        Identifies the product and the body's index in it: bodies with the same key are
        instances of one geometry, so their placement-free properties can be shared.
    material : XcafMaterial or None
        The material the file attaches to the body's product, if any.
    made_from_shell : bool
        True for a closed shell that the reader made into a solid.
    """

    nodes: tuple[Node, ...]
    kind: str
    shape: TopoDS_Shape
    local_shape: TopoDS_Shape
    placement: TopLoc_Location
    product_key: str
    material: XcafMaterial | None = None
    made_from_shell: bool = False
    root: str = ""  # the common top assembly's name, when every body sits under one

    @cached_property
    def path(self) -> str:
        """Unique path name, e.g. ``sat/board/R12``."""
        return "/".join(n.name for n in self.nodes)

    @cached_property
    def rigid(self) -> tuple[FloatArray, FloatArray] | None:
        """Rotation and translation (mm, file unit) of :attr:`placement`; None if it is not
        rigid (:func:`cadcog.cad.occt.rigid_transform`, computed once)."""
        return rigid_transform(self.placement)

    @property
    def name(self) -> str:
        """The body's own name (the last path element)."""
        return self.nodes[-1].name

    @cached_property
    def assembly_paths(self) -> tuple[str, ...]:
        """Path of every assembly node above the body, from the root: ``a``, ``a/b``, ..."""
        return tuple("/".join(n.name for n in self.nodes[:k]) for k in range(1, len(self.nodes)))

    @cached_property
    def short_path(self) -> str:
        """The path below the common top assembly (how tables and messages show it)."""
        prefix = f"{self.root}/" if self.root else ""
        return self.path[len(prefix) :] if prefix and self.path.startswith(prefix) else self.path

    def match_names(self) -> tuple[str, ...]:
        """Every name a pattern may match: the full path, the path below the common top
        assembly, each node's unique, instance and product name (the body's own first)."""
        return self._match_names

    @cached_property
    def _match_names(self) -> tuple[str, ...]:
        names = [self.path, self.short_path]
        for n in reversed(self.nodes):
            names.extend(v for v in (n.name, n.instance, n.product) if v)
        return tuple(dict.fromkeys(names))

    @cached_property
    def rule_names(self) -> tuple[str, ...]:
        """Names a materials rule may match: the body's own (:meth:`match_names`), then its
        assemblies' (deepest first), as full paths and as paths below the common top
        assembly (computed once: every rule table asks)."""
        root = f"{self.root}/" if self.root else ""
        above = tuple(reversed(self.assembly_paths))
        below = tuple(a[len(root) :] for a in above if root and a.startswith(root))
        return (*self.match_names(), *above, *below)

    @cached_property
    def item_candidates(self) -> tuple[tuple[str, tuple[str, ...]], ...]:
        """(node path, names a rule may match) of the body, then of its assemblies deepest
        first, paths both full and below the common top assembly: where mass-uncertainty,
        growth and CoG-uncertainty rules look for the body's item (computed once)."""
        root = f"{self.root}/" if self.root else ""

        def below(path: str) -> str:
            return path[len(root) :] if root and path.startswith(root) else ""

        own = self.nodes[-1]
        own_names = (self.path, below(self.path), own.name, own.instance, own.product)
        candidates = [(self.path, tuple(dict.fromkeys(v for v in own_names if v)))]
        for k in range(len(self.nodes) - 1, 0, -1):
            node = self.nodes[k - 1]
            prefix = "/".join(n.name for n in self.nodes[:k])
            names = (prefix, below(prefix), node.name, node.instance, node.product)
            candidates.append((prefix, tuple(dict.fromkeys(v for v in names if v))))
        return tuple(candidates)


@dataclass(frozen=True)
class StepModel:
    """What :func:`read_step` found in a file.

    Attributes
    ----------
    source : Path
    bodies : tuple of StepBody
        Solids and surface bodies, in file order.
    declared_units : tuple of str
        Length units the file declares (normally one), e.g. ``("millimetre",)``.
    n_products, n_instances : int
        Distinct products (parts and assemblies) and instances of them.
    curve_only_parts : tuple of str
        Paths of parts holding neither solids nor faces (wires, points): no mass.
    """

    source: Path
    bodies: tuple[StepBody, ...]
    declared_units: tuple[str, ...]
    n_products: int
    n_instances: int
    curve_only_parts: tuple[str, ...] = field(default=())

    @property
    def solids(self) -> tuple[StepBody, ...]:
        return tuple(b for b in self.bodies if b.kind == "solid")

    @property
    def surfaces(self) -> tuple[StepBody, ...]:
        return tuple(b for b in self.bodies if b.kind == "surface")

    @property
    def declared_unit(self) -> str | None:
        """The one declared length unit, or None if the file declares none or several."""
        units = set(self.declared_units)
        return self.declared_units[0] if len(units) == 1 else None


def clean_name(raw: str) -> str:
    """A name usable in a path: control characters dropped, ``/`` replaced, spaces trimmed.

    Examples
    --------
    >>> clean_name(" bracket/left\\x00 ")
    'bracket_left'
    """
    text = "".join(ch for ch in raw if unicodedata.category(ch)[0] != "C")
    return text.replace("/", "_").strip()
