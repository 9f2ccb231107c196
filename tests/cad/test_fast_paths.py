"""The shortcuts that keep ``massprops`` fast give what the long way gives: the sweep's candidate
pairs are every pair's, a cut shared by instances of one subassembly is each instance's own
cut, ``skip`` counts what ``allow`` counts, and topology is checked where it matters."""

from __future__ import annotations

import numpy as np
import pytest

from cadcog.cad import bodies, overlaps, resolve
from cadcog.cad.occt import volume_properties
from cadcog.cad.overlaps import candidate_pairs, cut_by
from cadcog.cad.stepmass import model_mass_properties
from cadcog.cad.stepread import read_step
from cadcog.core import tolerances
from cadcog.mass.materials import load_materials
from support.stepfixtures import Assembly, Place, kicad_like_board, write_step


def _all_pairs(lo, hi, depth=tolerances.BOX_OVERLAP_MM):
    """Every pair compared, as the previous release did."""
    d = np.minimum(hi[:, None, :], hi[None, :, :]) - np.maximum(lo[:, None, :], lo[None, :, :])
    i, j = np.nonzero(np.all(d > depth, axis=2))
    return sorted((int(a), int(b)) for a, b in zip(i, j, strict=True) if a < b)


@pytest.mark.parametrize(("n", "spread"), [(1, 1.0), (2, 1.0), (60, 4.0), (400, 30.0), (300, 1.0)])
def test_sweep_finds_the_pairs_every_pair_comparison_finds(n, spread):
    rng = np.random.default_rng(n)
    lo = rng.uniform(0.0, spread, (n, 3))
    hi = lo + rng.uniform(0.0, 3.0, (n, 3))
    lo[::5], hi[::5] = np.round(lo[::5]), np.round(hi[::5])  # ties and degenerate boxes
    hi[1::9] = lo[1::9] + tolerances.BOX_OVERLAP_MM  # boxes exactly at the depth threshold
    assert candidate_pairs(lo, hi) == _all_pairs(lo, hi)


def test_sweep_blocks_give_the_same_pairs(monkeypatch):
    rng = np.random.default_rng(7)
    lo = rng.uniform(0.0, 10.0, (500, 3))
    hi = lo + 2.0
    whole = candidate_pairs(lo, hi)
    monkeypatch.setattr(overlaps, "_BLOCK_PAIRS", 37)
    assert candidate_pairs(lo, hi) == whole and len(whole) > 37


def _boards(tmp_path, copies: int, axis=(1, 1, 0)):
    """``copies`` instances of one KiCad-like board (its PCB cut by the same pins in each)."""
    board = kicad_like_board(6)
    sat = Assembly("sat")
    for k in range(copies):
        sat.add(board, Place((150.0 * k, 10.0 * k, 5.0 * k), axis, 30.0 * k))
    return read_step(write_step(sat, tmp_path / "boards.step"))


def _densities(tmp_path):
    path = tmp_path / "materials.toml"
    path.write_text('[materials]\n"PCB*" = 1850.0\n"*" = 3000.0\n', encoding="utf-8")
    return load_materials(path)


def test_instances_share_one_cut_equal_to_each_instances_own(tmp_path, monkeypatch):
    model = _boards(tmp_path, 3)
    calls = []

    def counted(shape, tools):
        calls.append(len(tools))
        return cut_by(shape, tools)

    monkeypatch.setattr(resolve, "cut_by", counted)
    r = model_mass_properties(model, _densities(tmp_path), overlaps="resolve", workers=1)
    assert calls == [12]  # one PCB, its 12 pins: once, not once per board
    by_path = {b.path: b for b in model.bodies}
    pcbs = [b for b in r.bodies if b.path.endswith("/PCB")]
    assert len(pcbs) == 3
    for got in pcbs:
        pins = [p for p in r.bodies if p.path.startswith(got.path[: -len("PCB")]) and p is not got]
        tools = [by_path[p.path].shape for p in pins if "COMPOUND" in p.path]
        cut = cut_by(by_path[got.path].shape, tools)
        assert cut is not None
        own = volume_properties(cut)  # unit density: scale by the PCB's
        rho = got.density_kg_m3 * 1e-9
        assert got.properties.volume_mm3 == pytest.approx(own.volume_mm3, rel=1e-12)
        assert got.properties.mass_kg == pytest.approx(own.mass_kg * rho, rel=1e-12)
        np.testing.assert_allclose(got.properties.cog_mm, own.cog_mm, rtol=0, atol=1e-9)
        np.testing.assert_allclose(
            got.properties.inertia_kg_mm2,
            own.inertia_kg_mm2 * rho,
            rtol=0,
            atol=1e-12 * np.abs(own.inertia_kg_mm2 * rho).max(),
        )


def test_skip_counts_what_allow_counts_without_a_boolean(tmp_path, monkeypatch):
    model = _boards(tmp_path, 2)
    allowed = model_mass_properties(model, _densities(tmp_path), overlaps="allow", workers=1)
    assert allowed.overlaps.pairs  # there are overlaps to skip
    monkeypatch.setattr(overlaps, "common_volume", lambda a, b: pytest.fail("a boolean ran"))
    skipped = model_mass_properties(model, _densities(tmp_path), overlaps="skip", workers=1)
    assert skipped.total.to_dict() == allowed.total.to_dict()
    assert [b.to_dict() for b in skipped.bodies] == [b.to_dict() for b in allowed.bodies]
    assert skipped.overlaps.n_candidates == 0 and not skipped.overlaps.pairs
    assert any("overlaps not searched" in line for line in skipped.info)


def test_topology_is_checked_for_the_solids_in_booleans_and_all_under_strict(tmp_path, monkeypatch):
    model = _boards(tmp_path, 2, axis=(0, 0, 1))  # boards level: boxes as tight as the solids
    checked: list[object] = []

    def valid(shape):
        checked.append(shape)
        return True

    monkeypatch.setattr(bodies, "_valid", valid)
    model_mass_properties(model, _densities(tmp_path), overlaps="allow", workers=1)
    # Products: the PCB, and the component's three solids (body and two pins). The bodies sit
    # on the PCB's top face (contact: boxes touching, not candidates); the pins sink into it.
    assert len(checked) == 3
    checked.clear()
    model_mass_properties(model, _densities(tmp_path), overlaps="skip", workers=1)
    assert checked == []
    model_mass_properties(model, _densities(tmp_path), overlaps="allow", strict=True, workers=1)
    assert len(checked) == 4  # every product, for --strict
