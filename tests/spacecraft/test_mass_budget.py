"""The mass budget's rollup and uncertainties, checked against direct sampling."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.mass.properties import MassProperties, box_properties, combine
from cadcog.spacecraft.mass_budget import mass_budget
from tests.mass.exact import assert_close_to_exact


@dataclass(frozen=True)
class Line:
    nodes: tuple[str, ...]
    properties: MassProperties
    sigma_rel: float | None = None
    g: float = 0.0

    @property
    def item(self) -> str:
        """The battery's cells are one item; every other body is its own."""
        return "sat/battery" if self.nodes[1] == "battery" else "/".join(self.nodes)

    @property
    def growth(self) -> float:
        return self.g


RAIL = [8, 8, 300]
CELL = [18, 18, 65]
PAYLOAD = [60, 60, 100]


def _size(line: Line) -> list[int]:
    return {"structure": RAIL, "battery": CELL, "payload": PAYLOAD}[line.nodes[1]]


def _lines(k: float = 1.0):
    """A satellite: a structure (two rails), a battery pack (two cells, one item), a payload;
    item uncertainties 2 %, 5 %, 10 %, times ``k``."""
    box = box_properties
    rail = RAIL
    cell = CELL
    return [
        Line(("sat", "structure", "rail_1"), box(rail, [-46, -46, 0], mass_kg=0.05), 0.02 * k),
        Line(("sat", "structure", "rail_2"), box(rail, [46, 46, 0], mass_kg=0.05), 0.02 * k),
        Line(("sat", "battery", "c1"), box(cell, [-10, 0, -100], mass_kg=0.047), 0.05 * k),
        Line(("sat", "battery", "c2"), box(cell, [10, 0, -100], mass_kg=0.047), 0.05 * k),
        Line(("sat", "payload"), box(PAYLOAD, [0, 5, 90], mass_kg=0.8), 0.10 * k, g=0.2),
    ]


def test_rollup_by_node():
    b = mass_budget(_lines())
    assert b.root.name == "sat" and [c.name for c in b.root.children] == [
        "structure",
        "battery",
        "payload",
    ]
    total = combine(x.properties for x in _lines())
    assert b.root.mass_kg == pytest.approx(total.mass_kg)
    battery = b.root.children[1]
    assert battery.mass_kg == pytest.approx(0.094) and battery.n_bodies == 2
    np.testing.assert_allclose(battery.cog_mm, [0, 0, -100])
    assert sum(c.share for c in b.root.children) == pytest.approx(1.0)
    # The battery is one item: its two cells vary together, σ = 5 % of 94 g.
    assert battery.mass_sigma_kg == pytest.approx(0.05 * 0.094)
    assert b.root.children[0].mass_sigma_kg == pytest.approx(np.hypot(0.001, 0.001))


