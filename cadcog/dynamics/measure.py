"""The object's inertia tensor from its hangs' swings: the chain ``cadcog inertia`` runs.

1. The CoG from the same hangs' settled readings (``cadcog estimate``'s estimator): the hung
   assembly's CoG and covariance, the object's mass (weighed, or the CAD's).
2. Each swing's modes (:func:`cadcog.dynamics.modalfit.fit_swing`), started from the modes the
   CAD's tensor predicts at that hang.
3. The assembly's tensor that explains every frequency (:mod:`cadcog.dynamics.tensorfit`), the
   ME removed from it, every input's uncertainty propagated.
4. Principal moments and axes with their σ, the fit's χ², each input's share of the variance,
   and the comparison with the CAD's tensor.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
import numpy.typing as npt

from cadcog.core import tolerances
from cadcog.core.errors import DegenerateGeometryError, ReadingsError, named_by
from cadcog.core.fittest import TEST_LEVEL, FitTest, chi2_sf
from cadcog.core.units import STANDARD_GRAVITY_M_S2
from cadcog.dynamics.context import InertiaContext, context_for_rig, context_for_setup
from cadcog.dynamics.hungbody import HangGeometry, hang_modes
from cadcog.dynamics.result import (
    CLOSE_PAIR_SIGMAS,
    HangSwing,
    InertiaResult,
    bilinear_gradient,
    close_pairs,
    principal_with_sigma,
)
from cadcog.dynamics.swingfile import Swing
from cadcog.dynamics.swingselect import UsedHangs, usable_swings, worst_contradiction
from cadcog.dynamics.tensorfit import (
    ENTRIES,
    Geometry,
    Nuisances,
    SwingData,
    compensate,
    direct_jacobian,
    entries,
    fit_tensor,
    hang_geometry,
    model_nuisance_jacobian,
    nuisances,
    reweighted,
    swing_data,
    tensor,
    weighted_chi2,
)
from cadcog.mass.properties import combine
from cadcog.method.cogestimate import CogEstimate
from cadcog.method.readings import Suspension
from cadcog.rig.parameters import Rig

if TYPE_CHECKING:
    from cadcog.spacecraft.setup import Setup

FloatArray = npt.NDArray[np.float64]

#: The variance budget's groups: name, and the nuisance names' prefixes that belong to it.
BUDGET_GROUPS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("object mass", ("object mass",)),
    ("wire length", ("wire length",)),
    ("sensor position", ("sensor ",)),
    # one group: the wire's λ moves the exits and the top clamp's hinge together, and the CoG
    # the same hangs give follows their pivots (their errors partly cancel in the moment arms)
    (
        "pivots, the top clamp's hinge and the CoG they give (play, the wire's λ, readings)",
        ("exit ", "wire top", "CoG "),
    ),
    ("ME CoGs", ("ME ",)),
)


#: The frequencies' χ² beyond its (1 − this) quantile is a misfit: every σ then grows by the
#: Birge ratio √(χ²/dof) (the level of every test of fit).
MISFIT_P = TEST_LEVEL

#: A Birge ratio √(χ²/dof) above this is not a misfit to scale the σ by but a model that does
#: not hold (frequencies a hundred σ from any rigid body on this wire: a weighed mass 97× the
#: CAD's gave χ² 102 331 for 6 dof, and σ scaled 130× over a linearisation that no longer
#: holds): the tensor is refused. The nonlinear study's misfit-scaled campaigns stay below 3.
MAX_MISFIT_SCALE = 10.0

#: A frequency is left out only if the fit without it is no worse than with it, by this much
#: χ² (leaving a frequency out cannot raise the χ² of the same minimum): a 75 mm campaign of
#: the nonlinear study went from χ² 32 to 91 without a mode the linearised check said
#: contradicted the rest, to another minimum with I₁ 58 % off, where the right fast mode of
#: another hang was then left out as contradicting it.
WORSE_CHI2 = 1.0

#: A principal moment whose 1 σ exceeds this share of its value is not determined: the result
#: says so (the tensor is printed all the same, with its σ).
UNDETERMINED_MOMENT_REL = 0.5

#: A principal moment whose 1 σ exceeds this share of its value is not a measurement: the
#: tensor is refused (a first-day trial printed moments of 2 ± 55, 35 and 48 kg·mm², which no
#: body can have, with exit 0 and a warning).
UNMEASURED_MOMENT_REL = 1.0


def _pair(
    swings: Sequence[Swing], suspensions: Sequence[Suspension], source: str
) -> list[tuple[Swing, Suspension]]:
    by_id = {s.id: s for s in suspensions}
    out = []
    for sw in swings:
        if sw.point_id not in by_id:
            raise ReadingsError(
                f"{source}, line {sw.line}: hang {sw.point_id!r} has a swing but no settled "
                f"readings (the readings have {', '.join(sorted(by_id))})"
            )
        out.append((sw, by_id[sw.point_id]))
    if len(out) < 3:
        raise ReadingsError(
            f"{source}: {len(out)} hang(s) with a swing; the whole tensor needs at least 3 "
            "(six entries, two frequencies a hang)"
        )
    return out


def compare_inertia(
    measured: FloatArray, cov: FloatArray, cad: FloatArray, cad_cov: FloatArray
) -> dict[str, Any]:
    """The measured tensor against the CAD's: differences, their σ (both covariances), and one
    joint χ² over the six entries."""
    diff = entries(measured) - entries(cad)
    total = np.asarray(cov) + np.asarray(cad_cov)
    sig = np.sqrt(np.maximum(np.diag(total), 0.0))
    chi2 = float(diff @ np.linalg.solve(total, diff))
    return {
        "cad_inertia_kg_mm2": np.asarray(cad).tolist(),
        "cad_sigma_kg_mm2": tensor(np.sqrt(np.maximum(np.diag(cad_cov), 0.0))).tolist(),
        "difference_kg_mm2": tensor(diff).tolist(),
        "difference_sigma": tensor(diff / np.where(sig > 0, sig, np.inf)).tolist(),
        "difference_relative": tensor(diff / np.abs(entries(cad)).max()).tolist(),
        "chi2": chi2,
        "dof": len(ENTRIES),
        "p": FitTest(chi2, len(ENTRIES)).p,
    }


def _budget(
    nuis: Nuisances, jac: FloatArray, cov_freq: FloatArray, p: FloatArray
) -> tuple[tuple[str, float], ...]:
    pr = principal_with_sigma(p, np.zeros((6, 6)))
    g_all = np.array([bilinear_gradient(v, v) for v in pr.axes])

    def share(c: FloatArray) -> float:
        return float(np.trace(g_all @ c @ g_all.T))

    parts = [("swing frequencies (fit, amplitude, model)", share(cov_freq))]
    names = np.array(nuis.names)
    for label, prefixes in BUDGET_GROUPS:
        idx = [i for i, n in enumerate(names) if n.startswith(prefixes)]
        if label == "ME CoGs":
            own = [i for i in idx if names[i].endswith("own inertia")]
            idx = [i for i in idx if i not in own]
            c_own = jac[:, own] @ nuis.cov[np.ix_(own, own)] @ jac[:, own].T
            parts.append(("ME own inertia", share(c_own)))
        c = jac[:, idx] @ nuis.cov[np.ix_(idx, idx)] @ jac[:, idx].T
        parts.append((label, share(c)))
    total = sum(v for _, v in parts) or 1.0
    return tuple(sorted(((n, v / total) for n, v in parts), key=lambda t: -t[1]))


@dataclass(frozen=True)
class _Inputs:
    """What every fit of the tensor to a set of hangs shares: the context, the CoG estimate,
    the object's mass and σ, the ME's mass, and the tensor the fit starts from (the CAD
    assembly's entries)."""

    context: InertiaContext
    estimate: CogEstimate
    object_mass_kg: float
    object_mass_sigma_kg: float
    me_mass_kg: float
    start: FloatArray


class _TensorFit(NamedTuple):
    """One fit of the assembly's tensor: the data as weighed, the nuisances, the model's
    geometry at their values, the six entries and the fit's gain (∂p/∂f)."""

    data: SwingData
    nuis: Nuisances
    geo: Geometry
    p_asm: FloatArray
    gain: FloatArray


def _fit_tensor_to(inputs: _Inputs, used: UsedHangs) -> _TensorFit:
    """The assembly's tensor that explains ``used``'s frequencies, in two steps: weighed by the
    frequencies' own covariance, then by that plus what the nuisances do to the modelled
    frequencies (efficient weights; the χ²'s reference)."""
    ctx, est = inputs.context, inputs.estimate
    data = swing_data(used.fits, used.records_s, ctx.frequency_model_rel)
    nuis = nuisances(
        object_mass_kg=inputs.object_mass_kg,
        object_mass_sigma_kg=inputs.object_mass_sigma_kg,
        cog_mm=est.assembly_cog_mm,
        wire_length_mm=ctx.swing.wire_length_mm,
        wire_length_sigma_mm=ctx.swing.wire_length_sigma_mm,
        top_hinge_mm=used.terms.top_mm,
        sensor_mm=ctx.sensor_mm,
        sensor_sigma_mm=ctx.swing.sensor_position_sigma_mm,
        exits_mm=used.pivots_mm,
        geometry_cov_mm2=used.terms.cov_mm2,
        me_parts=ctx.me_parts,
        me_cog_sigma_mm=ctx.me_cog_sigma_mm,
        me_inertia_rel=ctx.swing.me_inertia_rel,
    )
    geo0 = hang_geometry(nuis, nuis.values, inputs.me_mass_kg, ctx.signs)
    p_first, _ = fit_tensor(data, geo0, inputs.start)
    m_v = model_nuisance_jacobian(p_first, data, nuis, inputs.me_mass_kg, ctx.signs)
    data = reweighted(data, m_v, nuis.cov)
    p_asm, gain = fit_tensor(data, geo0, p_first)
    return _TensorFit(data, nuis, geo0, p_asm, gain)


def _without_contradictions(
    inputs: _Inputs, used: UsedHangs, state: _TensorFit
) -> tuple[UsedHangs, _TensorFit, list[str]]:
    """Frequencies the others contradict left out, the least likely first (a single mode or a
    hang's whole swing: :func:`~cadcog.dynamics.swingselect.worst_contradiction`), while a
    check remains and the others still determine the tensor; a note for each."""
    notes: list[str] = []
    while (worst := worst_contradiction(used.fits, state.p_asm, state.data, state.geo)) is not None:
        hi, drop, d_chi2, p_value = worst
        fit = used.fits[hi]
        what = (
            "its swing"
            if len(drop) == len(fit.frequencies_hz)
            else f"its mode at {fit.frequencies_hz[min(drop)]:.3f} Hz "
            f"({fit.amplitudes_deg[min(drop)]:.2g}°)"
        )
        trial = used.without(hi, drop)
        try:
            state_t = _fit_tensor_to(inputs, trial)
        except DegenerateGeometryError:
            break  # the others alone do not determine the tensor: keep what was to go
        before = weighted_chi2(state.p_asm, state.data, state.geo)
        if weighted_chi2(state_t.p_asm, state_t.data, state_t.geo) > before + WORSE_CHI2:
            # fewer frequencies fitting worse: the fit went to another minimum, where the
            # others would now contradict right frequencies; keep what was to go (its misfit
            # then scales the σ)
            notes.append(
                f"hang {used.pairs[hi][0].point_id}: {what} disagrees with the other "
                f"frequencies (p = {p_value:.2g}), but the fit without it is worse: kept"
            )
            break
        notes.append(
            f"hang {used.pairs[hi][0].point_id}: {what} disagrees with the other frequencies "
            f"(the χ² falls by {d_chi2:.3g} without it, p = {p_value:.2g}): left out of the "
            "tensor"
        )
        used, state = trial, state_t
    return used, state, notes


def _hang_swings(used: UsedHangs, state: _TensorFit) -> tuple[HangSwing, ...]:
    """Each used hang's frequencies, their σ, the model's at the fitted tensor, the damping
    ratios, amplitudes and record."""
    data, geo0 = state.data, state.geo
    sig_all = data.per_hang(np.sqrt(np.diag(data.cov_hz2)))
    freq_all = data.per_hang(data.frequencies_hz)
    out = []
    for (sw, _), fit, f, sig, h in zip(
        used.pairs, used.fits, freq_all, sig_all, geo0.hangs, strict=True
    ):
        model = hang_modes(tensor(state.p_asm), geo0.mass_kg, geo0.cog_mm, h).frequencies_hz
        omega = 2 * np.pi * fit.frequencies_hz
        out.append(
            HangSwing(
                sw.point_id,
                f,
                sig,
                model[fit.mode_index],
                fit.decay_per_s / np.sqrt(omega**2 + fit.decay_per_s**2),
                fit.amplitudes_deg,
                len(sw.t_s),
                sw.duration_s,
            )
        )
    return tuple(out)


def _misfit_scale(chi2: float, dof: int) -> tuple[float, list[str]]:
    """The factor every σ of the result grows by, and a warning when the misfit is strong.

    Raises
    ------
    DegenerateGeometryError
        Beyond :data:`MAX_MISFIT_SCALE`: the model does not hold, no σ would be honest.

    The frequencies scatter more than their σ say (the χ² beyond its 95 % quantile): the σ the
    fit states cannot be trusted as they are. The Birge ratio √(χ²/dof) grows every σ of the
    result to what the scatter supports; never shrinks them. (Applied below that too, as the
    Particle Data Group does, it over-covered: 100 % where 95-98 % were covered unscaled;
    docs/inertia_validation.md.)
    """
    misfit = dof > 0 and chi2_sf(chi2, dof) < MISFIT_P
    scale = float(np.sqrt(chi2 / dof)) if misfit else 1.0
    if scale > MAX_MISFIT_SCALE:
        raise DegenerateGeometryError(
            f"the frequencies do not agree with one rigid body on this wire (χ² {chi2:.4g} for "
            f"{dof} dof: {scale:.3g}× their σ, beyond the {MAX_MISFIT_SCALE:g}× a misfit is "
            "scaled by): check the weighed mass, the wire length and the sensor's position, "
            "and that nothing touched the object"
        )
    if dof > 0 and chi2_sf(chi2, dof) < 0.01:
        return scale, [
            f"the frequencies do not agree with one rigid body on a wire (χ² {chi2:.1f} for "
            f"{dof} dof, p = {chi2_sf(chi2, dof):.2g}): every σ of the tensor is multiplied "
            f"by √(χ²/dof) = {scale:.2f}; check the wire length, that nothing touched the "
            "object, and each hang's residuals"
        ]
    return scale, []


def _undetermined(moments: FloatArray, moment_sigmas: FloatArray) -> list[str]:
    """A warning when a principal moment is not determined (its σ above
    :data:`UNDETERMINED_MOMENT_REL` of it).

    Raises
    ------
    DegenerateGeometryError
        If a principal moment is not positive (unphysical), or its σ is above
        :data:`UNMEASURED_MOMENT_REL` of it (not a measurement): refused, never printed.
    """
    listed = ", ".join(f"{m:.4g} ± {s:.2g}" for m, s in zip(moments, moment_sigmas, strict=True))
    if np.any(moments <= 0):
        raise DegenerateGeometryError(
            f"the swings give a principal moment that is not positive ({listed} kg·mm²): they "
            "do not determine the tensor (a light object under a heavy ME, a wrong weighed "
            "mass, or too few distinct hangs: see `cadcog plan --for inertia`)"
        )
    if np.any(moment_sigmas > UNMEASURED_MOMENT_REL * moments):
        raise DegenerateGeometryError(
            f"the swings do not determine the tensor: a principal moment came out with a 1 σ "
            f"above its value ({listed} kg·mm²); a light object under a heavy ME, or too few "
            "distinct hangs: see `cadcog plan --for inertia`"
        )
    if np.any(moment_sigmas > UNDETERMINED_MOMENT_REL * moments):
        return [
            "the swings do not determine the tensor: a principal moment came out with a 1 σ "
            f"above half its value ({listed} kg·mm²); a light object under a heavy ME, or too "
            "few distinct hangs: see `cadcog plan --for inertia`"
        ]
    return []


def measure_inertia(
    swings: Sequence[Swing],
    estimate: CogEstimate,
    context: InertiaContext,
    *,
    object_mass_kg: float,
    object_mass_sigma_kg: float,
    mass_source: str,
    source: str = "swings",
) -> InertiaResult:
    """The object's inertia tensor about its CoG from the swings of hangs already estimated.

    Parameters
    ----------
    swings : sequence of Swing
        At least three hangs, each with settled readings in ``estimate``.
    estimate : CogEstimate
        The CoG estimate of the same hangs (its assembly CoG and covariance are used).
    context : InertiaContext
    object_mass_kg, object_mass_sigma_kg : float
        The object's mass used (the estimate's) and its 1 σ.
    mass_source : str
    source : str
        The swing file's name, for messages.
    """
    pairs = _pair(swings, estimate.suspensions, source)
    ctx = context
    me_mass = sum(p.mass_kg for p in ctx.me_parts)
    cad_assembly = combine([ctx.object_cad, *ctx.me_parts])
    weight_n = (object_mass_kg + me_mass) * STANDARD_GRAVITY_M_S2
    positions = np.array([s.position_mm for _, s in pairs], dtype=float)
    lines = {s.id: i for i, s in enumerate(estimate.suspensions)}
    # λ as the CoG's joint fit found it (its prior otherwise), and how the fit's CoG follows
    # each hang's point
    rows = [lines[s.id] for _, s in pairs]
    terms = ctx.hang_terms(positions, estimate.assembly_cog_mm, weight_n, estimate.joint, rows)
    geometry = [
        HangGeometry(pivot, ctx.sensor_mm, ctx.swing.wire_length_mm, terms.top_mm, *ctx.signs)
        for pivot in terms.pivots_mm
    ]
    used, dropped = usable_swings(pairs, terms, cad_assembly, geometry)
    inputs = _Inputs(
        ctx,
        estimate,
        object_mass_kg,
        object_mass_sigma_kg,
        me_mass,
        entries(cad_assembly.inertia_kg_mm2),
    )
    try:
        state = _fit_tensor_to(inputs, used)
    except DegenerateGeometryError as exc:
        raise DegenerateGeometryError(f"{exc}{used.weak_note()}") from None
    used, state, mode_notes = _without_contradictions(inputs, used, state)
    data, nuis, geo0, p_asm, gain = state
    fit_chi2 = weighted_chi2(p_asm, data, geo0)
    p_obj, cog_obj = compensate(p_asm, nuis, nuis.values, ctx.me_parts)
    # The object's entries move with a nuisance through the fit (−A M) and through the
    # compensation (∂/∂p of the compensation is the identity).
    m_v = model_nuisance_jacobian(p_asm, data, nuis, me_mass, ctx.signs)
    jac = -gain @ m_v + direct_jacobian(lambda v: compensate(p_asm, nuis, v, ctx.me_parts)[0], nuis)
    cov_freq = gain @ data.cov_hz2 @ gain.T
    cov = cov_freq + jac @ nuis.cov @ jac.T
    cov = 0.5 * (cov + cov.T)
    hangs = _hang_swings(used, state)
    chi2, dof = fit_chi2, len(data.frequencies_hz) - 6
    warnings = [f"{d}: this hang is left out of the tensor" for d in dropped] + mode_notes
    warnings += used.halves_notes()
    scale, misfit_warning = _misfit_scale(chi2, dof)
    warnings += misfit_warning
    if dof == 0:
        warnings.append(
            f"{len(data.frequencies_hz)} frequencies for the six entries, none to spare: the fit "
            "cannot check itself and its σ is optimistic (docs/inertia.md, 'At least three "
            "hangs'): hang from more points"
        )
    shares = _budget(nuis, jac, cov_freq, p_obj)  # a common scale leaves the shares as they are
    cov = cov * scale**2
    cov_freq = cov_freq * scale**2
    principal = principal_with_sigma(p_obj, cov)
    warnings += _undetermined(principal.moments_kg_mm2, principal.moments_sigma_kg_mm2)
    warnings += [
        f"I{c.lower + 1} and I{c.lower + 2} differ by {c.split_kg_mm2:.3g} kg·mm², less than "
        f"{CLOSE_PAIR_SIGMAS:g}× what the noise alone makes of two equal moments "
        f"({c.split_sigma_kg_mm2:.3g}): sorted, the larger reads high and the smaller low, and "
        f"their axes are not determined; their mean, {c.mean_kg_mm2:.6g} ± "
        f"{c.mean_sigma_kg_mm2:.3g} kg·mm², is not biased so"
        for c in close_pairs(principal, cov)
    ]
    result_t = tensor(p_obj)
    return InertiaResult(
        result_t,
        cov,
        cov_freq,
        principal,
        cog_obj,
        object_mass_kg,
        object_mass_sigma_kg,
        mass_source,
        hangs,
        chi2,
        dof,
        shares,
        compare_inertia(result_t, cov, ctx.object_cad.inertia_kg_mm2, ctx.cad_cov_kg2_mm4),
        tuple(warnings),
        scale,
    )


def inertia_for_rig(
    rig: Rig,
    swings: Sequence[Swing],
    suspensions: Sequence[Suspension],
    *,
    weighed_mass_kg: float | None = None,
    mass_sigma_kg: float = tolerances.DEFAULT_WEIGHING_SIGMA_KG,
    source: str = "swings",
    readings_source: str | None = None,
) -> InertiaResult:
    """``cadcog inertia --rig``: the rig's object (its proof mass) from its swings; refusals
    name the swing file (``source``) or the readings' (``readings_source``)."""
    from cadcog.method.estimate import estimate_for_rig

    with named_by(readings_source):
        estimate = estimate_for_rig(
            rig, suspensions, weighed_mass_kg=weighed_mass_kg, mass_sigma_kg=mass_sigma_kg
        )
    comp = estimate.compensation
    assert comp is not None  # a rig always gives its measurement equipment
    with named_by(source, values=False):
        return measure_inertia(
            swings,
            estimate,
            context_for_rig(rig),
            object_mass_kg=comp.object_mass_kg,
            object_mass_sigma_kg=comp.object_mass_sigma_kg,
            mass_source=comp.object_mass_source,
            source=source,
        )


def inertia_for_setup(
    setup: Setup,
    swings: Sequence[Swing],
    suspensions: Sequence[Suspension],
    *,
    weighed_mass_kg: float | None = None,
    mass_sigma_kg: float = tolerances.DEFAULT_WEIGHING_SIGMA_KG,
    source: str = "swings",
    readings_source: str | None = None,
) -> InertiaResult:
    """``cadcog inertia --setup``: a spacecraft from its swings, against its CAD with the CAD's
    stated uncertainty; refusals name the swing file or the readings' as
    :func:`inertia_for_rig`'s."""
    from cadcog.spacecraft.explanations import cad_inertia_prior
    from cadcog.spacecraft.items import items_from_bodies
    from cadcog.spacecraft.setup import estimate_for_setup

    with named_by(readings_source):
        estimate = estimate_for_setup(
            setup, suspensions, weighed_mass_kg=weighed_mass_kg, mass_sigma_kg=mass_sigma_kg
        )
    me = setup.me_data(weighed_mass_kg, mass_sigma_kg)
    items, fixed = items_from_bodies(setup.bodies)
    with named_by(source, values=False):
        return measure_inertia(
            swings,
            estimate,
            context_for_setup(setup, cad_inertia_prior(items, fixed)),
            object_mass_kg=me.object_mass_kg,
            object_mass_sigma_kg=me.object_mass_sigma_kg,
            mass_source=me.object_mass_source,
            source=source,
        )


def inertia_observation(
    setup: Setup,
    swings_path: str | Path,
    suspensions: Sequence[Suspension],
    *,
    weighed_mass_kg: float,
    mass_sigma_kg: float,
) -> tuple[FloatArray, FloatArray]:
    """The tensor a swing file measures, as ``cadcog update --swings`` observes it: its six
    entries ``[xx, yy, zz, xy, xz, yz]`` and their covariance (through the results cache, as
    :func:`cadcog.runs.inertia.inertia_from_files`)."""
    from cadcog.dynamics.cached import cached_inertia
    from cadcog.dynamics.swingfile import read_swings

    def compute() -> InertiaResult:
        return inertia_for_setup(
            setup,
            read_swings(swings_path),
            suspensions,
            weighed_mass_kg=weighed_mass_kg,
            mass_sigma_kg=mass_sigma_kg,
            source=str(swings_path),
        )

    inputs = {
        "setup": setup,
        "suspensions": tuple(suspensions),
        "weighed_mass_kg": weighed_mass_kg,
        "mass_sigma_kg": mass_sigma_kg,
        "swings": str(swings_path),
    }
    measured, _ = cached_inertia(compute, inputs, [Path(swings_path)])
    return entries(measured.inertia_kg_mm2), measured.cov_kg2_mm4
