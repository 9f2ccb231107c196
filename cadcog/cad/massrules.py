"""Which rules of a materials file a STEP body falls under: the names a rule may match, the
density each body gets and where it came from, its mass-uncertainty and growth items, and the
rules that match nothing (see :func:`cadcog.cad.stepmass.model_mass_properties`)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from cadcog.cad.bodies import Body
from cadcog.cad.stepmodel import StepBody
from cadcog.core.errors import CadcogError
from cadcog.mass.materials import (
    DENSITY_RANGE_KG_M3,
    ItemRule,
    MaterialMap,
    glob_match,
    is_placeholder_material,
)


def matches_any(patterns: Sequence[str], body: StepBody) -> bool:
    """Whether any pattern matches the body's own names, an assembly path above it, or such
    a path below the common top assembly."""
    if not patterns:
        return False
    root = f"{body.root}/" if body.root else ""
    below = tuple(a[len(root) :] for a in body.assembly_paths if root and a.startswith(root))
    names = (*body.match_names(), *body.assembly_paths, *below)
    return any(glob_match(n, pat) for pat in patterns for n in names)


def item_rules(
    body: StepBody, materials: MaterialMap | None
) -> tuple[ItemRule | None, ItemRule | None]:
    """The body's mass uncertainty and growth allowance rules (item = deepest matched node)."""
    if materials is None:
        return None, None
    candidates = item_candidates(body)
    return materials.uncertainty(candidates), materials.growth(candidates)


def item_candidates(body: StepBody) -> Sequence[tuple[str, tuple[str, ...]]]:
    """(node path, names a rule may match), the body first, then its assemblies deepest first
    (:attr:`cadcog.cad.stepmodel.StepBody.item_candidates`)."""
    return body.item_candidates


def unmatched_rules(materials: MaterialMap, bodies: Sequence[StepBody]) -> list[str]:
    """``"[table] pattern"`` of every rule that matches no name of any body or assembly: most
    often a typo, whose bodies then fall to a later rule (a default) without a word."""
    names: set[str] = set()
    for b in bodies:
        names.update(b.rule_names)
        for _, n in item_candidates(b):
            names.update(n)
    tables = {
        "materials": [p for p, _ in materials.rules],
        "surfaces": [p for p, _, _ in materials.surface_rules],
        "mass_uncertainty": [p for p, _, _ in materials.uncertainty_rules],
        "growth_allowance": [p for p, _, _ in materials.growth_rules],
        "cog_uncertainty": [p for p, _ in materials.cog_rules],
    }
    return [
        f"[{table}] {pattern!r}"
        for table, patterns in tables.items()
        for pattern in dict.fromkeys(patterns)
        if not any(glob_match(n, pattern) for n in names)
    ]


