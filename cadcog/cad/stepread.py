"""Reading a STEP file as an assembly tree: every body at its global placement, uniquely named.

A STEP assembly is a tree of product *instances*: each instance places a product (a part or a
sub-assembly) with a location relative to its parent, and one product may be instanced many
times (KiCad nests every component under its board; a bracket sub-assembly is used twice). The
reader walks OCCT's XCAF document (``STEPCAFControl_Reader``) and composes the locations from
the root down, so a body three levels deep gets ``L_root · L_level1 · L_level2`` whatever the
exporter. (build123d's ``import_step`` tree moves each node by its own location only, so bodies
two or more levels deep lose their parents' placements: do not take solids from its leaves.)

Each body gets a unique, stable path name: the names of the instances from the root to the
body, joined by ``/``. An instance is named by its instance name when the exporter gave a
meaningful one, otherwise by its product's name; siblings that share a name get ``[k]``
(1-based, in file order); a part holding several solids names them ``#1``, ``#2``, ...
Surface bodies (open shells and free faces, which have no volume) are kept as separate bodies
of kind ``"surface"``; a closed shell that is not a solid is made into one.

Lengths are in mm: OCCT's reader converts the file's declared length unit, which is reported
(:attr:`StepModel.declared_units`) so that a file whose declaration is wrong can be corrected.
No build123d import is needed, only OCP.
"""

from __future__ import annotations

import os
import re
import sys
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from OCP.BRep import BRep_Builder, BRep_Tool
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeSolid
from OCP.BRepGProp import BRepGProp
from OCP.collections import Sequence_TCollection_AsciiString, Sequence_TDF_Label
from OCP.GProp import GProp_GProps
from OCP.IFSelect import IFSelect_ReturnStatus
from OCP.STEPCAFControl import STEPCAFControl_Reader
from OCP.TCollection import TCollection_AsciiString, TCollection_ExtendedString
from OCP.TDataStd import TDataStd_Name, TDataStd_TreeNode
from OCP.TDF import TDF_Label, TDF_Tool
from OCP.TDocStd import TDocStd_Document
from OCP.TopAbs import TopAbs_FACE, TopAbs_SHELL, TopAbs_SOLID
from OCP.TopExp import TopExp_Explorer
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS, TopoDS_Compound, TopoDS_Shape
from OCP.XCAFApp import XCAFApp_Application
from OCP.XCAFDoc import XCAFDoc, XCAFDoc_DocumentTool, XCAFDoc_Material, XCAFDoc_ShapeTool

from cadcog.cad.flatassembly import isolate_sibling_placements
from cadcog.cad.stepmodel import (
    _GENERATED_NAME,
    Node,
    StepBody,
    StepModel,
    XcafMaterial,
    clean_name,
)
from cadcog.core.errors import CadcogError
from cadcog.core.fileio import not_a_regular_file, note_input
from cadcog.core.heartbeat import heartbeat
from cadcog.core.paramfile import STEP_MAGIC, file_head
from cadcog.core.units import LENGTH_UNIT_MM, density_kg_m3_from_step

#: Instance names that exporters generate rather than users give: OCCT's label entries
#: (``=>[0:1:1:4]``), bare NAUO ids and numbers. Such an instance is named by its product.
#: Files from this size (MB) say what is being read and show a heartbeat while OCCT works
#: (:func:`cadcog.core.heartbeat.heartbeat`): 20 MB take about 10 s to read and transfer.
STEP_HEARTBEAT_MIN_MB = 20.0


@contextmanager
def _phase(large: bool, what: str) -> Iterator[None]:
    if not large:
        yield
        return
    with heartbeat(what):
        yield


def _find(label: TDF_Label, guid: Any, attr: Any) -> bool:
    """``label.FindAttribute`` guarded by ``IsAttribute``: OCP's binding crashes the process
    when ``FindAttribute`` is asked for an attribute the label does not have."""
    return bool(label.IsAttribute(guid)) and bool(label.FindAttribute(guid, attr))


