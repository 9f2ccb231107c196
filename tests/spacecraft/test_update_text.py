"""``cadcog update``'s readable numbers (text and page): significant figures, units that fit,
the products' convention named, on a small object whose masses used to print as zeros."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from cadcog.cli.update import print_update
from cadcog.mass.properties import MassProperties, box_properties
from cadcog.spacecraft import update_text as ut
from cadcog.spacecraft.items import Item
from cadcog.spacecraft.update import Measurement, update_budget

# A 30 mg screw in a 5 g bracket, with a 2 g fixed clip: masses the old fixed decimals
# (".1f" in g, ".4f" in kg) printed as 0.0 and 0.0050.
SCREW = box_properties([2, 2, 8], [0, 0, 20], mass_kg=0.00003)
BRACKET = box_properties([20, 20, 5], [0, 0, 0], mass_kg=0.005)
CLIP = box_properties([5, 5, 5], [5, 0, 0], mass_kg=0.002)
ITEMS = [
    Item.with_default_cog("bracket", BRACKET, 0.02),
    Item.with_default_cog("screw", SCREW, 0.1),
]

# The updated inertia of the tests of the inertia's cells: every entry below 1 kg·mm² (so in
# g·mm²), ∫xy dm = +0.0005 kg·mm² (tensor entry −0.0005), ∫xz dm = −0.0002, ∫yz dm = 0.
TENSOR = np.array([[0.004, -0.0005, 0.0002], [-0.0005, 0.005, 0.0], [0.0002, 0.0, 0.006]])
TENSOR_SIGMA = np.full((3, 3), 0.00001)


def _result():
    total = 0.00003 + 0.005 + 0.002
    cog = (0.00003 * SCREW.cog_mm + 0.005 * BRACKET.cog_mm + 0.002 * CLIP.cog_mm) / total
    me_mass, me_cog = 0.001, np.array([0.0, 0.0, 30.0])
    assembly = (total * cog + me_mass * me_cog) / (total + me_mass)
    meas = Measurement(
        assembly, np.eye(3) * 0.01, total, 0.000001, me_mass, me_cog, np.zeros((3, 3))
    )
    return update_budget(ITEMS, CLIP, meas)


@pytest.fixture(scope="module")
def result():
    r = _result()
    posterior = MassProperties(r.posterior.mass_kg, r.posterior.cog_mm, TENSOR, 1.0)
    return replace(r, posterior=posterior, posterior_inertia_sigma_kg_mm2=TENSOR_SIGMA)


def test_a_small_object_is_in_grams_to_the_weighing_s_resolution(result):
    rows = ut.mass_cog_rows(result)
    assert rows[0][0] == "mass (g)"
    # weighed 7.030 g to 1 mg: σ to two figures, the value to σ's last decimal
    assert rows[0][2] == "7.0300 ± 0.0010 (weighed)"
    assert rows[1][0] == "CoG x (mm)" and len(rows) == 4


def test_the_screw_s_mass_and_change_print_with_significant_figures(result):
    headers, rows = ut.item_table(result.ranked_items())
    assert headers[2] == "CAD mass (g)" and headers[4] == "change (g)"
    by_key = {row[0]: row for row in rows}
    assert by_key["screw"][2] == "0.03"  # was "0.0" (".1f" in g)
    assert by_key["bracket"][2] == "5"
    screw = next(c for c in result.items if c.key == "screw")
    sigma_g = screw.cad_mass_kg * screw.delta_sigma_rel * 1e3  # about 10 % of 30 mg
    assert 0.001 < sigma_g < 0.01 and screw.delta_rel == 0.0  # no gap: nothing moved
    assert by_key["screw"][4] == f"0.0000 ± {sigma_g:.4f}"  # was "+0.0 g"


def test_an_unmodelled_milligram_is_not_zero(result):
    r = replace(
        result,
        unmodelled_mass_kg=0.00003,
        unmodelled_mass_sigma_kg=0.00001,
        unmodelled_probability=1.0,
        unmodelled_cog_mm=None,
        unmodelled_cog_cov_mm2=None,
        unmodelled_negative=False,
    )
    # was "0.0 ± 0.0 g"
    assert ut.unmodelled_summary(r).startswith("0.030 ± 0.010 g (not resolved")


def test_the_inertia_names_its_entries_and_their_convention(result):
    assert ut.inertia_unit(result) == ("g·mm²", 1000.0)
    assert ut.moment_cells(result) == [
        "Ixx 4.000 ± 0.010",
        "Iyy 5.000 ± 0.010",
        "Izz 6.000 ± 0.010",
    ]
    # positive: Pxy = +∫xy dm = −(tensor entry)
    assert ut.product_cells(result, "positive") == [
        "0.500 ± 0.010",
        "-0.200 ± 0.010",
        "0.000 ± 0.010",
    ]
    assert ut.product_cells(result, "negative") == [
        "-0.500 ± 0.010",
        "0.200 ± 0.010",
        "0.000 ± 0.010",
    ]
    assert ut.tensor_rows(result)[0] == ["x", "4.000 ± 0.010", "-0.500 ± 0.010", "0.200 ± 0.010"]


def test_the_command_prints_grams_and_named_products(result, capsys):
    print_update(result)
    out = capsys.readouterr().out
    assert "\nmass (g)  " in out
    assert "updated inertia about the CoG, model axes (g·mm², ± 1 σ):" in out
    assert "  Ixx 4.000 ± 0.010  Iyy 5.000 ± 0.010  Izz 6.000 ± 0.010\n" in out
    line = next(s for s in out.splitlines() if s.startswith("  Pxy "))
    assert line.startswith("  Pxy 0.500 ± 0.010  Pxz -0.200 ± 0.010  Pyz 0.000 ± 0.010  ")
    assert "Pxy = +∫xy dm" in line  # massprops's words for its default convention
    items = out.split("\nitems (", 1)[1].splitlines()
    screw = next(s for s in items if s.startswith("  screw "))
    assert screw.split()[2] == "0.03"  # its CAD mass in the items' column in g (was "0.0")
