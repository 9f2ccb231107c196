"""Closed-form mass properties and their combination."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from cadcog.mass.properties import MassProperties, box_properties, combine, cylinder_properties
from tests.mass.exact import assert_close_to_exact

lengths = st.floats(min_value=0.5, max_value=500.0)
coords = st.floats(min_value=-500.0, max_value=500.0)


@given(lengths, lengths, lengths, coords, coords, coords, st.floats(0.01, 0.99))
def test_box_split_in_two_recombines_to_the_whole(a, b, c, x, y, z, frac):
    """Cutting a box along x and combining the halves must give the whole box back."""
    rho = 7.85e-6
    whole = box_properties([a, b, c], [x, y, z], mass_kg=rho * a * b * c)
    a1, a2 = frac * a, (1 - frac) * a
    left = box_properties([a1, b, c], [x - a / 2 + a1 / 2, y, z], mass_kg=rho * a1 * b * c)
    right = box_properties([a2, b, c], [x + a / 2 - a2 / 2, y, z], mass_kg=rho * a2 * b * c)
    both = combine([left, right])
    assert both.mass_kg == pytest.approx(whole.mass_kg, rel=1e-12)
    np.testing.assert_allclose(both.cog_mm, whole.cog_mm, atol=1e-9 * (a + abs(x)))
    np.testing.assert_allclose(
        both.inertia_kg_mm2,
        whole.inertia_kg_mm2,
        rtol=1e-9,
        atol=1e-12 * np.abs(whole.inertia_kg_mm2).max(),
    )


def test_cylinder_along_z_matches_textbook():
    m_per_v = 2.0
    p = cylinder_properties([1.0, 2.0, 3.0], [0, 0, 1], 2.0, 6.0, density_kg_mm3=m_per_v)
    mass = m_per_v * np.pi * 4.0 * 6.0
    assert p.mass_kg == pytest.approx(mass)
    np.testing.assert_allclose(p.cog_mm, [1.0, 2.0, 6.0])
    expected = np.diag([mass * (3 * 4 + 36) / 12, mass * (3 * 4 + 36) / 12, mass * 4 / 2])
    np.testing.assert_allclose(p.inertia_kg_mm2, expected)


@given(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1))
def test_cylinder_inertia_is_a_rotation_of_the_axis_aligned_one(ax, ay, az):
    axis = np.array([ax, ay, az])
    if np.linalg.norm(axis) < 1e-3:
        axis = np.array([0.0, 0.0, 1.0])
    axis /= np.linalg.norm(axis)
    p = cylinder_properties([0, 0, 0], axis, 1.5, 4.0, density_kg_mm3=1.0)
    eig = np.sort(np.linalg.eigvalsh(p.inertia_kg_mm2))
    ref = cylinder_properties([0, 0, 0], [0, 0, 1], 1.5, 4.0, density_kg_mm3=1.0)
    np.testing.assert_allclose(eig, np.sort(np.diag(ref.inertia_kg_mm2)), rtol=1e-12)
    np.testing.assert_allclose(p.inertia_kg_mm2 @ axis, ref.inertia_kg_mm2[2, 2] * axis, atol=1e-9)


def test_removing_a_hole_then_adding_it_back_restores_the_box():
    box = box_properties([20, 10, 10], [10, 5, 5], mass_kg=2000 * 1e-3)
    hole = cylinder_properties([5, 5, 10], [0, 0, -1], 1.0, 4.0, density_kg_mm3=1e-3)
    holed = combine([box, hole.scaled(-1.0)])
    assert holed.mass_kg == pytest.approx(2.0 - hole.mass_kg)
    assert holed.cog_mm[0] > 10.0  # material removed at x = 5 moves the CoG towards +x
    assert holed.cog_mm[2] < 5.0  # and removed near the top moves it down
    back = combine([holed, hole])
    np.testing.assert_allclose(back.cog_mm, box.cog_mm, atol=1e-12)
    np.testing.assert_allclose(back.inertia_kg_mm2, box.inertia_kg_mm2, atol=1e-10)


def test_inertia_about_a_point_uses_the_parallel_axis_theorem():
    p = box_properties([2, 2, 2], [0, 0, 0], mass_kg=3.0)
    about = p.inertia_about([0, 0, 5])
    assert about[0, 0] == pytest.approx(p.inertia_kg_mm2[0, 0] + 3.0 * 25)
    assert about[2, 2] == pytest.approx(p.inertia_kg_mm2[2, 2])


def test_combine_rejects_empty_and_nonpositive_totals():
    with pytest.raises(ValueError, match="at least one part"):
        combine([])
    p = box_properties([1, 1, 1], [0, 0, 0], mass_kg=1.0)
    with pytest.raises(ValueError, match="combined mass must be positive"):
        combine([p, p.scaled(-1.0)])


def test_shapes_are_checked():
    with pytest.raises(ValueError, match=r"cog_mm must have shape \(3,\)"):
        MassProperties(1.0, [0, 0], np.eye(3), 1.0)
    with pytest.raises(ValueError, match=r"inertia_kg_mm2 must have shape \(3, 3\)"):
        MassProperties(1.0, [0, 0, 0], np.eye(2), 1.0)


def test_results_are_immutable():
    p = box_properties([1, 1, 1], [0, 0, 0], mass_kg=1.0)
    with pytest.raises(ValueError):
        p.cog_mm[0] = 3.0


@given(
    st.lists(
        st.tuples(
            st.floats(1e-6, 1e3),
            st.lists(st.floats(-1e4, 1e4), min_size=3, max_size=3),
            st.lists(st.floats(-10.0, 10.0), min_size=6, max_size=6),
        ),
        min_size=1,
        max_size=12,
    )
)
# The counterexample to the former claim "equal to the part-by-part loop to the bit" (a fresh
# hypothesis draw, issue 30): kept, now against the exact combination.
@example(
    [
        (1.0, [0.0, 0.0, 1.0], [0.0] * 6),
        (0.5, [0.0] * 3, [0.0] * 6),
        (0.25, [0.0, 1.0, 0.0], [0.0] * 6),
    ]
)
@example(
    [
        (1.0, [0.0, 0.0, 1.0], [1.0] * 6),
        (0.5, [0.0] * 3, [0.5] * 6),
        (0.25, [0.0, 1.0, 0.0], [-2.0] * 6),
    ]
)
def test_combine_is_the_exact_combination_within_rounding(parts):
    # combine() is vectorised over the parts; whatever order numpy sums in, it must be the
    # definition (computed exactly, in rationals) within the floating-point bound of its sums.
    items = []
    for mass, cog, a in parts:
        lower = np.array([[a[0], 0, 0], [a[1], a[2], 0], [a[3], a[4], a[5]]])
        items.append(MassProperties(mass, cog, lower @ lower.T, 1.0))
    assert_close_to_exact(combine(items), items)


def test_the_exact_reference_catches_a_wrong_combination():
    """The bound is tight enough to matter: one part's parallel-axis term left out fails it."""
    a = box_properties([1, 1, 1], [0, 0, 0], mass_kg=1.0)
    b = box_properties([1, 1, 1], [3, 0, 0], mass_kg=3.0)
    right = combine([a, b])
    wrong = MassProperties(4.0, right.cog_mm, a.inertia_kg_mm2 + b.inertia_about(right.cog_mm), 2)
    assert_close_to_exact(right, [a, b])
    with pytest.raises(AssertionError):
        assert_close_to_exact(wrong, [a, b])


@given(
    st.floats(1e-6, 1e3),
    st.lists(st.floats(-1e4, 1e4), min_size=3, max_size=3),
    st.lists(st.floats(-1e4, 1e4), min_size=3, max_size=3),
)
def test_inertia_about_a_point_is_the_parallel_axis_theorem(mass, cog, point):
    p = box_properties([2, 4, 6], cog, mass_kg=mass)
    assert_close_to_exact(
        p, [p], inertia_about_mm=np.array(point), about_value_kg_mm2=p.inertia_about(point)
    )