def _label_name(label: TDF_Label) -> str:
    attr = TDataStd_Name()
    if _find(label, TDataStd_Name.GetID_s(), attr):
        return clean_name(TCollection_AsciiString(attr.Get()).ToCString())
    return ""


def _xcaf_material(label: TDF_Label) -> XcafMaterial | None:
    node = TDataStd_TreeNode()
    if not _find(label, XCAFDoc.MaterialRefGUID_s(), node) or not node.HasFather():
        return None
    material = XCAFDoc_Material()
    if not _find(node.Father().Label(), XCAFDoc_Material.GetID_s(), material):
        return None
    name = clean_name(material.GetName().ToCString()) if material.GetName() else ""
    value = float(material.GetDensity())
    unit = material.GetDensName().ToCString() if material.GetDensName() else ""
    density = density_kg_m3_from_step(value, unit)
    return XcafMaterial(name or "unnamed material", density, f"{value:g} {unit}".strip())


def _faces_outside_solids(shape: TopoDS_Shape) -> Iterator[tuple[TopoDS_Shape, bool]]:
    """Shells not inside a solid (with their closedness) and faces not inside a shell."""
    shells = TopExp_Explorer(shape, TopAbs_SHELL, TopAbs_SOLID)
    while shells.More():
        shell = TopoDS.Shell(shells.Current())
        yield shell, bool(BRep_Tool.IsClosed_s(shell))
        shells.Next()
    faces = TopExp_Explorer(shape, TopAbs_FACE, TopAbs_SHELL)
    while faces.More():
        yield faces.Current(), False
        faces.Next()


def _solid_from_closed_shell(shell: TopoDS_Shape) -> TopoDS_Shape | None:
    """A solid bounded by a closed shell, oriented to positive volume; None if it fails."""
    maker = BRepBuilderAPI_MakeSolid(TopoDS.Shell(shell))
    if not maker.IsDone():
        return None
    solid = maker.Solid()
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(solid, props)
    if props.Mass() < 0:
        solid = TopoDS.Solid(solid.Reversed())
    return solid


@dataclass
class _Part:
    """The bodies of one product in its own frame (cached: instances share them)."""

    solids: list[tuple[TopoDS_Shape, bool]]  # (solid, made from a closed shell)
    surface: TopoDS_Shape | None
    materials: list[XcafMaterial | None] = field(default_factory=list)  # per solid
    surface_material: XcafMaterial | None = None


def _solids_of(shape: TopoDS_Shape) -> list[TopoDS_Shape]:
    found = []
    explorer = TopExp_Explorer(shape, TopAbs_SOLID)
    while explorer.More():
        found.append(explorer.Current())
        explorer.Next()
    return found


def _part_materials(ref: TDF_Label, part: _Part) -> None:
    """Each solid's material: on the sub-shape that is (or holds) it, else on the product.

    Exporters attach materials either to the product or to its bodies (sub-shapes: Fusion 360
    writes one per body), so both places are searched, most specific first. A solid with no
    material of its own takes the product's, or else the one material its part's bodies carry
    (OCCT attaches a part-level material to the sub-shape of its first solid).
    """
    own = _xcaf_material(ref)
    subs = Sequence_TDF_Label()
    XCAFDoc_ShapeTool.GetSubShapes_s(ref, subs)
    tagged = []
    for i in range(1, subs.Length() + 1):
        material = _xcaf_material(subs.Value(i))
        if material is not None:
            tagged.append((XCAFDoc_ShapeTool.GetShape_s(subs.Value(i)), material))
    if own is None and len({m for _, m in tagged}) == 1:
        own = tagged[0][1]
    for solid, _ in part.solids:
        found = own
        for sub_shape, material in tagged:
            if sub_shape.IsSame(solid):
                found = material
                break
            if any(s.IsSame(solid) for s in _solids_of(sub_shape)):
                found = material
        part.materials.append(found)
    part.surface_material = own


