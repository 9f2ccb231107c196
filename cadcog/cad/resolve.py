"""Overlapping solids of a model: found (:mod:`cadcog.cad.overlaps`), summarised, refused,
allowed or resolved as the caller chose (see :func:`cadcog.cad.stepmass.model_mass_properties`)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Literal

from OCP.TopoDS import TopoDS_Shape

from cadcog.cad.bodies import Body, ProgressFactory, scaled_lengths, with_mass_factor
from cadcog.cad.massresults import OverlapPair, OverlapSummary
from cadcog.cad.occt import placed, rigid_transform, volume_properties
from cadcog.cad.overlaps import Overlap, Placed, cut_by, find_overlaps, relative_key
from cadcog.core import tolerances
from cadcog.core.errors import CadcogError
from cadcog.core.parallel import fork_map
from cadcog.mass.properties import MassProperties, combine

OverlapPolicy = Literal["check", "allow", "resolve", "skip"]


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
) -> tuple[OverlapSummary, list[str], set[str], str | None]:
    """Find overlaps among solids, summarise them, refuse or resolve them per ``policy``.

    Returns the summary, info lines, the product keys of the solids that took part in a
    boolean (whose topology is then worth checking), and under ``check`` the refusal's message
    when the mass counted more than once is above the threshold (else None): the caller still
    counts the model as ``allow`` would, for the refusal to carry. ``skip``: no search at all.

    Raises
    ------
    CadcogError
        If OCCT cannot cut the overlaps out of a solid (to count the overlap exactly).
    """
    solids = [b for b in bodies if b.step.kind == "solid"]
    if policy == "skip":
        info = ["--skip-overlaps: overlaps not searched; each solid counted as it is"]
        return OverlapSummary(policy), info if len(solids) >= 2 else [], set(), None
    if len(solids) < 2:
        return OverlapSummary(policy), [], set(), None
    placed_solids = [
        Placed(
            b.step.shape,
            b.step.local_shape,
            b.step.placement,
            b.step.product_key,
            b.box_lo,
            b.box_hi,
            b.step.rigid,
        )
        for b in solids
    ]
    volumes = [b.props.volume_mm3 for b in solids]
    found, candidates, n_contact = find_overlaps(
        placed_solids, volumes, scale=scale, progress=progress, workers=workers
    )
    n_candidates = len(candidates)
    in_booleans = {solids[k].step.product_key for pair in candidates for k in pair}
    if not found:
        summary = OverlapSummary(policy, n_candidates=n_candidates, n_contact=n_contact)
        return summary, [], in_booleans, None
    pairs, partners = _pairs(found, solids, scale)
    # Exact totals, also where three or more solids share a region: each less dense solid is cut
    # by its denser partners; what it loses is what was counted more than once.
    after = _cut_losers(placed_solids, solids, partners, scale, src, progress, workers)
    removed = []
    for i, props in after.items():
        if solids[i].props.volume_mm3 - props.volume_mm3 > 0:
            region = combine([solids[i].props, props.scaled(-1.0)])
            removed.append(with_mass_factor(region, solids[i].density_kg_mm3))
    summary = _summary(policy, bodies, pairs, removed, n_candidates, n_contact)
    if policy == "check" and summary.mass_fraction > tolerances.OVERLAP_REFUSE_MASS_FRACTION:
        return summary, [], in_booleans, _refusal(summary, bodies, src)
    if policy != "resolve":
        return summary, [], in_booleans, None
    for i, props in after.items():
        solids[i].removed_mm3 = solids[i].props.volume_mm3 - props.volume_mm3
        solids[i].props = props
    info = [
        f"--resolve-overlaps: {len(found)} overlapping pair(s) resolved, the denser solid of "
        f"each keeping the common volume ({summary.mass_kg * 1e3:.4g} g no longer counted more "
        "than once)"
    ]
    return summary, info, in_booleans, None


def _pairs(
    found: Sequence[Overlap], solids: Sequence[Body], scale: float
) -> tuple[list[OverlapPair], dict[int, list[int]]]:
    """Each overlap as a pair (its common volume's mass at the less dense solid's density,
    which loses it), and each losing solid's denser partners."""
    pairs = []
    partners: dict[int, list[int]] = {}
    for o in found:
        da, db = solids[o.a].density_kg_mm3, solids[o.b].density_kg_mm3
        lose, keep = (o.b, o.a) if db <= da else (o.a, o.b)  # the later solid loses a tie
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
    return pairs, partners


