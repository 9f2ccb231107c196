"""``cadcog/runs/simulate.py``: ``--paper`` is the paper's Monte Carlo whatever else is asked,
and a run is its seed's."""

from __future__ import annotations

from cadcog.runs.simulate import simulate_rig

BASE = {"points": 0, "trials": 200, "seed": 5, "group_size": 2, "min_angle_deg": 0.0, "workers": 1}


def test_the_papers_monte_carlo_ignores_the_wire_correction_asked_for(paper_rig):
    a = simulate_rig(paper_rig, **BASE, wire_correction=True, paper=True)
    b = simulate_rig(paper_rig, **BASE, wire_correction=False, paper=True)
    ours = simulate_rig(paper_rig, **BASE, wire_correction=True, paper=False)
    assert a.to_json() == b.to_json() != ours.to_json()


def test_same_seed_same_report_another_seed_another(paper_rig):
    a = simulate_rig(paper_rig, **BASE, wire_correction=True, paper=False)
    b = simulate_rig(paper_rig, **BASE, wire_correction=True, paper=False)
    c = simulate_rig(paper_rig, **{**BASE, "seed": 6}, wire_correction=True, paper=False)
    assert a.to_json() == b.to_json() != c.to_json()
