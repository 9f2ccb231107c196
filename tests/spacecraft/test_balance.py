"""The least ballast (``cadcog.spacecraft.balance``): closed forms, an independent linear
programme, brute force over discrete pieces, infeasible cases, and the confidence checked by
drawing the spacecraft from its stated uncertainty."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.optimize import linprog
from scipy.stats import norm

from cadcog.spacecraft.balance import face_quantile, least_ballast, with_ballast
from cadcog.spacecraft.ballast_spec import BallastPoint, BallastSpec, UncertainMass


def state(mass=1.0, cog=(0.0, 0.0, 0.0), sigma=(0.0, 0.0, 0.0), mass_sigma=0.0, cross=None):
    return UncertainMass(
        mass,
        mass_sigma,
        np.asarray(cog, dtype=float),
        np.diag(np.square(sigma)).astype(float),
        np.zeros(3) if cross is None else np.asarray(cross, dtype=float),
        "test",
    )


def spec(*points, sizes=None, total=None):
    return BallastSpec(
        tuple(BallastPoint(f"p{i}", np.asarray(p[0], float), p[1]) for i, p in enumerate(points)),
        sizes,
        total,
        "test",
    )


def test_one_location_closed_form_with_the_binding_face_s_quantile():
    """x: M c + m p over M + m, plus z σ' (σ' = M σ / (M + m)), equals L at the least m:
    m = M (c + z σ - L) / (L - p); the reported P(inside) is at least the confidence."""
    s = state(2.0, (15.0, 0, 0), (1.5, 0.0, 0.0))
    sp = spec(((-60.0, 0.0, 0.0), None))
    r = least_ballast(s, sp, np.zeros(3), [10.0, 20.0, 20.0], 0.95)
    z = r.face_quantiles[0]  # the +x face binds
    expected = 2.0 * (15.0 + z * 1.5 - 10.0) / (10.0 + 60.0)
    assert r.total_ballast_kg == pytest.approx(expected, rel=1e-9)
    assert r.cog_mm[0] + z * np.sqrt(r.cog_cov_mm2[0, 0]) == pytest.approx(10.0, abs=1e-9)
    assert r.probability_inside >= 0.95 - 1e-6
    assert r.optimal and r.feasible


def test_the_union_bound_budgets_sum_to_at_most_the_miss_probability():
    """Whatever the shares chosen, the six faces' budgets sum to at most 1 - P (the
    guarantee), and the face that binds spends nearly all of it."""
    s = state(2.0, (15.0, -4.0, 30.0), (1.5, 2.0, 3.0))
    sp = spec(((-60.0, 0.0, 0.0), None), ((0.0, 0.0, -100.0), None))
    for confidence in (0.9, 0.95, 0.99):
        r = least_ballast(s, sp, np.zeros(3), [10.0, 20.0, 20.0], confidence)
        assert norm.sf(r.face_quantiles).sum() <= (1 - confidence) * (1 + 1e-9)
        assert norm.sf(r.face_quantiles).sum() > 0.99 * (1 - confidence)  # all spent


def test_nothing_needed_when_inside_already():
    r = least_ballast(
        state(1.0, (1.0, 0, 0), (0.5, 0.5, 0.5)),
        spec(((50.0, 0, 0), None)),
        np.zeros(3),
        [20.0, 20.0, 20.0],
    )
    assert r.feasible and r.total_ballast_kg == 0.0 and r.probability_inside > 0.99


def test_an_axis_short_only_because_another_misses_is_named():
    """y far out (its face misses with P ≈ 0.9), x centred: x's margin is negative only
    because y spends more than the whole 5 %; ``before`` names x (its own faces miss with
    ~1e-8), not y (short on its own) nor z (positive)."""
    s = state(1.0, (0.0, 28.0, 0.0), (3.0, 3.0, 0.02))
    r = least_ballast(s, spec(((0.0, -60.0, 0.0), None)), np.zeros(3), [20.0, 25.0, 5.0], 0.95)
    b = r.before
    assert norm.sf((25.0 - 28.0) / 3.0) > 0.05  # y alone spends the budget
    assert b["margin_mm"][0] < 0 and b["margin_mm"][2] > 0
    assert b["axes_without_budget"] == ["x"]
    assert r.feasible and min(r.margin_mm) >= -1e-7  # with the ballast, every axis inside


def _independent_lp(s, positions, caps, total, centre, limits, z):
    """The multiplied-out programme written again from its definition, for linprog."""
    a, b = [], []
    sd = np.sqrt(np.diag(s.cog_cov_mm2))
    for k in range(3):
        for sign in (1, -1):
            # sign (c'_k - o_k) + z σ'_k <= L_k, times (M + Σm), σ' = M σ / (M + Σm)
            a.append([sign * (p[k] - centre[k]) - limits[k] for p in positions])
            b.append(
                limits[k] * s.mass_kg
                - sign * s.mass_kg * (s.cog_mm[k] - centre[k])
                - z * s.mass_kg * sd[k]
            )
    a_ub, b_ub = np.array(a), np.array(b)
    if total is not None:
        a_ub = np.vstack([a_ub, np.ones(len(positions))])
        b_ub = np.append(b_ub, total)
    return linprog(
        np.ones(len(positions)),
        A_ub=a_ub,
        b_ub=b_ub,
        bounds=[(0, c) for c in caps],
        method="highs-ipm",
    )


def test_the_programme_agrees_with_an_independent_linprog_on_random_problems():
    """200 random problems (equal shares, exact mass): the same feasibility and the same least
    total as linprog on the programme written out again; every solution meets the envelope
    when checked directly (not multiplied out)."""
    rng = np.random.default_rng(7)
    agreed = 0
    for _ in range(200):
        n = int(rng.integers(1, 6))
        s = state(rng.uniform(0.5, 5), rng.normal(0, 15, 3), rng.uniform(0, 3, 3))
        positions = rng.uniform(-120, 120, (n, 3))
        caps = [None if rng.random() < 0.3 else float(rng.uniform(0.01, 2)) for _ in range(n)]
        total = None if rng.random() < 0.5 else float(rng.uniform(0.05, 3))
        limits = rng.uniform(5, 40, 3)
        sp = spec(*zip(positions, caps, strict=True), total=total)
        r = least_ballast(s, sp, np.zeros(3), limits, 0.95, allocate=False)
        z = face_quantile(0.95)
        ref = _independent_lp(s, positions, caps, total, np.zeros(3), limits, z)
        assert r.feasible == (ref.status == 0), ref.message
        if r.feasible:
            agreed += 1
            assert r.total_ballast_kg == pytest.approx(ref.fun, rel=1e-6, abs=1e-9)
            _, _, cog, cov = with_ballast(s, positions, r.masses_kg)
            margin = limits - np.abs(cog) - z * np.sqrt(np.diag(cov))
            assert np.all(margin >= -1e-7), margin
    assert agreed > 40  # the draw holds feasible problems, not only refusals


def test_discrete_pieces_match_brute_force():
    """Two locations, pieces of 3 g and 7 g, up to 12 of each: the integer programme finds
    the least total that meets the envelope, as enumerating every combination does."""
    rng = np.random.default_rng(3)
    for _ in range(15):
        s = state(0.4, (rng.uniform(8, 14), rng.uniform(-3, 3), 0.0), (0.3, 0.3, 0.3))
        positions = np.array([[-45.0, rng.uniform(-10, 10), 5.0], [-30.0, 20.0, -5.0]])
        sizes = (0.003, 0.007)
        sp = spec((positions[0], 12 * 0.007 + 12 * 0.003), (positions[1], None), sizes=sizes)
        limits = np.array([6.0, 20.0, 20.0])
        r = least_ballast(s, sp, np.zeros(3), limits, 0.9, allocate=False)
        z = face_quantile(0.9)
        counts = np.array(list(itertools.product(range(13), repeat=4)), dtype=float)
        m = np.c_[
            counts[:, 0] * 0.003 + counts[:, 1] * 0.007, counts[:, 2] * 0.003 + counts[:, 3] * 0.007
        ]
        total = s.mass_kg + m.sum(axis=1, keepdims=True)
        cog = (s.mass_kg * s.cog_mm + m @ positions) / total  # every combination at once
        sd = s.mass_kg * np.sqrt(np.diag(s.cog_cov_mm2)) / total  # exact mass
        ok = np.all(limits - np.abs(cog) - z * sd >= -1e-12, axis=1)
        best = m.sum(axis=1)[ok].min() if ok.any() else None
        if best is None:
            assert not r.feasible
        else:
            assert r.feasible and r.optimal
            assert r.total_ballast_kg == pytest.approx(best, abs=1e-12)
            assert r.counts is not None
            assert r.counts @ np.array(sizes) == pytest.approx(r.masses_kg, abs=1e-12)


def test_infeasible_says_which_face_and_how_much_moment():
    """One location capped at 50 g: the +x face stays short by exactly the moment the
    constraint misses at the cap; the shortfall in mm is that moment over the mass."""
    s = state(1.0, (20.0, 0, 0))
    sp = spec(((-50.0, 0.0, 0.0), 0.05))
    r = least_ballast(s, sp, np.zeros(3), [10.0, 20.0, 20.0], 0.95)
    assert not r.feasible and r.total_ballast_kg == 0.0
    (short,) = r.shortfall
    assert (short["axis"], short["side"]) == ("x", "+")
    # at the cap: M (c - L) + m (p - L) = 1 (10) + 0.05 (-60) = 7 kg·mm short
    assert short["moment_kg_mm"] == pytest.approx(7.0, rel=1e-9)
    assert short["cog_shift_mm"] == pytest.approx(7.0 / 1.05, rel=1e-9)


def test_an_uncertainty_wider_than_the_envelope_is_said():
    s = state(1.0, (0.0, 0, 0), (10.0, 0, 0))
    sp = spec(((-50.0, 0.0, 0.0), 0.01))
    r = least_ballast(s, sp, np.zeros(3), [10.0, 20.0, 20.0], 0.95)
    assert not r.feasible
    assert any("exceeds the half-width" in n for n in r.notes)


def test_the_confidence_holds_when_the_spacecraft_is_drawn_from_its_uncertainty():
    """The CoG (σ 2-4 mm) and the mass (5 %, correlated with the CoG) drawn 200 000 times:
    with the ballast found, the CoG falls inside the envelope in at least the confidence
    (union bound), and the reported P(inside) is the drawn rate within its sampling error."""
    rng = np.random.default_rng(11)
    cov = np.array([[4.0, 1.0, 0.5], [1.0, 9.0, -1.0], [0.5, -1.0, 16.0]])
    cross = np.array([0.004, -0.002, 0.01])  # Cov(c, M), mm·kg
    s = UncertainMass(2.5, 0.125, np.array([6.0, -3.0, 25.0]), cov, cross, "test")
    sp = spec(((-40.0, 30.0, -150.0), 0.4), ((40.0, -30.0, -150.0), 0.4), ((-45.0, 0, 0), None))
    limits = np.array([20.0, 20.0, 15.0])
    r = least_ballast(s, sp, np.zeros(3), limits, 0.95)
    assert r.feasible and r.total_ballast_kg > 0
    joint = np.zeros((4, 4))
    joint[:3, :3], joint[:3, 3], joint[3, :3], joint[3, 3] = cov, cross, cross, 0.125**2
    draws = rng.multivariate_normal(np.r_[s.cog_mm, s.mass_kg], joint, size=200_000)
    positions = np.array([p.position_mm for p in sp.points])
    moment = draws[:, 3:4] * draws[:, :3] + r.masses_kg @ positions
    cog = moment / (draws[:, 3:4] + r.total_ballast_kg)
    rate = np.mean(np.all(np.abs(cog) <= limits, axis=1))
    se = np.sqrt(rate * (1 - rate) / len(draws))
    assert rate >= 0.95 - 4 * se
    assert rate == pytest.approx(r.probability_inside, abs=5 * se + 2e-3)


@settings(max_examples=60, deadline=None)
@example(cog=[36.5, 0.0, 0.0], sigma=[0.0, 0.0, 0.0], x=9.5, confidence=0.5)  # on the face
# x put exactly on its face (its gap -4e-15 mm with no spread) while z spends the budget: the
# margin once read the exact face as missed and left z none (found by a fresh hypothesis run)
@example(cog=[-33.5, 0.0, -1.0], sigma=[0.0, 0.0, 0.359375], x=0.3125, confidence=0.5)
@given(
    cog=st.lists(st.floats(-40, 40), min_size=3, max_size=3),
    sigma=st.lists(st.floats(0, 3), min_size=3, max_size=3),
    x=st.floats(-100, 100),
    confidence=st.floats(0.5, 0.999),
)
def test_any_solution_meets_its_envelope_and_its_confidence(cog, sigma, x, confidence):
    s = state(1.0, cog, sigma)
    sp = spec(((x, 30.0, -60.0), None), ((-x, -30.0, 60.0), 0.5))
    limits = np.array([20.0, 20.0, 20.0])
    r = least_ballast(s, sp, np.zeros(3), limits, confidence)
    if r.feasible:
        assert np.all(r.margin_mm >= -1e-7)
        assert r.probability_inside >= confidence - 1e-4
        assert norm.sf(r.face_quantiles).sum() <= (1 - confidence) * (1 + 1e-9)
    else:
        assert r.shortfall or r.notes


@pytest.mark.parametrize("confidence", [0.0, 1.0, -0.1, 1.5])
def test_a_confidence_outside_zero_one_is_refused(confidence):
    with pytest.raises(ValueError, match="confidence"):
        least_ballast(state(), spec(((1.0, 0, 0), None)), np.zeros(3), [1.0, 1.0, 1.0], confidence)


def _least_by_search(s, position, centre, limits, confidence):
    """The least mass at one location meeting the union bound, from its definition: at mass
    m each face needs the tail Φ̄((L ∓ o'(m)) / σ'(m)); feasible when they sum to at most
    1 - P; the least feasible m on a fine grid, refined by bisection."""
    sd = np.sqrt(np.diag(s.cog_cov_mm2))

    def spent(m):  # m: an array of masses
        m = np.atleast_1d(m)[:, None]
        total = s.mass_kg + m
        o = (s.mass_kg * s.cog_mm + m * position) / total - centre
        sig = s.mass_kg * sd / total
        tails = np.zeros(len(m))
        for k in range(3):
            for sign in (1, -1):
                gap = limits[k] - sign * o[:, k]
                tails += norm.sf(gap / sig[:, k]) if sd[k] > 0 else (gap < 0).astype(float)
        return tails

    alpha = 1 - confidence
    grid = np.linspace(0, 5 * s.mass_kg, 20001)
    ok = spent(grid) <= alpha
    if not ok.any():
        return None
    k = int(np.argmax(ok))
    if k == 0:
        return 0.0
    lo, hi = grid[k - 1], grid[k]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if spent(mid)[0] <= alpha else (mid, hi)
    return hi


def test_the_shares_chosen_give_the_least_mass_the_union_bound_allows():
    """One location, two faces binding (the CoG pulled across x while z is fixed): the least
    mass equals the one found by searching the union bound's definition directly; two
    locations whose sum acts at that point need no more (a trial found 135 g for 118 g)."""
    rng = np.random.default_rng(5)
    checked = 0
    for _ in range(12):
        s = state(2.5, (rng.uniform(-1, 3), 0.0, rng.uniform(8, 16)), (0.7, 0.7, rng.uniform(1, 3)))
        p = np.array([rng.uniform(-60, -20), 0.0, -160.0])
        limits = np.array([rng.uniform(2.5, 6), 20.0, 10.0])
        expected = _least_by_search(s, p, np.zeros(3), limits, 0.95)
        r = least_ballast(s, spec((p, None)), np.zeros(3), limits, 0.95)
        if expected is None:
            assert not r.feasible
            continue
        checked += 1
        assert r.feasible and r.optimal
        # the least within 0.1 % (the inner programme keeps 0.1 % of the budget in hand)
        assert r.total_ballast_kg == pytest.approx(expected, rel=2e-3, abs=1e-9)
        assert r.total_ballast_kg >= expected * (1 - 1e-6)  # never less: the bound holds
        assert r.bound_kg <= r.total_ballast_kg * (1 + 1e-6)  # HiGHS's tolerances
    assert checked >= 6
    s = state(2.58, (0.8, -0.4, 12.3), (0.66, 0.68, 3.14))
    one = least_ballast(s, spec(((0.0, 0.0, -160.0), None)), np.zeros(3), [3.0, 20, 10])
    two = least_ballast(
        s,
        spec(((-40.0, 0.0, -160.0), None), ((40.0, 0.0, -160.0), None)),
        np.zeros(3),
        [3.0, 20, 10],
    )
    assert two.total_ballast_kg <= one.total_ballast_kg * (1 + 2e-3)


def test_a_configuration_s_shortfall_is_shifted_by_its_own_mass():
    """A configuration ten times heavier: its face's shortfall in mm is its moment over its
    own mass (plus the ballast), not the first configuration's (a trial found 206 mm for
    57)."""
    light = state(1.0, (0.0, 0.0, 0.0))
    heavy = state(10.0, (30.0, 0.0, 0.0))
    sp = spec(((-50.0, 0.0, 0.0), 0.01))
    r = least_ballast(light, sp, np.zeros(3), [10.0, 20, 20], configurations=[("heavy", heavy)])
    assert not r.feasible
    (short,) = [s for s in r.shortfall if s.get("configuration") == "heavy"]
    # at the cap: 10 (30 - 10) + 0.01 (-50 - 10) = 199.4 kg·mm short, over 10.01 kg
    assert short["moment_kg_mm"] == pytest.approx(199.4, rel=1e-6)
    assert short["cog_shift_mm"] == pytest.approx(199.4 / 10.01, rel=1e-6)


def _draw_shifted(s, dm, ds, cov4, rng, n=400_000):
    """G' = (M G + ΔS) / (M + ΔM) by drawing (G, M) and (ΔS, ΔM) independently."""
    joint = np.zeros((4, 4))
    joint[:3, :3], joint[:3, 3], joint[3, :3] = (
        s.cog_cov_mm2,
        s.cog_mass_cov_mm_kg,
        (s.cog_mass_cov_mm_kg),
    )
    joint[3, 3] = s.mass_sigma_kg**2
    a = rng.multivariate_normal(np.r_[s.cog_mm, s.mass_kg], joint, size=n)
    b = rng.multivariate_normal(np.r_[ds, dm], cov4, size=n)
    total = a[:, 3] + b[:, 3]
    g = (a[:, 3:4] * a[:, :3] + b[:, :3]) / total[:, None]
    return g, total


