"""Options several commands take, declared once, and what they resolve to: ``--json``; the
rig (``--rig``, the paper's by default) or a spacecraft set-up (``--setup``); a model's
overlap policy (``--allow-overlap`` / ``--resolve-overlaps``).

A command whose help for such an option says more than the shared text passes its own
``help``; the option's name, type and default stay the same everywhere.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any

from cadcog.core.errors import CadcogError

if TYPE_CHECKING:
    from cadcog.cad.resolve import OverlapPolicy
    from cadcog.rig.parameters import Rig
    from cadcog.spacecraft.setup import Setup

#: ``--rig``'s help where the paper's rig is the default.
RIG_HELP = "rig file (default: the paper's rig)"
#: ``--json``'s help where the result is one object.
JSON_HELP = "print one JSON object"


def add_json(p: Any, help: str = JSON_HELP) -> None:
    """``--json``: the result as one JSON object on standard output."""
    p.add_argument("--json", action="store_true", help=help)


def add_rig(p: Any, help: str = RIG_HELP) -> None:
    """``--rig FILE``."""
    p.add_argument("--rig", type=Path, help=help)


def rig_of(args: argparse.Namespace) -> Rig:
    """The rig ``--rig`` names, or the paper's."""
    from cadcog.rig.file import default_rig_path, load_rig

    return load_rig(args.rig if args.rig is not None else default_rig_path())


def refuse_rig_and_setup(args: argparse.Namespace) -> None:
    """Refuse ``--rig`` with ``--setup`` (a set-up names its own rig), before any file is read.

    Raises
    ------
    CadcogError
        ``give either --rig or --setup, not both (a set-up names its rig)``.
    """
    if args.rig is not None and args.setup is not None:
        raise CadcogError("give either --rig or --setup, not both (a set-up names its rig)")


def rig_or_setup(args: argparse.Namespace) -> tuple[Rig | None, Setup | None]:
    """``(None, set-up)`` with ``--setup``, else ``(rig, None)`` (:func:`rig_of`).

    Raises
    ------
    CadcogError
        Both given: a set-up names its own rig.
    """
    refuse_rig_and_setup(args)
    if args.setup is None:
        return rig_of(args), None
    from cadcog.spacecraft.setup import load_setup

    return None, load_setup(args.setup)


def add_overlap_modes(p: Any, *, allow_help: str, resolve_help: str) -> Any:
    """``--allow-overlap`` or ``--resolve-overlaps`` (neither: overlapping solids refused); the
    group, for a command with a third way (``massprops --skip-overlaps``)."""
    group = p.add_mutually_exclusive_group()
    group.add_argument("--allow-overlap", action="store_true", help=allow_help)
    group.add_argument("--resolve-overlaps", action="store_true", help=resolve_help)
    return group


def overlap_mode(args: argparse.Namespace) -> OverlapPolicy:
    """The policy the options chose, as
    :func:`cadcog.cad.stepmass.model_mass_properties`' ``overlaps`` takes it: ``"allow"``,
    ``"resolve"``, ``"skip"`` (where the command has ``--skip-overlaps``) or ``"check"``."""
    if args.allow_overlap:
        return "allow"
    if args.resolve_overlaps:
        return "resolve"
    return "skip" if getattr(args, "skip_overlaps", False) else "check"
