"""Which swings, and which of their modes, the tensor is fitted to (cadcog.dynamics.swingselect)."""

from __future__ import annotations

import numpy as np

from cadcog.dynamics.context import HangTerms
from cadcog.dynamics.modalfit import ModalFit
from cadcog.dynamics.swingfile import Swing
from cadcog.dynamics.swingselect import MIN_RATE_OVER_MODE, UsedHangs, record_problem


def _fit(k: int) -> ModalFit:
    one = np.ones(k)
    return ModalFit(
        "x", np.arange(k), np.arange(2.0, 2.0 + k), np.eye(k), one, one, np.ones(2), 1.0
    )


def _used(*fits: ModalFit) -> UsedHangs:
    pairs = tuple(
        (Swing(p, np.zeros(2), np.zeros((2, 2))), None) for p in ("S1", "S2", "S3", "S4")
    )[: len(fits)]
    pivots = np.arange(3.0 * len(fits)).reshape(-1, 3)
    n = 4 + 3 * len(fits)
    cov = np.arange(float(n * n)).reshape(n, n)
    records = tuple(float(i) for i in range(len(fits)))
    return UsedHangs(pairs, fits, records, HangTerms(pivots, 0.5, cov))  # type: ignore[arg-type]


def test_a_refusal_names_the_hangs_whose_swing_showed_one_body_mode():
    """Five usable frequencies for six entries because one hang showed one body mode of two:
    the refusal says to release with a larger swing, not only to add hangs."""
    assert "S2 showed one body mode of two" in _used(_fit(2), _fit(1), _fit(2)).weak_note()
    assert _used(_fit(2), _fit(2), _fit(2)).weak_note() == ""


def test_leaving_out_a_mode_keeps_the_hang_and_all_its_modes_the_hang_goes():
    """``without``: one mode of two leaves the hang with the other (its pivot and covariance
    as they were); both modes take the hang away with its pivot's rows and columns (its
    covariance with the CoG, the hinge and the other pivots), the CoG's and the hinge's kept."""
    used = _used(_fit(2), _fit(2), _fit(2), _fit(2))
    one = used.without(1, {0})
    assert [len(f.frequencies_hz) for f in one.fits] == [2, 1, 2, 2]
    assert one.fits[1].frequencies_hz.tolist() == [3.0]
    np.testing.assert_array_equal(one.terms.cov_mm2, used.terms.cov_mm2)
    gone = used.without(1, {0, 1})
    assert [sw.point_id for sw, _ in gone.pairs] == ["S1", "S3", "S4"]
    assert gone.records_s == (0.0, 2.0, 3.0)
    np.testing.assert_array_equal(gone.pivots_mm, used.pivots_mm[[0, 2, 3]])
    rows = [0, 1, 2, 3, 4, 5, 6, 10, 11, 12, 13, 14, 15]  # CoG, hinge, hangs 1, 3 and 4
    np.testing.assert_array_equal(gone.terms.cov_mm2, used.terms.cov_mm2[np.ix_(rows, rows)])
    assert gone.terms.top_mm == used.terms.top_mm


def test_a_record_that_cannot_show_its_modes_says_why():
    """A record in milliseconds, or sampled below MIN_RATE_OVER_MODE times its highest mode,
    names the hang and what to do; a good record has no problem."""
    t = np.arange(0.0, 30.0, 0.05)  # 20 Hz for 30 s
    sw = Swing("S4", t, np.zeros((len(t), 2)))
    assert record_problem(sw, 3.0) is None
    ms = Swing("S4", t * 1000.0, np.zeros((len(t), 2)))
    assert "hang S4" in record_problem(ms, 3.0) and "milliseconds" in record_problem(ms, 3.0)
    slow = record_problem(sw, 20.0 / MIN_RATE_OVER_MODE + 0.1)
    assert slow is not None and slow.startswith("hang S4: sampled at 20 Hz, too slow")
