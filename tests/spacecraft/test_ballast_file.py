"""``cadcog/spacecraft/ballast_file.py``: a ballast file reads back as written, for any valid
one, and each way of being invalid is refused naming its key."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cadcog.core.errors import ParameterFileError
from cadcog.spacecraft.ballast_file import load_ballast

IDS = st.from_regex(r"[A-Za-z0-9][A-Za-z0-9_.+-]{0,10}", fullmatch=True)
COORD = st.integers(-1500, 1500).map(lambda v: v / 10.0)  # mm, 0.1 mm steps
POINT = st.tuples(IDS, st.tuples(COORD, COORD, COORD), st.one_of(st.none(), st.just(0.2)))


def _text(points, sizes=None, total=None) -> str:
    lines = []
    if total is not None:
        lines.append(f"max_total_mass_kg = {total!r}")
    if sizes is not None:
        lines.append(f"sizes_kg = {list(sizes)!r}")
    for pid, pos, cap in points:
        lines += ["", "[[points]]", f'id = "{pid}"', f"position_mm = {list(pos)!r}"]
        if cap is not None:
            lines.append(f"max_mass_kg = {cap!r}")
    return "\n".join(lines) + "\n"


@settings(max_examples=50, deadline=None)
@given(
    st.lists(POINT, min_size=1, max_size=5, unique_by=(lambda p: p[0], lambda p: p[1])),
    st.one_of(
        st.none(),
        st.lists(st.sampled_from([0.002, 0.005, 0.01, 0.02]), min_size=1, max_size=4, unique=True),
    ),
    st.one_of(st.none(), st.just(0.3)),
)
def test_a_valid_file_reads_back_as_written(tmp_path_factory, points, sizes, total):
    path = tmp_path_factory.mktemp("b") / "ballast.toml"
    path.write_text(_text(points, sizes, total), encoding="utf-8")
    spec = load_ballast(path)
    assert [q.id for q in spec.points] == [p[0] for p in points]
    for q, (_, pos, cap) in zip(spec.points, points, strict=True):
        np.testing.assert_array_equal(q.position_mm, pos)
        assert q.max_mass_kg == cap
    assert spec.sizes_kg == (None if sizes is None else tuple(sorted(sizes)))
    assert spec.max_total_mass_kg == total and spec.source == str(path)


GOOD = [("B1", (0.0, 0.0, -100.0), None), ("B2", (10.0, 0.0, -100.0), None)]


@pytest.mark.parametrize(
    ("points", "sizes", "total", "key", "says"),
    [
        ([*GOOD, ("B1", (20.0, 0.0, 0.0), None)], None, None, "points[2].id", "listed twice"),
        ([*GOOD, ("B3", (10.0, 0.0, -100.0), None)], None, None, "points[2].position_mm",
         "at the position of 'B2'"),
        ([("../x", (0.0, 0.0, 0.0), None)], None, None, "points[0].id", "a short label"),
        (GOOD, [0.005, 0.005], None, "sizes_kg", "listed twice"),
        (GOOD, [0.00005], None, "sizes_kg", "is not ballast (is it in kg?)"),
        ([("B1", (0.0, 0.0, 0.0), 0.001)], [0.002], None, "points[0].max_mass_kg",
         "could take nothing"),
        (GOOD, [0.01], 0.005, "max_total_mass_kg", "no piece could be used"),
    ],
)  # fmt: skip
def test_each_invalid_file_names_its_key(tmp_path, points, sizes, total, key, says):
    path = tmp_path / "ballast.toml"
    path.write_text(_text(points, sizes, total), encoding="utf-8")
    with pytest.raises(ParameterFileError) as exc:
        load_ballast(path)
    assert exc.value.key == key and says in str(exc.value)
