"""Flat STEP assemblies read in linear time: each child's placement given its own parent record.

OCCT's STEP transfer places every child of an assembly through a
``SHAPE_REPRESENTATION_RELATIONSHIP`` whose second representation (``Rep2``) is the parent's.
For each child it asks which entities share that parent representation
(``STEPConstruct_Assembly::CheckSRRReversesNAUO``, to tell the relationship's direction) and
scans the representation's items for the child's placement
(``STEPControl_ActorRead::ComputeTransformation``). Under a parent with N children both are
O(N) per child, O(N²) in all: reading a flat file of 20 000 products took 377 s of CPU, 332
of them in the transfer, where a ``perf`` profile put 45 % in the first and most of the rest in
the lists it builds and frees (4000 products: 15 of 24 s; OCCT 8.0.1; docs/performance.md).

:func:`isolate_sibling_placements` runs between parsing and transfer. For every placement
relationship under a parent with at least :data:`MIN_SIBLINGS` children whose ``Rep2`` is
that parent's shape representation (checked, so the direction is known), it gives the
relationship a private copy of the parent representation holding only the child's target
placement, with the parent's name and context (its length unit). The copy belongs to no
model: nothing shares it, so OCCT finds the direction at once (the same answer) and the
placement among one item. Shapes, placements, names and units come out the same
(``tests/cad/test_flatassembly.py`` compares every body with and without it); the
relationships that do not match the pattern (written the other way round, placed by a
Cartesian operator, ...) are left as they are.

OCP hands STEP entities to OCCT functions that take ``Standard_Transient`` handles as null
(``Interface_Graph.Sharings``, ``StepData_StepModel.Number``), so entities are matched by the
identity of their Python wrappers, which pybind11 keeps one per C++ object while alive: every
wrapper used as a key is kept in a list until the pass ends.
"""

from __future__ import annotations

from typing import Any

from OCP.collections import HArray1_StepRepr_RepresentationItem
from OCP.StepRepr import StepRepr_ShapeRepresentationRelationshipWithTransformation
from OCP.StepShape import StepShape_ShapeRepresentation

#: Children under one parent from which the pass pays: it costs ~0.35 s of CPU per 1000
#: relationships (two scans of the model), the quadratic cost it removes breaks even at about
#: 1000-2000 siblings (2.75 vs 2.52 s of transfer at 1000, 15.9 vs 12.3 s at 4000).
MIN_SIBLINGS = 1000


def _entities(step_reader: Any, step_type: str) -> list[Any]:
    """The parsed model's entities of one STEP type (OCCT's own selection, in C++)."""
    found = step_reader.GiveList(f"xst-type({step_type})")
    if found is None:
        return []
    return [found.Value(i) for i in range(1, found.Length() + 1)]


def _parent_of(cdsr: Any) -> Any:
    """The assembly product definition a placement relationship places its child in (None if
    the chain is incomplete)."""
    try:
        nauo = cdsr.RepresentedProductRelation().Definition().ProductDefinitionRelationship()
        return nauo.RelatingProductDefinition()
    except AttributeError:  # a link of the chain is absent (None)
        return None


def isolate_sibling_placements(step_reader: Any, min_siblings: int | None = None) -> int:
    """Give each child placement under a large assembly a private parent representation.

    Parameters
    ----------
    step_reader : OCP.STEPControl.STEPControl_Reader
        After ``ReadFile``, before any transfer (``STEPCAFControl_Reader.ChangeReader()``).
    min_siblings : int, optional
        Only parents with at least this many placed children are changed (default
        :data:`MIN_SIBLINGS`).

    Returns
    -------
    int
        The number of relationships changed (0 when no parent is large enough).
    """
    threshold = MIN_SIBLINGS if min_siblings is None else min_siblings
    keep: list[Any] = []  # wrappers whose id() is a key below: alive until the pass ends
    placements = _entities(step_reader, "ContextDependentShapeRepresentation")
    parents: list[Any] = []
    children: dict[int, int] = {}
    for cdsr in placements:
        parent = _parent_of(cdsr)
        parents.append(parent)
        if parent is not None:
            keep.append(parent)
            children[id(parent)] = children.get(id(parent), 0) + 1
    if not children or max(children.values()) < threshold:
        return 0
    representations: dict[int, set[int]] = {}  # id(product definition) -> ids of its shapes
    for sdr in _entities(step_reader, "ShapeDefinitionRepresentation"):
        try:
            definition = sdr.Definition().PropertyDefinition().Definition().ProductDefinition()
            shape = sdr.UsedRepresentation()
        except AttributeError:
            continue
        if definition is None or shape is None:
            continue
        keep += [definition, shape]
        representations.setdefault(id(definition), set()).add(id(shape))
    changed = 0
    for cdsr, parent in zip(placements, parents, strict=True):
        if parent is None or children[id(parent)] < threshold:
            continue
        relation = cdsr.RepresentationRelation()
        if not isinstance(relation, StepRepr_ShapeRepresentationRelationshipWithTransformation):
            continue
        operator = relation.TransformationOperator()
        placed = operator.ItemDefinedTransformation() if operator is not None else None
        parent_shape = relation.Rep2()
        if placed is None or parent_shape is None:
            continue  # a Cartesian transformation operator: left to OCCT as it is
        keep.append(parent_shape)
        if id(parent_shape) not in representations.get(id(parent), ()):
            continue  # Rep2 is not the parent's representation (written the other way round)
        items = HArray1_StepRepr_RepresentationItem(1, 1)
        items.SetValue(1, placed.TransformItem2())
        private = StepShape_ShapeRepresentation()
        private.Init(parent_shape.Name(), items, parent_shape.ContextOfItems())
        relation.SetRep2(private)
        changed += 1
    return changed
