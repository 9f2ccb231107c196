"""Readings CSV parsing: averaging, raw counts, and every error with file and line."""

from __future__ import annotations

import numpy as np
import pytest

from cadcog.core.errors import ReadingsError
from cadcog.method.readings import read_readings
from cadcog.rig.inclinometer import InclinometerConfig
from support.rigtools import HEADER, write_csv

ROWS = [
    "S1,0,0,100,10.0,5.0,true",
    "S1,0,0,100,10.2,5.4,1",
    "S1,0,0,100,10.4,5.2,TRUE",
    "S2,100,0,0,-30.0,0.0,false",
]


def test_samples_are_averaged_with_count_and_sample_std(tmp_path):
    s1, s2 = read_readings(write_csv(tmp_path / "r.csv", ROWS))
    assert (s1.id, s1.n_samples, s1.top_face_up, s1.line) == ("S1", 3, True, 2)
    assert s1.inc_x_deg == pytest.approx(10.2)
    assert s1.std_x_deg == pytest.approx(np.std([10.0, 10.2, 10.4], ddof=1))
    assert s1.inc_y_deg == pytest.approx(5.2)
    assert (s2.n_samples, s2.top_face_up, s2.std_x_deg) == (1, False, None)
    assert s2.position_mm == (100.0, 0.0, 0.0)


def test_comments_blank_lines_and_extra_columns_are_ignored(tmp_path):
    rows = ["# a comment", "", "S1,0,0,100,10,5,true,note", "S2,100,0,0,-30,0,0,x"]
    path = write_csv(tmp_path / "r.csv", rows, HEADER + ",remark")
    assert [s.id for s in read_readings(path)] == ["S1", "S2"]


def test_a_reversal_is_read_as_a_hang_of_its_own_with_its_angles_negated(tmp_path):
    """``sensor_turned``: optional (false when absent); a turned hang's vertical is
    that of the negated angles (no shared figures: the offset is not modelled)."""
    from cadcog.method.readings import suspension_verticals

    rows = [f"{r},0" for r in ROWS] + ["S2~,100,0,0,30.0,0.0,false,1"]
    sus = read_readings(write_csv(tmp_path / "r.csv", rows, HEADER + ",sensor_turned"))
    assert [(s.id, s.sensor_turned) for s in sus] == [("S1", False), ("S2", False), ("S2~", True)]
    v = suspension_verticals(sus).u
    np.testing.assert_allclose(v[2], v[1], atol=1e-15)
    assert all(not s.sensor_turned for s in read_readings(write_csv(tmp_path / "o.csv", ROWS)))


def test_raw_counts_go_through_the_sensor_model(tmp_path):
    cfg = InclinometerConfig()
    counts = float(np.round(cfg.sensor.deg_to_counts(30.0)))
    rows = [f"S1,0,0,100,{counts:g},511.5,true", "S2,100,0,0,511.5,511.5,true"]
    header = "point_id,x_mm,y_mm,z_mm,inc_x_counts,inc_y_counts,top_face_up"
    s1, s2 = read_readings(write_csv(tmp_path / "r.csv", rows, header), cfg)
    assert s1.inc_x_deg == pytest.approx(float(cfg.sensor.counts_to_deg(counts)))
    assert abs(s1.inc_x_deg - 30.0) <= cfg.sensor.lsb_deg / 2
    assert s2.inc_x_deg == pytest.approx(0.0)


