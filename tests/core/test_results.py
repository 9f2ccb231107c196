"""``cadcog.core.results``: every array a result holds is read-only, down through the plain
dataclasses and tuples in it; the arrays it was built from stay the caller's."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import cadcog
from cadcog.core.results import JsonResult

EXAMPLE = "docs/examples/paper_rig_readings.csv"


def _arrays(value, depth=0):
    """Every numpy array reachable through dataclass fields and tuples (not dicts or lists)."""
    if isinstance(value, np.ndarray):
        yield value
    elif depth < 4 and isinstance(value, tuple):
        for v in value:
            yield from _arrays(v, depth + 1)
    elif depth < 4 and dataclasses.is_dataclass(value) and not isinstance(value, type):
        for f in dataclasses.fields(value):
            yield from _arrays(getattr(value, f.name), depth + 1)


def test_an_estimate_cannot_be_changed_through_its_arrays():
    """A notebook user wrote ``est.joint.cog_mm[0] = 1`` and ``to_dict()`` then said so."""
    est = cadcog.estimate(EXAMPLE, cadcog.load_rig())
    before = est.to_json()
    arrays = list(_arrays(est))
    assert len(arrays) > 10  # the CoG, its covariance, the verticals, the joint fit's...
    for a in arrays:
        assert not a.flags.writeable
    with pytest.raises(ValueError, match="read-only"):
        est.joint.cog_mm[0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        est.cov_mm2[0, 0] = 1.0
    assert est.to_json() == before


def test_the_arrays_a_result_is_built_from_stay_writable():
    @dataclasses.dataclass(frozen=True)
    class Inner:
        values: np.ndarray

    @dataclasses.dataclass(frozen=True, repr=False)
    class Result(JsonResult):
        a: np.ndarray
        pair: tuple
        inner: Inner

        def to_dict(self):
            return {"a": self.a.tolist()}

    a, b, c = np.zeros(3), np.ones(2), np.arange(4.0)
    r = Result(a, (b, 1.0), Inner(c))
    assert not r.a.flags.writeable and not r.pair[0].flags.writeable
    assert not r.inner.values.flags.writeable
    a[0] = 5.0  # the caller's array: writable, and seen through the result's view
    assert a.flags.writeable and b.flags.writeable and r.a[0] == 5.0
    assert r.pair[1] == 1.0
