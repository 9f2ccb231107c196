"""The spacecraft in each of its configurations: parts moved about hinges or along rails, masses
changed, applied to the bodies already counted (the CAD is not read again).

A configurations file (TOML)::

    [[configurations]]
    name = "deployed"                    # letters, digits, _ and -
    [[configurations.moves]]
    parts = ["*panel_+x*"]               # patterns of bodies or assemblies (as --exclude's)
    axis_point_mm = [50.0, 0.0, -170.0]  # a rotation about a hinge: a point on its axis,
    axis_direction = [0.0, 1.0, 0.0]     # its direction (right-hand rule),
    angle_deg = 90.0                     # and the angle
    [[configurations.moves]]
    parts = ["boom*"]
    translation_mm = [0.0, 0.0, 100.0]   # or a translation
    [[configurations.mass_changes]]
    parts = ["propellant*"]
    mass_fraction = 0.3                  # of the CAD's mass left (a tank drawn down evenly)

Moves apply in order, each to its parts' current placement (a panel on a boom: the boom's move,
then the panel's about its hinge, which the boom's move does not carry: give the hinge where it
is after the earlier moves). A moved body keeps its shape: its CoG turns about the axis point,
its inertia tensor turns with it (``R J Rᵀ``), its mass and stated uncertainty are its own. A
mass change scales a body's mass and inertia (its CoG stays): the stated relative uncertainty
scales with it. The configuration's totals and their uncertainty then follow exactly as the CAD's
do (:func:`cadcog.spacecraft.items.linear_prior`).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import CadcogError
from cadcog.core.paramfile import TableReader, read_toml
from cadcog.core.results import JsonResult
from cadcog.core.units import deg_to_rad
from cadcog.mass.materials import glob_match
from cadcog.mass.properties import MassProperties, combine
from cadcog.spacecraft.envelope import EnvelopeCheck
from cadcog.spacecraft.items import items_from_bodies, linear_prior, parameter_prior_cov

FloatArray = npt.NDArray[np.float64]

_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_-]{0,63}")

#: Most configurations a file may list, and moves or mass changes per configuration.
MAX_CONFIGURATIONS = 100
MAX_MOVES = 100

#: A hinge direction shorter than this (in the file's numbers) has no direction.
MIN_AXIS_NORM = 1e-9


@dataclass(frozen=True)
class Move:
    """A rigid move of some parts: ``x → R (x - a) + a + t``."""

    parts: tuple[str, ...]
    rotation: FloatArray  # (3, 3)
    axis_point_mm: FloatArray
    translation_mm: FloatArray
    key: str  # where it is in the file (for messages)

    def point(self, x_mm: npt.ArrayLike) -> FloatArray:
        """A point moved."""
        x = np.asarray(x_mm, dtype=float)
        return np.asarray(
            self.rotation @ (x - self.axis_point_mm) + self.axis_point_mm + self.translation_mm
        )

    def properties(self, p: MassProperties) -> MassProperties:
        """A body's mass properties moved (CoG moved, inertia turned)."""
        return moved_properties(p, self.rotation, self.point(np.zeros(3)))


def moved_properties(p: MassProperties, rotation: FloatArray, t_mm: FloatArray) -> MassProperties:
    """Mass properties moved rigidly, ``x → R x + t``: ``c' = R c + t``, ``J' = R J Rᵀ``."""
    r = np.asarray(rotation, dtype=float)
    return MassProperties(p.mass_kg, r @ p.cog_mm + t_mm, r @ p.inertia_kg_mm2 @ r.T, p.volume_mm3)


@dataclass(frozen=True)
class MassChange:
    """Some parts' mass scaled by ``fraction`` (their CoG kept)."""

    parts: tuple[str, ...]
    fraction: float
    key: str


@dataclass(frozen=True)
class Configuration:
    """A named configuration: its moves, then its mass changes."""

    name: str
    moves: tuple[Move, ...]
    mass_changes: tuple[MassChange, ...]


