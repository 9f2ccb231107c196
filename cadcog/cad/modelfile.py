"""The model keys shared by set-up and requirements files: which CAD, which densities.

A file names its model either as a cadcog CubeSat spec (``model = "cubesat_3u.toml"``: built,
written to STEP and read back like any export) or as a STEP file
(``model_step = "sat.step"``), with optional keys that mean what the ``cadcog massprops``
options mean:

===================  ==========================================================================
``materials``        materials file (densities, surfaces, mass uncertainties, growth)
``total_mass_kg``    scale every density to a weighing
``units``            the STEP file's true length unit, when its declaration is wrong
``exclude``          array of patterns of bodies or assemblies to leave out
``overlaps``         ``"check"`` (default), ``"allow"``, ``"resolve"`` or ``"skip"``
===================  ==========================================================================

Paths are relative to the file that names them.
"""

from __future__ import annotations

import tempfile
from dataclasses import replace
from pathlib import Path

from cadcog.cad.stepmass import (
    AllExcludedError,
    ModelMassProperties,
    OverlapPolicy,
    model_mass_properties,
)
from cadcog.cad.stepread import read_step
from cadcog.core.errors import CadcogError
from cadcog.core.paramfile import TableReader
from cadcog.core.units import UNIT_CHOICES
from cadcog.mass.materials import MaterialMap, load_materials

#: Keys :func:`load_model` reads (a file's other tables are its own).
MODEL_KEYS = ("model", "model_step", "materials", "total_mass_kg", "units", "exclude", "overlaps")


def load_model(t: TableReader, base: Path, *, strict: bool = False) -> ModelMassProperties:
    """The mass properties of the model a table names (see the module docstring); ``strict``
    turns every note about the model into an error, as ``cadcog massprops --strict``."""
    total = t.number("total_mass_kg", positive=True) if t.has("total_mass_kg") else None
    if t.has("model"):
        from cadcog.cad.assembly import write_assembly
        from cadcog.cad.cubesat import build_cubesat, load_cubesat, material_map

        spec_path = base / t.string("model")
        spec = load_cubesat(spec_path)
        asm, mats = build_cubesat(spec)
        with tempfile.TemporaryDirectory() as tmp:
            step = Path(tmp) / "model.step"
            try:
                write_assembly(asm, step)  # read back as any export is
            except CadcogError as exc:  # name the user's spec, not the temporary file
                why = str(exc).replace(str(step), "a temporary STEP file")
                raise CadcogError(f"{spec_path}: cannot build its model: {why}") from None
            except OSError as exc:
                raise CadcogError(
                    f"{spec_path}: cannot build its model in a temporary folder "
                    f"({exc.strerror or exc})"
                ) from None
            model = read_step(step)
        materials: MaterialMap | None = material_map(spec, mats)
        if t.has("materials"):  # a materials file's rules come first, the spec's complete them
            extra = load_materials(base / t.string("materials"))
            assert materials is not None
            materials = MaterialMap(
                extra.rules + materials.rules,
                extra.source,
                extra.surface_rules,
                extra.uncertainty_rules + materials.uncertainty_rules,
                extra.growth_rules,
            )
    elif t.has("model_step"):
        model = read_step(base / t.string("model_step"))
        materials = load_materials(base / t.string("materials")) if t.has("materials") else None
    else:
        raise t.error("model", "missing: give model (a cadcog CubeSat spec) or model_step")
    units = t.string("units", choices=UNIT_CHOICES) if t.has("units") else None
    exclude = t.strings("exclude") if t.has("exclude") else []
    overlaps: OverlapPolicy = "check"
    if t.has("overlaps"):
        value = t.string("overlaps", choices=("check", "allow", "resolve", "skip"))
        overlaps = value if value in ("allow", "resolve", "skip") else "check"  # type: ignore[assignment]
    try:
        result = model_mass_properties(
            model,
            materials,
            total_mass_kg=total,
            units=units,
            exclude=exclude,
            overlaps=overlaps,
            strict=strict,
        )
    except AllExcludedError:
        raise t.error("exclude", f"{exclude!r} excludes every body of the model") from None
    if t.has("model"):  # name the spec, not the temporary STEP it was read back from
        source = f"{base / t.string('model')} (built)"
        result = replace(result, audit=replace(result.audit, source=source))
    return result