@pytest.mark.parametrize("origin", [0.0, 1000.0])
def test_a_change_with_an_uncertain_mass_is_carried_whatever_the_origin(origin):
    """A spacecraft (σ_M 20 g, its CoG correlated with M) loses a 0.3 kg part whose mass is
    10 % uncertain: the CoG's covariance and Cov(G', M') from the first-order formula match a
    Monte Carlo, in a frame at the origin and in one 1000 mm away (a review found the
    removed mass's uncertainty left out: σ 0.89 mm became 15.8 mm with the origin moved)."""
    rng = np.random.default_rng(3)
    shift = np.array([origin, 0.0, 0.0])
    c_part = np.array([40.0, 10.0, -30.0]) + shift
    s = UncertainMass(
        2.3,
        0.02,
        np.array([2.0, -1.0, 5.0]) + shift,
        np.diag([0.25, 0.3, 0.4]),
        np.array([0.002, -0.001, 0.003]),
        "test",
    )
    # the part removed: ΔM = -m, ΔS = -m c_part; m ~ N(0.3, 0.03²), c_part exact
    dm, ds = -0.3, -0.3 * c_part
    var_m = 0.03**2
    cov4 = np.zeros((4, 4))
    cov4[:3, :3] = var_m * np.outer(c_part, c_part)
    cov4[:3, 3] = cov4[3, :3] = var_m * c_part
    cov4[3, 3] = var_m
    t = s.shifted(
        dm, ds, cov4[:3, :3], "gone", mass_var_kg2=var_m, moment_mass_cov_kg2_mm=cov4[:3, 3]
    )
    g, total = _draw_shifted(s, dm, ds, cov4, rng)
    mc = np.cov(g.T)
    assert np.allclose(np.sqrt(np.diag(t.cog_cov_mm2)), np.sqrt(np.diag(mc)), rtol=0.03)
    cross = np.array([np.cov(g[:, k], total)[0, 1] for k in range(3)])
    assert np.allclose(t.cog_mass_cov_mm_kg, cross, rtol=0.05, atol=2e-4)
    assert t.mass_sigma_kg == pytest.approx(np.sqrt(0.02**2 + var_m), rel=1e-12)


