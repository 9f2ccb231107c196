"""What the bench measures: a rig or a spacecraft set-up, its planned hangs, and the estimate.

:func:`estimate_hangs` and :func:`line_check` are the bench's only calls into the estimator
(:func:`cadcog.method.estimate.estimate_cog` and its result): when the estimator's options or result
change, re-point these two functions and nothing else.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from cadcog.mass.properties import MassProperties, box_properties, combine
from cadcog.method.cogestimate import CogEstimate
from cadcog.method.errormodel import ErrorModel
from cadcog.method.estimate import MEData, estimate_for_rig
from cadcog.method.readings import Suspension
from cadcog.rig.geometry import FloatArray, ideal_reading
from cadcog.rig.inclinometer import InclinometerConfig
from cadcog.rig.parameters import Rig
from cadcog.uncertainty.montecarlo import Scenario

if TYPE_CHECKING:
    from cadcog.spacecraft.setup import Setup


@dataclass(frozen=True)
class PlannedHang:
    """One planned suspension, as the operator is told about it.

    Attributes
    ----------
    id : str
    position_mm : tuple of 3 floats
        Where the wire leaves the object (body frame): the readings CSV's x_mm, y_mm, z_mm.
    normal : tuple of 3 floats
        Outward normal of the face the point is on (the bolt axis).
    top_face_up : bool
        Whether the inclinometer's top face points up when hanging (from the CAD CoG).
    expected_x_deg, expected_y_deg : float
        Device readings expected from the CAD CoG (signs of the configuration applied).
    sensor_turned : bool
        Read with the sensor turned 180° on its mount (a reversal: the point's id followed by
        :data:`REVERSAL_SUFFIX`); the expected readings are then negated.
    """

    id: str
    position_mm: tuple[float, float, float]
    normal: tuple[float, float, float]
    top_face_up: bool
    expected_x_deg: float
    expected_y_deg: float
    sensor_turned: bool = False


#: A hang's id ending in this names the point before it, read with the sensor turned 180° on
#: its mount (a reversal, docs/bench.md): ``S1~`` is S1 hung again with the sensor turned.
REVERSAL_SUFFIX = "~"


def point_of(hang_id: str, known: Iterable[str]) -> tuple[str, bool]:
    """The point a hang id names and whether it is a reversal: ``S1~`` → ``("S1", True)``
    unless ``S1~`` is itself a known point.

    Raises
    ------
    ValueError
        If both ``S1~`` and ``S1`` are known points (which one is meant cannot be told).

    Examples
    --------
    >>> point_of("S1~", ["S1", "S2"]), point_of("S2", ["S1", "S2"])
    (('S1', True), ('S2', False))
    """
    names = set(known)
    if not hang_id.endswith(REVERSAL_SUFFIX):
        return hang_id, False
    base = hang_id[: -len(REVERSAL_SUFFIX)]
    if hang_id in names and base in names:
        raise ValueError(
            f"{hang_id!r} is both a point and the reversal of point {base!r}: rename the point "
            f"(ids ending in {REVERSAL_SUFFIX!r} name reversals)"
        )
    return (hang_id, False) if hang_id in names else (base, True)


@dataclass(frozen=True)
class BenchTarget:
    """A rig (``setup`` None) or a spacecraft set-up, with the hangs to make in order."""

    name: str
    source: Path
    rig: Rig
    hangs: tuple[PlannedHang, ...]
    setup: Setup | None = None

    @property
    def inclinometer(self) -> InclinometerConfig:
        return self.rig.inclinometer

    @property
    def object_cog_mm(self) -> FloatArray:
        """CAD CoG of the object without the ME."""
        if self.setup is None:
            return self.rig.analytic_proof_mass.cog_mm
        return self.setup.mass.cog_mm

    @property
    def assembly(self) -> MassProperties:
        """Object plus measurement equipment (mass, CoG, inertia), from CAD."""
        if self.setup is None:
            return self.rig.analytic_assembly
        me = [
            box_properties(v.size_mm, v.center_mm, mass_kg=v.mass_kg) for v in self.setup.me_volumes
        ]
        return combine([self.setup.mass, *me])

    def scenario(self) -> Scenario:
        """The planned hangs as a Monte Carlo scenario (in the order of :attr:`hangs`)."""
        ids = tuple(h.id for h in self.hangs)
        points = np.array([h.position_mm for h in self.hangs])
        normals = np.array([h.normal for h in self.hangs])
        if self.setup is None:
            return Scenario.from_rig(self.rig).with_points(ids, points, normals)
        return self.setup.scenario().with_points(ids, points, normals)

    def error_model(self) -> ErrorModel:
        return ErrorModel.from_rig(self.rig) if self.setup is None else self.setup.error_model()

    def me_data(self) -> MEData:
        return MEData.from_rig(self.rig) if self.setup is None else self.setup.me_data()


def _planned(
    ids: Sequence[str],
    positions: Sequence[FloatArray],
    normals: Sequence[FloatArray],
    assembly_cog_mm: FloatArray,
    config: InclinometerConfig,
    turned: Sequence[bool],
) -> tuple[PlannedHang, ...]:
    out = []
    for pid, p, n, t in zip(ids, positions, normals, turned, strict=True):
        r = ideal_reading(p, assembly_cog_mm)
        flip = -1.0 if t else 1.0
        out.append(
            PlannedHang(
                pid,
                (float(p[0]), float(p[1]), float(p[2])),
                (float(n[0]), float(n[1]), float(n[2])),
                r.top_face_up,
                flip * r.inc_x_deg * config.sign_x,
                flip * r.inc_y_deg * config.sign_y,
                t,
            )
        )
    return tuple(out)


def target_from_rig(rig: Rig, ids: Sequence[str] | None = None) -> BenchTarget:
    """The rig's suspension points (all, or ``ids`` in that order), wire exits as positions."""
    by_id = {p.id: p for p in rig.suspension_points}
    chosen = [p.id for p in rig.suspension_points] if ids is None else list(ids)
    named = [point_of(i, by_id) for i in chosen]
    points = [by_id[i] for i, _ in named]
    hangs = _planned(
        chosen,
        [rig.wire_exit_mm(p) for p in points],
        [p.normal for p in points],
        rig.analytic_assembly.cog_mm,
        rig.inclinometer,
        [t for _, t in named],
    )
    return BenchTarget(rig.name, rig.source, rig, hangs)