def _split_part(shape: TopoDS_Shape) -> _Part:
    solids: list[tuple[TopoDS_Shape, bool]] = []
    explorer = TopExp_Explorer(shape, TopAbs_SOLID)
    while explorer.More():
        solids.append((explorer.Current(), False))
        explorer.Next()
    builder = BRep_Builder()
    surface = TopoDS_Compound()
    builder.MakeCompound(surface)
    n_faces = 0
    for sub, closed in _faces_outside_solids(shape):
        solid = _solid_from_closed_shell(sub) if closed else None
        if solid is not None:
            solids.append((solid, True))
        else:
            builder.Add(surface, sub)
            n_faces += 1
    return _Part(solids, surface if n_faces else None)


def _suffix_repeats(names: list[str]) -> list[str]:
    counts: dict[str, int] = {}
    for name in names:
        counts[name] = counts.get(name, 0) + 1
    seen: dict[str, int] = {}
    out = []
    for name in names:
        if counts[name] > 1:
            seen[name] = seen.get(name, 0) + 1
            out.append(f"{name}[{seen[name]}]")
        else:
            out.append(name)
    return out


def _unique_names(raw: list[str]) -> list[str]:
    """Siblings sharing a name get ``[k]`` (1-based, in order); unique names stay as they are.
    A generated name that a sibling already has literally (``COMPOUND`` ×2 beside
    ``COMPOUND[1]``) is suffixed again, until every name is unique.

    Examples
    --------
    >>> _unique_names(["screw", "plate", "screw"])
    ['screw[1]', 'plate', 'screw[2]']
    >>> _unique_names(["COMPOUND", "COMPOUND", "COMPOUND[1]"])
    ['COMPOUND[1][1]', 'COMPOUND[2]', 'COMPOUND[1][2]']
    """
    out = _suffix_repeats(raw)
    while len(set(out)) < len(out):
        out = _suffix_repeats(out)
    return out


class _Said:
    def __init__(self) -> None:
        self.text = ""

    def getvalue(self) -> str:
        return self.text


@contextmanager
def _captured_stdout() -> Iterator[_Said]:
    """Capture what C++ code writes to file descriptor 1 (OCCT prints parse errors there)."""
    said = _Said()
    sys.stdout.flush()
    saved = os.dup(1)
    with tempfile.TemporaryFile(mode="w+b") as sink:
        os.dup2(sink.fileno(), 1)
        try:
            yield said
        finally:
            os.dup2(saved, 1)
            os.close(saved)
            sink.seek(0)
            said.text = sink.read().decode("utf-8", "replace")


def _occt_reason(text: str) -> str:
    """The first error OCCT printed, without its colour codes and stars."""
    for line in text.splitlines():
        line = re.sub(r"\x1b\[[0-9;]*m", "", line).strip(" *")
        if "ERR" in line or "Fail" in line:
            return line.replace("ERR StepFile : ", "").strip()
    return ""


def _unique_paths(bodies: list[StepBody]) -> list[StepBody]:
    """A part's ``#k`` bodies may meet a sibling literally named so (``two#1``): such bodies
    get ``~k`` (in file order) on their own name, so that every path is unique."""
    counts: dict[str, int] = {}
    for b in bodies:
        counts[b.path] = counts.get(b.path, 0) + 1
    if all(c == 1 for c in counts.values()):
        return bodies
    seen: dict[str, int] = {}
    out = []
    for b in bodies:
        if counts[b.path] > 1:
            seen[b.path] = seen.get(b.path, 0) + 1
            last = b.nodes[-1]
            renamed = Node(f"{last.name}~{seen[b.path]}", last.instance, last.product)
            b = replace(b, nodes=(*b.nodes[:-1], renamed))
        out.append(b)
    return _unique_paths(out)