def test_the_least_ballast_with_an_uncertain_mass_is_the_root_of_the_true_constraint():
    """The CoG's spread depends on the ballast (the mass's own uncertainty, correlated with
    the CoG): with Bonferroni's equal shares, the least mass at one location is where the true
    face condition, σ' computed at that mass, is met exactly (a review found a conservative
    answer called least when the correlation shrinks σ')."""
    from scipy.optimize import brentq

    for cross in (-0.19, 0.0, 0.19):
        s = UncertainMass(
            1.0, 0.2, np.array([12.0, 0, 0]), np.diag([1.0, 1, 1]), np.array([cross, 0, 0]), "test"
        )
        p = np.array([-60.0, 0.0, 0.0])
        limits = np.array([8.0, 30.0, 30.0])
        r = least_ballast(s, spec((p, None)), np.zeros(3), limits, 0.95, allocate=False)
        z = face_quantile(0.95)

        def g(m, s=s, p=p, z=z, limits=limits):
            _, _, cog, cov = with_ballast(s, p[None], [m])
            return cog[0] + z * np.sqrt(cov[0, 0]) - limits[0]

        root = brentq(g, 0.0, 5.0, xtol=1e-14)
        assert r.optimal
        assert r.total_ballast_kg == pytest.approx(root, rel=1e-6)


