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
        The material the STEP file carries for it (name and density), if any.
    """

    path: str
    volume_mm3: float
    step_material: str | None = None


def part_name(path: str) -> str:
    """The name a materials rule would match: the last path element without ``[k]``/``#k``.

    Examples
    --------
    >>> part_name("sat/board/COMPOUND[12]#2"), part_name("rail_3")
    ('COMPOUND', 'rail_3')
    """
    return _SUFFIX.sub("", path.rsplit("/", 1)[-1]) or path


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


def _toml_str(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _fmt(v: float) -> str:
    return f"{round(float(v), 3) + 0.0:g}"


def draft_materials(parts: Sequence[DraftPart], source: str) -> str:
    """The materials file's text: one commented rule per part, heaviest volume first."""
    groups: dict[str, list[DraftPart]] = {}
    for p in parts:
        groups.setdefault(part_name(p.path), []).append(p)
    total = sum(p.volume_mm3 for p in parts) or 1.0
    ranked = sorted(groups.items(), key=lambda kv: -sum(p.volume_mm3 for p in kv[1]))
    width = max((len(_toml_str(k)) for k in groups), default=8) + 2
    lines = [
        f"# Materials of {source}, drafted by `cadcog setup init`: fill in each part's material",
        "# (a library name, see `cadcog massprops --help`, or a density in kg/m³) and remove the",
        "# '#'. The first matching rule wins; a rule matches a body's own name, any assembly's",
        "# above it, or its path (docs/spacecraft.md, 'Materials file').",
        "",
        "[materials]",
    ]
    for name, group in ranked:
        vol = sum(p.volume_mm3 for p in group)
        stamped = sorted({p.step_material for p in group if p.step_material})
        note = f"; STEP material {', '.join(stamped)}" if stamped else ""
        rule = f"# {_toml_str(name):<{width}}= ?"
        lines.append(
            f"{rule:<{width + 6}}  # {len(group)} bod{'y' if len(group) == 1 else 'ies'}, "
            f"{vol:,.0f} mm³ ({vol / total:.1%} of the volume){note}"
        )
    lines += [
        '"*" = "aluminium 6061-T6"   # a default so that the draft runs: replace it, or delete',
        "                            # it to be told which solids still lack a material",
        "",
        "# [mass_uncertainty]        # 1-σ relative mass uncertainty per item",
        '# "*" = 0.05',
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


def draft_setup(
    name: str,
    model_step: str,
    materials: str,
    bbox_lo_mm: npt.ArrayLike,
    bbox_hi_mm: npt.ArrayLike,
    overlaps: str = "",
) -> str:
    """The set-up file's text for a model with this bounding box (paths relative to it).

    ``overlaps``: the overlap summary when the model's solids overlap above the refusal
    threshold; the draft then resolves them (``overlaps = "resolve"``), saying why.
    """
    lo = np.asarray(bbox_lo_mm, dtype=float)
    hi = np.asarray(bbox_hi_mm, dtype=float)
    ext = hi - lo
    centre = 0.5 * (lo + hi)
    ident = _NOT_ID.sub("_", name).strip("_-") or "spacecraft"
    if not ident[0].isalpha():
        ident = "sc_" + ident
    form = guess_form_factor(lo, hi)
    side = float(min(ext[0], ext[1], ext[2]))
    spacing = max(5.0, round(GRID_SPACING_FRACTION * side / 5.0) * 5.0)
    margin = max(2.0, round(GRID_MARGIN_FRACTION * side))
    form_line = (
        f'form_factor = "{form}"              # guessed from the bounding box: check it'
        if form
        else '# form_factor = "3U"            # no CubeSat envelope matched the bounding box '
        f"({' × '.join(_fmt(v) for v in ext)} mm)"
    )
    base = [_fmt(centre[0]), _fmt(centre[1]), _fmt(hi[2])]
    return "\n".join(
        [
            f"# Test set-up of {model_step}, drafted by `cadcog setup init`: check every line,",
            "# then `cadcog plan` on it. Paths are relative to this file (docs/spacecraft.md).",
            "",
            f'name = "{ident[:64]}"',
            f"model_step = {_toml_str(model_step)}",
            f"materials = {_toml_str(materials)}",
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
            f"base_center_mm = [{', '.join(base)}]   # where the ME base sits: here the centre "
            "of the +z face",
            "",
            "# Candidate suspension points: a grid on faces of the bounding box "
            f"({' × '.join(_fmt(v) for v in ext)} mm);",
            "# `cadcog plan` checks each and recommends a set; add your own points with",
            "# [[candidates.points]] (id, position_mm).",
            "[candidates]",
            'faces = ["+x", "-x", "+y", "-y"]',
            f"spacing_mm = {_fmt(spacing)}",
            f"margin_mm = {_fmt(margin)}",
            "",
        ]
    )
