"""``cadcog/runs/acquire_log.py``: a log's readings CSV reads back as the hangs it was cut
into, and a log's run writes new files only."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from cadcog.bench.logsegments import LogHang
from cadcog.core.errors import CadcogError
from cadcog.method.readings import read_readings
from cadcog.rig.inclinometer import InclinometerConfig
from cadcog.runs.acquire_log import log_path_for, readings_text, refuse_taken_outputs


@dataclass(frozen=True)
class Planned:
    id: str
    position_mm: tuple[float, float, float]
    sensor_turned: bool = False


def _hang(acc_g: np.ndarray, start_s: float) -> LogHang:
    t = start_s + 5.0 + 0.5 * np.arange(len(acc_g))
    return LogHang(start_s, float(t[-1]), start_s + 5.0, ((t[0], t[-1]),), t, acc_g, 3.0)


BINS = arrays(float, st.tuples(st.integers(1, 12), st.just(3)),
              elements=st.floats(-1.2, 1.2, allow_subnormal=False))  # fmt: skip


@settings(max_examples=25, deadline=None)
@given(st.lists(BINS, min_size=2, max_size=4), st.booleans())
def test_the_readings_read_back_as_the_hangs_bins(tmp_path_factory, bins, turned):
    """Each hang's rows average, as ``cadcog estimate`` reads them, to the mean of its bins
    (to the 7 decimals written), with its point, position and orientation."""
    assume(all(np.linalg.norm(b.mean(axis=0)) >= 0.2 for b in bins))  # gravity, not a fall
    planned = [
        Planned(f"P{i}", (10.0 * i, -3.25, 0.5 + i), sensor_turned=turned and i == 1)
        for i in range(len(bins))
    ]
    found = [_hang(b, 100.0 * i) for i, b in enumerate(bins)]
    path = tmp_path_factory.mktemp("log") / "r.csv"
    path.write_text(readings_text(planned, found, Path("cut.log.csv")), encoding="utf-8")
    config = InclinometerConfig(device="accelerometer")
    hangs = read_readings(path, config)
    assert [h.id for h in hangs] == [p.id for p in planned]
    for p, h, b in zip(planned, hangs, bins, strict=True):
        assert h.n_samples == len(b) and h.position_mm == p.position_mm
        assert h.sensor_turned == p.sensor_turned
        np.testing.assert_allclose(h.acc_g, b.mean(axis=0), rtol=0, atol=1e-7)


def test_log_outputs_are_new_distinct_files(tmp_path):
    out = tmp_path / "r.csv"
    assert log_path_for(out) == tmp_path / "r.log.csv"
    refuse_taken_outputs([("--out", out), ("--swings", tmp_path / "s.csv"), ("--log-out", None)])
    (tmp_path / "taken.csv").write_text("x")
    with pytest.raises(CadcogError, match=r"^--swings .*taken\.csv: exists"):
        refuse_taken_outputs([("--out", out), ("--swings", tmp_path / "taken.csv")])
    with pytest.raises(CadcogError, match=r"^--out -: expected a new file"):
        refuse_taken_outputs([("--out", Path("-"))])
    with pytest.raises(CadcogError, match=r"^--log-out and --out name the same file"):
        refuse_taken_outputs([("--out", out), ("--log-out", tmp_path / "." / "r.csv")])