def target_from_setup(setup: Setup, ids: Sequence[str]) -> BenchTarget:
    """A spacecraft set-up's candidates ``ids``, in that order."""
    by_id = {c.id: c for c in setup.candidates}
    named = [point_of(i, by_id) for i in ids]
    cands = [by_id[i] for i, _ in named]
    hangs = _planned(
        list(ids),
        [c.position_mm for c in cands],
        [c.normal for c in cands],
        setup.assembly_cog_mm,
        setup.rig.inclinometer,
        [t for _, t in named],
    )
    return BenchTarget(setup.name, setup.source, setup.rig, hangs, setup)


# --- the one place the bench calls the estimator ------------------------------------------------
def estimate_hangs(target: BenchTarget, suspensions: Sequence[Suspension]) -> CogEstimate:
    """The compensated CoG from recorded suspensions, as ``cadcog estimate`` computes it
    (``--rig RIG`` or ``--setup SETUP``: the error model's line covariances, the expected wire
    offset corrected)."""
    if target.setup is None:
        return estimate_for_rig(target.rig, suspensions)
    from cadcog.spacecraft.setup import estimate_for_setup

    return estimate_for_setup(target.setup, suspensions)


def inertia_hangs(
    target: BenchTarget,
    swings: Sequence[Any],
    suspensions: Sequence[Suspension],
    source: str = "swings",
) -> tuple[Any, str]:
    """The inertia tensor from the hangs' swings (``cadcog.dynamics.swingfile.Swing``), as
    ``cadcog inertia`` computes it, or ``None`` and why there is none: what a run reports
    beside its CoG (a run's readings stand without it). ``source`` names the swing file in
    messages."""
    from cadcog.core.errors import CadcogError
    from cadcog.dynamics.measure import inertia_for_rig, inertia_for_setup

    if len(swings) < 3:
        return None, f"{len(swings)} hang(s) with a swing: the tensor needs 3 or more"
    try:
        if target.setup is None:
            return inertia_for_rig(target.rig, swings, suspensions, source=source), ""
        return inertia_for_setup(target.setup, swings, suspensions, source=source), ""
    except CadcogError as exc:
        return None, str(exc)


@dataclass(frozen=True)
class LineCheck:
    """How one suspension's plumb line agrees with the others.

    Attributes
    ----------
    distance_mm : float
        Distance of its line from the joint estimate.
    sigma : float
        Its leave-one-out statistic in sigmas (the pair's gap with two lines).
    p_value : float
    consistent : bool
    """

    distance_mm: float
    sigma: float
    p_value: float
    consistent: bool


def line_check(estimate: CogEstimate, point_id: str) -> LineCheck:
    """The estimator's consistency verdict on one suspension."""
    for r in estimate.joint.residuals:
        if r.id == point_id:
            return LineCheck(r.distance_mm, r.normalized, r.p_value, not r.inconsistent)
    raise KeyError(point_id)


def inconsistent_ids(estimate: CogEstimate) -> list[str]:
    """Ids of the suspensions the estimator flags as inconsistent with the others."""
    return [r.id for r in estimate.joint.residuals if r.inconsistent]


def estimate_summary(estimate: CogEstimate) -> dict[str, Any]:
    """The estimate as plain JSON (the estimator's own ``to_dict``)."""
    return estimate.to_dict()