def rotation_about(axis_direction: npt.ArrayLike, angle_deg: float) -> FloatArray:
    """The rotation by ``angle_deg`` about a direction (right-hand rule; Rodrigues).

    Examples
    --------
    >>> rotation_about([0, 0, 1], 90.0).round(12).tolist()
    [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    """
    u = np.asarray(axis_direction, dtype=float)
    big = float(np.max(np.abs(u))) if u.size else 0.0
    if not (np.isfinite(big) and big > MIN_AXIS_NORM):
        raise ValueError(f"axis direction {u.tolist()} has no direction")
    u = u / big  # scaled first: a direction of 1e200 squares to infinity
    u = u / float(np.linalg.norm(u))
    theta = float(deg_to_rad(angle_deg))
    k = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
    return np.asarray(np.eye(3) + np.sin(theta) * k + (1.0 - np.cos(theta)) * (k @ k))


def body_names(body: Any) -> tuple[str, ...]:
    """Every name a pattern may match on a counted body: its path, the path below its top
    assembly, each assembly path above it, each node's name and each product's."""
    nodes = tuple(body.nodes)
    names = [body.path]
    if len(nodes) > 1:
        names.append("/".join(nodes[1:]))
    names.extend("/".join(nodes[:k]) for k in range(1, len(nodes)))
    names.extend(reversed(nodes))
    names.extend(p for p in getattr(body, "products", ()) if p)
    return tuple(dict.fromkeys(names))


def matches(patterns: Sequence[str], body: Any) -> bool:
    """Whether any pattern matches any of the body's names (:func:`body_names`)."""
    names = body_names(body)
    return any(glob_match(n, pat) for pat in patterns for n in names)


def _parts(t: TableReader) -> tuple[str, ...]:
    if t.is_string("parts"):
        return (t.string("parts"),)
    return tuple(t.strings("parts"))


def load_configurations(path: str | Path) -> tuple[Configuration, ...]:
    """Read a configurations file (module docstring).

    Raises
    ------
    ParameterFileError
        Naming the file and key: a bad or repeated name, a hinge without a direction, a move
        with both or neither of a rotation and a translation, a mass fraction outside [0, 10].
    """
    p = Path(path)
    root = TableReader(read_toml(p), p)
    tables = root.tables("configurations")
    if len(tables) > MAX_CONFIGURATIONS:
        raise root.error("configurations", f"{len(tables)}; at most {MAX_CONFIGURATIONS}")
    out: list[Configuration] = []
    for t in tables:
        name = t.string("name")
        if not _NAME.fullmatch(name):
            raise t.error("name", f"{name!r}: expected letters, digits, _ and -, from a letter")
        if any(c.name == name for c in out):
            raise t.error("name", f"{name!r} is listed twice")
        moves: list[Move] = []
        for m in t.tables("moves", min_count=0) if t.has("moves") else []:
            parts = _parts(m)
            rotates = m.has("angle_deg") or m.has("axis_direction") or m.has("axis_point_mm")
            if rotates == m.has("translation_mm"):
                raise m.error(
                    "translation_mm" if rotates else "angle_deg",
                    "give a rotation (axis_point_mm, axis_direction, angle_deg) or a "
                    "translation (translation_mm), one of them",
                )
            if rotates:
                point = np.array(m.vector("axis_point_mm"))
                direction = m.vector("axis_direction")
                angle = m.number("angle_deg")
                try:
                    rot = rotation_about(direction, angle)
                except ValueError as exc:
                    raise m.error("axis_direction", f"{exc}: a hinge needs an axis") from None
                move = Move(parts, rot, point, np.zeros(3), m.key("parts"))
            else:
                shift = np.array(m.vector("translation_mm"))
                move = Move(parts, np.eye(3), np.zeros(3), shift, m.key("parts"))
            m.finish()
            moves.append(move)
        changes: list[MassChange] = []
        for c in t.tables("mass_changes", min_count=0) if t.has("mass_changes") else []:
            parts = _parts(c)
            fraction = c.number("mass_fraction", nonnegative=True)
            if fraction > 10.0:
                raise c.error("mass_fraction", f"{fraction:g}: expected a fraction of 0 to 10")
            c.finish()
            changes.append(MassChange(parts, fraction, c.key("parts")))
        if len(moves) + len(changes) > MAX_MOVES:
            raise t.error("moves", f"more than {MAX_MOVES} moves and mass changes")
        t.finish()
        out.append(Configuration(name, tuple(moves), tuple(changes)))
    root.finish()
    return tuple(out)


