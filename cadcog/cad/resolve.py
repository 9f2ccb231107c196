"""Overlapping solids of a model: found (:mod:`cadcog.cad.overlaps`), summarised, refused,
allowed or resolved as the caller chose (see :func:`cadcog.cad.stepmass.model_mass_properties`)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Literal

from OCP.TopoDS import TopoDS_Shape

from cadcog.cad.bodies import Body, ProgressFactory, scaled_lengths, with_mass_factor
from cadcog.cad.massresults import OverlapPair, OverlapSummary
from cadcog.cad.occt import volume_properties
from cadcog.cad.overlaps import Overlap, Placed, cut_by, find_overlaps
from cadcog.core import tolerances
from cadcog.core.errors import CadcogError
from cadcog.core.parallel import fork_map
from cadcog.mass.properties import MassProperties, combine

OverlapPolicy = Literal["check", "allow", "resolve"]


def _common_root(paths: Sequence[str]) -> str:
    """``"top/"`` when every path lies below one top assembly, else ``""``."""
    firsts = {p.split("/", 1)[0] for p in paths}
    if len(firsts) == 1 and all("/" in p for p in paths):
        return f"{firsts.pop()}/"
    return ""


def handle_overlaps(
    bodies: list[Body],
    policy: OverlapPolicy,
    scale: float,
    progress: ProgressFactory | None,
    src: Any,
    workers: int,
) -> tuple[OverlapSummary, list[str]]:
    """Find overlaps among solids, summarise them, refuse or resolve them per ``policy``."""
    solids = [b for b in bodies if b.step.kind == "solid"]
    if len(solids) < 2:
        return OverlapSummary(policy), []
    placed_solids = [
        Placed(b.step.shape, b.step.local_shape, b.step.placement, b.step.product_key, lo, hi)
        for b, lo, hi in ((b, b.box_lo, b.box_hi) for b in solids)
    ]
    volumes = [b.props.volume_mm3 for b in solids]
    found, n_candidates, n_contact = find_overlaps(
        placed_solids, volumes, scale=scale, progress=progress, workers=workers
    )
    if not found:
        return OverlapSummary(policy, n_candidates=n_candidates, n_contact=n_contact), []

    def lighter(o: Overlap) -> tuple[int, int]:
        """(less dense, denser): the later solid in file order loses a tie."""
        da, db = solids[o.a].density_kg_mm3, solids[o.b].density_kg_mm3
        return (o.b, o.a) if db <= da else (o.a, o.b)

    pairs = []
    partners: dict[int, list[int]] = {}
    for o in found:
        lose, keep = lighter(o)
        partners.setdefault(lose, []).append(keep)
        common = scaled_lengths(o.common, scale, 3)
        pairs.append(
            OverlapPair(
                solids[o.a].step.path,
                solids[o.b].step.path,
                common.volume_mm3,
                common.mass_kg * solids[lose].density_kg_mm3,
                solids[keep].step.path,
            )
        )
    # Exact totals, also where three or more solids share a region: each less dense solid is cut
    # by its denser partners; what it loses is what was counted more than once.
    losers = list(partners)
    jobs = [(solids[i].step.shape, [solids[k].step.shape for k in partners[i]]) for i in losers]
    tick = progress("resolving overlaps", len(jobs)) if progress else None
    cuts = fork_map(_cut_properties, jobs, workers=workers, progress=tick)
    failed = [solids[i].step.path for i, c in zip(losers, cuts, strict=True) if c is None]
    if failed:
        raise CadcogError(
            f"{src}: OCCT could not cut the overlaps out of {', '.join(failed[:10])}; "
            "--exclude them or fix the model"
        )
    removed = []
    after: dict[int, MassProperties] = {}
    for i, cut in zip(losers, cuts, strict=True):
        assert cut is not None
        after[i] = scaled_lengths(cut, scale, 3)
        lost = solids[i].props.volume_mm3 - after[i].volume_mm3
        if lost > 0:
            region = combine([solids[i].props, after[i].scaled(-1.0)])
            removed.append(with_mass_factor(region, solids[i].density_kg_mm3))
    as_is = [with_mass_factor(b.props, b.density_kg_mm3) for b in bodies if b.density_kg_mm3 > 0]
    total_as_is = combine(as_is)
    double_mass = sum(r.mass_kg for r in removed)
    single = combine([*as_is, *(r.scaled(-1.0) for r in removed)]) if removed else total_as_is
    fraction = double_mass / total_as_is.mass_kg
    shift = total_as_is.cog_mm - single.cog_mm
    ranked = tuple(sorted(pairs, key=lambda p: -p.mass_kg))
    summary = OverlapSummary(
        policy,
        ranked,
        sum(r.volume_mm3 for r in removed),
        double_mass,
        fraction,
        (float(shift[0]), float(shift[1]), float(shift[2])),
        n_candidates,
        n_contact,
    )
    if policy == "check" and fraction > tolerances.OVERLAP_REFUSE_MASS_FRACTION:
        root = _common_root([b.step.path for b in bodies])
        worst = "; ".join(p.describe(root) for p in ranked[:3])
        raise CadcogError(
            f"{src}: {summary.headline()}, above the "
            f"{tolerances.OVERLAP_REFUSE_MASS_FRACTION:.1%} threshold; worst: {worst}. Fix the "
            "model, --exclude one of each pair, --resolve-overlaps (the denser solid keeps the "
            "common volume) or --allow-overlap (count each solid as it is); --json lists every "
            "pair"
        )
    if policy != "resolve":
        return summary, []
    for i, props in after.items():
        solids[i].removed_mm3 = solids[i].props.volume_mm3 - props.volume_mm3
        solids[i].props = props
    info = [
        f"--resolve-overlaps: {len(found)} overlapping pair(s) resolved, the denser solid of "
        f"each keeping the common volume ({double_mass * 1e3:.4g} g no longer counted more than "
        "once)"
    ]
    return summary, info


def _cut_properties(job: tuple[TopoDS_Shape, list[TopoDS_Shape]]) -> MassProperties | None:
    """Unit-density properties of a solid minus its tools (None if OCCT fails)."""
    cut = cut_by(*job)
    return None if cut is None else volume_properties(cut)