def test_an_axis_without_spread_but_an_uncertain_mass_is_balanced():
    """σ = 0 along x as the CAD states it, the mass uncertain and correlated: the ballast's
    spread along x comes from the mass term alone; the answer meets its margin (a review
    reached a 'please report' error here)."""
    s = UncertainMass(
        1.0,
        0.1,
        np.array([12.0, 0, 0]),
        np.diag([0.0, 1.0, 1.0]),
        np.array([0.0, 0.0, 0.0]),
        "test",
    )
    r = least_ballast(s, spec(((-60.0, 0.0, 0.0), None)), np.zeros(3), [8.0, 30, 30], 0.95)
    assert r.feasible and np.all(r.margin_mm >= -1e-7)
    assert r.cog_cov_mm2[0, 0] > 0  # the mass term, once ballast is added


def test_among_equally_light_answers_the_fewest_pieces():
    """Pieces of 3 and 5 g at one location, 25 random needs: the total is the least, and its
    pieces are the fewest that make a least total (brute force over every count; the least-mass
    programme alone gave 16 × 3 g for 48 g, where 1 × 3 g + 9 × 5 g is as light in 10)."""
    rng = np.random.default_rng(2)
    sizes = (0.003, 0.005)
    counts = np.array(list(itertools.product(range(67), range(41))), dtype=float)
    masses = counts @ np.array(sizes)
    p = np.array([-50.0, 0.0, 0.0])
    for _ in range(25):
        limit = float(rng.uniform(7.0, 9.5))
        s = state(1.0, (10.0, 0, 0))
        r = least_ballast(s, spec((p, None), sizes=sizes), np.zeros(3), [limit, 20, 20])
        cog = (10.0 + masses * p[0]) / (1.0 + masses)
        ok = cog <= limit + 1e-12
        least = masses[ok].min()
        fewest = counts[ok & (np.abs(masses - least) < 1e-12)].sum(axis=1).min()
        assert r.total_ballast_kg == pytest.approx(least, abs=1e-12)
        assert r.counts is not None and r.counts.sum() == fewest
