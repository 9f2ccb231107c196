"""``cadcog/cli/_options.py``: an option several commands take means the same in each."""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest

from cadcog.cli._main import _subparsers, build_parser
from cadcog.cli._options import overlap_mode, refuse_rig_and_setup, rig_of, rig_or_setup
from cadcog.core.errors import CadcogError

PARTS = Path(__file__).resolve().parents[2] / "parts"


def _ns(**kw) -> argparse.Namespace:
    return argparse.Namespace(**{"rig": None, "setup": None, **kw})


def test_the_paper_rig_by_default_and_the_rig_named_otherwise(tmp_path):
    assert rig_of(_ns()).name == "paper_rig"
    other = tmp_path / "mine.toml"
    other.write_text(
        (PARTS / "paper_rig.toml")
        .read_text(encoding="utf-8")
        .replace('name = "paper_rig"', 'name = "mine"'),
        encoding="utf-8",
    )
    rig, setup = rig_or_setup(_ns(rig=other))
    assert rig is not None and rig.name == "mine" and setup is None


def test_rig_and_set_up_together_are_refused_before_either_is_read(tmp_path):
    both = _ns(rig=tmp_path / "absent_rig.toml", setup=tmp_path / "absent_setup.toml")
    for refuse in (refuse_rig_and_setup, rig_or_setup):
        with pytest.raises(CadcogError, match=r"^give either --rig or --setup, not both"):
            refuse(both)


@pytest.mark.parametrize(
    ("flags", "policy"),
    [({}, "check"), ({"allow_overlap": True}, "allow"), ({"resolve_overlaps": True}, "resolve"),
     ({"skip_overlaps": True}, "skip")],
)  # fmt: skip
def test_the_overlap_flags_name_one_policy(flags, policy):
    args = {"allow_overlap": False, "resolve_overlaps": False, **flags}
    assert overlap_mode(argparse.Namespace(**args)) == policy


def test_every_command_declares_a_shared_option_alike():
    """--json, --rig and the overlap flags: the same type, default and action in every command
    that takes them (only their help may say more)."""
    seen: dict[str, set[tuple]] = {}
    for sub in _subparsers(build_parser()).values():
        for a in sub._actions:
            for option in set(a.option_strings) & {"--json", "--rig", "--allow-overlap",
                                                   "--resolve-overlaps"}:  # fmt: skip
                seen.setdefault(option, set()).add((type(a).__name__, a.type, a.default))
    assert set(seen) == {"--json", "--rig", "--allow-overlap", "--resolve-overlaps"}
    assert all(len(kinds) == 1 for kinds in seen.values()), seen