def read_step(path: str | Path) -> StepModel:
    """Read a STEP file's bodies at their global placements, with unique path names.

    Parameters
    ----------
    path : path-like

    Returns
    -------
    StepModel

    Raises
    ------
    CadcogError
        If the file is missing, unreadable as STEP, or holds no solid and no surface.
    """
    p = Path(path)
    if p.is_dir():
        raise CadcogError(f"{p}: is a directory, expected a STEP file")
    if not p.is_file():  # OCCT reads STEP files from disk, not from a pipe
        raise CadcogError(f"{p}: {not_a_regular_file(p)}")
    note_input(p, "the STEP model it reads")
    doc, declared = _transfer(p)
    shape_tool = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    free = Sequence_TDF_Label()
    shape_tool.GetFreeShapes(free)
    tree = _Tree()
    tree.walk([free.Value(i) for i in range(1, free.Length() + 1)], TopLoc_Location(), ())
    bodies = _unique_paths(tree.bodies)
    firsts = {b.nodes[0].name for b in bodies}
    if len(firsts) == 1 and all(len(b.nodes) > 1 for b in bodies):
        root = firsts.pop()
        bodies = [replace(b, root=root) for b in bodies]
    if not bodies:
        raise CadcogError(f"{p}: no solids and no surfaces found")
    return StepModel(
        p, tuple(bodies), declared, len(tree.products), tree.n_instances, tuple(tree.curve_only)
    )


def _not_step(p: Path) -> str | None:
    """Why a file OCCT could not read is no STEP file at all, when its first line says so
    (a STEP file begins ``ISO-10303-21;``), else None."""
    try:
        with open(p, "rb") as fh:
            head = file_head(fh.read(200))
    except OSError:
        return None
    if head.startswith(STEP_MAGIC):
        return None
    first = head.split(b"\n", 1)[0][:60].decode("utf-8", "replace").strip()
    return (
        f"not a STEP file: a STEP file begins 'ISO-10303-21;', this one begins {first!r} (a "
        "parameter file goes to the commands that take one: plan, estimate --setup, check...)"
    )


def _transfer(p: Path) -> tuple[TDocStd_Document, tuple[str, ...]]:
    """Read ``p`` into an XCAF document (names and materials kept), and its declared length
    units; a file OCCT cannot read or transfer is refused, naming it."""
    app = XCAFApp_Application.GetApplication_s()
    doc = TDocStd_Document(TCollection_ExtendedString("XmlXCAF"))
    app.InitDocument(doc)
    reader = STEPCAFControl_Reader()
    reader.SetNameMode(True)
    reader.SetMatMode(True)
    reader.SetColorMode(False)
    reader.SetLayerMode(False)
    size_mb = p.stat().st_size / 1e6
    large = size_mb >= STEP_HEARTBEAT_MIN_MB
    with _captured_stdout() as said, _phase(large, f"reading {p} ({size_mb:.0f} MB)"):
        try:
            status = reader.ReadFile(str(p))
        except Exception as exc:  # OCCT raises plain exceptions on some corrupt files
            raise CadcogError(f"{p}: cannot read as STEP ({exc})") from None
    if status != IFSelect_ReturnStatus.IFSelect_RetDone:
        reason = _occt_reason(said.getvalue()) or f"reader status {status.name}"
        raise CadcogError(f"{p}: {_not_step(p) or f'cannot read as STEP ({reason})'}")
    lengths = Sequence_TCollection_AsciiString()
    reader.ChangeReader().FileUnits(
        lengths, Sequence_TCollection_AsciiString(), Sequence_TCollection_AsciiString()
    )
    declared = tuple(  # INCH, MILLIMETRE (SolidWorks, HFSS) shown as inch, millimetre
        lengths.Value(i).ToCString().lower() for i in range(1, lengths.Length() + 1)
    )
    with _phase(large, f"building the shapes of {p}"):
        isolate_sibling_placements(reader.ChangeReader())  # flat assemblies: linear transfer
        transferred = reader.Transfer(doc)
    if not transferred:
        raise CadcogError(f"{p}: the STEP file holds nothing OCCT can transfer to shapes")
    return doc, declared


def _entry(label: TDF_Label) -> str:
    """A label's XCAF entry (``0:1:1:3``): one per product."""
    text = TCollection_AsciiString()
    TDF_Tool.Entry_s(label, text)
    return str(text.ToCString())


