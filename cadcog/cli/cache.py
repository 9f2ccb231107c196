"""``cadcog cache``: where the mass-properties cache is, what it holds, and clearing it."""

from __future__ import annotations

import argparse
from typing import Any

from cadcog.cad import cachestore
from cadcog.cli._options import add_json
from cadcog.cli._output import print_json


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "cache",
        help="where the mass-properties cache is, its size, and --clear",
        description="massprops, plan, estimate --setup, update, check and report keep models' "
        "mass properties (and a rig's CAD parts, and setup init its survey of a model) in a "
        "cache, by the content of every input, so that a second run on unchanged files reads "
        "no CAD. This shows its folder "
        "(CADCOG_CACHE_DIR, else XDG_CACHE_HOME/cadcog, else ~/.cache/cadcog), whether it is "
        f"on (CADCOG_NO_CACHE=1 turns it off), its entries and size (at most "
        f"{cachestore.MAX_BYTES / 1e9:g} GB: the entries used least recently go first). "
        "See docs/performance.md.",
    )
    p.add_argument(
        "--clear",
        action="store_true",
        help="delete every entry (only cadcog's entry files; the folder and anything else in "
        "it stay)",
    )
    add_json(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    folder, chosen_by = cachestore.where()
    cleared = cachestore.clear(folder) if args.clear else None
    n, size = cachestore.usage(folder)
    data: dict[str, Any] = {
        "folder": str(folder),
        "chosen_by": chosen_by,
        "enabled": not cachestore.turned_off(),
        "entries": n,
        "size_bytes": size,
        "max_bytes": cachestore.MAX_BYTES,
    }
    if cleared is not None:
        data["cleared_entries"], data["cleared_bytes"] = cleared
    if args.json:
        print_json(data)
        return 0
    how = "the default" if chosen_by == "default" else f"from {chosen_by}"
    print(f"cache folder: {folder} ({how})")
    print("state: " + ("on" if data["enabled"] else "off (CADCOG_NO_CACHE is set)"))
    if cleared is not None:
        print(f"cleared: {cleared[0]} entries, {_mb(cleared[1])}")
    print(f"entries: {n}, {_mb(size)} (at most {_mb(cachestore.MAX_BYTES)})")
    return 0


def _mb(n_bytes: int) -> str:
    """A size in kB below 1 MB, else in MB (a 3U model's entry is 13 kB)."""
    return f"{n_bytes / 1e3:.1f} kB" if n_bytes < 1e6 else f"{n_bytes / 1e6:.1f} MB"
