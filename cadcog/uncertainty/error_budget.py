"""Error budget: each source's distribution, its size, and its share of the CoG error.

Shares are for one representative pair, by linear propagation: the pair's CoG error is
differentiated (central differences of :func:`cadcog.uncertainty.montecarlo.propagate`) with respect
to every random parameter, and each source contributes ``Σ var_i J_i J_iᵀ`` over its parameters. The
tests check this against a Monte Carlo run with that source alone.

The sensor's errors shared by the hangs (``[inclinometer]`` ``offset_deg``, ``scale_error_rel``,
``mounting_misalignment_deg``) are a row of their own, :data:`SHARED_SENSOR_ROW`, part of the
``inclinometer`` source (turned off with it): a pair cannot calibrate them, so their row is what
they cost a test that does not.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.results import JsonResult
from cadcog.method.errormodel import SOURCES, ErrorModel
from cadcog.method.mecog import me_cog_pdf
from cadcog.method.wire import elastica_length_mm
from cadcog.rig.geometry import angle_between_lines_deg
from cadcog.uncertainty.montecarlo import (
    EstimatorOptions,
    Perturbations,
    Scenario,
    all_pairs,
    propagate,
)

FloatArray = npt.NDArray[np.float64]

#: The budget's row of the sensor's shared errors (of the ``inclinometer`` source).
SHARED_SENSOR_ROW = "sensor_shared"


@dataclass(frozen=True)
class SourceBudget:
    """One error source: its distribution, its std, and its share for the representative pair."""

    source: str
    distribution: str
    sigma: float
    unit: str
    cog_sigma_mm: float  # √trace of its CoG-error covariance
    share: float  # of the total CoG-error variance


@dataclass(frozen=True)
class Budget(JsonResult):
    pair: tuple[str, str]
    pair_angle_deg: float
    sources: tuple[SourceBudget, ...]
    bias_mm: FloatArray  # CoG error with every parameter at its mean
    cov_mm2: FloatArray  # total linearised covariance
    me_cog_sigma_mm: FloatArray
    me_cog_max_cdf_difference: float
    inclinometer_sigma_deg: float

    def to_dict(self) -> dict[str, Any]:
        return {
            "representative_pair": list(self.pair),
            "pair_angle_deg": self.pair_angle_deg,
            "sources": [
                {
                    "source": s.source,
                    "distribution": s.distribution,
                    "sigma": s.sigma,
                    "unit": s.unit,
                    "cog_sigma_mm": s.cog_sigma_mm,
                    "share": s.share,
                }
                for s in self.sources
            ],
            "bias_mm": self.bias_mm.tolist(),
            "cog_sigma_mm": float(np.sqrt(np.trace(self.cov_mm2))),
            "cov_mm2": self.cov_mm2.tolist(),
            "me_cog_sigma_mm": self.me_cog_sigma_mm.tolist(),
            "me_cog_max_cdf_difference_from_normal": self.me_cog_max_cdf_difference,
            "inclinometer_sigma_deg": self.inclinometer_sigma_deg,
        }


def representative_pair(scenario: Scenario) -> tuple[int, int]:
    """The pair whose plumb lines meet at the median angle among all pairs."""
    g = scenario.assembly_cog_mm
    pairs = all_pairs(len(scenario.ids))
    angles = [
        angle_between_lines_deg(scenario.points_mm[a] - g, scenario.points_mm[b] - g)
        for a, b in pairs
    ]
    return pairs[int(np.argsort(angles)[len(angles) // 2])]


def _parameters(model: ErrorModel) -> list[tuple[str, str, tuple[int, ...], float, float]]:
    """(source, field, index, mean, variance) of every random parameter of a pair."""
    out: list[tuple[str, str, tuple[int, ...], float, float]] = []
    w = np.asarray(model.me_masses_kg) / sum(model.me_masses_kg) * np.asarray(model.me_edges_mm)
    for axis in range(3):
        out.append(("me_cog", "me_mm", (axis, 0), 0.0, float(np.sum(w**2) / 12.0)))
    if model.wire_model == "elastica":  # one wire for the campaign: one shared factor
        m1, var = _wire_factor_moments(model)
        out.append(("wire_offset", "wire", (0, 0), m1, var))
    elif model.wire_model == "one-wire":  # one wire: one λ, uniform in 0 … the bound
        m = model.wire_offset_max_mm
        out.append(("wire_offset", "wire", (0, 0), 0.5 * m, m * m / 12.0))
    for j in range(2):
        for t in range(2):
            out.append(("point_play", "play_mm", (t, j, 0), 0.0, model.play_mm**2 / 12.0))
        if model.wire_model == "paper":
            m = model.wire_offset_max_mm
            out.append(("wire_offset", "wire", (j, 0), 0.5 * m, m * m / 12.0))
        for axis in range(2):
            out.append(("inclinometer", "reading_deg", (axis, j, 0), 0.0, model.reading_var_deg2()))
    for j, sigma in enumerate(model.shared_sensor_sigmas):
        if sigma > 0:
            out.append((SHARED_SENSOR_ROW, "shared", (j, 0), 0.0, float(sigma) ** 2))
    return out


def _wire_factor_moments(model: ErrorModel) -> tuple[float, float]:
    """Mean and variance of the elastica's factor √(1 + U) on λ."""
    prior = model.wire_prior(1.0)
    lam = model.wire_length_mm(1.0)
    return prior.scale_mm / lam, prior.scale_var_mm2 / lam**2


