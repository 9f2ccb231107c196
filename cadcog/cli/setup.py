"""``cadcog setup init MODEL.step``: draft a set-up file and a materials file from one's STEP."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from cadcog.cli._options import add_json
from cadcog.cli._output import print_json, wrote
from cadcog.core.units import UNIT_CHOICES


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "setup",
        help="draft a test set-up file from your own STEP model (setup init MODEL.step)",
        description="Set-up files for `plan`, `estimate --setup` and `update`. `setup init` "
        "reads a STEP model and drafts SETUP.toml (model, materials, the CubeSat form factor "
        "guessed from the bounding box, the measurement equipment on the +z face, a grid of "
        "candidate points on the side faces) and a materials file beside it listing every part, "
        "heaviest first, to fill in. See docs/spacecraft.md.",
    )
    actions = p.add_subparsers(dest="action", metavar="ACTION", required=True)
    init = actions.add_parser(
        "init",
        help="draft SETUP.toml and its materials file from MODEL.step",
        description="Draft a set-up file and a materials file from a STEP model; neither "
        "replaces an existing file unless --force.",
    )
    init.add_argument("model", type=Path, help="STEP file (part or assembly)")
    init.add_argument(
        "--out",
        type=Path,
        help="the set-up file to write (default: MODEL's name with _setup.toml, beside it); "
        "the materials file goes beside it as NAME_materials.toml",
    )
    init.add_argument(
        "--units",
        choices=UNIT_CHOICES,
        help="the file's true length unit, when its declared unit is wrong",
    )
    init.add_argument("--force", action="store_true", help="replace existing files")
    add_json(init, "print what was drafted as one JSON object")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from cadcog.runs.setup_init import run_setup_init

    draft = run_setup_init(Path(args.model), out=args.out, units=args.units, force=args.force)
    wrote(draft.setup)
    wrote(draft.materials)
    if args.json:
        print_json(draft.to_dict())
        return 0
    points = (
        f"{draft.n_points} candidate points on the model"
        if draft.n_points
        else "a candidate grid on the bounding box"
    )
    resolve = " --resolve-overlaps" if draft.resolves_overlaps else ""
    print(
        f"drafted {draft.setup} and {draft.materials} ({_count(draft.n_solids, 'solid')} in "
        f"{_count(draft.n_parts, 'part')}, {draft.n_lacking_material} without a material of "
        "their own in "
        f"the STEP; {points}). Next: fill in the materials, check the set-up, then\n"
        f"  cadcog massprops {args.model} --materials {draft.materials}{resolve}\n"
        f"  cadcog plan {draft.setup} --for both"
    )
    return 0


def _count(n: int, noun: str) -> str:
    """``1 solid``, ``2 solids``."""
    return f"{n} {noun}{'' if n == 1 else 's'}"
