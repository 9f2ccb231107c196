"""Draft a set-up file and a materials file from one's own STEP model (``cadcog setup init``).

A new user has a STEP file, not a set-up file. :func:`draft_setup` writes the two TOML texts a
first ``cadcog plan`` needs, from the model's bounding box and its parts:

- the **materials file** lists every part (bodies grouped by their name without instance
  suffixes ``[k]`` and ``#k``), heaviest volume first, each as a commented rule to fill in,
  with the STEP material the exporter stamped on it when there is one; one active default rule
  (``"*" = "aluminium 6061-T6"``) lets the draft run at once, and says to replace it. A 5 % mass
  uncertainty per body and a growth-allowance table by maturity (the levels are an example of
  AIAA S-120A's kind: enter your programme's) come commented out;
- the **set-up file** names the model and the materials, guesses the CubeSat form factor from
  the bounding box (each extent within :data:`FORM_FACTOR_TOLERANCE` of the CDS envelope, the
  long axis along z; else left commented), puts the measurement equipment's base at the centre
  of the +z face, and asks for a grid of candidate points on the four side faces, at a spacing
  of 60 % of the smaller side face's width.

Nothing here reads CAD: the caller gives the bounding box and the parts.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from cadcog.rig.geometry import FACES

FloatArray = npt.NDArray[np.float64]

#: CDS outer envelopes (mm, sorted ascending) by form factor, for the guess.
CDS_ENVELOPES_MM: dict[str, tuple[float, float, float]] = {
    "1U": (100.0, 100.0, 113.5),
    "1.5U": (100.0, 100.0, 170.2),
    "2U": (100.0, 100.0, 227.0),
    "3U": (100.0, 100.0, 340.5),
    "6U": (100.0, 226.3, 366.0),
    "12U": (226.3, 226.3, 366.0),
}

#: Relative difference of each bounding-box extent from a CDS envelope within which the form
#: factor is guessed (deployables and rails make real models a little larger).
FORM_FACTOR_TOLERANCE = 0.08

#: Candidate grid spacing as a fraction of the smaller side face's width, and its margin.
GRID_SPACING_FRACTION = 0.6
GRID_MARGIN_FRACTION = 0.15

#: A box extent under this fraction of the next one is a thin body's (a board, a panel): the
#: grid is sized by the next extent, not by the thickness (a 1.6 mm solar panel drafted 272
#: points 5 mm apart; its thin edges get one row each, :data:`THIN_ROWS`).
THIN_EXTENT_FRACTION = 0.2

_SUFFIX = re.compile(r"(\[\d+\]|#\d+)+$")
_NOT_ID = re.compile(r"[^A-Za-z0-9_-]+")


@dataclass(frozen=True)
class DraftPart:
    """A body of the model as the draft needs it.

    Attributes
    ----------
    path : str
        The body's unique path (``sat/board/C12[3]#2``).
    volume_mm3 : float
    step_material : str or None
        The name of the material the STEP file carries for it, if any.
    step_density_kg_m3 : float or None
        That material's density, when the file gives a usable one.
    placeholder : bool
        The material is an exporter's placeholder (Inventor's "Generic" ...), not the part's.
    label : str
        The part's name for the materials file (:func:`part_label`), '' for its path's.
    """

    path: str
    volume_mm3: float
    step_material: str | None = None
    step_density_kg_m3: float | None = None
    placeholder: bool = False
    label: str = ""

    @property
    def name(self) -> str:
        """The part it belongs to in the materials file: :attr:`label`, else
        :func:`part_name` of its path."""
        return self.label or part_name(self.path)

    @property
    def has_material(self) -> bool:
        """Whether the STEP gives it a material of its own (a density, not a placeholder)."""
        return self.step_density_kg_m3 is not None and not self.placeholder


def part_name(path: str) -> str:
    """The name a materials rule would match: the last path element without ``[k]``/``#k``.

    Examples
    --------
    >>> part_name("sat/board/COMPOUND[12]#2"), part_name("rail_3")
    ('COMPOUND', 'rail_3')
    """
    return _SUFFIX.sub("", path.rsplit("/", 1)[-1]) or path


#: Product names exporters give a body that says nothing of the part (KiCad's "COMPOUND" and
#: "SOLID" below every component, Open CASCADE's root), compared in lower case.
GENERIC_PRODUCT_NAMES = frozenset({"compound", "solid", "body", "part", "shape", "shell", "mesh"})


def part_label(products: Sequence[str], path: str) -> str:
    """The name of the part a body belongs to, as the materials file lists it: the product of
    its own node, or of the nearest node above it whose product is not generic, below the top
    assembly; copies share it whatever the tool named the instances (Inventor ``part:2``,
    SolidWorks ``part-2``, KiCad reference designators). Without one, :func:`part_name`.

    Examples
    --------
    >>> part_label(["Open CASCADE STEP translator 6.9 1", "C_0603_1608Metric", "COMPOUND"], "x")
    'C_0603_1608Metric'
    >>> part_label(["Batery Pack v3 v5", "A123 battery v4"], "Batery Pack v3 v5/A123 battery v4:2")
    'A123 battery v4'
    >>> part_label(["top", "COMPOUND"], "top/COMPOUND#3")
    'COMPOUND'
    """
    for product in reversed(products[1:] if len(products) > 1 else products):
        name = product.strip()
        if name and name.lower() not in GENERIC_PRODUCT_NAMES:
            return name
    return part_name(path)


def guess_form_factor(bbox_lo_mm: npt.ArrayLike, bbox_hi_mm: npt.ArrayLike) -> str | None:
    """The CubeSat form factor whose envelope the bounding box matches, with z the long axis.

    Examples
    --------
    >>> guess_form_factor([-50, -50, -170.25], [50, 50, 170.25])
    '3U'
    >>> guess_form_factor([-170, -50, -50], [170, 50, 50]) is None  # long axis along x
    True
    """
    ext = np.asarray(bbox_hi_mm, dtype=float) - np.asarray(bbox_lo_mm, dtype=float)
    if ext[2] < max(ext[0], ext[1]) * (1 - FORM_FACTOR_TOLERANCE):
        return None
    srt = np.sort(ext)
    for name, env in CDS_ENVELOPES_MM.items():
        if np.all(np.abs(srt - env) <= FORM_FACTOR_TOLERANCE * np.asarray(env)):
            return name
    return None


def form_factor_mismatch(form_factor: str | None, extent_mm: npt.ArrayLike) -> str | None:
    """A note when a box (extents in the envelope's axes) is not that CubeSat form factor's
    (:func:`guess_form_factor`), else None (and None for a PocketQube or no form factor).

    Examples
    --------
    >>> form_factor_mismatch("3U", [100, 100, 340.5]) is None
    True
    >>> form_factor_mismatch("3U", [120, 120, 120]).split(":")[0]
    'form factor 3U'
    """
    if form_factor not in CDS_ENVELOPES_MM:
        return None
    ext = np.asarray(extent_mm, dtype=float)
    if guess_form_factor(np.zeros(3), ext) == form_factor:
        return None
    shown = " × ".join(f"{v:.4g}" for v in ext)
    env = " × ".join(f"{v:g}" for v in CDS_ENVELOPES_MM[form_factor])
    return (
        f"form factor {form_factor}: the model's box ({shown} mm in the envelope's axes) is not "
        f"a {form_factor}'s ({env} mm within 8 %, z the long axis): the envelope check assumes "
        "it is one"
    )


def _toml_str(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _fmt(v: float) -> str:
    return f"{round(float(v), 3) + 0.0:g}"


def _stamp(p: DraftPart) -> str:
    d = f", {p.step_density_kg_m3:g} kg/m³" if p.step_density_kg_m3 is not None else ""
    return f"{p.step_material!r}{d}"


def stamped_default(parts: Sequence[DraftPart]) -> bool:
    """Every solid carries one and the same STEP material: an exporter's default, which a
    catch-all rule replaces (as :func:`cadcog.cad.massrules.assign_densities` does)."""
    stamps = {(p.step_material, p.step_density_kg_m3) for p in parts}
    return len(parts) >= 2 and len(stamps) == 1 and all(p.has_material for p in parts)


def lacking_material(parts: Sequence[DraftPart]) -> int:
    """Solids the STEP gives no material of their own (none, a placeholder, a default)."""
    if stamped_default(parts):
        return len(parts)
    return sum(1 for p in parts if not p.has_material)


def draft_materials(parts: Sequence[DraftPart], source: str) -> str:
    """The materials file's text: one commented rule per part, heaviest volume first."""
    groups: dict[str, list[DraftPart]] = {}
    for p in parts:
        groups.setdefault(p.name, []).append(p)
    total = sum(p.volume_mm3 for p in parts) or 1.0
    ranked = sorted(groups.items(), key=lambda kv: -sum(p.volume_mm3 for p in kv[1]))
    width = max((len(_toml_str(k)) for k in groups), default=8) + 2
    lines = [
        f"# Materials of {source}, drafted by `cadcog setup init`: fill in each part's material",
        "# (a library name, see `cadcog massprops --help`, or a density in kg/m³) and remove the",
        "# '#'. The first matching rule wins; a rule matches a body's own name, any assembly's",
        "# above it, or its path (docs/spacecraft.md, 'Materials file'). A material the STEP",
        '# carries is used unless a named rule overrides it; "*" only fills what it leaves open.',
        "",
        "[materials]",
    ]
    default = stamped_default(parts)
    for name, group in ranked:
        vol = sum(p.volume_mm3 for p in group)
        size = (
            f"{len(group)} bod{'y' if len(group) == 1 else 'ies'}, {vol:,.0f} mm³ "
            f"({vol / total:.1%} of the volume)"
        )
        own = sorted({_stamp(p) for p in group if p.has_material})
        stubs = sorted({_stamp(p) for p in group if p.step_material and not p.has_material})
        if default:
            note = f'; the STEP\'s {own[0]} (on every solid) is replaced by the "*" rule'
        elif own and len(own) == 1 and all(p.has_material for p in group):
            note = f"; the STEP's {own[0]} is used (a rule here overrides it)"
        elif stubs:
            note = f"; the STEP gives only the placeholder {', '.join(stubs)}: give its material"
        else:
            note = "; the STEP gives no material" + (f" to some ({', '.join(own)})" if own else "")
        rule = f"# {_toml_str(name):<{width}}= ?"
        lines.append(f"{rule:<{width + 6}}  # {size}{note}")
    stamped = {_stamp(p) for p in parts}
    lacking = lacking_material(parts)
    if default:
        lines.append(
            f"# every solid carries the same STEP material, {next(iter(stamped))}: an exporter's "
            "default (Fusion 360\n# writes 'Steel' on boards and plastics alike), which the "
            '"*" rule below replaces: name each part\'s material above'
        )
    lines += [
        '"*" = "aluminium 6061-T6"   # the default for what the STEP leaves open '
        f"({lacking} of {len(parts)} solids):",
        "                            # replace it, or delete it to be told which solids lack one",
        "",
        "[mass_uncertainty]          # 1-σ relative mass uncertainty per item: 5 % is a guess",
        '"*" = 0.05                  # so that `cadcog update` can weigh the parts: enter yours',
        "",
        "# [maturity_levels]         # your programme's growth allowances (AIAA S-120A's kind;",
        "# new = 0.20                # these figures are an example, not the standard's)",
        "# modified = 0.10",
        "# flight-proven = 0.05",
        "",
        "# [growth_allowance]        # a fraction or a maturity level per item",
        '# "*" = "new"',
        "",
    ]
    return "\n".join(lines)


#: The faces the draft puts candidate points on (the ME sits on +z).
DRAFT_FACES = ("+x", "-x", "+y", "-y")


@dataclass(frozen=True)
class DraftPoint:
    """A candidate point the draft lists: on the model, with its face (bolt axis)."""

    id: str
    face: str
    position_mm: tuple[float, float, float]
    depth_mm: float


def grid_spacing(bbox_lo_mm: npt.ArrayLike, bbox_hi_mm: npt.ArrayLike) -> tuple[float, float]:
    """The draft's grid spacing and margin (mm): 60 % and 15 % of the box's smallest extent,
    or of the next one when the smallest is a thin body's (:data:`THIN_EXTENT_FRACTION`).

    Examples
    --------
    >>> grid_spacing([-50, -50, -170], [50, 50, 170])
    (60.0, 15.0)
    >>> grid_spacing([0, 0, 0], [98, 82.6, 1.6])  # a 1U solar panel: by its width, not 1.6 mm
    (50.0, 12.0)
    """
    ext = np.sort(np.asarray(bbox_hi_mm, dtype=float) - np.asarray(bbox_lo_mm, dtype=float))
    side = float(ext[1] if ext[0] < THIN_EXTENT_FRACTION * ext[1] else ext[0])
    spacing = max(5.0, round(GRID_SPACING_FRACTION * side / 5.0) * 5.0)
    margin = max(2.0, float(round(GRID_MARGIN_FRACTION * side)))
    return spacing, margin


#: An extent the grid crosses in this many rows or fewer is thin (a board with its parts, whose
#: middle may fall between the board and a part): each row is cast at several heights within
#: its band, at these fractions of it, and the ray that meets a solid nearest the box face is
#: kept (the board's edge, not a part behind it).
THIN_ROWS = 1
THIN_ROW_FRACTIONS = (0.5, 0.3, 0.7, 0.1, 0.9)


def face_grid(
    face: str, bbox_lo_mm: npt.ArrayLike, bbox_hi_mm: npt.ArrayLike, refine: int = 0
) -> FloatArray:
    """The draft's grid of one box face, shape (m, k, 3): centred, at :func:`grid_spacing`
    halved ``refine`` times (its margin too), each point with ``k`` alternatives across a thin
    extent (:data:`THIN_ROWS`; at :data:`THIN_ROW_FRACTIONS` of its row's band, the middle
    first; ``k`` = 1 when none is).

    Examples
    --------
    >>> face_grid("+x", [-50, -50, -170], [50, 50, 170])[:2, 0].tolist()
    [[50.0, -30.0, -150.0], [50.0, -30.0, -90.0]]
    >>> g = face_grid("+x", [-50, -40, -5], [50, 40, 1.6])  # a board, a part below it
    >>> g.shape, g[0, :, 2].round(2).tolist()  # one row in z: its heights, the middle first
    ((2, 5, 3), [-1.7, -3.02, -0.38, -4.34, 0.94])
    >>> face_grid("+x", [-50, -50, -170], [50, 50, 170], refine=1).shape  # 30 mm apart
    (33, 1, 3)
    """
    lo = np.asarray(bbox_lo_mm, dtype=float)
    hi = np.asarray(bbox_hi_mm, dtype=float)
    spacing, margin = (v / 2**refine for v in grid_spacing(lo, hi))
    axis, sign = FACES[face]
    others = [j for j in range(3) if j != axis]
    lines: list[list[FloatArray]] = []  # per in-face axis: its grid lines, each as alternatives
    for j in others:
        n = max(int((hi[j] - lo[j] - 2 * margin) // spacing) + 1, 1)
        if n <= THIN_ROWS:  # few rows across: each tried at several heights within its band
            band = (hi[j] - lo[j]) / n
            fractions = np.asarray(THIN_ROW_FRACTIONS)
            lines.append([lo[j] + band * (k + fractions) for k in range(n)])
        else:
            centres = 0.5 * (lo[j] + hi[j]) + spacing * (np.arange(n) - (n - 1) / 2)
            lines.append([np.array([c]) for c in centres])
    points = []
    for alts_a in lines[0]:
        for alts_b in lines[1]:
            a, b = np.meshgrid(alts_a, alts_b, indexing="ij")
            p = np.empty((a.size, 3))
            p[:, axis] = hi[axis] if sign > 0 else lo[axis]
            p[:, others[0]], p[:, others[1]] = a.ravel(), b.ravel()
            points.append(p)
    return np.asarray(points)


#: Two drafted points closer than this (mm) are one: the rays of two faces meeting at an edge.
DRAFT_MIN_SEPARATION_MM = 1.0

#: A draft wants at least this many points on the model: with fewer (a thin part, a bent pipe,
#: a frame whose grid rays pass between its members) the grid is halved, up to
#: :data:`DRAFT_MAX_REFINE` times, and at most :data:`DRAFT_MAX_POINTS` of the points the finer
#: grid finds are kept, spread over the model (each the farthest from those kept before it).
DRAFT_MIN_POINTS = 6
DRAFT_MAX_REFINE = 4
DRAFT_MAX_POINTS = 24


def distinct_points(
    found: Sequence[tuple[str, npt.ArrayLike, float]], keep: int | None = None
) -> list[DraftPoint]:
    """Drafted points from (face, position_mm, depth_mm) in order, without one closer than
    :data:`DRAFT_MIN_SEPARATION_MM` to an earlier one, at most ``keep`` of them spread over
    the model (:func:`spread`), labelled per face from 1.

    Examples
    --------
    >>> [p.id for p in distinct_points([("+x", [1, 0, 0], 0), ("+x", [1, 5, 0], 0),
    ...                                 ("+y", [1, 5.2, 0], 2), ("+y", [0, 9, 0], 1)])]
    ['+x1', '+x2', '+y1']
    >>> [p.position_mm for p in distinct_points([("+x", [0, 0, 0], 0), ("+x", [0, 1, 0], 0),
    ...                                          ("+x", [0, 9, 0], 0)], keep=2)]
    [(0.0, 0.0, 0.0), (0.0, 9.0, 0.0)]
    """
    apart: list[tuple[str, FloatArray, float]] = []
    for face, pos, depth in found:
        p = np.asarray(pos, dtype=float)
        if any(np.linalg.norm(p - q) < DRAFT_MIN_SEPARATION_MM for _, q, _ in apart):
            continue
        apart.append((face, p, float(depth)))
    if keep is not None and len(apart) > keep:
        chosen = spread(np.array([q for _, q, _ in apart]), keep)
        apart = [apart[i] for i in chosen]
    kept: list[DraftPoint] = []
    count: dict[str, int] = {}
    for face, p, depth in apart:
        count[face] = count.get(face, 0) + 1
        xyz = (float(p[0]), float(p[1]), float(p[2]))
        kept.append(DraftPoint(point_label(face, count[face]), face, xyz, depth))
    return kept


def spread(points_mm: npt.ArrayLike, n: int) -> list[int]:
    """Indices of ``n`` of the points spread over them, in their order: the first point, then
    each time the point farthest from those chosen (the first of equals).

    Examples
    --------
    >>> spread([[0, 0, 0], [1, 0, 0], [10, 0, 0], [5, 0, 0]], 3)
    [0, 2, 3]
    """
    pts = np.asarray(points_mm, dtype=float)
    if n >= len(pts):
        return list(range(len(pts)))
    chosen = [0]
    dist = np.linalg.norm(pts - pts[0], axis=1)
    while len(chosen) < n:
        i = int(np.argmax(dist))
        chosen.append(i)
        dist = np.minimum(dist, np.linalg.norm(pts - pts[i], axis=1))
    return sorted(chosen)


def point_label(face: str, k: int) -> str:
    """A candidate's id, short enough to write on tape: the face and a number from 1.

    Examples
    --------
    >>> point_label("+x", 1), point_label("-y", 12)
    ('+x1', '-y12')
    """
    return f"{face}{k}"


def draft_setup(
    name: str,
    model_step: str,
    materials: str,
    bbox_lo_mm: npt.ArrayLike,
    bbox_hi_mm: npt.ArrayLike,
    overlaps: str = "",
    points: Sequence[DraftPoint] = (),
    units: str | None = None,
    refine: int = 0,
    *,
    me_base_mm: Sequence[float] | None = None,
) -> str:
    """The set-up file's text for a model with this bounding box (paths relative to it).

    ``me_base_mm``: where the ME's base sits on the model (the survey's top surface under the
    +z face's centre, or the highest near it); None: the +z face's centre, with a comment
    asking to move it onto the model.

    ``overlaps``: the overlap summary when the model's solids overlap above the refusal
    threshold; the draft then resolves them (``overlaps = "resolve"``), saying why. ``points``:
    candidate points on the model (:func:`cadcog.cad.surfacepoints.project_grid`); without two
    of them the draft asks for the grid on the bounding box's faces instead. ``units``: the
    file's true length unit when the draft was read with one (positions are in its mm).
    ``refine``: how many times the points' grid was halved (:data:`DRAFT_MIN_POINTS`).
    """
    lo = np.asarray(bbox_lo_mm, dtype=float)
    hi = np.asarray(bbox_hi_mm, dtype=float)
    ext = hi - lo
    centre = 0.5 * (lo + hi)
    ident = _NOT_ID.sub("_", name).strip("_-") or "spacecraft"
    if not ident[0].isalpha():
        ident = "sc_" + ident
    form = guess_form_factor(lo, hi)
    spacing, margin = grid_spacing(lo, hi)
    form_line = (
        f'form_factor = "{form}"              # guessed from the bounding box: check it'
        if form
        else "# no form_factor: the bounding box "
        f"({' × '.join(_fmt(v) for v in ext)} mm) matches no CubeSat envelope (1U ... 12U, "
        "z the long axis); give cog_limits_mm = [X, Y, Z] for an envelope of your own"
    )
    if me_base_mm is None:
        base = [_fmt(centre[0]), _fmt(centre[1]), _fmt(hi[2])]
        where = "the centre of the +z face of the box (no ray down met the model: move it onto it)"
    else:
        base = [_fmt(v) for v in me_base_mm]
        on_axis = np.allclose(np.asarray(me_base_mm)[:2], centre[:2], atol=1e-6)
        where = (
            "the model's top surface under the centre of its +z face"
            if on_axis
            else "the model's highest surface near the centre of its +z face"
        )
    return "\n".join(
        [
            f"# Test set-up of {model_step}, drafted by `cadcog setup init`: check every line,",
            "# then `cadcog plan` on it. Paths are relative to this file (docs/spacecraft.md).",
            "",
            f'name = "{ident[:64]}"',
            f"model_step = {_toml_str(model_step)}",
            f"materials = {_toml_str(materials)}",
            *(
                [f"units = {_toml_str(units)}               # the file's true unit"]
                if units
                else []
            ),
            form_line,
            *(
                [
                    'overlaps = "resolve"            # the denser solid of each pair keeps the '
                    "common volume;",
                    f"# the draft found {overlaps} (or fix the model, or exclude = [...])",
                ]
                if overlaps
                else []
            ),
            "",
            "[measurement_equipment]",
            '# rig = "my_rig.toml"          # your rig file (its ME); without it, the paper\'s rig',
            f"base_center_mm = [{', '.join(base)}]   # where the ME base sits: here {where}",
            "",
            *(
                _points_text(points, spacing / 2**refine)
                if len(points) >= 2
                else _grid_text(ext, spacing, margin)
            ),
        ]
    )


def _grid_text(ext: FloatArray, spacing: float, margin: float) -> list[str]:
    return [
        "# Candidate suspension points: a grid on faces of the bounding box "
        f"({' × '.join(_fmt(v) for v in ext)} mm);",
        "# `cadcog plan` checks each and recommends a set; add your own points with",
        "# [[candidates.points]] (id, position_mm).",
        "[candidates]",
        f"faces = [{', '.join(_toml_str(f) for f in DRAFT_FACES)}]",
        f"spacing_mm = {_fmt(spacing)}",
        f"margin_mm = {_fmt(margin)}",
        "",
    ]


def _points_text(points: Sequence[DraftPoint], spacing: float) -> list[str]:
    lines = [
        f"# Candidate suspension points on the model: a {_fmt(spacing)} mm grid on the side faces",
        "# of its bounding box, each moved along the face's inward normal to the first solid it",
        "# meets (the wire leaves along that normal, the face's bolt axis). Ids are short, to",
        "# write on tape; `cadcog plan` checks each and recommends a set. Add or remove freely.",
        "[candidates]",
    ]
    for p in points:
        pos = ", ".join(_fmt(v) for v in p.position_mm)
        lines += [
            "",
            "[[candidates.points]]",
            f'id = "{p.id}"',
            f'face = "{p.face}"',
            f"position_mm = [{pos}]"
            + (f"   # {_fmt(p.depth_mm)} mm inside the box face" if p.depth_mm > 0.0005 else ""),
        ]
    return [*lines, ""]
