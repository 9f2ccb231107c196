"""``cadcog.uncertainty.histogram``: a quantile from the bins is within one bin's relative width
of the sample's, for any sample; counts do not depend on how the trials were chunked."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from cadcog.uncertainty.histogram import NormHistogram

norms = arrays(float, st.integers(1, 300), elements=st.floats(1e-5, 1e5))


@given(norms, st.floats(0.001, 0.999))
def test_a_quantile_is_within_a_bin_of_the_sample_s(x, q):
    h = NormHistogram()
    h.add(x)
    exact = float(np.quantile(x, q, method="inverted_cdf"))  # the ⌈q n⌉-th smallest
    # Both lie in the bin holding that order statistic (its edges rounded to ~1e-15).
    assert abs(h.quantile(q) - exact) <= NormHistogram.REL_WIDTH * exact * (1 + 1e-9)


@given(norms, st.lists(st.integers(0, 300), max_size=5))
def test_counts_do_not_depend_on_the_chunks(x, cuts):
    whole = NormHistogram()
    whole.add(x)
    parts = NormHistogram()
    for chunk in np.split(x, sorted(c % (x.size + 1) for c in cuts)):
        parts.add(chunk)
    assert np.array_equal(whole.counts, parts.counts)
    assert whole.n == x.size


@given(norms, st.floats(1e-5, 1e5))
def test_the_fraction_below_is_bracketed_by_the_bin_edges(x, eps):
    h = NormHistogram()
    h.add(x)
    edges, cdf = h.cdf_at_edges()
    k = int(np.searchsorted(edges, eps, side="right"))
    below = float(np.mean(x < eps))
    assert cdf[k - 1] - 1e-12 <= below <= cdf[k] + 1e-12
    assert cdf[k - 1] - 1e-12 <= h.fraction_below(eps) <= cdf[k] + 1e-12


def test_out_of_range_and_nan_go_to_the_end_bins():
    h = NormHistogram()
    h.add(np.array([0.0, 1e-9, 1e9, np.inf, np.nan, 1.0]))
    assert h.counts[0] == 2 and h.counts[-1] == 3 and h.n == 6
    assert h.quantile(1.0) <= NormHistogram.HI_MM  # clamped to the range
