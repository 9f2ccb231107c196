"""``cadcog/runs/__init__.py``: a run's hangs are at least two distinct point ids."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.core.errors import CadcogError
from cadcog.runs import check_distinct_ids

IDS = st.lists(st.sampled_from(["S1", "S2", "S3", "+x_30_90", "-y_-30_-30"]), max_size=6)


@given(IDS)
def test_refused_exactly_when_an_id_repeats_or_fewer_than_two_are_given(ids):
    repeated = sorted({i for i in ids if ids.count(i) > 1})
    if not repeated and len(ids) >= 2:
        check_distinct_ids(ids)
        return
    with pytest.raises(CadcogError) as exc:
        check_distinct_ids(ids)
    message = str(exc.value)
    assert message.startswith("--points: ")
    if repeated:  # every id given twice is named, in order, once
        assert message == f"--points: {', '.join(repeated)} given more than once: each point once"
    else:
        assert "at least two distinct" in message