def _cut_losers(
    placed_solids: Sequence[Placed],
    solids: Sequence[Body],
    partners: dict[int, list[int]],
    scale: float,
    src: Any,
    progress: ProgressFactory | None,
    workers: int,
) -> dict[int, MassProperties]:
    """Each losing solid's unit-density properties once its partners are cut out of it.

    Raises
    ------
    CadcogError
        If OCCT cannot cut one.
    """
    losers = list(partners)
    cuts = _cuts(placed_solids, losers, partners, progress, workers)
    failed = [solids[i].step.path for i, c in zip(losers, cuts, strict=True) if c is None]
    if failed:
        raise CadcogError(
            f"{src}: OCCT could not cut the overlaps out of {', '.join(failed[:10])}; "
            "--exclude them or fix the model"
        )
    return {
        i: scaled_lengths(c, scale, 3) for i, c in zip(losers, cuts, strict=True) if c is not None
    }


def _summary(
    policy: OverlapPolicy,
    bodies: Sequence[Body],
    pairs: Sequence[OverlapPair],
    removed: Sequence[MassProperties],
    n_candidates: int,
    n_contact: int,
) -> OverlapSummary:
    """The overlaps' totals: the mass counted more than once, its share of the model's, and
    how far it moves the CoG."""
    as_is = [with_mass_factor(b.props, b.density_kg_mm3) for b in bodies if b.density_kg_mm3 > 0]
    total_as_is = combine(as_is)
    double_mass = sum(r.mass_kg for r in removed)
    single = combine([*as_is, *(r.scaled(-1.0) for r in removed)]) if removed else total_as_is
    shift = total_as_is.cog_mm - single.cog_mm
    return OverlapSummary(
        policy,
        tuple(sorted(pairs, key=lambda p: -p.mass_kg)),
        sum(r.volume_mm3 for r in removed),
        double_mass,
        double_mass / total_as_is.mass_kg,
        (float(shift[0]), float(shift[1]), float(shift[2])),
        n_candidates,
        n_contact,
    )


def _refusal(summary: OverlapSummary, bodies: Sequence[Body], src: Any) -> str:
    """The message that refuses a model whose overlaps count too much mass twice."""
    root = _common_root([b.step.path for b in bodies])
    worst = "; ".join(p.describe(root) for p in summary.pairs[:3])
    return (
        f"{src}: {summary.headline()}, above the "
        f"{tolerances.OVERLAP_REFUSE_MASS_FRACTION:.1%} threshold; worst: {worst}. Fix the "
        "model, --exclude one of each pair, --resolve-overlaps (the denser solid keeps the "
        "common volume) or --allow-overlap (count each solid as it is); --json lists every "
        "pair"
    )


def _cuts(
    solids: Sequence[Placed],
    losers: Sequence[int],
    partners: dict[int, list[int]],
    progress: ProgressFactory | None,
    workers: int,
) -> list[MassProperties | None]:
    """Unit-density properties of each loser cut by its partners, at its global placement.

    One boolean per distinct configuration: a loser whose product and partners (products and
    placements relative to it) repeat an earlier one's (the board of every copy of a
    subassembly, cut by the same pins) gets that one's result moved rigidly to its placement.
    """
    jobs: list[tuple[TopoDS_Shape, list[TopoDS_Shape]]] = []
    first_of: dict[object, int] = {}  # configuration → index into jobs
    firsts: list[int] = []  # the loser each job was computed for
    where: list[tuple[int, int]] = []  # (job, loser it was computed for)
    for i in losers:
        keys = [relative_key(solids[i], solids[k]) for k in partners[i]]
        key = None if None in keys else (solids[i].key, tuple(sorted(keys)))  # type: ignore[type-var]
        if key is not None and key in first_of:
            where.append((first_of[key], firsts[first_of[key]]))
            continue
        if key is not None:
            first_of[key] = len(jobs)
        where.append((len(jobs), i))
        firsts.append(i)
        jobs.append((solids[i].shape, [solids[k].shape for k in partners[i]]))
    tick = progress("resolving overlaps", len(jobs)) if progress else None
    done = fork_map(_cut_properties, jobs, workers=workers, progress=tick)
    out: list[MassProperties | None] = []
    for i, (job, first) in zip(losers, where, strict=True):
        cut = done[job]
        if cut is not None and first != i:  # from the first loser's placement to this one's
            move = solids[i].placement.Multiplied(solids[first].placement.Inverted())
            rigid = rigid_transform(move)
            cut = None if rigid is None else placed(cut, *rigid)
        out.append(cut)
    return out


def _cut_properties(job: tuple[TopoDS_Shape, list[TopoDS_Shape]]) -> MassProperties | None:
    """Unit-density properties of a solid minus its tools (None if OCCT fails)."""
    cut = cut_by(*job)
    return None if cut is None else volume_properties(cut)