BAD = [
    (
        "missing column",
        "point_id,x_mm,y_mm,inc_x_deg,inc_y_deg,top_face_up",
        ROWS,
        r"line 1: missing column\(s\) z_mm",
    ),
    (
        "no angle columns",
        "point_id,x_mm,y_mm,z_mm,top_face_up",
        ["S1,0,0,1,true"],
        r"line 1: missing column\(s\) inc_x_deg, inc_y_deg",
    ),
    ("both angle kinds", HEADER + ",inc_x_counts,inc_y_counts", ROWS, "not both"),
    (
        "non-numeric",
        HEADER,
        [*ROWS[:2], "S1,0,0,100,ten,5,true"],
        "line 4: column inc_x_deg: expected a number, got 'ten'",
    ),
    (
        "NaN",
        HEADER,
        [*ROWS, "S3,0,nan,1,1,1,true"],
        "line 6: column y_mm: expected a finite number, got 'nan'",
    ),
    ("beyond 90", HEADER, [*ROWS, "S3,1,1,1,95,1,true"], r"line 6: column inc_x_deg: .*±90°"),
    ("bad flag", HEADER, [*ROWS, "S3,1,1,1,5,1,yes"], "line 6: column top_face_up: expected"),
    ("short row", HEADER, [*ROWS, "S3,1,1,1,5,1"], "line 6: expected 7 fields"),
    (
        "two positions",
        HEADER,
        [*ROWS, "S2,100,0,1,-30,0,false"],
        "line 6: point S2 at .* but line 5 puts it at",
    ),
    (
        "two orientations",
        HEADER,
        [*ROWS, "S2,100,0,0,-30,0,true"],
        "line 6: point S2: top_face_up differs from line 5",
    ),
    ("one point", HEADER, ROWS[:3], "1 distinct suspension point"),
    (
        "bad turn flag",
        HEADER + ",sensor_turned",
        [f"{r},false" for r in ROWS] + ["S2~,100,0,0,30,0,false,half"],
        "line 6: column sensor_turned: expected true, false, 1 or 0, got 'half'",
    ),
    (
        "empty turn flag",
        HEADER + ",sensor_turned",
        [f"{r},false" for r in ROWS] + ["S2~,100,0,0,30,0,false,"],
        "line 6: column sensor_turned: expected true, false, 1 or 0, got ''",
    ),
    (
        "turned and not",
        HEADER + ",sensor_turned",
        [f"{r},false" for r in ROWS] + ["S2,100,0,0,30,0,false,true"],
        "line 6: point S2: sensor_turned differs from line 5 .*its own point_id",
    ),
    ("empty id", HEADER, [*ROWS, ",1,1,1,5,1,true"], "line 6: column point_id: empty"),
]


@pytest.mark.parametrize(
    ("header", "rows", "message"), [b[1:] for b in BAD], ids=[b[0] for b in BAD]
)
def test_bad_files_name_file_and_line(tmp_path, header, rows, message):
    path = write_csv(tmp_path / "bad.csv", rows, header)
    with pytest.raises(ReadingsError, match=message) as info:
        read_readings(path)
    assert str(info.value).startswith(f"{path}")


def test_counts_outside_the_adc(tmp_path):
    header = "point_id,x_mm,y_mm,z_mm,inc_x_counts,inc_y_counts,top_face_up"
    path = write_csv(tmp_path / "c.csv", ["S1,0,0,1,1024,3,true", "S2,1,0,0,3,3,true"], header)
    with pytest.raises(ReadingsError, match="line 2: column inc_x_counts: 1024 outside the 10-bit"):
        read_readings(path)


def test_empty_and_missing_files(tmp_path):
    (tmp_path / "empty.csv").write_text("", encoding="utf-8")
    with pytest.raises(ReadingsError, match="empty file"):
        read_readings(tmp_path / "empty.csv")
    with pytest.raises(ReadingsError, match="file not found"):
        read_readings(tmp_path / "none.csv")


def test_a_fifo_is_refused_without_waiting_for_a_writer(tmp_path):
    import os

    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)  # opening it for reading would block until a writer comes
    with pytest.raises(ReadingsError, match=r"pipe\.csv: is a FIFO \(named pipe\), expected"):
        read_readings(fifo)


@pytest.mark.filterwarnings("error")  # a point and its reversal hang alike: no numpy warning
def test_a_reversal_id_without_its_flag_is_warned_about(tmp_path):
    """``S2~`` at S2's position with no ``sensor_turned`` column is read as a plain hang, as the
    format says, and the estimate says what is missing."""
    from cadcog.method.estimate import estimate_cog

    rows = [*ROWS, "S2~,100,0,0,30.0,0.0,false", "S3,0,100,0,0.0,-30.0,false"]
    est = estimate_cog(read_readings(write_csv(tmp_path / "r.csv", rows)))
    assert any("S2~ is named as the reversal of S2 but is read as a plain hang" in w
               for w in est.warnings)  # fmt: skip
    flagged = rows[:4] + [f"{r},true" if r.startswith("S2~") else f"{r},false" for r in rows[4:]]
    flagged = [f"{r},false" for r in rows[:4]] + flagged[4:]
    est = estimate_cog(
        read_readings(write_csv(tmp_path / "f.csv", flagged, HEADER + ",sensor_turned"))
    )
    assert not any("named as the reversal" in w for w in est.warnings)
    assert not any("S2 & S2~" in w for w in est.warnings)  # a reversal pair hangs alike
    # Two plain hangs alike are an ill-conditioned pair, and the warning says which.
    twice = [*ROWS, "S2b,100,0,0,-30.0,0.0,false", "S3,0,100,0,0.0,-30.0,false"]
    est = estimate_cog(read_readings(write_csv(tmp_path / "t.csv", twice)))
    assert any(w.startswith("pair S2 & S2b: plumb lines meet at 0.00°") for w in est.warnings)