def assign_densities(
    bodies: list[Body],
    materials: MaterialMap | None,
    total_mass_kg: float | None,
    notes: list[str],
    src: Any,
    info: list[str] | None = None,
) -> None:
    """Fill each body's material, density and its source; raise for solids without one.
    ``notes`` get what the user should look at (placeholders); ``info`` what was done as the
    materials file asked (its catch-all rule replacing a material stamped on every solid)."""
    solids = [b for b in bodies if b.step.kind == "solid"]
    xcaf_usable = [b for b in solids if b.step.material and b.step.material.density_kg_m3]
    uniform = materials is None and total_mass_kg is not None and not xcaf_usable
    origin = (materials.source if materials is not None else "") or "materials"
    bad_xcaf: set[str] = set()
    missing: list[str] = []
    placeholder: dict[str, list[Body]] = {}  # placeholder STEP material → bodies that used it
    defaulted: dict[str, list[Body]] = {}  # ... → bodies the catch-all rule gave a density
    overridden: dict[tuple[str, str], list[Body]] = {}  # (rule, STEP material) → bodies
    lo_d, hi_d = DENSITY_RANGE_KG_M3
    # One material stamped on every solid is the exporter's default (Fusion 360's 'Steel'):
    # a catch-all rule replaces it, as it replaces a placeholder.
    stamps = {(m.name, m.density_kg_m3) for b in xcaf_usable if (m := b.step.material)}
    stamped_default = len(solids) >= 2 and len(xcaf_usable) == len(solids) and len(stamps) == 1
    for b in bodies:
        if b.step.kind == "surface":
            _assign_surface(b, materials, origin)
            continue
        outcome = _assign_solid(b, materials, origin, uniform, stamped_default)
        xm = b.step.material
        if outcome == "defaulted" and xm is not None:
            defaulted.setdefault(xm.name, []).append(b)
        elif outcome == "overridden" and xm is not None:
            overridden.setdefault((b.source, xm.name), []).append(b)
        elif outcome == "placeholder" and xm is not None:
            placeholder.setdefault(xm.name, []).append(b)
        elif outcome == "missing":
            if xm is not None:
                bad_xcaf.add(f"{xm.name} ({xm.raw or 'no density'})")
            missing.append(b.step.path)
    notes += _placeholder_notes(placeholder)
    _defaulted_lines(defaulted, stamped_default, notes, info)
    if info is not None:
        info += [
            f"{len(group)} solid(s) with their own STEP material {name!r} "
            f"({group[0].step.material.density_kg_m3:g} kg/m³) took {rule} instead (a named "
            f'rule overrides the STEP\'s material; a catch-all "*" does not): '
            f"{_listed([g.step.path for g in group])}"
            for (rule, name), group in sorted(overridden.items())
            if group[0].step.material is not None
        ]
    notes += _stamp_notes(solids, materials is not None)
    if bad_xcaf:
        notes.append(
            "STEP materials without a usable density (kg/m³ between "
            f"{lo_d:g} and {hi_d:g}): {', '.join(sorted(bad_xcaf))}"
        )
    if missing:
        shown = _listed(missing)
        raise CadcogError(
            f"{src}: no density for {len(missing)} solid(s): {shown}; give a materials file "
            '(--materials; a catch-all "*" rule gives a default) or --density-kg-m3'
        )


def _assign_surface(b: Body, materials: MaterialMap | None, origin: str) -> None:
    """A surface body's areal density from the materials file's ``[surfaces]``, or none (it is
    left out)."""
    found = materials.assign_surface(b.step.rule_names) if materials is not None else None
    if found is None:
        b.material, b.source = "none", "left out (no areal density)"
        b.areal_density_kg_m2 = 0.0
    else:
        b.material = found.material
        b.source = f"materials rule {found.rule!r} ({origin})"
        b.areal_density_kg_m2 = found.areal_density_kg_m2


def _assign_solid(
    b: Body, materials: MaterialMap | None, origin: str, uniform: bool, stamped_default: bool
) -> str | None:
    """A solid's material and density: a materials rule (a catch-all one only where the STEP's
    own material is a placeholder or a stamped default, or the file says rules come first),
    else uniform, else the STEP's own material. Returns what the caller must note:
    ``"defaulted"`` (a catch-all rule replaced the STEP's placeholder or stamp),
    ``"overridden"`` (a named rule replaced the STEP's own material, of another density),
    ``"placeholder"`` (the STEP's placeholder kept), ``"missing"`` (no density), or None."""
    lo_d, hi_d = DENSITY_RANGE_KG_M3
    found = materials.assign(b.step.rule_names) if materials is not None else None
    xm = b.step.material
    usable = xm is not None and xm.density_kg_m3 and lo_d <= xm.density_kg_m3 <= hi_d
    named_stub = bool(usable and xm is not None and is_placeholder_material(xm.name))
    stub = named_stub or stamped_default
    # A catch-all rule of a materials file is a default: the STEP's own material first.
    default_only = (
        found is not None and found.rule == "*" and materials is not None and materials.step_first
    )
    if found is not None and default_only and usable and not stub:
        found = None
    if found is not None:
        b.material, b.density_kg_m3 = found.material, found.density_kg_m3
        b.source = f"materials rule {found.rule!r} ({origin})"
        if stub and default_only and xm is not None:
            return "defaulted"
        named = found.rule != "*"  # a catch-all is a default (or --density-kg-m3, asked for)
        if named and usable and not stub and xm is not None:
            return "overridden" if xm.density_kg_m3 != found.density_kg_m3 else None
        return None
    if uniform:
        b.material, b.density_kg_m3 = "uniform", 1000.0
        b.source = "uniform (scaled to --total-mass-kg)"
        return None
    if usable and xm is not None and xm.density_kg_m3 is not None:
        b.material, b.density_kg_m3 = xm.name, xm.density_kg_m3
        b.source = f"STEP material {xm.name!r} ({xm.density_kg_m3:g} kg/m³)"
        if named_stub:
            b.source += ", a placeholder"
            return "placeholder"
        return None
    return "missing"


