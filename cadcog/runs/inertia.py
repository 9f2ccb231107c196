"""``cadcog inertia`` and :func:`cadcog.inertia`: the object's tensor from a swing file and the
readings of the same hangs, for a rig or a set-up, through the results cache."""

from __future__ import annotations

from pathlib import Path

from cadcog.core import tolerances
from cadcog.core.errors import CadcogError
from cadcog.dynamics.cached import cached_inertia
from cadcog.dynamics.measure import inertia_for_rig, inertia_for_setup
from cadcog.dynamics.result import InertiaResult
from cadcog.dynamics.swingfile import read_swings
from cadcog.method.readings import read_readings
from cadcog.rig.parameters import Rig
from cadcog.spacecraft.setup import Setup


def inertia_from_files(
    swings_path: str | Path,
    readings_path: str | Path,
    *,
    rig: Rig | None = None,
    setup: Setup | None = None,
    weighed_mass_kg: float | None = None,
    mass_sigma_kg: float = tolerances.DEFAULT_WEIGHING_SIGMA_KG,
) -> InertiaResult:
    """Read a swing file and a readings CSV and run the chain for a rig or a set-up (what the
    command and :func:`cadcog.inertia` share), through the results cache
    (:func:`cadcog.dynamics.cached.cached_inertia`: unchanged inputs are not fitted again)."""
    if (rig is None) == (setup is None):
        raise ValueError("give a rig or a set-up")

    def compute() -> InertiaResult:
        swings = read_swings(swings_path)
        if setup is not None:
            return inertia_for_setup(
                setup,
                swings,
                read_readings(readings_path, setup.rig.inclinometer),
                weighed_mass_kg=weighed_mass_kg,
                mass_sigma_kg=mass_sigma_kg,
                source=str(swings_path),
                readings_source=str(readings_path),
            )
        assert rig is not None  # checked above
        return inertia_for_rig(
            rig,
            swings,
            read_readings(readings_path, rig.inclinometer),
            weighed_mass_kg=weighed_mass_kg,
            mass_sigma_kg=mass_sigma_kg,
            source=str(swings_path),
            readings_source=str(readings_path),
        )

    inputs = {
        "rig": rig,
        "setup": setup,
        "weighed_mass_kg": weighed_mass_kg,
        "mass_sigma_kg": mass_sigma_kg,
        "swings": str(swings_path),
        "readings": str(readings_path),
    }
    try:
        return cached_inertia(compute, inputs, [Path(swings_path), Path(readings_path)])[0]
    except CadcogError as exc:
        hint = "" if rig is None else _not_the_rigs_hint(rig, readings_path)
        if not hint:
            raise
        raise CadcogError(f"{hint}; {exc}") from None


def _not_the_rigs_hint(rig: Rig, readings_path: str | Path) -> str:
    """When a refusal comes from readings that name none of the rig's points (a spacecraft's
    files read with the paper's rig, the default): what to give instead."""
    try:
        ids = {s.id for s in read_readings(readings_path, rig.inclinometer)}
    except CadcogError:
        return ""
    own = {p.id for p in rig.suspension_points}
    if ids & own:
        return ""
    return (
        f"{readings_path}: the readings name none of rig {rig.name}'s points "
        f"({', '.join(sorted(own))}): a spacecraft's swings and readings go with its set-up "
        "(--setup, or setup=)"
    )
