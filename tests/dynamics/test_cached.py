"""Inertia results kept by content (cadcog.dynamics.cached): read back exactly; fitted again
whenever a byte of a file or a number of the inputs changes; the swings' own refusal kept with
its message; the command's output the same hit or miss."""

from __future__ import annotations

import json

import pytest

import cadcog
from cadcog.cli import main
from cadcog.core.errors import DegenerateGeometryError
from cadcog.dynamics.cached import cached_inertia
from cadcog.dynamics.result import InertiaResult


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cached")
    readings, swings = folder / "c.csv", folder / "s.csv"
    assert main(["campaign", "--seed", "4", "--out", str(readings), "--swings", str(swings)]) == 0
    return readings, swings, cadcog.inertia(swings, readings)


def test_the_json_round_trip_is_exact(campaign):
    result = campaign[2]
    back = InertiaResult.from_dict(json.loads(json.dumps(result.to_dict())))
    assert back.to_dict() == result.to_dict()
    assert back.to_json() == result.to_json()
    assert (back.sigma_kg_mm2 == result.sigma_kg_mm2).all()


def test_a_second_call_reads_the_result_back_and_a_change_fits_again(campaign, tmp_path):
    _, swings, result = campaign
    calls = []

    def compute():
        calls.append(1)
        return result

    inputs = {"weighed_mass_kg": 1.0, "swings": str(swings)}
    first, hit1 = cached_inertia(compute, inputs, [swings])
    second, hit2 = cached_inertia(compute, inputs, [swings])
    assert (hit1, hit2, len(calls)) == (False, True, 1)
    assert first.to_dict() == second.to_dict() == result.to_dict()
    # another number among the inputs: another entry
    cached_inertia(compute, {**inputs, "weighed_mass_kg": 1.0 + 1e-15}, [swings])
    assert len(calls) == 2
    # one byte of the file: another entry
    copy = tmp_path / "s.csv"
    text = swings.read_text(encoding="utf-8")
    copy.write_text(text, encoding="utf-8")
    cached_inertia(compute, inputs, [copy])
    assert len(calls) == 2  # the same bytes elsewhere: the same entry (the path is an input)
    copy.write_text(text.replace("0", "1", 1), encoding="utf-8")
    cached_inertia(compute, inputs, [copy])
    assert len(calls) == 3


def test_the_swings_refusal_is_kept_with_its_message(campaign):
    swings = campaign[1]
    calls = []

    def refuse():
        calls.append(1)
        raise DegenerateGeometryError("hang S1: no swing mode stands out of the noise")

    for _ in range(2):
        with pytest.raises(DegenerateGeometryError, match="S1: no swing mode stands out"):
            cached_inertia(refuse, {"k": "refused"}, [swings])
    assert len(calls) == 1

    def other():
        calls.append(1)
        raise ValueError("not a refusal of the swings")

    for _ in range(2):
        with pytest.raises(ValueError):
            cached_inertia(other, {"k": "other"}, [swings])
    assert len(calls) == 3  # any other error is not kept


def test_the_command_prints_the_same_hit_or_miss(campaign, capsys, monkeypatch):
    readings, swings, _ = campaign
    args = ["inertia", str(swings), "--readings", str(readings), "--json"]
    capsys.readouterr()
    assert main(args) == 0
    miss = capsys.readouterr()
    import cadcog.dynamics.swingselect as swingselect

    def no_fit(*a, **k):
        raise AssertionError("fitted again on unchanged inputs")

    monkeypatch.setattr(swingselect, "fit_swing", no_fit)
    assert main(args) == 0
    hit = capsys.readouterr()
    assert (hit.out, hit.err) == (miss.out, miss.err)