def _placeholder_notes(placeholder: dict[str, list[Body]]) -> list[str]:
    """A note per exporter's placeholder material kept: which solids, how much mass."""
    notes = []
    for name, group in sorted(placeholder.items()):
        mass_g = 1e3 * sum(g.props.mass_kg * g.density_kg_mm3 for g in group)
        notes.append(
            f"{len(group)} solid(s) carry the exporter's placeholder material {name!r} "
            f"({group[0].density_kg_m3:g} kg/m³), {mass_g:.4g} g as counted: "
            f"{_listed([g.step.path for g in group])}; give them their material"
        )
    return notes


def _defaulted_lines(
    defaulted: dict[str, list[Body]],
    stamped_default: bool,
    notes: list[str],
    info: list[str] | None,
) -> None:
    """A line per STEP material a catch-all rule replaced: an info line for a stamped default
    (the file asked for it), a note for a placeholder."""
    for name, group in sorted(defaulted.items()):
        stamp = stamped_default and not is_placeholder_material(name)
        what = (
            "the same STEP material on every solid, taken as the exporter's default"
            if stamp
            else "the exporter's placeholder material"
        )
        (info if stamp and info is not None else notes).append(
            f"{len(group)} solid(s) carry {what} {name!r}: the catch-all rule gave them "
            f"{group[0].material!r}: {_listed([g.step.path for g in group])}; name a part in "
            "the materials file to keep the STEP's"
        )


def _stamp_notes(solids: Sequence[Body], with_materials: bool) -> list[str]:
    """A note where the STEP's own materials look like an exporter's stamp: one material on
    every solid, or a lone solid in Fusion 360's default 'Steel'; what to do depends on
    whether a materials file was given (its catch-all rule does not override a STEP's own
    material: only a rule that names the part does)."""
    remedy = (
        'name the part in the materials file (its "*" rule does not override a STEP\'s own '
        "material)"
        if with_materials
        else "give a materials file"
    )
    from_file = [b for b in solids if b.source.startswith("STEP material")]
    if len(from_file) >= 2 and len({(b.material, b.density_kg_m3) for b in from_file}) == 1:
        b0 = from_file[0]
        return [
            f"all {len(from_file)} solids without a materials rule carry the same STEP material "
            f"{b0.material!r} ({b0.density_kg_m3:g} kg/m³): exporters stamp a default material "
            "on every body (Fusion 360 writes 'Steel' on boards and plastics alike); check it, "
            f"or {remedy}"
        ]
    if len(solids) == 1 and from_file and from_file[0].material.strip().lower() == "steel":
        b0 = from_file[0]  # one solid cannot show a stamp: Fusion 360's default is its name
        return [
            f"the one solid carries the STEP material {b0.material!r} ({b0.density_kg_m3:g} "
            f"kg/m³), the default Fusion 360 writes on every body: check it, or {remedy}"
        ]
    return []


def _listed(paths: Sequence[str], most: int = 10) -> str:
    """The first ``most`` paths, and how many more."""
    return ", ".join(paths[:most]) + (f" and {len(paths) - most} more" if len(paths) > most else "")
