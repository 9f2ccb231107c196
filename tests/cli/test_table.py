"""``cadcog/cli/_table.py``: columns as wide as their widest cell, for any cells."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.cli._table import GAP, text_table

CELL = st.text(alphabet=st.characters(min_codepoint=33, max_codepoint=126), max_size=8)


@given(st.integers(1, 4).flatmap(lambda n: st.tuples(
    st.lists(CELL, min_size=n, max_size=n),
    st.lists(st.lists(CELL, min_size=n, max_size=n), max_size=5),
    st.text(alphabet="lr", min_size=n, max_size=n),
    st.integers(0, 3),
)))  # fmt: skip
def test_every_cell_is_in_its_column_aligned_as_asked(table):
    headers, rows, align, indent = table
    lines = text_table(headers, rows, align, indent).split("\n")
    assert len(lines) == 1 + len(rows)
    widths = [max(len(c) for c in col) for col in zip(headers, *rows, strict=True)]
    for line, cells in zip(lines, [headers, *rows], strict=True):
        padded = line.ljust(indent + sum(widths) + GAP * (len(widths) - 1))
        start = indent
        assert padded[:indent] == " " * indent
        for c, w, a in zip(cells, widths, align, strict=True):
            field = padded[start : start + w]
            assert field == (c.ljust(w) if a == "l" else c.rjust(w))
            start += w + GAP
        assert line == line.rstrip()


def test_a_row_or_an_alignment_of_another_length_is_refused():
    with pytest.raises(ValueError, match="one entry per header"):
        text_table(["a", "b"], [["1"]])
    with pytest.raises(ValueError, match="one entry per header"):
        text_table(["a", "b"], [["1", "2"]], "l")