@pytest.mark.parametrize("k", [0.2, 1.0])
def test_rolled_up_uncertainty_matches_sampling(k):
    """Scale each item's mass by (1 + ε), ε ~ N(0, σ²), and shift its CoG by the documented
    default, N(0, (σ · spread)²) per axis, the spread of its mass computed here from the boxes'
    sizes: the sampled total mass and CoG covariances match the budget's first-order figures:
    closely at 0.4-2 % item uncertainty, within 7 % at 2-10 % (the CoG is a ratio: its spread
    grows faster than linear)."""
    lines = _lines(k)
    b = mass_budget(lines)
    rng = np.random.default_rng(7)
    items = sorted({x.item for x in lines})
    n = 400_000
    eps = {k: rng.normal(0.0, next(x.sigma_rel for x in lines if x.item == k), n) for k in items}
    m = np.array([x.properties.mass_kg for x in lines])
    c = np.array([x.properties.cog_mm for x in lines])
    scale = np.stack([1.0 + eps[x.item] for x in lines])  # (bodies, n)
    shifts = {}
    for key in items:
        members = [x for x in lines if x.item == key]
        mi = sum(x.properties.mass_kg for x in members)
        ci = sum(x.properties.mass_kg * x.properties.cog_mm for x in members) / mi
        second = sum(
            x.properties.mass_kg
            * (np.array(_size(x)) ** 2 / 12.0 + (x.properties.cog_mm - ci) ** 2)
            for x in members
        )
        sigma_c = members[0].sigma_rel * np.sqrt(second / mi)
        shifts[key] = rng.normal(0.0, 1.0, (n, 3)) * sigma_c
    masses = m[:, None] * scale
    total = masses.sum(axis=0)
    moved = c[:, None, :] + np.stack([shifts[x.item] for x in lines])  # (bodies, n, 3)
    cogs = np.einsum("bn,bnk->nk", masses, moved) / total[:, None]
    assert total.std() == pytest.approx(b.mass_sigma_kg, rel=0.02)
    sampled = np.cov(cogs.T)
    scale = np.sqrt(np.outer(np.diag(b.cog_cov_mm2), np.diag(b.cog_cov_mm2)))
    tolerance = 0.03 if k < 1 else 0.07
    assert np.max(np.abs(sampled - b.cog_cov_mm2) / scale) < tolerance
    # Weighed (--total-mass-kg): the spacecraft's total is known. The draws whose total lies
    # within 0.05 σ of the model's are the spacecraft that weigh what it does: the spread of
    # their CoG is the budget's conditioned covariance (the unconditioned σ_z is 31 %
    # wider here: the heavy payload's mass moves the total and the CoG together).
    if k < 1:
        weighed = mass_budget(lines, total_given=True)
        assert weighed.mass_sigma_kg == 0.0
        near = np.abs(total - b.root.mass_kg) < 0.05 * b.mass_sigma_kg
        assert near.sum() > 1000
        kept = np.cov(cogs[near].T)
        err = np.abs(kept - weighed.cog_cov_mm2) / scale
        assert np.max(err) < 0.03, err
        assert np.max(np.abs(kept - b.cog_cov_mm2) / scale) > 0.1  # conditioning matters


def test_growth_gives_the_predicted_mass_and_cog():
    b = mass_budget(_lines())
    assert b.growth_kg == pytest.approx(0.2 * 0.8)
    grown = combine(
        MassProperties(
            x.properties.mass_kg * (1 + x.growth),
            x.properties.cog_mm,
            x.properties.inertia_kg_mm2,
            x.properties.volume_mm3,
        )
        for x in _lines()
    )
    np.testing.assert_allclose(b.predicted.cog_mm, grown.cog_mm)


def test_bodies_without_uncertainty_are_counted_in_the_coverage():
    lines = [
        *_lines()[:2],
        Line(("sat", "harness"), box_properties([1, 1, 1], [0, 0, 0], mass_kg=0.1)),
    ]
    b = mass_budget(lines)
    assert b.sigma_coverage == pytest.approx(0.1 / 0.2)
    assert not b.root.sigma_complete
    assert mass_budget(lines[2:]).mass_sigma_kg is None


def test_an_empty_budget_is_refused():
    with pytest.raises(ValueError, match="at least one body"):
        mass_budget([])


@given(
    st.lists(
        st.tuples(
            st.lists(st.sampled_from("abc"), min_size=1, max_size=3),
            st.floats(1e-4, 10.0),
            st.lists(st.floats(-500.0, 500.0), min_size=3, max_size=3),
        ),
        min_size=1,
        max_size=10,
    )
)
def test_every_node_is_the_combination_of_its_bodies(bodies):
    # The budget computes single-body nodes for all bodies at once (speed): every node must
    # still be the combination of the bodies below it (computed exactly, in rationals), and its
    # inertia about the total's CoG that combination's, within the floating-point bound.
    lines = [
        Line(("sat", *path, f"body{k}"), box_properties([1, 2, 3], cog, mass_kg=mass))
        for k, (path, mass, cog) in enumerate(bodies)
    ]
    budget = mass_budget(lines)
    total = combine(b.properties for b in lines)
    for _, node in budget.root.walk():
        below = [
            b
            for b in lines
            if "/".join(b.nodes).startswith(node.path + "/") or ("/".join(b.nodes) == node.path)
        ]
        if node is budget.root and node.path in ("", "sat"):
            below = lines
        got = MassProperties(node.mass_kg, node.cog_mm, node.inertia_kg_mm2, 1.0)
        assert_close_to_exact(
            got,
            [b.properties for b in below],
            inertia_about_mm=total.cog_mm,
            about_value_kg_mm2=node.inertia_total_cog_kg_mm2,
        )
