"""The readings file: what acquire writes is what `cadcog estimate` reads."""

from __future__ import annotations

import numpy as np
import pytest

from cadcog.bench.protocol import ANALOG_EXAMPLE
from cadcog.bench.readingsfile import ReadingsFile, block_text, parse_block, suspension_of
from cadcog.bench.recorder import DeviceUnits, HangData
from cadcog.bench.swing import SwingRecord
from cadcog.core.errors import CadcogError
from cadcog.method.readings import read_readings
from cadcog.rig.inclinometer import InclinometerConfig

UNITS = DeviceUnits(ANALOG_EXAMPLE, InclinometerConfig())


def _data(seed, n=50, centre=(300.0, 700.0)):
    rng = np.random.default_rng(seed)
    values = np.array(centre) + rng.normal(0, 0.4, (n, 2))
    return HangData(
        np.arange(n) * 0.05, values, UNITS.degrees(values), 12.0,
        SwingRecord(0.7, 5.0, 0.02, 3.0), 0.03, None,
    )  # fmt: skip


def test_blocks_read_back_as_the_readings_reader_reads_them(tmp_path):
    out = tmp_path / "r.csv"
    rfile, blocks, repaired = ReadingsFile.open(out, UNITS, ["a comment"])
    assert blocks == [] and repaired == 0
    mine = []
    for i, (pid, pos) in enumerate([("A", (0, 0, 10)), ("B", (10, 0, 5)), ("C", (0, 8, 5))]):
        text = block_text(pid, pos, i != 1, _data(i), UNITS, f"attempt=1 i={i}")
        rfile.append(text)
        mine.append(suspension_of(parse_block(text), UNITS))
    theirs = read_readings(out, UNITS.config)
    for a, b in zip(mine, theirs, strict=True):
        assert (a.id, a.position_mm, a.top_face_up, a.n_samples) == (
            b.id, b.position_mm, b.top_face_up, b.n_samples
        )  # fmt: skip
        np.testing.assert_allclose(
            [a.inc_x_deg, a.inc_y_deg, a.std_x_deg, a.std_y_deg],
            [b.inc_x_deg, b.inc_y_deg, b.std_x_deg, b.std_y_deg],
            rtol=1e-12,
        )
    _, blocks, _ = ReadingsFile.open(out, UNITS)
    assert [b.point_id for b in blocks] == ["A", "B", "C"]


def test_a_rejected_hang_is_only_comments(tmp_path):
    out = tmp_path / "r.csv"
    rfile, _, _ = ReadingsFile.open(out, UNITS)
    rfile.append(block_text("A", (0, 0, 10), True, _data(0), UNITS, "attempt=1"))
    rfile.append_rejected(block_text("B", (9, 0, 5), True, _data(1), UNITS, "x"), "slipped")
    rfile.append(block_text("B", (10, 0, 5), True, _data(2), UNITS, "attempt=2"))
    assert [s.position_mm for s in read_readings(out, UNITS.config)] == [(0, 0, 10), (10, 0, 5)]


def test_another_devices_file_is_not_taken_up(tmp_path):
    out = tmp_path / "r.csv"
    ReadingsFile.open(out, UNITS)
    digital = DeviceUnits(
        ANALOG_EXAMPLE.__class__("d", "SCL3300", "angle", 20.0, deg_per_lsb=0.1), UNITS.config
    )
    with pytest.raises(CadcogError, match=r"r.csv: exists with columns .*inc_x_deg.*another --out"):
        ReadingsFile.open(out, digital)


def test_a_hand_written_file_is_not_taken_up(tmp_path):
    out = tmp_path / "r.csv"
    out.write_text(
        "point_id,x_mm,y_mm,z_mm,inc_x_counts,inc_y_counts,top_face_up,t_s\nS1,0,0,1,5,5,true,0\n"
    )
    with pytest.raises(CadcogError, match=r"line 2: a reading outside a recorded hang"):
        ReadingsFile.open(out, UNITS)
    assert out.read_text().count("\n") == 2  # untouched


def test_a_full_disk_mid_hang_leaves_the_file_as_it_was_and_names_it(tmp_path, monkeypatch):
    import errno
    import os

    from cadcog.bench import readingsfile

    out = tmp_path / "r.csv"
    rfile, _, _ = ReadingsFile.open(out, UNITS)
    rfile.append(block_text("A", (0, 0, 10), True, _data(0), UNITS, "attempt=1"))
    before = out.read_bytes()
    real_write = os.write

    def half_then_full(fd, data):  # a file-size limit reached inside the block
        if len(data) > 100:
            return real_write(fd, bytes(data[: len(data) // 2]))
        raise OSError(errno.EFBIG, os.strerror(errno.EFBIG))

    monkeypatch.setattr(readingsfile.os, "write", half_then_full)
    with pytest.raises(CadcogError, match=r"r\.csv: cannot append the hang \(File too large: .*"
                       r"ulimit -f.*the hangs recorded before it are kept"):  # fmt: skip
        rfile.append(block_text("B", (10, 0, 5), True, _data(1), UNITS, "attempt=1"))
    assert out.read_bytes() == before  # no half block for the next run to stumble on
