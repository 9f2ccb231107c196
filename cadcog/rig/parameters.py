"""The suspension test rig as validated parameters, and its closed-form mass properties.

A :class:`Rig` is what :func:`cadcog.rig.file.load_rig` returns: a proof mass (a homogeneous box
with one drilled, tapped hole per suspension point), the suspension points, the measurement
equipment (ME) as homogeneous boxes on the proof mass's +z face, and the inclinometer's range.
Frames and face names are those of :mod:`cadcog.rig.geometry`.

The closed forms here (:meth:`Rig.analytic_proof_mass` and friends) are the independent
expectation the CAD's exact B-rep integration is tested against.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Literal

import numpy as np
import numpy.typing as npt

from cadcog.core.units import STANDARD_GRAVITY_M_S2
from cadcog.mass.properties import MassProperties, box_properties, combine, cylinder_properties
from cadcog.rig.geometry import FloatArray, IdealReading, face_normal, ideal_reading
from cadcog.rig.inclinometer import InclinometerConfig


@dataclass(frozen=True)
class ProofMass:
    """A homogeneous box occupying ``[0, size_mm]`` in the body frame.

    ``mass_kg`` is the mass as machined, holes drilled, bolts out; the density is derived from it.
    """

    size_mm: tuple[float, float, float]
    mass_kg: float
    material: str


@dataclass(frozen=True)
class HoleSpec:
    """The drilled and tapped hole under every suspension point.

    Attributes
    ----------
    diameter_mm : float
        Diameter of the modelled cylinder (the tap drill: thread crests are removed material only
        down to this diameter).
    depth_mm : float
        Depth of the flat-bottomed cylinder.
    wire_exit_height_mm : float
        Height above the face at which the wire leaves the bolt (the top of its head). The bolt
        itself is not part of the ground truth: it is screwed into the hole in use only, and a
        mass on the suspension line does not change the direction of that line.
    """

    diameter_mm: float
    depth_mm: float
    wire_exit_height_mm: float


@dataclass(frozen=True)
class SuspensionPoint:
    """A suspension point: the centre of its hole on a face of the proof mass."""

    id: str
    face: str
    position_mm: tuple[float, float, float]

    @property
    def normal(self) -> FloatArray:
        """Outward unit normal of its face."""
        return face_normal(self.face)


@dataclass(frozen=True)
class MEVolume:
    """One sub-volume of the measurement equipment: a homogeneous box.

    ``cog_uncertainty_cube_mm`` is the edge of the cube, centred on the CAD CoG, in which the real
    CoG of this sub-volume is taken to lie with uniform probability (docs/method.md §4.1).
    """

    name: str
    size_mm: tuple[float, float, float]
    center_mm: tuple[float, float, float]
    mass_kg: float
    cog_uncertainty_cube_mm: float

    @property
    def min_mm(self) -> FloatArray:
        return np.asarray(self.center_mm) - 0.5 * np.asarray(self.size_mm)

    @property
    def max_mm(self) -> FloatArray:
        return np.asarray(self.center_mm) + 0.5 * np.asarray(self.size_mm)


InclinometerModel = Literal["hang-bias", "paper-averaged"]
WireModel = Literal["one-wire", "paper", "elastica"]
INCLINOMETER_MODELS: tuple[InclinometerModel, ...] = ("hang-bias", "paper-averaged")
WIRE_MODELS: tuple[WireModel, ...] = ("one-wire", "paper", "elastica")


@dataclass(frozen=True)
class ErrorOptions:
    """The ``[error_model]`` table of a rig file: everything not already in its other tables.

    Defaults are the paper's, or documented assumptions (``docs/montecarlo.md``).
    """

    samples: int = 10
    inclinometer_model: InclinometerModel = "hang-bias"
    sensor_noise_deg: float = 0.05
    play_mm: float = 1.0
    wire_model: WireModel = "one-wire"
    wire_offset_max_mm: float = 1.0
    wire_bending_stiffness_n_mm2: float = 30.0
    wire_stiffness_rel_uncertainty: float = 0.5


@dataclass(frozen=True)
class SwingOptions:
    """The ``[swing]`` table: what the inertia estimate needs besides the swings
    (``docs/inertia.md``). Defaults are documented assumptions.

    Attributes
    ----------
    wire_length_mm : float
        Free wire from the fixed clamp to where it leaves the object (0: a pivot).
    wire_length_sigma_mm : float
        1 σ of that length (a tape measure's reading, the clamp's own play).
    sensor_position_mm : tuple of 3 floats or None
        The sensor's sensing point, object frame; None: the centre of the ME volume whose name
        contains ``inclinometer``, ``accelerometer`` or ``phone``, else the ME's centre of mass
        (the measured tensor does not depend on it; a simulated swing's amplitudes do).
    sensor_position_sigma_mm : float
        1 σ per axis of that point.
    frequency_model_rel : float or None
        Relative 1 σ of every modelled frequency for what the linear model leaves out (air's
        added inertia, the wire's mass and torsion): an assumption. None (the default): the
        air the object carries, from its box and mass
        (:attr:`cadcog.dynamics.context.InertiaContext.frequency_model_rel`).
    me_inertia_rel : float
        Relative 1 σ of each ME volume's own inertia (a homogeneous box is an approximation).
    """

    wire_length_mm: float = 300.0
    wire_length_sigma_mm: float = 2.0
    sensor_position_mm: tuple[float, float, float] | None = None
    sensor_position_sigma_mm: float = 5.0
    frequency_model_rel: float | None = None
    me_inertia_rel: float = 0.3


def me_cog_sigma_mm(masses_kg: npt.ArrayLike, edges_mm: npt.ArrayLike) -> float:
    """Per-axis standard deviation of the ME CoG error: ``√(Σ (m_k/m_ME)² a_k² / 12)``.

    Examples
    --------
    >>> round(me_cog_sigma_mm([1, 1, 1, 1], [10, 10, 10, 10]), 6)  # 10/√12 · √(4/16)
    1.443376
    """
    m = np.asarray(masses_kg, dtype=float)
    a = np.asarray(edges_mm, dtype=float)
    return float(np.sqrt(np.sum((m / m.sum() * a) ** 2) / 12.0))


def me_cog_cov_mm2(volumes: tuple[MEVolume, ...]) -> FloatArray:
    """Covariance of the ME CoG from the sub-volumes' uniform uncertainty cubes (mm²).

    ``e_ME = Σ (m_k/m_ME) U_k`` with ``U_k`` uniform in a cube of edge ``a_k``: independent
    axes, each of variance ``Σ (m_k/m_ME)² a_k²/12``.
    """
    sigma = me_cog_sigma_mm(
        [v.mass_kg for v in volumes], [v.cog_uncertainty_cube_mm for v in volumes]
    )
    return np.asarray(sigma**2 * np.eye(3))


@dataclass(frozen=True)
class Rig:
    """A validated rig: read one with ``cadcog.load_rig(path)`` (:func:`cadcog.rig.file.load_rig`).

    Lengths in mm and masses in kg in the body frame of ``docs/rig.md``; the ``analytic_*``
    methods are the closed forms the CAD is checked against.
    """

    name: str
    source: Path
    proof_mass: ProofMass
    holes: HoleSpec
    suspension_points: tuple[SuspensionPoint, ...]
    me_volumes: tuple[MEVolume, ...]
    inclinometer: InclinometerConfig
    error_options: ErrorOptions = field(default_factory=ErrorOptions)
    swing: SwingOptions = field(default_factory=SwingOptions)

    @property
    def inclinometer_range_deg(self) -> float:
        """Measurement range of the inclinometer (degrees, each axis)."""
        return self.inclinometer.range_deg

    @property
    def weight_n(self) -> float:
        """Weight of the hung assembly (proof mass + ME): the wire's tension (N)."""
        return self.analytic_assembly.mass_kg * STANDARD_GRAVITY_M_S2

    # --- derived geometry -------------------------------------------------------------------
    @property
    def hole_radius_mm(self) -> float:
        """Radius of the suspension holes (mm)."""
        return 0.5 * self.holes.diameter_mm

    @property
    def hole_volume_mm3(self) -> float:
        """Volume of one hole."""
        return float(np.pi * self.hole_radius_mm**2 * self.holes.depth_mm)

    @property
    def proof_mass_volume_mm3(self) -> float:
        """Box volume less every hole."""
        box = float(np.prod(self.proof_mass.size_mm))
        return box - len(self.suspension_points) * self.hole_volume_mm3

    @property
    def proof_mass_density_kg_mm3(self) -> float:
        """Density implied by the proof mass's mass and holed volume."""
        return self.proof_mass.mass_kg / self.proof_mass_volume_mm3

    def wire_exit_mm(self, point: SuspensionPoint) -> FloatArray:
        """Where the wire leaves the bolt: the hole centre raised along the face normal."""
        return np.asarray(point.position_mm) + self.holes.wire_exit_height_mm * point.normal

    # --- closed-form mass properties ------------------------------------------------------
    def analytic_hole(self, point: SuspensionPoint) -> MassProperties:
        """The material removed by one hole (positive mass, proof-mass density)."""
        return cylinder_properties(
            point.position_mm,
            -point.normal,
            self.hole_radius_mm,
            self.holes.depth_mm,
            density_kg_mm3=self.proof_mass_density_kg_mm3,
        )

    @cached_property
    def analytic_proof_mass(self) -> MassProperties:
        """Closed-form mass properties of the proof mass: box minus its holes."""
        size = np.asarray(self.proof_mass.size_mm)
        box_mass = self.proof_mass_density_kg_mm3 * float(np.prod(size))
        box = box_properties(size, 0.5 * size, mass_kg=box_mass)
        holes = [self.analytic_hole(p).scaled(-1.0) for p in self.suspension_points]
        return combine([box, *holes])

    def analytic_me_volume(self, volume: MEVolume) -> MassProperties:
        """Closed-form mass properties of one ME sub-volume (a homogeneous box)."""
        return box_properties(volume.size_mm, volume.center_mm, mass_kg=volume.mass_kg)

    @cached_property
    def analytic_me(self) -> MassProperties:
        """Closed-form mass properties of the whole measurement equipment."""
        return combine(self.analytic_me_volume(v) for v in self.me_volumes)

    @property
    def me_cog_cov_mm2(self) -> FloatArray:
        """Covariance of the ME CoG (mm²), see :func:`me_cog_cov_mm2`."""
        return me_cog_cov_mm2(self.me_volumes)

    @cached_property
    def analytic_assembly(self) -> MassProperties:
        """Proof mass plus measurement equipment."""
        return combine([self.analytic_proof_mass, self.analytic_me])

    def ideal_readings(self, cog_mm: FloatArray | None = None) -> dict[str, IdealReading]:
        """Noise-free readings when hanging from each suspension point's wire exit.

        Parameters
        ----------
        cog_mm : ndarray, shape (3,), optional
            Assembly CoG; defaults to the closed-form one.
        """
        g = self.analytic_assembly.cog_mm if cog_mm is None else cog_mm
        return {p.id: ideal_reading(self.wire_exit_mm(p), g) for p in self.suspension_points}
