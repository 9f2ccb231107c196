"""The swing file: round trip and one-line refusals naming the file and line."""

from __future__ import annotations

import numpy as np
import pytest

from cadcog.core.errors import ReadingsError
from cadcog.dynamics.swingfile import MIN_SAMPLES, Swing, read_swings, write_swings


def _swing(pid: str, n: int = MIN_SAMPLES, t0: float = 0.0) -> Swing:
    t = t0 + np.arange(n) * 0.02
    return Swing(pid, t, np.column_stack([np.sin(t), np.cos(t) - 40.0]))


def test_round_trip_keeps_every_sample(tmp_path):
    path = tmp_path / "s.csv"
    write_swings(path, [_swing("S1"), _swing("S2", t0=100.0)])
    back = read_swings(path)
    assert [s.point_id for s in back] == ["S1", "S2"]
    np.testing.assert_allclose(back[1].t_s, _swing("S2", t0=100.0).t_s, atol=5e-7)
    np.testing.assert_allclose(back[0].inc_deg, _swing("S1").inc_deg, atol=5e-6)
    assert back[1].line == MIN_SAMPLES + 2


def test_extra_columns_and_comments_are_allowed(tmp_path):
    rows = ["# from the bench", "point_id,t_s,inc_x_deg,inc_y_deg,temp_c"]
    rows += [f"A,{i * 0.05:.2f},{np.sin(i):.4f},1.0,21" for i in range(MIN_SAMPLES)]
    path = tmp_path / "s.csv"
    path.write_text("\n".join(rows) + "\n")
    (s,) = read_swings(path)
    assert len(s.t_s) == MIN_SAMPLES and s.rate_hz == pytest.approx(20.0)


@pytest.mark.parametrize(
    ("body", "match"),
    [
        ("point_id,t_s,inc_x_deg\nS1,0,1\n", r"line 1: missing column\(s\) inc_y_deg"),
        (
            "point_id,t_s,inc_x_deg,inc_y_deg\nS1,0,1,2\nS1,0,1,2\n",
            r"line 3: column t_s: .*must increase",
        ),
        (
            "point_id,t_s,inc_x_deg,inc_y_deg\nS1,0,nan,2\n",
            r"line 2: column inc_x_deg: expected a finite",
        ),
        (
            "point_id,t_s,inc_x_deg,inc_y_deg\nS1,0,91,2\n",
            r"line 2: column inc_x_deg: 91.0 is beyond ±90°",
        ),
        (
            "point_id,t_s,inc_x_deg,inc_y_deg\nS1,0,1,2\nS2,1,1,2\nS1,2,1,2\n",
            r"line 4: point 'S1' again",
        ),
        (
            "point_id,t_s,inc_x_deg,inc_y_deg\nS1,0,1,2\n",
            r"line 2: hang 'S1' has 1 sample, expected a swing",
        ),
        ("", r"empty file"),
        ("point_id,t_s,inc_x_deg,inc_y_deg\n,0,1,2\n", r"line 2: column point_id: '' is empty"),
    ],
)
def test_bad_files_are_refused_with_file_and_line(tmp_path, body, match):
    path = tmp_path / "bad.csv"
    path.write_text(body)
    with pytest.raises(ReadingsError, match=match) as info:
        read_swings(path)
    assert str(info.value).startswith(str(path))


def test_a_directory_is_not_a_swing_file(tmp_path):
    with pytest.raises(ReadingsError, match="is a directory, expected a regular file"):
        read_swings(tmp_path)
