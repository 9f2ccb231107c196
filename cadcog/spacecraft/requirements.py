"""Mass-properties requirements, checked the way a systems engineer would, for CI.

A requirements file (TOML; ``parts/cubesat_3u_requirements.toml`` is the example) names the
model as a set-up file does (:mod:`cadcog.cad.modelfile`) and the limits:

- ``[mass]``: ``max_kg`` (the allowable) with a required ``margin`` on the *predicted* mass
  (current best estimate plus growth allowances, AIAA S-120A's sense):
  ``predicted ≤ max_kg × (1 − margin)``; ``min_kg`` (dispensers with a minimum) on the current
  best estimate; ``[[mass.allocation]]`` entries ``node`` (a budget node: its path, its path
  below the top assembly, or a pattern matching one node) with ``max_kg``;
- ``[cog]``: the CubeSat envelope (``form_factor`` or ``limits_mm``, in ``axes``) around the
  geometric centre, nominally and, with ``at_95 = true``, at the 95 % edge of the rolled-up CAD
  uncertainty;
- ``[inertia]``: in a frame (``about``, ``axes``): ``max_misalignment_deg`` of the principal
  axes from the frame's, ``max_product_kg_mm2`` on the products of inertia, and
  ``[[inertia.ratio]]`` bounds (``min``, ``max``) on a ratio of moments (``min``,
  ``intermediate``, ``max`` principal moments, or ``xx``, ``yy``, ``zz`` in the frame);
- ``[baseline]``: a committed baseline (``file``) and tolerances: any body whose mass or CoG
  changed beyond them fails the check, with a readable diff (:mod:`cadcog.spacecraft.baseline`).

:func:`evaluate` turns a model's :class:`~cadcog.spacecraft.mass_summary.MassReport` and the
requirements into one :class:`RequirementResult` per requirement.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from cadcog.core import numformat as nf
from cadcog.core.errors import CadcogError, ParameterFileError
from cadcog.core.numformat import signed
from cadcog.core.paramfile import TableReader
from cadcog.core.results import JsonResult
from cadcog.mass.inertia import Frame, principal_axes, products_of_inertia
from cadcog.mass.materials import glob_match
from cadcog.spacecraft.baseline import BaselineDiff
from cadcog.spacecraft.mass_budget import BudgetNode
from cadcog.spacecraft.mass_summary import MassReport
from cadcog.spacecraft.requirements_file import (
    Requirements,
    load_requirements,
)

if TYPE_CHECKING:
    from cadcog.cad.stepmass import ModelMassProperties


@dataclass(frozen=True)
class RequirementResult(JsonResult):
    """One checked requirement: what it says, what was found, and whether it holds."""

    id: str
    title: str
    value: str
    limit: str
    passed: bool
    detail: str = ""

    def to_dict(self) -> dict[str, Any]:
        return {
            "id": self.id,
            "title": self.title,
            "value": self.value,
            "limit": self.limit,
            "passed": self.passed,
            "detail": self.detail,
        }


# --- evaluation ----------------------------------------------------------------------------------
def find_node(root: BudgetNode, spec: str) -> BudgetNode:
    """The one budget node ``spec`` names: its path, its path below the root, or a pattern.

    Raises
    ------
    ValueError
        If no node or several nodes match.
    """
    nodes = [n for _, n in root.walk()]
    prefix = f"{root.path}/" if root.path else ""
    exact = [n for n in nodes if spec in (n.path, n.path[len(prefix) :])]
    if len(exact) == 1:
        return exact[0]
    found = [
        n for n in nodes if glob_match(n.path, spec) or glob_match(n.path[len(prefix) :], spec)
    ]
    if len(found) != 1:
        what = "no budget node" if not found else f"{len(found)} budget nodes"
        raise ValueError(f"{what} match {spec!r}; nodes: {', '.join(n.path for n in nodes[:12])}")
    return found[0]


def _kg(x: float) -> str:
    """A mass for the result lines: significant figures, g below 1 kg (:mod:`.numformat`)."""
    return nf.mass(x, 5)


def evaluate(
    req: Requirements, report: MassReport, baseline: BaselineDiff | None
) -> list[RequirementResult]:
    """Every requirement of ``req`` against the model's ``report`` (and its baseline diff)."""
    out: list[RequirementResult] = []
    b = report.budget
    cbe, predicted = b.root.mass_kg, b.predicted.mass_kg
    if req.max_kg is not None:
        limit = req.max_kg * (1.0 - req.margin)
        sigma = "" if b.mass_sigma_kg is None else f", 1 σ {_kg(b.mass_sigma_kg)}"
        out.append(
            RequirementResult(
                "mass.max",
                f"predicted mass within {_kg(req.max_kg)} with a {req.margin:.0%} margin",
                _kg(predicted),
                f"≤ {_kg(limit)}",
                predicted <= limit,
                f"current best estimate {_kg(cbe)}, growth {_kg(predicted - cbe)}{sigma}; "
                f"margin {(req.max_kg - predicted) / req.max_kg:.1%}",
            )
        )
    if req.min_kg is not None:
        out.append(
            RequirementResult(
                "mass.min",
                f"mass at least {_kg(req.min_kg)}",
                _kg(cbe),
                f"≥ {_kg(req.min_kg)}",
                cbe >= req.min_kg,
            )
        )
    for alloc in req.allocations:
        try:
            node = find_node(b.root, alloc.node)
        except ValueError as exc:
            raise ParameterFileError(req.source, "mass.allocation.node", str(exc)) from None
        out.append(
            RequirementResult(
                f"mass.allocation.{alloc.node}",
                f"{node.path} within its allocation",
                _kg(node.predicted_mass_kg),
                f"≤ {_kg(alloc.max_kg)}",
                node.predicted_mass_kg <= alloc.max_kg,
                f"current best estimate {_kg(node.mass_kg)}",
            )
        )
    out.extend(_cog_results(req, report))
    out.extend(_inertia_results(req, report))
    if baseline is not None:
        out.append(
            RequirementResult(
                "baseline",
                f"no change beyond tolerances from {baseline.source.name}",
                f"{len(baseline.changes)} change(s)",
                f"mass ± {req.tolerances.mass_kg * 1e3:g} g, CoG ± {req.tolerances.cog_mm:g} mm",
                not baseline.changes,
                "; ".join(baseline.describe()),
            )
        )
    return out


