"""A model's mass properties gathered for people: budget, inertia in a chosen frame, envelope.

:func:`build_mass_report` takes the result of :func:`cadcog.cad.stepmass.model_mass_properties` and
adds what engineers read off it: the mass budget by assembly node
(:mod:`cadcog.spacecraft.mass_budget`), principal moments and axes, the inertia about a chosen point
in chosen axes (:mod:`cadcog.mass.inertia`), and the CubeSat CoG envelope
(:mod:`cadcog.spacecraft.envelope`). :meth:`MassReport.to_dict` is the JSON of ``cadcog massprops
--json`` (documented in ``docs/spacecraft.md``). Nothing here imports the CAD layer.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from cadcog.core import bounds
from cadcog.core.results import JsonResult
from cadcog.mass.inertia import (
    PRODUCT_CONVENTIONS,
    TENSOR_CONVENTION,
    Frame,
    PrincipalAxes,
    inertia_in_frame,
    principal_axes,
    products_of_inertia,
)
from cadcog.spacecraft.configurations import (
    Configuration,
    ConfigurationProperties,
    configuration_properties,
)
from cadcog.spacecraft.envelope import (
    CDS_COG_LIMITS_MM,
    EnvelopeCheck,
    check_envelope,
    limits_for,
    source_for,
)
from cadcog.spacecraft.mass_budget import MassBudget, mass_budget
from cadcog.spacecraft.setup_draft import form_factor_mismatch

if TYPE_CHECKING:
    from cadcog.cad.stepmass import ModelMassProperties

FloatArray = npt.NDArray[np.float64]

#: Named reference points for ``about``.
REFERENCE_POINTS = ("cog", "origin", "centre")


@dataclass(frozen=True, repr=False)  # JsonResult's one-line repr
class MassReport(JsonResult):
    """Everything ``cadcog massprops`` reports about a model.

    Attributes
    ----------
    result : ModelMassProperties
    budget : MassBudget
    principal : PrincipalAxes
        About the CoG, in model axes.
    frame : Frame
        The reference point and axes the user asked for.
    frame_inertia_kg_mm2 : ndarray, shape (3, 3)
        Inertia about ``frame``'s origin in its axes.
    envelope : EnvelopeCheck or None
        With a form factor or limits: the CoG against the envelope, in ``frame``'s axes around
        the geometric centre.
    configurations : tuple of ConfigurationProperties
        Each configuration asked for (:mod:`cadcog.spacecraft.configurations`), with its
        envelope check against the same envelope.
    """

    result: ModelMassProperties
    budget: MassBudget
    principal: PrincipalAxes
    frame: Frame
    frame_inertia_kg_mm2: FloatArray
    envelope: EnvelopeCheck | None
    configurations: tuple[ConfigurationProperties, ...] = ()

    @property
    def root_prefix(self) -> str:
        """``"root/"`` when every body sits under one top assembly, else ``""``."""
        firsts = {b.nodes[0] for b in self.result.bodies if len(b.nodes) > 1}
        if len(firsts) == 1 and all(len(b.nodes) > 1 for b in self.result.bodies):
            return f"{firsts.pop()}/"
        return ""

    def short(self, path: str) -> str:
        """A body path without the common top assembly, for tables."""
        prefix = self.root_prefix
        return path[len(prefix) :] if prefix and path.startswith(prefix) else path

    @property
    def geometric_center_mm(self) -> FloatArray:
        """Centre of the model's bounding box (mm): a CubeSat's geometric centre."""
        lo, hi = self.result.bbox_mm
        return np.asarray(0.5 * (lo + hi))

    def to_dict(self) -> dict[str, Any]:
        total = self.result.total
        j = total.inertia_kg_mm2
        out: dict[str, Any] = {
            "mass_kg": total.mass_kg,
            "cog_mm": total.cog_mm.tolist(),
            "volume_mm3": total.volume_mm3,
            "inertia_kg_mm2": {
                "about": "centre of gravity, model axes",
                "tensor": j.tolist(),
                "tensor_convention": TENSOR_CONVENTION,
                "products": {
                    "positive": {
                        "convention": PRODUCT_CONVENTIONS["positive"],
                        **products_of_inertia(j, "positive"),
                    },
                    "negative": {
                        "convention": PRODUCT_CONVENTIONS["negative"],
                        **products_of_inertia(j, "negative"),
                    },
                },
                "principal_moments": self.principal.moments_kg_mm2.tolist(),
                "principal_axes": self.principal.axes.tolist(),
                "principal_axes_degenerate": self.principal.degenerate,
                "principal_axes_angles_from_model_deg": (
                    self.principal.angles_from_frame_deg().tolist()
                ),
            },
            "frame": {
                "label": self.frame.label,
                "origin_mm": self.frame.origin_mm.tolist(),
                "axes": self.frame.axes.tolist(),
                "cog_mm": self.frame.point_to_frame(total.cog_mm).tolist(),
                "inertia_kg_mm2": self.frame_inertia_kg_mm2.tolist(),
            },
            "geometric_center_mm": self.geometric_center_mm.tolist(),
            "budget": self.budget.to_dict(),
            "bodies": [b.to_dict() for b in self.result.bodies],
            "audit": self.result.audit.to_dict(),
            "overlaps": self.result.overlaps.to_dict(),
            "notes": list(self.result.notes),
            "info": list(self.result.info),
        }
        if self.envelope is not None:
            out["envelope"] = self.envelope.to_dict()
        if self.configurations:
            out["configurations"] = {c.name: c.to_dict() for c in self.configurations}
        return out


def density_sources(bodies: Sequence[Any]) -> str:
    """Where the densities came from, as the user gave them: ``--density-kg-m3 2700 ×12``...

    Examples
    --------
    >>> from types import SimpleNamespace as B
    >>> bodies = [B(density_source="materials rule '*' (uniform density)", density_kg_m3=2700.0)]
    >>> density_sources(bodies * 3)
    '--density-kg-m3 2700 ×3'
    >>> density_sources([B(density_source="materials rule 'rail*' (m.toml)", density_kg_m3=1.0),
    ...                  B(density_source="STEP material 'Al' (AL6061)", density_kg_m3=1.0)])
    'materials file m.toml ×1, STEP materials ×1'
    """
    counts: dict[str, int] = {}
    for b in bodies:
        src = b.density_source
        if src.endswith("(uniform density)"):
            key = f"--density-kg-m3 {b.density_kg_m3:g}"
        elif src.startswith("materials rule") and src.endswith(")") and "(" in src:
            key = f"materials file {src[src.rindex('(') + 1 : -1]}"
        elif src.startswith("STEP material"):
            key = "STEP materials"
        elif src.startswith("uniform"):
            key = "one density scaled to --total-mass-kg"
        else:
            key = src.split(" (", 1)[0]
        counts[key] = counts.get(key, 0) + 1
    return ", ".join(f"{k} ×{n}" for k, n in counts.items())


def parse_point(text: str) -> str | tuple[float, float, float]:
    """``cog``, ``origin``, ``centre`` or ``X,Y,Z`` (mm).

    Raises
    ------
    ValueError
        For anything else.

    Examples
    --------
    >>> parse_point("centre"), parse_point("1, 2, 3.5")
    ('centre', (1.0, 2.0, 3.5))
    """
    word = text.strip().lower()
    if word in REFERENCE_POINTS or word == "center":
        return "centre" if word == "center" else word
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 3 or not all(np.isfinite(values)):
        raise ValueError(f"expected cog, origin, centre or X,Y,Z in mm, got {text!r}")
    for v in values:
        problem = bounds.check("point_mm", v)
        if problem is not None:
            raise ValueError(f"{problem}, got {text!r}")
    return values[0], values[1], values[2]


def build_mass_report(
    result: ModelMassProperties,
    *,
    about: str | Sequence[float] = "cog",
    axes: str = "+x,+y,+z",
    form_factor: str | None = None,
    cog_limits_mm: Sequence[float] | None = None,
    configurations: Sequence[Configuration] = (),
    configurations_source: str = "",
) -> MassReport:
    """Gather a model's mass report.

    Parameters
    ----------
    result : ModelMassProperties
    about : "cog", "origin", "centre" or (x, y, z)
        Reference point of the frame inertia (``centre``: the bounding box's centre, a
        CubeSat's geometric centre).
    axes : str
        The frame's axes as signed model axes, e.g. ``"+y,-x,+z"``.
    form_factor : str, optional
        CubeSat form factor for the envelope check.
    cog_limits_mm : sequence of 3 floats, optional
        Custom envelope half-widths (override the form factor's).
    configurations : sequence of Configuration
        Configurations to report (:func:`cadcog.spacecraft.configurations.load_configurations`;
        ``configurations_source`` names their file in messages).

    Raises
    ------
    ValueError
        For a bad point, axes or form factor.
    """
    total = result.total
    lo, hi = result.bbox_mm
    centre = 0.5 * (lo + hi)
    named = {"cog": total.cog_mm, "origin": np.zeros(3), "centre": centre}
    if isinstance(about, str):
        if about not in named:
            raise ValueError(f"about must be one of {', '.join(REFERENCE_POINTS)} or X,Y,Z")
        origin, label = named[about], f"{about}"
    else:
        origin = np.asarray(about, dtype=float)
        label = "point " + ", ".join(f"{v:g}" for v in origin)
    frame = Frame.parse(axes, origin, f"{label}, axes {axes}")
    budget = mass_budget(
        result.bodies,
        name=Path(result.audit.source).stem,
        total_given=result.audit.total_mass_given_kg is not None,
    )
    envelope = None
    if cog_limits_mm is not None:
        limits, source = np.asarray(cog_limits_mm, dtype=float), "custom limits"
    elif form_factor is not None:
        if form_factor not in CDS_COG_LIMITS_MM:
            known = ", ".join(CDS_COG_LIMITS_MM)
            raise ValueError(f"unknown form factor {form_factor!r}; known: {known}")
        limits, source = limits_for(form_factor), source_for(form_factor)
    if cog_limits_mm is not None or form_factor is not None:
        envelope = check_envelope(
            total.cog_mm,
            centre,
            limits,
            cov_mm2=budget.cog_cov_mm2,
            axes=frame.axes,
            form_factor=form_factor,
            source=source,
        )
    mismatch = form_factor_mismatch(form_factor, np.abs(frame.axes) @ (hi - lo))
    if mismatch is not None:  # a CubeSat's box, in the envelope's axes
        remedy = " (a model whose long axis is not its z: --axes names the envelope's axes)"
        result = replace(result, notes=(*result.notes, mismatch + remedy))
    configs = configuration_properties(result.bodies, configurations, configurations_source)
    if envelope is not None:
        configs = tuple(
            replace(
                c,
                envelope=check_envelope(
                    c.total.cog_mm,
                    centre,
                    envelope.limits_mm,
                    cov_mm2=c.cog_cov_mm2,
                    axes=frame.axes,
                    form_factor=form_factor,
                    source=envelope.source,
                ),
            )
            for c in configs
        )
    return MassReport(
        result,
        budget,
        principal_axes(total.inertia_kg_mm2),
        frame,
        inertia_in_frame(total, frame),
        envelope,
        configs,
    )
