"""Draft a set-up file and a materials file from one's STEP model: ``cadcog setup init`` and
:func:`cadcog.setup_init`.

Reads the model once (geometry at one density; each solid counted whole), lists its parts with
the materials the STEP carries (:func:`cadcog.spacecraft.setup_draft.draft_materials`), casts
the candidate grid onto the model (:func:`cadcog.cad.surfacepoints.project_grid`), and writes
both files together: a failure while writing leaves neither (the materials file is put in place
first, then the set-up that names it), and neither replaces a file unless ``force``.
"""

from __future__ import annotations

import dataclasses
import os
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from cadcog.core import tolerances
from cadcog.core.errors import CadcogError
from cadcog.core.fileio import note_input, staged_file
from cadcog.core.results import JsonResult


@dataclass(frozen=True, repr=False)  # JsonResult's one-line repr
class SetupDraft(JsonResult):
    """What ``setup init`` wrote.

    Attributes
    ----------
    setup : str
        The set-up file.
    materials : str
        The materials file.
    n_solids : int
        Solids of the model.
    n_parts : int
        Parts the materials file lists.
    n_points : int
        Candidate points on the model (0: the draft asks for the grid on the box instead).
    n_lacking_material : int
        Solids the STEP gives no material of their own (none, or a placeholder).
    form_factor : str or None
        The CubeSat form factor guessed from the bounding box.
    resolves_overlaps : bool
        The draft resolves overlapping solids (``overlaps = "resolve"``): ``massprops`` needs
        ``--resolve-overlaps`` to count the model the same way.
    """

    setup: str
    materials: str
    n_solids: int
    n_parts: int
    n_points: int
    n_lacking_material: int
    form_factor: str | None
    resolves_overlaps: bool = False

    def to_dict(self) -> dict[str, Any]:
        return dict(self.__dict__)


def draft_paths(model: Path, out: Path | None) -> tuple[Path, Path, str]:
    """The set-up file, the materials file beside it, and the set-up's name.

    Examples
    --------
    >>> [str(p) for p in draft_paths(Path("cad/sat.step"), None)[:2]]
    ['cad/sat_setup.toml', 'cad/sat_materials.toml']
    """
    setup = Path(out) if out is not None else model.with_name(f"{model.stem}_setup.toml")
    if setup.suffix.lower() != ".toml":
        raise CadcogError(f"--out {setup}: expected a file name ending in .toml")
    stem = setup.name[: -len("_setup.toml")] if setup.name.endswith("_setup.toml") else setup.stem
    return setup, setup.with_name(f"{stem}_materials.toml"), stem


def run_setup_init(
    model: Path, *, out: Path | None = None, units: str | None = None, force: bool = False
) -> SetupDraft:
    """Draft ``out`` (default ``MODEL_setup.toml`` beside the model) and its materials file.

    Raises
    ------
    CadcogError
        A file exists (without ``force``), the model cannot be read, an output cannot be
        written (then neither is).
    """
    from cadcog.cad import cache
    from cadcog.spacecraft.setup_draft import (
        DraftPart,
        DraftPoint,
        draft_materials,
        draft_setup,
        guess_form_factor,
        lacking_material,
    )

    setup_path, materials_path, stem = draft_paths(Path(model), out)
    for path in (setup_path, materials_path):
        if path.exists() and not force:
            raise CadcogError(
                f"{path}: exists; --force (force=True from Python) replaces it (a draft never "
                "overwrites)"
            )
    survey, hit = cache.cached_data(
        {"kind": "setup init", "units": units},
        [Path(model)],
        lambda: _survey(Path(model), units),
        code=("cad", "mass", "core", "rig", "spacecraft", "runs"),
    )
    if hit:  # read from the cache: the model is still this command's input
        note_input(Path(model), "the STEP model it reads")
    try:
        parts = [DraftPart(**p) for p in survey["parts"]]
        points = [
            DraftPoint(p["id"], p["face"], tuple(p["position_mm"]), p["depth_mm"])
            for p in survey["points"]
        ]
        lo, hi = np.array(survey["lo_mm"]), np.array(survey["hi_mm"])
        overlaps = str(survey["overlaps"])
        refine = int(survey["refine"])
        base = survey["me_base_mm"]
        base_mm = None if base is None else tuple(float(v) for v in base)
    except (KeyError, TypeError, ValueError):  # a damaged entry that passed its digest
        raise CadcogError(
            f"{model}: the cached survey cannot be read; cadcog cache --clear"
        ) from None
    step_rel = Path(os.path.relpath(Path(model).resolve(), setup_path.resolve().parent))
    materials_text = draft_materials(parts, Path(model).name)
    setup_text = draft_setup(
        stem,
        step_rel.as_posix(),
        materials_path.name,
        lo,
        hi,
        overlaps,
        points,
        units,
        refine,
        me_base_mm=base_mm,
    )
    # Both filled before either is put in place; renamed last entered first: the materials
    # file, then the set-up that names it.
    with ExitStack() as stack:
        stack.enter_context(staged_file(setup_path)).write_text(setup_text, encoding="utf-8")
        stack.enter_context(staged_file(materials_path)).write_text(
            materials_text, encoding="utf-8"
        )
    return SetupDraft(
        str(setup_path),
        str(materials_path),
        len(parts),
        len({p.name for p in parts}),
        len(points) if len(points) >= 2 else 0,
        lacking_material(parts),
        guess_form_factor(lo, hi),
        bool(overlaps),
    )