def _overlap_results(
    req: Requirements,
    path: Path,
    result: ModelMassProperties,
    configs: Sequence[Any],
    strict: bool,
) -> list[RequirementResult]:
    """For each configuration a requirement names: no moved part overlaps one it did not move
    with (both would be counted whole); with ``strict`` an overlap is an error."""
    from cadcog.cad.modelfile import named_model, named_model_file
    from cadcog.spacecraft.configurations import cached_overlap_notes

    names = set(req.cog_configurations) | set(req.inertia_configurations)
    used = [c for c in configs if "*" in names or c.name in names]
    if not used:
        return []
    assert req.configurations_file is not None
    model_file, units = named_model_file(path)
    notes = cached_overlap_notes(
        result.bodies,
        configs,
        lambda: named_model(path)[0],
        model_file,
        req.configurations_file,
        units=units,
        source=str(req.configurations_file),
    )
    out = []
    for c in used:
        found = notes.get(c.name, [])
        if strict and found:
            raise CadcogError(f"{req.configurations_file}: {found[0]} (--strict)")
        out.append(
            RequirementResult(
                f"configuration.overlaps@{c.name}",
                f"no moved part overlaps another ({c.name})",
                f"{len(found)} overlap(s)",
                "none",
                not found,
                "; ".join(found),
            )
        )
    return out


def _cog_results(req: Requirements, report: MassReport) -> list[RequirementResult]:
    """The ``[cog]`` requirements against a report's envelope check."""
    out: list[RequirementResult] = []
    env = report.envelope
    if env is not None:
        offset = ", ".join(signed(v, 2) for v in env.offset_mm)
        limits = ", ".join(f"±{v:g}" for v in env.limits_mm)
        label = env.form_factor or "custom"
        out.append(
            RequirementResult(
                "cog.envelope",
                f"CoG within the {label} envelope",
                f"[{offset}] mm",
                f"[{limits}] mm",
                env.within,
                env.source,
            )
        )
        if req.cog_at_95:
            if env.sigma_mm is None:
                out.append(
                    RequirementResult(
                        "cog.envelope_95",
                        f"CoG within the {label} envelope at 95 %",
                        "no uncertainty",
                        f"[{limits}] mm",
                        False,
                        "the materials give no mass uncertainty to roll up: add "
                        "[mass_uncertainty] rules",
                    )
                )
            else:
                edge = np.abs(env.offset_mm) + 1.959963984540054 * env.sigma_mm
                out.append(
                    RequirementResult(
                        "cog.envelope_95",
                        f"CoG within the {label} envelope at 95 %",
                        "|offset| + 1.96 σ = [" + ", ".join(f"{v:.2f}" for v in edge) + "] mm",
                        f"[{limits}] mm",
                        bool(env.within_at_95),
                        "σ from the rolled-up mass uncertainties",
                    )
                )
    return out


