"""``cadcog/runs/balance.py``: the least ballast from the files, and what it says about them."""

from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("build123d")

from cadcog.runs.balance import run_balance

SETUP = Path(__file__).resolve().parents[2] / "parts" / "cubesat_3u_setup.toml"
POINT = '[[points]]\nid = "zm"\nposition_mm = [0.0, 0.0, -160.0]\n'


def _ballast(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "ballast.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_pieces_and_limits_heavier_than_the_spacecraft_are_said(tmp_path):
    """5 kg and 20 kg pieces for a 2.58 kg CubeSat (grams typed as kg) found no ballast and
    said nothing of why (second new-user trial)."""
    grams = run_balance(_ballast(tmp_path, "sizes_kg = [5, 20]\n" + POINT), setup=SETUP,
                        cog_limits_mm=(20.0, 20.0, 10.0))  # fmt: skip
    assert not grams.feasible
    assert any(n.startswith("the smallest piece (5 kg) weighs more than the spacecraft")
               for n in grams.notes)  # fmt: skip
    capped = run_balance(_ballast(tmp_path, POINT + "max_mass_kg = 300\n"), setup=SETUP,
                         cog_limits_mm=(20.0, 20.0, 10.0))  # fmt: skip
    assert any("location(s) zm take more than the spacecraft weighs" in n for n in capped.notes)


def test_a_sensible_file_gets_no_unit_note(tmp_path):
    fine = run_balance(_ballast(tmp_path, "sizes_kg = [0.005, 0.02]\n" + POINT), setup=SETUP,
                       cog_limits_mm=(20.0, 20.0, 10.0))  # fmt: skip
    assert fine.feasible and fine.total_ballast_kg > 0
    assert not any("in grams?" in n for n in fine.notes)
