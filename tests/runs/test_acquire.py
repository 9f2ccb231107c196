"""``cadcog/runs/acquire.py``: a run's hangs are checked whole before the first is hung."""

from __future__ import annotations

import pytest

from cadcog.bench.target import REVERSAL_SUFFIX
from cadcog.core.errors import CadcogError
from cadcog.runs.acquire import acquire_target, check_report_folder


def test_every_rig_point_in_order_by_default_and_the_ones_given_otherwise(paper_rig):
    ids = [p.id for p in paper_rig.suspension_points]
    assert [h.id for h in acquire_target(rig=paper_rig).hangs] == ids
    chosen = [ids[3], ids[0], ids[3] + REVERSAL_SUFFIX]
    target = acquire_target(rig=paper_rig, points=[f" {i} " for i in chosen])
    assert [h.id for h in target.hangs] == chosen


@pytest.mark.parametrize(
    ("points", "message"),
    [
        (["S1", "S9"], r"--points: unknown point\(s\) S9 in .*paper_rig\.toml"),
        (["S1", "S2", "S1"], "--points: S1 given more than once"),
        (["S1", "S1~"], "a point and its reversal hang alike"),
        (["S1"], "at least two distinct"),
        (["S1", "S,2"], r"--points: 'S,2': "),
    ],
)
def test_ids_that_cannot_make_a_test_are_refused_before_any_hang(paper_rig, points, message):
    said: list[str] = []
    with pytest.raises(CadcogError, match=message):
        acquire_target(rig=paper_rig, points=points, say=said.append)
    assert said == []


def test_neither_or_both_of_rig_and_set_up_are_refused(paper_rig, cubesat_setup):
    with pytest.raises(CadcogError, match="give a rig or a set-up"):
        acquire_target()
    with pytest.raises(CadcogError, match="not both"):
        acquire_target(rig=paper_rig, setup=cubesat_setup, points=["+x_30_90", "-x_-30_90"])


def test_a_report_folder_that_is_a_file_is_refused(tmp_path):
    check_report_folder(None)
    check_report_folder(tmp_path / "new")
    check_report_folder(tmp_path)
    (tmp_path / "f").write_text("x")
    with pytest.raises(CadcogError, match=r"--report .*f: exists and is not a directory"):
        check_report_folder(tmp_path / "f")