def configuration_results(
    req: Requirements, result: ModelMassProperties, configs: Sequence[Any]
) -> list[RequirementResult]:
    """The ``[cog]`` and ``[inertia]`` requirements in each configuration they name (ids
    ``cog.envelope@deployed``, titles ending ``(deployed)``)."""
    from dataclasses import replace

    from cadcog.spacecraft.configurations import configured_result

    by_name = {c.name: c for c in configs}
    for key, names in (("cog", req.cog_configurations), ("inertia", req.inertia_configurations)):
        for name in names:
            if name != "*" and name not in by_name:
                raise ParameterFileError(
                    req.source,
                    f"{key}.configurations",
                    f"{name!r} is not a configuration of {req.configurations_file} (it has "
                    f"{', '.join(by_name) or 'none'})",
                )
    out: list[RequirementResult] = []
    for config in configs:
        cog = "*" in req.cog_configurations or config.name in req.cog_configurations
        inertia = "*" in req.inertia_configurations or config.name in req.inertia_configurations
        if not (cog or inertia):
            continue
        report = model_report(req, configured_result(result, config, str(req.configurations_file)))
        found = (_cog_results(req, report) if cog else []) + (
            _inertia_results(req, report) if inertia else []
        )
        out.extend(
            replace(r, id=f"{r.id}@{config.name}", title=f"{r.title} ({config.name})")
            for r in found
        )
    return out


def _inertia_results(req: Requirements, report: MassReport) -> list[RequirementResult]:
    if req.max_misalignment_deg is None and req.max_product_kg_mm2 is None and not req.ratios:
        return []
    total = report.result.total
    lo, hi = report.result.bbox_mm
    named = {"cog": total.cog_mm, "centre": 0.5 * (lo + hi), "origin": np.zeros(3)}
    about = req.inertia_about
    origin = named[about] if isinstance(about, str) else np.asarray(about, dtype=float)
    frame = Frame.parse(req.inertia_axes, origin)
    r = frame.axes
    central = principal_axes(r @ total.inertia_kg_mm2 @ r.T)  # CoG inertia, frame axes
    j_frame = r @ total.inertia_about(origin) @ r.T
    where = f"about {about if isinstance(about, str) else list(about)}, axes {req.inertia_axes}"
    out = []
    if req.max_misalignment_deg is not None:
        angles = central.angles_from_frame_deg()
        moments = central.moments_kg_mm2
        scale = max(float(np.max(np.abs(moments))), 1e-300)
        near = req.distinct_moments_rel
        distinct = [
            k
            for k in range(3)
            if all(abs(moments[k] - moments[m]) > near * scale for m in range(3) if m != k)
        ]
        worst = float(max((angles[k] for k in distinct), default=0.0))
        detail = (
            ""
            if len(distinct) == 3
            else "equal moments: only distinct principal axes count"
            if near <= 1e-6
            else f"moments within {100 * near:g} % of each other: only the distinct axes count"
        )
        out.append(
            RequirementResult(
                "inertia.misalignment",
                "principal axes aligned with the frame axes",
                f"{worst:.2f}°",
                f"≤ {req.max_misalignment_deg:g}°",
                worst <= req.max_misalignment_deg,
                detail or "angle of each principal axis from the nearest frame axis",
            )
        )
    if req.max_product_kg_mm2 is not None:
        p = products_of_inertia(j_frame, "positive")
        worst_p = max(abs(v) for v in p.values())
        out.append(
            RequirementResult(
                "inertia.products",
                f"largest |Pxy| {where}",
                f"{worst_p:.3f} kg·mm²",
                f"≤ {req.max_product_kg_mm2:g} kg·mm²",
                worst_p <= req.max_product_kg_mm2,
                ", ".join(f"P{k} {signed(v, 3)}" for k, v in p.items())
                + " kg·mm² (Pxy = +∫xy dm; the limit is on the magnitude, sign-free)",
            )
        )
    values = {
        "min": central.moments_kg_mm2[0],
        "intermediate": central.moments_kg_mm2[1],
        "max": central.moments_kg_mm2[2],
        "xx": j_frame[0, 0],
        "yy": j_frame[1, 1],
        "zz": j_frame[2, 2],
    }
    for ratio in req.ratios:
        value = float(values[ratio.numerator] / values[ratio.denominator])
        ok = (ratio.min is None or value >= ratio.min) and (ratio.max is None or value <= ratio.max)
        bounds = " and ".join(
            x
            for x in (
                f"≥ {ratio.min:g}" if ratio.min is not None else "",
                f"≤ {ratio.max:g}" if ratio.max is not None else "",
            )
            if x
        )
        out.append(
            RequirementResult(
                f"inertia.ratio.{ratio.numerator}/{ratio.denominator}",
                f"moment ratio {ratio.numerator}/{ratio.denominator}",
                f"{value:.4f}",
                bounds,
                ok,
                where,
            )
        )
    return out


