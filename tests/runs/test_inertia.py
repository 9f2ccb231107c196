"""``cadcog/runs/inertia.py``: a spacecraft's swings read with a rig (the paper's, by default)
are told to give the set-up; readings of the rig's own points are refused as they are."""

from __future__ import annotations

from pathlib import Path

import pytest

from cadcog.core.errors import CadcogError
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.runs.inertia import inertia_from_files

EXAMPLES = Path(__file__).resolve().parents[2] / "docs" / "examples"


@pytest.fixture(scope="module")
def rig():
    return load_rig(default_rig_path())


def test_neither_or_both_of_rig_and_set_up_is_refused(rig):
    with pytest.raises(ValueError, match="give a rig or a set-up"):
        inertia_from_files("s.csv", "r.csv")
    with pytest.raises(ValueError, match="give a rig or a set-up"):
        inertia_from_files("s.csv", "r.csv", rig=rig, setup=object())  # type: ignore[arg-type]


def test_readings_naming_none_of_the_rigs_points_are_told_to_give_the_set_up(rig, tmp_path):
    """The rig's own swings (a virtual campaign's) with the 3U example's readings: the refusal
    says first that the readings are another object's (the full case, a spacecraft's campaign
    without its set-up, is ``tests/cli/test_inertia.py``'s)."""
    from cadcog.runs.campaign import run_campaign

    swings = tmp_path / "swings.csv"
    run_campaign(tmp_path / "rig.csv", rig=rig, seed=1, swings=swings)
    readings = EXAMPLES / "cubesat_3u_readings.csv"
    with pytest.raises(CadcogError) as exc:
        inertia_from_files(swings, readings, rig=rig)
    message = str(exc.value)
    assert message.startswith(f"{readings}: the readings name none of rig paper_rig's points")
    assert "(S1, S2, S3, S4, S5, S6)" in message and "--setup, or setup=" in message


def test_readings_of_the_rigs_points_are_refused_without_the_hint(rig, tmp_path):
    from cadcog.runs.campaign import run_campaign

    swings = tmp_path / "swings.csv"
    run_campaign(tmp_path / "rig.csv", rig=rig, seed=1, swings=swings)
    text = swings.read_text(encoding="utf-8")
    (tmp_path / "cut.csv").write_text(
        "".join(
            x for x in text.splitlines(keepends=True) if not x.startswith(("S3", "S4", "S5", "S6"))
        )
    )
    with pytest.raises(CadcogError) as exc:
        inertia_from_files(tmp_path / "cut.csv", tmp_path / "rig.csv", rig=rig)
    assert "name none of" not in str(exc.value)
