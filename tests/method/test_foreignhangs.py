"""``cadcog/method/foreignhangs.py``: hangs from none of the rig's points are named."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from cadcog.core.errors import CadcogError
from cadcog.method.foreignhangs import foreign_hangs, refuse_foreign_hangs
from cadcog.method.readings import read_readings

READINGS = Path(__file__).resolve().parents[2] / "docs" / "examples" / "paper_rig_readings.csv"


def test_the_rigs_own_hangs_pass_and_a_moved_one_is_named(paper_rig):
    hangs = read_readings(READINGS, paper_rig.inclinometer)
    assert foreign_hangs(paper_rig, hangs) == []
    refuse_foreign_hangs(paper_rig, hangs, READINGS)
    moved = replace(hangs[2], position_mm=tuple(np.add(hangs[2].position_mm, (0.0, 0.0, 0.5))))
    mixed = [*hangs[:2], moved, *hangs[3:]]
    assert foreign_hangs(paper_rig, mixed) == [hangs[2].id]
    with pytest.raises(CadcogError, match=rf"^r\.csv: hang\(s\) {hangs[2].id} are from none of"):
        refuse_foreign_hangs(paper_rig, mixed, "r.csv")