def model_report(req: Requirements, result: ModelMassProperties) -> MassReport:
    """The mass report the requirements need (envelope in the ``[cog]`` axes)."""
    from cadcog.spacecraft.mass_summary import build_mass_report

    return build_mass_report(
        result,
        about="centre",
        axes=req.cog_axes,
        form_factor=req.form_factor,
        cog_limits_mm=req.cog_limits_mm,
    )


@dataclass(frozen=True, repr=False)  # JsonResult's one-line repr
class CheckResult(JsonResult):
    """A model checked against its requirements: what ``cadcog check`` prints.

    Attributes
    ----------
    name : str
        The requirements' name.
    requirements_file : Path
    model : str
        The model's source, as its import audit names it.
    mass_kg : float
    cog_mm : ndarray, shape (3,)
        The model's CoG (mm).
    results : tuple of RequirementResult
        One per requirement, in file order (baseline comparisons included).
    baseline : BaselineDiff or None
        What changed since the committed baseline, if the file names one.
    notes : tuple of str
        The model's notes (surfaces left out, overlaps counted, units).
    baseline_written : Path or None
        The baseline file, when ``update_baseline`` rewrote it.
    """

    name: str
    requirements_file: Path
    model: str
    mass_kg: float
    cog_mm: npt.NDArray[np.float64]
    results: tuple[RequirementResult, ...]
    baseline: BaselineDiff | None
    notes: tuple[str, ...]
    baseline_written: Path | None = None

    @property
    def passed(self) -> bool:
        """Every requirement holds."""
        return all(r.passed for r in self.results)

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "requirements_file": str(self.requirements_file),
            "model": self.model,
            "mass_kg": self.mass_kg,
            "cog_mm": self.cog_mm.tolist(),
            "passed": self.passed,
            "requirements": [r.to_dict() for r in self.results],
            "baseline": None if self.baseline is None else self.baseline.to_dict(),
            "notes": list(self.notes),
        }


def check_requirements(
    path: str | Path, *, strict: bool = False, update_baseline: bool = False
) -> CheckResult:
    """Check the model a requirements file names against it (``cadcog check``).

    Parameters
    ----------
    path : str or Path
        The requirements file (TOML; ``docs/ci.md`` documents its tables). Its model (a STEP
        file with materials, or a cadcog CubeSat spec) and baseline are relative to it.
    strict : bool
        A note about the model (surfaces left out, overlaps counted, units) is an error.
    update_baseline : bool
        First write the model's current mass properties to the ``[baseline]`` file (staged,
        then renamed), then compare with it.

    Raises
    ------
    CadcogError
        The file, a key or the model is not what is expected (naming the file and key), or
        ``update_baseline`` without a ``[baseline]`` file.
    """
    from cadcog.cad.modelfile import load_model
    from cadcog.core.fileio import staged_file
    from cadcog.core.jsontext import dumps_json
    from cadcog.core.paramfile import read_toml
    from cadcog.spacecraft.baseline import baseline_dict, diff, load_baseline

    path = Path(path)
    root = TableReader(read_toml(path), path)
    req = load_requirements(root, path)
    if update_baseline and req.baseline_file is None:
        raise CadcogError(f"{path}: --update-baseline needs a [baseline] table with a file")
    result = load_model(root, path.parent, strict=strict)
    root.finish()
    report = model_report(req, result)
    changes = None
    written = None
    if req.baseline_file is not None:
        if update_baseline:
            with staged_file(req.baseline_file) as tmp:
                tmp.write_text(dumps_json(baseline_dict(result)), encoding="utf-8")
            written = req.baseline_file
        changes = diff(load_baseline(req.baseline_file), result, req.tolerances, req.baseline_file)
    results = evaluate(req, report, changes)
    if req.configurations_file is not None:
        from cadcog.spacecraft.configurations import load_configurations

        configs = load_configurations(req.configurations_file)
        results.extend(configuration_results(req, result, configs))
        results.extend(_overlap_results(req, path, result, configs, strict))
    return CheckResult(
        name=req.name,
        requirements_file=path,
        model=result.audit.source,
        mass_kg=result.total.mass_kg,
        cog_mm=np.asarray(result.total.cog_mm, dtype=float),
        results=tuple(results),
        baseline=changes,
        notes=tuple(result.notes),
        baseline_written=written,
    )
