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
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from cadcog.cad import cache
from cadcog.cad.massresults import AllExcludedError, ModelMassProperties
from cadcog.core.errors import CadcogError
from cadcog.core.fileio import note_input
from cadcog.core.paramfile import TableReader
from cadcog.core.units import UNIT_CHOICES

if TYPE_CHECKING:
    from cadcog.cad.resolve import OverlapPolicy
    from cadcog.cad.stepmodel import StepModel
    from cadcog.mass.materials import MaterialMap

#: Keys :func:`load_model` reads (a file's other tables are its own).
MODEL_KEYS = ("model", "model_step", "materials", "total_mass_kg", "units", "exclude", "overlaps")


def load_model(t: TableReader, base: Path, *, strict: bool = False) -> ModelMassProperties:
    """The mass properties of the model a table names (see the module docstring); ``strict``
    turns every note about the model into an error, as ``cadcog massprops --strict``.

    The result is cached by the content of every input (:mod:`cadcog.cad.cache`): a second
    run on unchanged files reads it back instead of building and integrating the model.
    """
    total = t.number("total_mass_kg", positive=True) if t.has("total_mass_kg") else None
    model_key = _model_key(t)
    source = base / t.string(model_key)
    materials_path = base / t.string("materials") if t.has("materials") else None
    units = t.string("units", choices=UNIT_CHOICES) if t.has("units") else None
    exclude = t.strings("exclude") if t.has("exclude") else []
    overlaps: OverlapPolicy = "check"
    if t.has("overlaps"):
        value = t.string("overlaps", choices=("check", "allow", "resolve", "skip"))
        overlaps = value if value in ("allow", "resolve", "skip") else "check"  # type: ignore[assignment]
    for key, path in ((model_key, source), ("materials", materials_path)):
        if path is not None and not path.exists():
            raise t.error(key, f"{path}: file not found (a path is read from the folder of "
                               "the file that names it)")  # fmt: skip
    files = [source] if materials_path is None else [source, materials_path]
    settings = cache.model_settings(
        model_key,
        total_mass_kg=total,
        units=units,
        exclude=exclude,
        overlaps=overlaps,
        strict=strict,
    )

    def compute() -> ModelMassProperties:
        model, materials = _read(t, source, materials_path)
        from cadcog.cad.stepmass import model_mass_properties

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
            result = replace(result, audit=replace(result.audit, source=f"{source} (built)"))
        return result

    result, hit = cache.mass_properties(settings, files, compute)
    if hit:  # read from the cache: the inputs are still this command's inputs
        what = "a parameter file it reads" if t.has("model") else "the STEP model it reads"
        note_input(source, what)
        if materials_path is not None:
            note_input(materials_path, "a parameter file it reads")
    return result


def _read(
    t: TableReader, source: Path, materials_path: Path | None
) -> tuple[StepModel, MaterialMap | None]:
    """The model (a spec built and read back, or a STEP file) and its materials."""
    from cadcog.cad.stepread import read_step
    from cadcog.mass.materials import MaterialMap, load_materials

    if not t.has("model"):
        model = read_step(source)
        return model, (load_materials(materials_path) if materials_path is not None else None)
    from cadcog.cad.assembly import write_assembly
    from cadcog.cad.cubesat import build_cubesat, load_cubesat, material_map

    spec = load_cubesat(source)
    asm, mats = build_cubesat(spec)
    with tempfile.TemporaryDirectory() as tmp:
        step = Path(tmp) / "model.step"
        try:
            write_assembly(asm, step)  # read back as any export is
        except CadcogError as exc:  # name the user's spec, not the temporary file
            why = str(exc).replace(str(step), "a temporary STEP file")
            raise CadcogError(f"{source}: cannot build its model: {why}") from None
        except OSError as exc:
            raise CadcogError(
                f"{source}: cannot build its model in a temporary folder ({exc.strerror or exc})"
            ) from None
        model = read_step(step)
    materials: MaterialMap | None = material_map(spec, mats)
    if materials_path is not None:  # a materials file's rules come first, the spec's complete them
        extra = load_materials(materials_path)
        assert materials is not None
        materials = MaterialMap(
            extra.rules + materials.rules,
            extra.source,
            extra.surface_rules,
            extra.uncertainty_rules + materials.uncertainty_rules,
            extra.growth_rules,
        )
    return model, materials


def _model_key(t: TableReader) -> str:
    """Which key names the model: ``model`` (a cadcog CubeSat spec), else ``model_step``.

    Raises
    ------
    ParameterFileError
        Neither given (naming a misspelt key the table has).
    """
    for key in ("model", "model_step"):
        if t.has(key):
            return key
    raise t.error(
        "model",
        "missing: give model (a cadcog CubeSat spec) or model_step"
        + t.misspelt("model", "model_step"),
    )


def named_model_file(path: Path) -> tuple[Path, str | None]:
    """The model file a set-up or requirements file names (``model`` or ``model_step``,
    relative to it) and its ``units`` override, the keys checked (reads no CAD)."""
    from cadcog.core.paramfile import read_toml

    t = TableReader(read_toml(path), path)
    source = path.parent / t.string(_model_key(t))
    units = t.string("units", choices=UNIT_CHOICES) if t.has("units") else None
    return source, units


def named_model(path: Path) -> tuple[StepModel, Path, str | None]:
    """The model a set-up or requirements file names, read (a spec built and read back), the
    file it came from, and the ``units`` override: for what needs the solids themselves, not
    their mass properties (a ballast location checked against them)."""
    from cadcog.core.paramfile import read_toml

    source, units = named_model_file(path)
    model, _ = _read(TableReader(read_toml(path), path), source, None)
    return model, source, units


def solids_holding_points(
    points_mm: Sequence[Sequence[float]],
    *,
    kind: str,
    step: Path | None = None,
    setup: Path | None = None,
    units: str | None = None,
) -> list[str | None]:
    """For each point (mm, model axes), the solid of the model holding it, or None
    (:func:`cadcog.cad.pointclass.solids_holding`): the model a STEP file (``step``, with its
    ``units`` override) or a set-up (``setup``, the model it names) holds. Kept in the cache by
    content (:func:`cadcog.cad.cache.cached_data`: the files, the points, ``kind``), so that
    only the first check of an unchanged model reads its CAD."""
    if (step is None) == (setup is None):
        raise ValueError("give a STEP file or a set-up")
    settings: dict[str, Any] = {
        "kind": kind,
        "points": [[float(v) for v in p] for p in points_mm],
        "units": units,
    }
    files = [step] if step is not None else [setup, named_model_file(setup)[0]]  # type: ignore[arg-type]

    def compute() -> dict[str, Any]:
        from cadcog.cad.pointclass import solids_holding
        from cadcog.cad.stepmass import unit_scale

        if step is not None:
            from cadcog.cad.stepread import read_step

            model, override = read_step(step), units
        else:
            assert setup is not None
            model, _, override = named_model(setup)
        scale, _, _ = unit_scale(model, override)
        solids = [(b.path, b.shape) for b in model.solids]
        return {"inside": solids_holding(solids, settings["points"], scale_to_mm=scale)}

    data, _ = cache.cached_data(settings, [f for f in files if f is not None], compute)
    return list(data["inside"])