def _nominal(model: ErrorModel) -> Perturbations:
    if model.wire_model == "paper":
        wire0 = np.full((2, 1), 0.5 * model.wire_offset_max_mm)
    elif model.wire_model == "one-wire":
        wire0 = np.full((1, 1), 0.5 * model.wire_offset_max_mm)
    else:
        wire0 = np.full((1, 1), _wire_factor_moments(model)[0])
    shared = np.zeros((7, 1)) if model.has_shared_sensor else None
    return Perturbations(np.zeros((3, 1)), np.zeros((2, 2, 1)), wire0, np.zeros((2, 2, 1)), shared)


def _wire_row(model: ErrorModel, lam: float, w: float, weight_n: float) -> tuple[str, float, str]:
    """The wire offset's row of the budget: its model, its spread (mm) and unit."""
    if model.wire_model == "paper":
        return (
            f"U(0, {w:g} mm) along the bolt axis (mean {w / 2:g} mm), per hang",
            w / 12**0.5,
            "mm",
        )
    if model.wire_model == "one-wire":
        return (
            f"one wire for all hangs: Δ = λ/cos(θ/2), λ U(0, {w:g} mm) (a string to a stiff wire)",
            w / 12**0.5,
            "mm",
        )
    return (
        f"elastica Δ = λ/cos(θ/2), λ = {lam:.3f} mm, "
        f"EI ±{model.wire_stiffness_rel_uncertainty:.0%}, one wire for all hangs",
        float(np.sqrt(model.wire_prior(weight_n).scale_var_mm2)),
        "mm",
    )


def linearised_covariance(
    scenario: Scenario,
    model: ErrorModel,
    pair: tuple[int, int],
    options: EstimatorOptions = EstimatorOptions(),  # noqa: B008 - frozen dataclass
) -> tuple[FloatArray, dict[str, FloatArray]]:
    """CoG-error bias (parameters at their means) and each source's linearised covariance."""
    full = model.only(*SOURCES)
    base = _nominal(full)
    bias = propagate(scenario, full, pair, base, options)[0]
    covs = {s: np.zeros((3, 3)) for s in _rows(model)}
    for source, name, index, _, var in _parameters(full):
        gate = "inclinometer" if source == SHARED_SENSOR_ROW else source
        if var == 0.0 or gate not in model.sources:
            continue
        step = 1e-4 * max(np.sqrt(var), 1e-3)
        cols = []
        for sign in (1.0, -1.0):
            moved = getattr(base, name).copy()
            moved[index] += sign * step
            cols.append(propagate(scenario, full, pair, replace(base, **{name: moved}), options)[0])
        jac = (cols[0] - cols[1]) / (2 * step)
        covs[source] += var * np.outer(jac, jac)
    return np.asarray(bias), covs


