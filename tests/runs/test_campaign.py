"""``cadcog/runs/campaign.py``: a virtual campaign is its seed's, whole or not written at all;
its overrides are checked before any work."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.core.errors import CadcogError
from cadcog.method.errormodel import ErrorModel
from cadcog.method.readings import read_readings
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.runs.campaign import check_points, run_campaign, with_overrides

MODEL = ErrorModel((1.0,), (0.0,))


@given(
    st.one_of(st.none(), st.integers(-3, 50)),
    st.one_of(st.none(), st.floats(allow_nan=True, allow_infinity=False, width=32)),
)
def test_an_override_is_taken_when_valid_and_refused_naming_its_option(samples, noise_deg):
    bad_samples = samples is not None and samples < 1
    bad_noise = noise_deg is not None and not noise_deg >= 0
    if bad_samples or bad_noise:
        option = "--samples" if bad_samples else "--noise-deg"
        with pytest.raises(CadcogError, match=option):
            with_overrides(MODEL, samples=samples, noise_deg=noise_deg)
        return
    model = with_overrides(MODEL, samples=samples, noise_deg=noise_deg)
    assert model.samples == (MODEL.samples if samples is None else samples)
    expected = MODEL.sensor_noise_deg if noise_deg is None else noise_deg
    assert math.isclose(model.sensor_noise_deg, expected)


def test_a_set_up_campaign_needs_points_and_each_once():
    with pytest.raises(CadcogError, match="--setup needs --points"):
        check_points(None)
    with pytest.raises(CadcogError, match="given more than once"):
        check_points(["+x_30_90", " +x_30_90"])
    assert check_points([" +x_30_90", "-y_-30_-30 "]) == ["+x_30_90", "-y_-30_-30"]


@pytest.fixture(scope="module")
def rig():
    return load_rig(default_rig_path())


def test_same_seed_same_bytes_another_seed_other_readings(rig, tmp_path):
    a, b, c = (tmp_path / f"{n}.csv" for n in "abc")
    run_campaign(a, rig=rig, seed=7)
    run_campaign(b, rig=rig, seed=7)
    run = run_campaign(c, rig=rig, seed=8)
    assert a.read_bytes() == b.read_bytes() != c.read_bytes()
    hangs = read_readings(c, rig.inclinometer)
    assert [h.id for h in hangs] == [p.id for p in rig.suspension_points]
    assert run.n_hangs == len(hangs) and run.n_samples == sum(h.n_samples for h in hangs)
    assert run.seed == 8 and run.swings is None and run.warnings == ()


def test_readings_and_swings_are_written_together_or_neither(rig, tmp_path):
    out, folder, blocker = tmp_path / "c.csv", tmp_path / "taken", tmp_path / "a_file"
    folder.mkdir()
    blocker.write_text("not a folder")
    with pytest.raises(CadcogError, match="not a regular file"):  # refused before any work
        run_campaign(out, rig=rig, seed=1, swings=folder)
    with pytest.raises((CadcogError, OSError)):  # the swings' folder cannot be made: at staging
        run_campaign(out, rig=rig, seed=1, swings=blocker / "s.csv")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_file", "taken"]
    with pytest.raises(CadcogError, match="name the same file"):
        run_campaign(out, rig=rig, seed=1, swings=out)
    assert not out.exists()
    run_campaign(out, rig=rig, seed=1, swings=tmp_path / "new" / "s.csv")  # a new folder: made
    assert out.is_file() and (tmp_path / "new" / "s.csv").is_file()


def test_neither_or_both_of_rig_and_set_up_and_points_without_a_set_up_are_refused(rig, tmp_path):
    out = tmp_path / "c.csv"
    with pytest.raises(CadcogError, match="give a rig or a set-up"):
        run_campaign(out)
    with pytest.raises(CadcogError, match="--points goes with --setup"):
        run_campaign(out, rig=rig, points=["S1", "S2"])
    with pytest.raises(CadcogError, match="--seed must be non-negative"):
        run_campaign(out, rig=rig, seed=-1)
    assert not out.exists()


def test_a_virtual_campaign_replaces_only_a_virtual_campaign(rig, tmp_path):
    """A test day's readings are not replaced by a simulation (new-user trial: `campaign --out`
    over a measured file replaced it); a previous virtual campaign and its swings are."""
    out, swings = tmp_path / "c.csv", tmp_path / "s.csv"
    run_campaign(out, rig=rig, seed=1, swings=swings)
    first = out.read_bytes(), swings.read_bytes()
    run_campaign(out, rig=rig, seed=2, swings=swings)  # its own: replaced, both
    assert out.read_bytes() != first[0] and swings.read_bytes() != first[1]
    measured = tmp_path / "day.csv"
    measured.write_text(out.read_text(encoding="utf-8").split("\n", 1)[1], encoding="utf-8")
    before = measured.read_bytes()
    with pytest.raises(CadcogError, match=r"^--out .*day\.csv: exists and is not a virtual"):
        run_campaign(measured, rig=rig, seed=3)
    with pytest.raises(CadcogError, match=r"^--swings .*s\.csv: exists, and --out is not"):
        run_campaign(tmp_path / "new.csv", rig=rig, seed=3, swings=swings)
    assert measured.read_bytes() == before and not (tmp_path / "new.csv").exists()


def test_a_reversal_is_not_simulated_and_says_where_it_is_hung(cubesat_setup, tmp_path):
    with pytest.raises(
        CadcogError, match=r"^--points: \+x_30_90~: a reversal .*\(cadcog acquire\)"
    ):
        run_campaign(tmp_path / "c.csv", setup=cubesat_setup, points=["-x_-30_90", "+x_30_90~"])
    with pytest.raises(CadcogError, match=r"unknown candidate\(s\) nowhere~"):
        run_campaign(tmp_path / "c.csv", setup=cubesat_setup, points=["-x_-30_90", "nowhere~"])