def _survey(model: Path, units: str | None) -> dict[str, Any]:
    """What a draft needs of the model, as JSON data (cached by the model's content): every
    solid with its STEP material and part label, the candidate points cast onto the model,
    the box, and the overlaps summary when they would be refused."""
    from cadcog.cad.stepmass import model_mass_properties
    from cadcog.cad.stepread import read_step
    from cadcog.cad.surfacepoints import project_grid, top_surface_point
    from cadcog.mass.materials import DENSITY_RANGE_KG_M3, MaterialMap, is_placeholder_material
    from cadcog.spacecraft.setup_draft import (
        DRAFT_FACES,
        DRAFT_MAX_POINTS,
        DRAFT_MAX_REFINE,
        DRAFT_MIN_POINTS,
        DraftPart,
        DraftPoint,
        distinct_points,
        face_grid,
        part_label,
    )

    step_model = read_step(model)
    # geometry only: one density for all, each solid counted whole
    result = model_mass_properties(
        step_model, MaterialMap.uniform(1000.0), units=units, overlaps="allow"
    )
    stamped = {b.path: b.material for b in step_model.bodies if b.material is not None}
    products = {b.path: [n.product for n in b.nodes] for b in step_model.bodies}
    lo_d, hi_d = DENSITY_RANGE_KG_M3
    parts = []
    for b in result.bodies:
        if b.kind != "solid":
            continue
        xm = stamped.get(b.path)
        rho = xm.density_kg_m3 if xm is not None else None
        parts.append(
            DraftPart(
                b.path,
                b.properties.volume_mm3,
                None if xm is None else xm.name,
                rho if rho is not None and lo_d <= rho <= hi_d else None,
                xm is not None and is_placeholder_material(xm.name),
                part_label(products.get(b.path, []), b.path),
            )
        )
    lo, hi = result.bbox_mm
    ov = result.overlaps
    refused = ov.pairs and ov.mass_fraction > tolerances.OVERLAP_REFUSE_MASS_FRACTION
    overlaps = (
        f"{len(ov.pairs)} overlapping pair(s), {ov.mass_fraction:.2%} of the volume"
        if refused
        else ""
    )
    shapes = [b.shape for b in step_model.bodies if b.kind == "solid"]
    scale = result.audit.scale_to_mm
    points: list[DraftPoint] = []
    for refine in range(DRAFT_MAX_REFINE + 1):  # a finer grid while too few rays meet the model
        points = distinct_points(
            [
                (face, sp.position_mm, sp.depth_mm)
                for face in DRAFT_FACES
                for sp in project_grid(
                    shapes, face, face_grid(face, lo, hi, refine), lo, hi, scale_to_mm=scale
                )
            ],
            keep=DRAFT_MAX_POINTS if refine else None,
        )
        if len(points) >= DRAFT_MIN_POINTS:
            break
    return {
        "me_base_mm": top_surface_point(shapes, lo, hi, scale_to_mm=scale),
        "parts": [dataclasses.asdict(p) for p in parts],
        "points": [dataclasses.asdict(p) for p in points],
        "lo_mm": [float(v) for v in lo],
        "hi_mm": [float(v) for v in hi],
        "overlaps": overlaps,
        "refine": refine,
    }