def apply_configuration(
    bodies: Sequence[Any], config: Configuration, source: str = ""
) -> list[Any]:
    """The bodies as they are in ``config`` (each a copy with moved or scaled ``properties``).

    Raises
    ------
    CadcogError
        A move's or mass change's parts match no body (naming the file's key), or a move
        matches every body.
    """
    moves = placements(bodies, config, source)
    out = []
    for b in bodies:
        if b.path in moves:
            b = replace(b, properties=moved_properties(b.properties, *moves[b.path]))
        out.append(b)
    for change in config.mass_changes:
        for i in _matched(change.parts, out, change.key, config.name, source):
            out[i] = replace(out[i], properties=out[i].properties.scaled(change.fraction))
    kept = [b for b in out if b.properties.mass_kg > 0.0]  # a fraction of 0: the part is gone
    if not kept:
        raise CadcogError(f"{source}: configuration {config.name!r} leaves no mass")
    return kept


@dataclass(frozen=True, repr=False)
class ConfigurationProperties(JsonResult):
    """One configuration's mass properties and their first-order uncertainty."""

    name: str
    total: MassProperties
    mass_sigma_kg: float
    cog_cov_mm2: FloatArray
    cog_mass_cov_mm_kg: FloatArray
    moved: tuple[str, ...]
    envelope: EnvelopeCheck | None = None
    overlaps: tuple[str, ...] = ()

    @property
    def mass_kg(self) -> float:
        return self.total.mass_kg

    @property
    def cog_mm(self) -> FloatArray:
        return self.total.cog_mm

    @property
    def cog_sigma_mm(self) -> FloatArray:
        """1 σ of the CoG per axis (mm)."""
        return np.sqrt(np.maximum(np.diag(self.cog_cov_mm2), 0.0))

    @property
    def principal_moments_kg_mm2(self) -> FloatArray:
        """Principal moments about the CoG, smallest first (kg·mm²)."""
        return np.asarray(np.linalg.eigvalsh(self.total.inertia_kg_mm2), dtype=float)

    def to_dict(self) -> dict[str, Any]:
        out = {
            "mass_kg": self.total.mass_kg,
            "mass_sigma_kg": self.mass_sigma_kg,
            "cog_mm": self.total.cog_mm.tolist(),
            "cog_cov_mm2": self.cog_cov_mm2.tolist(),
            "cog_sigma_mm": self.cog_sigma_mm.tolist(),
            "inertia_kg_mm2": self.total.inertia_kg_mm2.tolist(),
            "inertia_about": "centre of gravity, model axes",
            "changed": list(self.moved),
        }
        if self.envelope is not None:
            out["envelope"] = self.envelope.to_dict()
        out["overlaps"] = list(self.overlaps)
        return out


def _changed(before: MassProperties, after: MassProperties | None) -> bool:
    """Whether a body's mass properties changed (moved, scaled or gone)."""
    if after is None:
        return True
    return not (
        after.mass_kg == before.mass_kg
        and np.allclose(after.cog_mm, before.cog_mm, rtol=0.0, atol=1e-9)
        and np.allclose(after.inertia_kg_mm2, before.inertia_kg_mm2, rtol=1e-12, atol=1e-12)
    )


@dataclass(frozen=True)
class _Linear:
    """A configuration's totals and their Jacobians in the model's own item parameters ``θ``
    (:mod:`cadcog.spacecraft.items`), with ``θ``'s covariance."""

    bodies: list[Any]
    total: MassProperties
    jac_mass: FloatArray  # (4N,)
    jac_cog: FloatArray  # (3, 4N)
    prior_cov: FloatArray  # (4N, 4N)

    @property
    def jac_moment(self) -> FloatArray:
        """``∂S/∂θ`` of the first moment ``S = M G`` (kg·mm)."""
        return np.asarray(
            self.total.cog_mm[:, None] * self.jac_mass[None, :] + self.total.mass_kg * self.jac_cog
        )