def _referred(label: TDF_Label) -> tuple[TDF_Label, TopLoc_Location | None]:
    """The product an instance refers to and the instance's own placement (None: a product)."""
    if XCAFDoc_ShapeTool.IsReference_s(label):
        ref = TDF_Label()
        XCAFDoc_ShapeTool.GetReferredShape_s(label, ref)
        return ref, XCAFDoc_ShapeTool.GetLocation_s(label)
    return label, None


def _node_names(label: TDF_Label, ref: TDF_Label) -> tuple[str, str]:
    """An instance's own name (empty for a product, or a CAD tool's generated ``=>[0:1:1:2]``)
    and its product's."""
    instance = _label_name(label) if label != ref else ""
    if _GENERATED_NAME.match(instance):
        instance = ""
    return instance, _label_name(ref)


@dataclass
class _Tree:
    """The assembly tree as it is walked: every body at its global placement, each product's
    split into solids and a surface once, the products and instances counted, and the paths of
    the nodes that hold only curves."""

    bodies: list[StepBody] = field(default_factory=list)
    parts: dict[str, _Part] = field(default_factory=dict)
    products: set[str] = field(default_factory=set)
    curve_only: list[str] = field(default_factory=list)
    n_instances: int = 0

    def walk(self, labels: list[TDF_Label], loc: TopLoc_Location, above: tuple[Node, ...]) -> None:
        """The nodes ``labels`` (siblings, named uniquely among themselves) under placement
        ``loc`` and path ``above``, and everything below them."""
        resolved = []
        for label in labels:
            ref, own = _referred(label)
            resolved.append((ref, own, *_node_names(label, ref)))
        display = [r[2] or r[3] or "unnamed" for r in resolved]
        for (ref, own, instance, product), name in zip(
            resolved, _unique_names(display), strict=True
        ):
            self.n_instances += 1
            key = _entry(ref)
            self.products.add(key)
            here_loc = loc if own is None else loc.Multiplied(own)
            here = (*above, Node(name, instance, product))
            if XCAFDoc_ShapeTool.IsAssembly_s(ref):
                comps = Sequence_TDF_Label()
                XCAFDoc_ShapeTool.GetComponents_s(ref, comps, False)
                self.walk([comps.Value(i) for i in range(1, comps.Length() + 1)], here_loc, here)
                continue
            self._add_part(ref, key, here, here_loc)

    def _add_part(
        self, ref: TDF_Label, key: str, here: tuple[Node, ...], here_loc: TopLoc_Location
    ) -> None:
        """A leaf's bodies: each solid, then its surface body, at the global placement
        (``#k``, ``#surface`` after the name when the product has several)."""
        part = self.parts.get(key)
        if part is None:
            part = self.parts[key] = _split_part(XCAFDoc_ShapeTool.GetShape_s(ref))
            _part_materials(ref, part)
        several = len(part.solids) + (part.surface is not None) > 1

        def nodes(suffix: str) -> tuple[Node, ...]:
            if not several:
                return here
            last = here[-1]
            return (*here[:-1], Node(f"{last.name}#{suffix}", last.instance, last.product))

        for k, (solid, from_shell) in enumerate(part.solids, start=1):
            self.bodies.append(
                StepBody(
                    nodes(str(k)),
                    "solid",
                    solid.Moved(here_loc),
                    solid,
                    here_loc,
                    f"{key}#{k}",
                    part.materials[k - 1],
                    from_shell,
                )
            )
        if part.surface is not None:
            self.bodies.append(
                StepBody(
                    nodes("surface"),
                    "surface",
                    part.surface.Moved(here_loc),
                    part.surface,
                    here_loc,
                    f"{key}#surface",
                    part.surface_material,
                )
            )
        if not part.solids and part.surface is None:
            self.curve_only.append("/".join(n.name for n in here))


def length_unit_mm(name: str) -> float | None:
    """Length of a declared STEP unit in mm, or None if unknown.

    Examples
    --------
    >>> length_unit_mm("metre"), length_unit_mm("inch"), length_unit_mm("parsec")
    (1000.0, 25.4, None)
    """
    return LENGTH_UNIT_MM.get(name.strip().lower())
