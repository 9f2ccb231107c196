"""A refusal carries the model counted as it is, to the bit what computing it again gives
(``check`` as ``allow``, without ``strict``), and the command computes the model once where it
computed it twice."""

from __future__ import annotations

import json

import pytest

import cadcog
from cadcog.cad import bodies, stepmass
from cadcog.cad.massresults import Refusal, to_data
from cadcog.cad.stepmass import model_mass_properties
from cadcog.cad.stepread import read_step
from cadcog.cli import main
from cadcog.mass.materials import MaterialMap
from support.stepfixtures import Assembly, Part, kicad_like_board, write_step


def _bits(result) -> str:
    return json.dumps(to_data(result), default=lambda v: v.tolist())


@pytest.fixture
def nested(tmp_path):
    top = Assembly("top")
    top.add(Part("outer", [((20.0, 20.0, 20.0), (0.0, 0.0, 0.0))], 2700.0))
    top.add(Part("inner", [((5.0, 5.0, 5.0), (2.0, 2.0, 2.0))], 19300.0))
    return write_step(top, tmp_path / "nested.step")


@pytest.mark.parametrize("strict", [False, True])
def test_refused_overlaps_carry_the_model_counted_as_allow_counts_it(nested, strict):
    model = read_step(nested)
    with pytest.raises(Refusal, match=r"above the 0\.1% threshold") as info:
        model_mass_properties(model, None, overlaps="check", strict=strict)
    allowed = model_mass_properties(read_step(nested), None, overlaps="allow")
    assert info.value.as_is.overlaps.policy == "allow"
    assert _bits(info.value.as_is) == _bits(allowed)


@pytest.mark.parametrize("policy", ["check", "allow", "resolve", "skip"])
def test_a_strict_refusal_carries_the_model_without_strict(tmp_path, monkeypatch, policy):
    """Every product's topology reported invalid: ``strict`` checks all four products, without
    it only the three in booleans (the PCB, two pins; not the component's body), so the model
    carried is not the strict one with its notes relabelled."""
    step = write_step(kicad_like_board(2), tmp_path / "board.step")
    monkeypatch.setattr(bodies, "_valid", lambda shape: False)
    densities = MaterialMap.uniform(1850.0)
    with pytest.raises(Refusal, match="--strict: ") as info:
        model_mass_properties(read_step(step), densities, overlaps=policy, strict=True)
    as_is = "allow" if policy == "check" else policy  # as --json has always written it
    without = model_mass_properties(read_step(step), densities, overlaps=as_is)
    assert _bits(info.value.as_is) == _bits(without)
    if policy != "skip":
        strict_count = str(info.value).split("invalid topology in ")[1].split(" ")[0]
        assert len(without.audit.invalid_topology) < int(strict_count)


def test_a_refusal_survives_pickling(nested):
    import pickle

    with pytest.raises(Refusal) as info:
        model_mass_properties(read_step(nested), None)
    back = pickle.loads(pickle.dumps(info.value))
    assert str(back) == str(info.value) and _bits(back.as_is) == _bits(info.value.as_is)


def test_the_command_computes_a_refused_model_once(nested, tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("CADCOG_NO_CACHE", "1")
    calls = []
    real = stepmass.model_mass_properties

    def counted(*a, **k):
        calls.append(k.get("overlaps"))
        return real(*a, **k)

    monkeypatch.setattr(stepmass, "model_mass_properties", counted)
    argv = ["massprops", str(nested), "--json", "--csv", str(tmp_path / "b.csv")]
    assert main(argv) == 2
    out = json.loads(capsys.readouterr().out)
    assert calls == ["check"]
    assert out["refused"]["counted_as"].startswith("each solid as it is")
    assert out["overlaps"]["policy"] == "allow" and out["overlaps"]["n_pairs"] == 1


def test_the_api_raises_the_refusal_and_a_cached_one_carries_the_same_model(nested, monkeypatch):
    from cadcog.cad import stepread

    with pytest.raises(Refusal) as first:
        cadcog.mass_properties(nested)
    monkeypatch.setattr(stepread, "read_step", lambda p: pytest.fail("read again"))
    with pytest.raises(Refusal) as again:  # read back from the cache
        cadcog.mass_properties(nested, workers=1)
    assert str(again.value) == str(first.value)
    assert _bits(again.value.as_is) == _bits(first.value.as_is)