def _linear(bodies: Sequence[Any], config: Configuration | None, source: str) -> _Linear:
    """:class:`_Linear` of the model (``config`` None) or of a configuration. An item keeps its
    parameters: its relative mass error, and its CoG error turned with it (``R s``: a panel's
    CoG uncertainty along its length stays along its length when it deploys); an item a
    configuration removes has none left."""
    base_items, _ = items_from_bodies(bodies)
    cov = parameter_prior_cov(base_items)
    index = {item.key: k for k, item in enumerate(base_items)}
    n = len(base_items)
    moved = list(bodies) if config is None else apply_configuration(bodies, config, source)
    turns = {} if config is None else placements(bodies, config, source)
    items, fixed = items_from_bodies(moved)
    own = linear_prior(items, fixed)
    jm = np.zeros(4 * n)
    jg = np.zeros((3, 4 * n))
    first = {b.item: b.path for b in moved if b.sigma_rel is not None}
    for k, item in enumerate(items):
        b = index.get(item.key)
        if b is None:  # fixed as modelled (no uncertainty): stays fixed
            continue
        rot = turns.get(first.get(item.key, ""), (np.eye(3), np.zeros(3)))[0]
        jm[b] = own.jac_mass[k]
        jg[:, b] = own.jac_cog[:, k]
        cols = slice(len(items) + 3 * k, len(items) + 3 * k + 3)
        jg[:, n + 3 * b : n + 3 * b + 3] = own.jac_cog[:, cols] @ rot
    total = combine(b.properties for b in moved)
    return _Linear(moved, total, jm, jg, cov)


def configuration_properties(
    bodies: Sequence[Any], configs: Sequence[Configuration], source: str = ""
) -> tuple[ConfigurationProperties, ...]:
    """Each configuration's totals and first-order uncertainty, from the counted bodies, in the
    model's own item parameters (:func:`_linear`)."""
    out = []
    for config in configs:
        lin = _linear(bodies, config, source)
        after = {b.path: b.properties for b in lin.bodies}
        changed = tuple(b.path for b in bodies if _changed(b.properties, after.get(b.path)))
        p = lin.prior_cov
        out.append(
            ConfigurationProperties(
                config.name,
                lin.total,
                float(np.sqrt(max(float(lin.jac_mass @ p @ lin.jac_mass), 0.0))),
                np.asarray(lin.jac_cog @ p @ lin.jac_cog.T),
                np.asarray(lin.jac_cog @ p @ lin.jac_mass),
                changed,
            )
        )
    return tuple(out)


@dataclass(frozen=True)
class ConfigurationDelta:
    """What a configuration changes against the model as it stands: mass ``ΔM``, first moment
    ``ΔS`` and their covariance from the items' stated uncertainty (a measured spacecraft,
    whose own figures come from a test, becomes ``G' = (M G + ΔS) / (M + ΔM)``)."""

    name: str
    mass_kg: float
    moment_kg_mm: FloatArray
    moment_cov_kg2_mm2: FloatArray
    mass_var_kg2: float
    moment_mass_cov_kg2_mm: FloatArray


def configuration_deltas(
    bodies: Sequence[Any], configs: Sequence[Configuration], source: str = ""
) -> tuple[ConfigurationDelta, ...]:
    """Each configuration's change of mass and first moment with their covariance: the
    Jacobians in the model's item parameters (:func:`_linear`), as configured minus as
    modelled."""
    base = _linear(bodies, None, source)
    out = []
    for config in configs:
        lin = _linear(bodies, config, source)
        dm = lin.jac_mass - base.jac_mass
        ds = lin.jac_moment - base.jac_moment
        p = base.prior_cov
        out.append(
            ConfigurationDelta(
                config.name,
                lin.total.mass_kg - base.total.mass_kg,
                lin.total.mass_kg * lin.total.cog_mm - base.total.mass_kg * base.total.cog_mm,
                np.asarray(ds @ p @ ds.T),
                float(dm @ p @ dm),
                np.asarray(ds @ p @ dm),
            )
        )
    return tuple(out)


def _matched(
    parts: Sequence[str], bodies: Sequence[Any], key: str, config: str, source: str
) -> list[int]:
    """The indices of the bodies ``parts`` match; every pattern must match one."""
    for pattern in parts:
        if not any(matches([pattern], b) for b in bodies):
            raise CadcogError(
                f"{source}: {key}: {pattern!r} matches no body of the model (configuration "
                f"{config!r}; * and ? are wildcards, [ ] match themselves)"
            )
    return [i for i, b in enumerate(bodies) if matches(parts, b)]