def _shared_row(model: ErrorModel) -> tuple[str, float, str]:
    """The shared sensor row's description, and the σ of its first declared figure (offset,
    else mounting, else sensitivity) with that figure's unit."""
    terms = [
        (name, text, sigma, unit)
        for name, text, sigma, unit, declared in (
            (
                "zero offset",
                f"zero offset U(±{model.sensor_offset_deg:g}°) per channel",
                model.sensor_offset_deg / np.sqrt(3.0),
                "deg per axis",
                model.sensor_offset_deg,
            ),
            (
                "mounting",
                f"mounting within {model.mounting_misalignment_deg:g}°",
                model.mounting_misalignment_deg / 3.0,
                "deg per axis",
                model.mounting_misalignment_deg,
            ),
            (
                "sensitivity",
                f"sensitivity U(±{model.sensor_scale_rel:g}) per channel",
                model.sensor_scale_rel / np.sqrt(3.0),
                "relative",
                model.sensor_scale_rel,
            ),
        )
        if declared
    ]
    if not terms:
        return "none declared", 0.0, ""
    name, _, sigma, unit = terms[0]
    listed = ", ".join(t[1] for t in terms)
    return f"one sensor for all hangs: {listed} (σ: the {name}'s)", float(sigma), unit


def _rows(model: ErrorModel) -> tuple[str, ...]:
    """The budget's rows: every source, and the sensor's shared errors when declared."""
    return SOURCES + ((SHARED_SENSOR_ROW,) if model.has_shared_sensor else ())


def error_budget(
    scenario: Scenario,
    model: ErrorModel,
    options: EstimatorOptions = EstimatorOptions(),  # noqa: B008 - frozen dataclass
) -> Budget:
    """The budget of ``model`` for the representative pair of ``scenario``."""
    model.require_angle_sensor("the Monte Carlo's error budget")
    pair = representative_pair(scenario)
    bias, covs = linearised_covariance(scenario, model, pair, options)
    total = sum(covs.values(), np.zeros((3, 3)))
    total_var = float(np.trace(total))
    pdf = me_cog_pdf(model.me_masses_kg, model.me_edges_mm)
    lam = elastica_length_mm(model.wire_bending_stiffness_n_mm2, scenario.weight_n)
    w = model.wire_offset_max_mm
    descriptions = {
        "me_cog": (
            f"Σ (m_k/m_ME)·U(±a_k/2) per axis, exact PDF by convolution "
            f"(max CDF difference from a normal {pdf.max_cdf_difference_from_normal:.4f})",
            pdf.sigma_mm,
            "mm per axis",
        ),
        "inclinometer": (
            (
                f"U(±{model.accuracy_deg:g}°) bias per hang + noise {model.sensor_noise_deg:g}° "
                f"and ADC (LSB {model.lsb_deg:.4f}°) per sample, mean of {model.samples}"
                if model.inclinometer_model == "hang-bias"
                else f"U(±{model.accuracy_deg:g}°) + U(±LSB/2), LSB {model.lsb_deg:.4f}°, "
                f"independent per sample, mean of {model.samples} (the paper's model)"
            ),
            model.reading_sigma_deg,
            "deg per axis",
        ),
        "point_play": (
            f"U(±{model.play_mm / 2:g} mm) on both face axes",
            model.play_mm / np.sqrt(12.0),
            "mm per axis",
        ),
        "wire_offset": _wire_row(model, lam, w, scenario.weight_n),
        SHARED_SENSOR_ROW: _shared_row(model),
    }
    rows = []
    for s in _rows(model):
        desc, sigma, unit = descriptions[s]
        var = float(np.trace(covs[s]))
        rows.append(
            SourceBudget(
                s, desc, float(sigma), unit, np.sqrt(var), var / total_var if total_var else 0
            )
        )
    g = scenario.assembly_cog_mm
    a, b = pair
    return Budget(
        (scenario.ids[a], scenario.ids[b]),
        angle_between_lines_deg(scenario.points_mm[a] - g, scenario.points_mm[b] - g),
        tuple(rows),
        bias,
        total,
        np.full(3, pdf.sigma_mm),
        pdf.max_cdf_difference_from_normal,
        model.reading_sigma_deg,
    )
