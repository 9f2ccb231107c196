"""The least ballast for a spacecraft's CoG envelope: ``cadcog balance`` and
:func:`cadcog.balance`, one composition.

What is balanced: the CAD's mass and CoG with the uncertainty its materials file states (a
STEP model with its materials, or a set-up's model), or, with a test's readings and the
weighed mass, what ``cadcog update`` makes of the test and the CAD together (its posterior mass
and CoG). The envelope: a CubeSat or PocketQube form factor's, or half-widths given, around the
model's geometric centre (its bounding box's). The ballast file's locations are checked
against the model's solids (none may lie inside one); that check is cached by the content of
the model and the locations, like the mass properties. The optimisation is
:func:`cadcog.spacecraft.balance.least_ballast`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core import tolerances
from cadcog.core.errors import CadcogError, ParameterFileError
from cadcog.spacecraft.balance import least_ballast
from cadcog.spacecraft.balance_result import BalanceResult
from cadcog.spacecraft.ballast_file import load_ballast
from cadcog.spacecraft.ballast_spec import BallastSpec, UncertainMass
from cadcog.spacecraft.envelope import CDS_COG_LIMITS_MM, source_for
from cadcog.spacecraft.items import DEFAULT_WEIGHING_SIGMA_KG, items_from_bodies, linear_prior
from cadcog.spacecraft.setup_draft import form_factor_mismatch

FloatArray = npt.NDArray[np.float64]

#: The confidences ``balance`` takes: below a half a "confidence" says little, and beyond
#: 0.9999 the miss budget nears the solver's tolerances.
MIN_CONFIDENCE = 0.5
MAX_CONFIDENCE = 0.9999


def run_balance(
    ballast: Path,
    *,
    model: Path | None = None,
    materials: Path | None = None,
    units: str | None = None,
    setup: Path | None = None,
    form_factor: str | None = None,
    cog_limits_mm: tuple[float, float, float] | None = None,
    confidence: float = 0.95,
    readings: Path | None = None,
    weighed_mass_kg: float | None = None,
    mass_sigma_kg: float | None = None,
    workers: int = 1,
    configurations: Path | None = None,
    overlaps: str = "check",
    max_product_kg_mm2: float | None = None,
    max_axis_angle_deg: float | None = None,
    inertia_confidence: float | None = None,
) -> BalanceResult:
    """The least ballast (module docstring), from checked arguments: a ``model`` or a
    ``setup``; ``readings`` with ``weighed_mass_kg`` (a set-up's) for the measured figures;
    ``configurations``: a configurations file whose every configuration the same ballast must
    satisfy too (the measured figures changed by each configuration's CAD change);
    ``mass_sigma_kg``: the weighing's 1 σ (default 1 g); ``overlaps``: a model's overlapping
    solids, as ``massprops``'s (``"check"``, ``"allow"``, ``"resolve"``);
    ``max_product_kg_mm2``, ``max_axis_angle_deg``: inertia objectives
    (:mod:`cadcog.spacecraft.balance_inertia`) at ``inertia_confidence`` (default
    ``confidence``), the tensor the CAD's with its items' uncertainty.

    Raises
    ------
    CadcogError
        Bad or missing options (naming them), a bad ballast file (naming its key), a location
        inside a solid (naming both), an envelope not given.
    """
    objectives = _objectives(
        model=model,
        setup=setup,
        confidence=confidence,
        readings=readings,
        weighed_mass_kg=weighed_mass_kg,
        mass_sigma_kg=mass_sigma_kg,
        overlaps=overlaps,
        form_factor=form_factor,
        cog_limits_mm=cog_limits_mm,
        configurations=configurations,
        max_product_kg_mm2=max_product_kg_mm2,
        max_axis_angle_deg=max_axis_angle_deg,
        inertia_confidence=inertia_confidence,
    )
    spec = load_ballast(ballast)
    configs: tuple[Any, ...] = ()
    if configurations is not None:
        from cadcog.spacecraft.configurations import load_configurations

        configs = load_configurations(configurations)
    notes: list[str] = []
    if setup is not None:
        state, box, limits, label, bodies, setup_source = _from_setup(
            setup, readings, weighed_mass_kg, mass_sigma_kg or DEFAULT_WEIGHING_SIGMA_KG, notes
        )
    else:
        assert model is not None
        state, box, label, bodies = _from_model(model, materials, units, workers, overlaps, notes)
        limits, setup_source = None, ""
    centre = 0.5 * (box[0] + box[1])
    _refuse_outside(spec, box, label)
    others = _configuration_states(state, bodies, configs, str(configurations or ""))
    limits, source = _envelope(cog_limits_mm, form_factor, box, limits, setup_source, label, notes)
    _refuse_inside(spec, model, setup, units)
    if configs:
        notes.extend(_configuration_overlaps(bodies, configs, model, setup, units, configurations))
    if not np.any(np.diag(state.cog_cov_mm2) > 0.0):
        notes.append(
            "the CoG carries no uncertainty (no [mass_uncertainty] in the materials file): the "
            "ballast meets the envelope only as the CAD stands"
        )
    if objectives is None:
        result = least_ballast(state, spec, centre, limits, confidence, configurations=others)
    else:
        from cadcog.spacecraft.balance_inertia import least_ballast_with_inertia

        result = least_ballast_with_inertia(
            state, _tensor_prior(bodies, state), spec, centre, limits, confidence, objectives
        )
    notes += _ballast_notes(result, state, measured=readings is not None)
    notes += _unit_notes(spec, state)
    return replace(result, notes=(*result.notes, *notes), envelope_source=source)


def _objectives(
    *,
    model: Path | None,
    setup: Path | None,
    confidence: float,
    readings: Path | None,
    weighed_mass_kg: float | None,
    mass_sigma_kg: float | None,
    overlaps: str,
    form_factor: str | None,
    cog_limits_mm: tuple[float, float, float] | None,
    configurations: Path | None,
    max_product_kg_mm2: float | None,
    max_axis_angle_deg: float | None,
    inertia_confidence: float | None,
) -> Any:
    """The options checked together (each refusal names them), and the inertia objectives
    they ask for (None: the CoG alone)."""
    if (model is None) == (setup is None):
        raise CadcogError("give a MODEL or --setup (one of them)")
    if not MIN_CONFIDENCE <= confidence <= MAX_CONFIDENCE:
        raise CadcogError(
            f"--confidence {confidence!r}: expected a probability from {MIN_CONFIDENCE} to "
            f"{MAX_CONFIDENCE} (the CoG inside the envelope at least that often)"
        )
    if mass_sigma_kg is not None and readings is None:
        raise CadcogError("--mass-sigma-kg goes with --readings and --weighed-mass-kg")
    if overlaps not in ("check", "allow", "resolve"):
        raise CadcogError(f"overlaps {overlaps!r}: expected check, allow or resolve")
    if setup is not None and overlaps != "check":
        raise CadcogError(
            "--allow-overlap and --resolve-overlaps go with a MODEL (a set-up "
            "says overlaps = ... itself)"
        )
    if readings is not None and setup is None:
        raise CadcogError("--readings needs --setup (its measurement equipment to remove)")
    if (readings is None) != (weighed_mass_kg is None):
        raise CadcogError("--readings and --weighed-mass-kg go together (a test is weighed)")
    if form_factor is not None and cog_limits_mm is not None:
        raise CadcogError("give --form-factor or --cog-limits-mm, not both")
    objectives = None
    if max_product_kg_mm2 is not None or max_axis_angle_deg is not None:
        from cadcog.spacecraft.balance_inertia import InertiaObjectives

        if configurations is not None:
            raise CadcogError(
                "--max-product-kg-mm2 and --max-axis-angle-deg balance the spacecraft as it "
                "stands, not its configurations: give them without --configurations"
            )
        objectives = InertiaObjectives(
            max_product_kg_mm2,
            max_axis_angle_deg,
            confidence if inertia_confidence is None else inertia_confidence,
        )
    elif inertia_confidence is not None:
        raise CadcogError(
            "--inertia-confidence goes with --max-product-kg-mm2 or --max-axis-angle-deg"
        )
    return objectives


def _envelope(
    cog_limits_mm: tuple[float, float, float] | None,
    form_factor: str | None,
    box: tuple[FloatArray, FloatArray],
    setup_limits: FloatArray | None,
    setup_source: str,
    label: str,
    notes: list[str],
) -> tuple[FloatArray, str]:
    """The envelope's half-widths and where they come from: ``--cog-limits-mm``, a form
    factor's (noted when the model's box does not fit it), or the set-up's."""
    limits = setup_limits
    if cog_limits_mm is not None:
        limits = np.array(cog_limits_mm, dtype=float)
    elif form_factor is not None:
        if form_factor not in CDS_COG_LIMITS_MM:
            raise CadcogError(
                f"--form-factor {form_factor!r}: expected one of {', '.join(CDS_COG_LIMITS_MM)}"
            )
        limits = np.array(CDS_COG_LIMITS_MM[form_factor])
        mismatch = form_factor_mismatch(form_factor, box[1] - box[0])  # model axes
        if mismatch is not None:  # balance has no --axes: the model's own are the envelope's
            notes.append(f"{mismatch} (balance takes the model's axes as the envelope's)")
    if cog_limits_mm is not None:
        source = "custom limits (--cog-limits-mm)"
    elif form_factor is not None:
        source = source_for(form_factor)
    else:
        source = setup_source
    if limits is None:
        raise CadcogError(
            f"{label}: no envelope: give --form-factor or --cog-limits-mm (or form_factor in "
            "the set-up)"
        )
    return limits, source


def _ballast_notes(result: BalanceResult, state: UncertainMass, measured: bool) -> list[str]:
    """What a team should know of the ballast found: that it mostly dilutes the CoG's
    uncertainty, or that it outweighs the spacecraft."""
    notes = []
    if result.feasible and result.total_ballast_kg > 0.0 and mostly_dilutes(result):
        better = "a tighter test" if measured else "measuring it (--readings)"
        notes.append(
            "the ballast mostly dilutes the CoG's uncertainty (σ × M/(M + m)) rather than "
            f"moving it: {better} may need none"
        )
    if result.feasible and result.total_ballast_kg > state.mass_kg:
        notes.append(
            f"the ballast ({result.total_ballast_kg:.3g} kg) outweighs the spacecraft "
            f"({state.mass_kg:.3g} kg): move mass inside it instead"
        )
    return notes


def _unit_notes(spec: BallastSpec, state: UncertainMass) -> list[str]:
    """A piece, or a location's limit, heavier than the spacecraft itself: kilograms typed
    for grams, most likely (a 5 kg piece for a 2.6 kg CubeSat found no ballast, silently)."""
    notes = []
    if spec.sizes_kg and spec.sizes_kg[0] > state.mass_kg:
        notes.append(
            f"the smallest piece ({spec.sizes_kg[0]:g} kg) weighs more than the spacecraft "
            f"({state.mass_kg:.4g} kg): is sizes_kg in grams? (the file is in kg)"
        )
    heavy = [
        p.id for p in spec.points if p.max_mass_kg is not None and p.max_mass_kg > state.mass_kg
    ]
    if heavy:
        notes.append(
            f"location(s) {', '.join(heavy[:8])} take more than the spacecraft weighs "
            f"({state.mass_kg:.4g} kg): is max_mass_kg in grams? (the file is in kg)"
        )
    return notes


def _tensor_prior(bodies: Sequence[Any], state: UncertainMass) -> Any:
    """The CAD's tensor about its CoG with its items' uncertainty, and its covariance with the
    CAD's mass and CoG; with a test's figures (measured apart from the CAD's tensor) that
    covariance is zero and the tensor is the CAD's about its own CoG (first order)."""
    from cadcog.spacecraft.balance_inertia import InertiaPrior
    from cadcog.spacecraft.explanations import cad_joint_prior

    mean, cov = cad_joint_prior(*items_from_bodies(bodies))
    prior = InertiaPrior.from_joint(mean, cov, "CAD")
    if state.source == "CAD":
        return prior
    return replace(prior, cross_cov=np.zeros((6, 4)), source="CAD, about the measured CoG")


def mostly_dilutes(result: BalanceResult) -> bool:
    """Whether, on the axis that binds, the ballast gains more margin by shrinking σ than by
    moving the CoG (a spacecraft balanced as it stands, its uncertainty too wide)."""
    k = int(np.argmin(result.margin_mm))
    before_sd = np.sqrt(max(result.before["cog_cov_mm2"][k][k], 0.0))
    after_sd = np.sqrt(max(float(result.cog_cov_mm2[k, k]), 0.0))
    z = float(np.max(result.face_quantiles[2 * k : 2 * k + 2]))
    moved = abs(result.before["offset_mm"][k]) - abs(float(result.offset_mm[k]))
    return z * (before_sd - after_sd) > moved


def _configuration_states(
    state: UncertainMass, bodies: Sequence[Any], configs: Sequence[Any], source: str
) -> list[tuple[str, UncertainMass]]:
    """Each configuration as a state to balance. The CAD's figures: the configuration's own
    (its moved bodies' totals and first-order uncertainty, exactly as the CAD's). A test's:
    the measured figures changed by what the configuration changes in the CAD, that change's
    uncertainty added as independent of the test's (first order; an approximation)."""
    from cadcog.spacecraft.configurations import configuration_deltas, configuration_properties

    if state.source == "CAD":
        return [
            (c.name, UncertainMass.from_prior(c, f"configuration {c.name}"))
            for c in configuration_properties(bodies, configs, source)
        ]
    return [
        (
            d.name,
            state.shifted(
                d.mass_kg,
                d.moment_kg_mm,
                d.moment_cov_kg2_mm2,
                f"configuration {d.name}",
                mass_var_kg2=d.mass_var_kg2,
                moment_mass_cov_kg2_mm=d.moment_mass_cov_kg2_mm,
            ),
        )
        for d in configuration_deltas(bodies, configs, source)
    ]


def _from_model(
    model: Path,
    materials: Path | None,
    units: str | None,
    workers: int,
    overlaps: str,
    notes: list[str],
) -> tuple[UncertainMass, tuple[np.ndarray, np.ndarray], str, Sequence[Any]]:
    from cadcog.cad.cache import step_mass_properties

    result, _ = step_mass_properties(
        model,
        materials,
        density_kg_m3=None,
        total_mass_kg=None,
        units=units,
        exclude=[],
        overlaps=overlaps,  # type: ignore[arg-type]
        strict=False,
        surface_areas=False,
        workers=workers,
    )
    lo, hi = result.bbox_mm
    state = UncertainMass.from_prior(linear_prior(*items_from_bodies(result.bodies)))
    notes.extend(f"{model}: {n}" for n in result.notes)  # a unit, a placeholder material...
    return state, (np.asarray(lo), np.asarray(hi)), str(model), result.bodies


def _from_setup(
    path: Path,
    readings: Path | None,
    weighed_mass_kg: float | None,
    mass_sigma_kg: float,
    notes: list[str],
) -> tuple[
    UncertainMass, tuple[np.ndarray, np.ndarray], np.ndarray | None, str, Sequence[Any], str
]:
    from cadcog.spacecraft.setup import load_setup

    s = load_setup(path)
    if readings is None:
        state = UncertainMass.from_prior(s.cad_prior())
    else:
        from cadcog.runs.update import update_from_files

        assert weighed_mass_kg is not None
        upd, _ = update_from_files(
            s,
            readings,
            weighed_mass_kg,
            mass_sigma_kg=mass_sigma_kg,
            unmodelled=None,
            swings=None,
        )
        state = UncertainMass(
            upd.posterior.mass_kg,
            upd.posterior_mass_sigma_kg,
            np.asarray(upd.posterior.cog_mm),
            np.asarray(upd.posterior_cog_cov_mm2),
            np.zeros(3),
            "update (test and CAD)",
        )
        if upd.model_rejected:
            notes.append(
                "the CAD does not explain the test (update rejects it): the figures balanced "
                "are the measurement's"
            )
    limits = None if s.cog_limits_mm is None else np.asarray(s.cog_limits_mm)
    lo, hi = s.bbox_mm
    if (
        s.form_factor is not None
        and s.cog_limits_mm is not None
        and np.allclose(s.cog_limits_mm, CDS_COG_LIMITS_MM[s.form_factor])
    ):
        source = source_for(s.form_factor)
    else:
        source = f"custom limits (cog_limits_mm in {path})"
    return state, (np.asarray(lo), np.asarray(hi)), limits, str(path), s.bodies, source


def _refuse_inside(
    spec: BallastSpec, model: Path | None, setup: Path | None, units: str | None
) -> None:
    """Refuse a ballast location inside a solid of the model (cached by content)."""
    from cadcog.cad.modelfile import solids_holding_points

    inside_of = solids_holding_points(
        [np.asarray(p.position_mm).tolist() for p in spec.points],
        kind="ballast locations",
        step=model,
        setup=setup,
        units=units,
    )
    for i, (point, inside) in enumerate(zip(spec.points, inside_of, strict=True)):
        if inside is not None:
            raise ParameterFileError(
                Path(spec.source),
                f"points[{i}].position_mm",
                f"{point.id!r} at {np.asarray(point.position_mm).tolist()} mm lies inside the "
                f"solid {inside!r}: ballast sits on a face, or in free space within the "
                "model's bounding box",
            )


def _refuse_outside(spec: Any, box: tuple[np.ndarray, np.ndarray], label: str) -> None:
    """Refuse a ballast location outside the model's bounding box: ballast sits on the
    spacecraft (a point beyond it is a typo or a unit slip)."""
    lo, hi = box
    tol = tolerances.SUSPENSION_ON_FACE_MM
    for i, point in enumerate(spec.points):
        pos = np.asarray(point.position_mm)
        if np.any(pos < lo - tol) or np.any(pos > hi + tol):
            raise ParameterFileError(
                Path(spec.source),
                f"points[{i}].position_mm",
                f"{point.id!r} at {pos.tolist()} mm lies outside the model's bounding box "
                f"{np.round(lo, 3).tolist()}..{np.round(hi, 3).tolist()} mm ({label}): ballast "
                "sits on the spacecraft (mm, model axes)",
            )


def _configuration_overlaps(
    bodies: Sequence[Any],
    configs: Sequence[Any],
    model: Path | None,
    setup: Path | None,
    units: str | None,
    configurations: Path | None,
) -> list[str]:
    """The configurations' moved parts that overlap others (cached by content, the entry
    ``massprops --configurations`` and ``check`` share)."""
    from cadcog.cad.modelfile import named_model, named_model_file
    from cadcog.cad.stepread import read_step
    from cadcog.spacecraft.configurations import cached_overlap_notes

    assert configurations is not None
    if model is not None:
        model_file, override = model, units

        def read() -> Any:
            return read_step(model)

    else:
        assert setup is not None
        model_file, override = named_model_file(setup)

        def read() -> Any:
            return named_model(setup)[0]

    notes = cached_overlap_notes(
        bodies,
        configs,
        read,
        model_file,
        configurations,
        units=override,
        source=str(configurations),
    )
    return [n for c in configs for n in notes.get(c.name, [])]