def placements(
    bodies: Sequence[Any], config: Configuration, source: str = ""
) -> dict[str, tuple[FloatArray, FloatArray]]:
    """Each moved body's whole move in ``config`` (its moves composed in order), as ``x → R x
    + t`` (mm), by path."""
    moves: dict[str, tuple[FloatArray, FloatArray]] = {}
    for move in config.moves:
        hit = [bodies[i] for i in _matched(move.parts, bodies, move.key, config.name, source)]
        if len(hit) == len(bodies):
            raise CadcogError(
                f"{source}: {move.key}: {list(move.parts)} matches every body (configuration "
                f"{config.name!r}): that is a change of frame"
            )
        for b in hit:
            r0, t0 = moves.get(b.path, (np.eye(3), np.zeros(3)))
            r = move.rotation @ r0
            t = move.point(t0)  # R (t0 - a) + a + t_m
            moves[b.path] = (r, t)
    return moves


def overlap_notes(
    solids: Sequence[tuple[str, Any]],
    bodies: Sequence[Any],
    configs: Sequence[Configuration],
    *,
    scale_to_mm: float = 1.0,
    source: str = "",
) -> dict[str, list[str]]:
    """Per configuration, a note for each moved body that overlaps one it did not move with
    (:func:`cadcog.cad.moved.moved_overlaps`): the mass properties count both whole."""
    from cadcog.cad.moved import moved_overlaps

    out: dict[str, list[str]] = {}
    for config in configs:
        pairs = moved_overlaps(solids, placements(bodies, config, source), scale_to_mm=scale_to_mm)
        out[config.name] = [
            f"configuration {config.name!r}: {a} overlaps {b} by {v:.4g} mm³ once moved "
            "(both counted whole: check the hinge, the angle or the parts moved)"
            for a, b, v in pairs
        ]
    return out


def cached_overlap_notes(
    bodies: Sequence[Any],
    configs: Sequence[Configuration],
    read: Callable[[], Any],
    model_file: Path,
    configurations_file: Path,
    *,
    units: str | None,
    source: str = "",
) -> dict[str, list[str]]:
    """:func:`overlap_notes` of every configuration, cached by the content of the model file
    and the configurations file, the bodies counted and the ``units`` override: one entry
    whichever command asks (``massprops``, ``check``, ``balance``), and a second run reads no
    CAD. ``read()`` gives the model (a :class:`cadcog.cad.stepmodel.StepModel`)."""
    from cadcog.cad import cache

    kept = sorted(b.path for b in bodies)

    def compute() -> dict[str, list[str]]:
        from cadcog.cad.stepmass import unit_scale

        model = read()
        scale = unit_scale(model, units)[0]
        solids = [(b.path, b.shape) for b in model.solids if b.path in set(kept)]
        return overlap_notes(solids, bodies, configs, scale_to_mm=scale, source=source)

    key = {"kind": "configuration overlaps", "bodies": kept, "units": units}
    notes, _ = cache.cached_data(
        key,
        [model_file, configurations_file],
        compute,
        code=("cad", "core", "mass", "spacecraft"),
    )
    return {str(k): [str(n) for n in v] for k, v in notes.items()}


def report_overlaps(
    report: Any,
    configs: Sequence[Configuration],
    read: Callable[[], Any],
    model: Path,
    configurations: Path,
    *,
    units: str | None,
    strict: bool = False,
) -> Any:
    """A mass report (:class:`cadcog.spacecraft.mass_summary.MassReport`) whose configurations
    carry their overlap notes (:func:`cached_overlap_notes`): what ``massprops
    --configurations`` and :func:`cadcog.mass_properties` both report; with ``strict`` a note
    is an error."""
    if not report.configurations:
        return report
    notes = cached_overlap_notes(
        report.result.bodies,
        configs,
        read,
        model,
        configurations,
        units=units,
        source=str(configurations),
    )
    first = next((n for c in configs for n in notes.get(c.name, [])), None)
    if strict and first is not None:
        raise CadcogError(f"{configurations}: {first} (--strict)")
    checked = tuple(
        replace(c, overlaps=tuple(notes.get(c.name, []))) for c in report.configurations
    )
    return replace(report, configurations=checked)


def configured_result(result: Any, config: Configuration, source: str = "") -> Any:
    """A model's counted result (:class:`cadcog.cad.massresults.ModelMassProperties`) as it is in
    ``config``: its bodies moved or scaled and its total recombined; the bounding box stays the
    model's as it stands (the envelope's geometric centre)."""
    moved = apply_configuration(result.bodies, config, source)
    return replace(result, bodies=tuple(moved), total=combine(b.properties for b in moved))
