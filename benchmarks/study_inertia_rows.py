"""The rows of ``benchmarks/study_inertia.py``: each a rig or set-up, the hangs, the
independent swing's configuration (:class:`support.swing_files.SwingConfig`) and the error
sources switched off in truth and estimator alike."""

from __future__ import annotations

import sys
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from scipy import stats

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from support import swing_files as sf  # noqa: E402

CACHE = ROOT / "build" / "study_inertia"
RIG = ROOT / "parts" / "paper_rig.toml"
SETUP = ROOT / "parts" / "cubesat_3u_setup.toml"
RIG6 = ("S1", "S2", "S3", "S4", "S5", "S6")
#: `cadcog plan parts/cubesat_3u_setup.toml` (default seed) recommends these four hangs (for
#: the CoG; 2026-11-23).
CUBESAT_PLAN = ("+x_-30_-30", "-x_30_-30", "+y_30_-30", "-y_-30_-30")
#: `cadcog plan parts/cubesat_3u_setup.toml --for inertia` (default seed; 2026-11-23, main 7ca6abd).
CUBESAT_INERTIA_PLAN = ("+x_-30_90", "+x_30_-150", "-x_-30_-150", "+y_30_-150", "-y_30_-90")
#: What `cadcog plan parts/cubesat_3u_setup.toml --for inertia` recommends on 2026-11-26.
CUBESAT_INERTIA_PLAN6 = (
    "+x_-30_-150", "+x_-30_90", "+y_-30_-150", "+y_30_-30", "-y_-30_-150", "-y_-30_-30",
)  # fmt: skip
CHI2_6_95 = float(stats.chi2.ppf(0.95, 6))


@dataclass(frozen=True)
class Row:
    name: str
    label: str
    source: str  # "rig" or "setup"
    points: tuple[str, ...]
    config: sf.SwingConfig
    hang_ids: tuple[str, ...] | None = None
    weighed: bool = False  # the object weighed (its true mass, a 1 g scale error per campaign)
    off: tuple[str, ...] = ()  # error sources switched off in truth and estimator (OFF)


@dataclass(frozen=True)
class Off:
    """An error source switched off in the truth and the estimator alike (a row's ``off``):
    the parameter file's lines replaced, the ``[swing]`` keys added, the campaign's
    configuration changed. Which of the estimator's stated sources is over- or under-stated
    shows in how the tensor's χ² moves without it."""

    edits: tuple[tuple[str, str], ...] = ()
    swing: str = ""
    config: tuple[tuple[str, Any], ...] = ()


OFF: dict[str, Off] = {
    "me": Off(
        ((r"(?m)^cog_uncertainty_cube_mm = [0-9.]+", "cog_uncertainty_cube_mm = 0.0"),),
        "me_inertia_rel = 0.0\n",
        (("me_errors", False),),
    ),
    "play": Off(((r"(?m)^play_mm = [0-9.]+", "play_mm = 0.001"),)),
    "lambda": Off(((r"(?m)^wire_offset_max_mm = [0-9.]+", "wire_offset_max_mm = 0.0"),)),
    "floor": Off(swing="frequency_model_rel = 0.0\n"),
    "wire-length": Off(config=(("wire_length_sigma_mm", 0.0),)),
}


def _off_row(off: tuple[str, ...]) -> Row:
    """The paper rig's 300 mm flexible-wire row with the ME drawn, ``off`` switched off."""
    cfg = replace(BASE, one_wire="flexible", me_errors=True)
    cfg = replace(cfg, **{k: v for o in off for k, v in OFF[o].config})
    return Row(
        "rig6h_flex_me_off_" + "_".join(o.replace("-", "") for o in off),
        f"paper rig S1-S6, one flexible wire, L = 300 mm, off: {', '.join(off)}",
        "rig",
        RIG6,
        cfg,
        off=off,
    )


BASE = sf.SwingConfig()
EXACT = replace(BASE, hinge_errors=False)
ROWS = {
    r.name: r
    for r in (
        Row("rig6h", "paper rig S1-S6, L = 300 mm, ≤ 10°", "rig", RIG6, BASE),
        # one wire per campaign (issue 31): an ideal string, or a stiff wire (EI 30 N·mm²)
        Row(
            "rig6h_flex",
            "paper rig S1-S6, one flexible wire, L = 300 mm, ≤ 10°",
            "rig",
            RIG6,
            replace(BASE, one_wire="flexible"),
        ),
        Row(
            "rig6h_L100_flex",
            "paper rig S1-S6, one flexible wire, L = 100 mm, ≤ 10°",
            "rig",
            RIG6,
            replace(BASE, one_wire="flexible", wire_length_mm=100.0),
        ),
        # the same short wire measured with a rule to ±0.5 mm (the rig file declares it)
        Row(
            "rig6h_L100_flex_rule",
            "paper rig S1-S6, one flexible wire, L = 100 ± 0.5 mm, ≤ 10°",
            "rig",
            RIG6,
            replace(BASE, one_wire="flexible", wire_length_mm=100.0, wire_length_sigma_mm=0.5),
        ),
        Row(
            "cubesat_ih_flex",
            "3U CubeSat, plan --for inertia's 6 hangs, one flexible wire, weighed, ≤ 10°",
            "setup",
            CUBESAT_INERTIA_PLAN6,
            replace(BASE, one_wire="flexible"),
            weighed=True,
        ),
        # diagnostics of the CubeSat row: releases of at most 3°, and exits exactly at the bolt
        Row(
            "cubesat_ih_flex_3deg",
            "3U CubeSat, plan --for inertia's 6 hangs, one flexible wire, weighed, ≤ 3°",
            "setup",
            CUBESAT_INERTIA_PLAN6,
            replace(BASE, one_wire="flexible", amplitude_deg=3.0),
            weighed=True,
        ),
        Row(
            "cubesat_ih_exact",
            "3U CubeSat, plan --for inertia's 6 hangs, exact exits, weighed, ≤ 10°",
            "setup",
            CUBESAT_INERTIA_PLAN6,
            EXACT,
            weighed=True,
        ),
        # the ME mounted once per test too (its CoG within its cube, its own inertia within
        # the declared spread): every shared error the estimator states, drawn
        Row(
            "rig6h_L100_flex_rule_me",
            "paper rig S1-S6, one flexible wire, L = 100 ± 0.5 mm, one ME drawn, ≤ 10°",
            "rig",
            RIG6,
            replace(
                BASE,
                one_wire="flexible",
                wire_length_mm=100.0,
                wire_length_sigma_mm=0.5,
                me_errors=True,
            ),
        ),
        Row(
            "rig6h_stiff_me",
            "paper rig S1-S6, one stiff wire (EI 30 N·mm²), L = 300 mm, one ME drawn, ≤ 10°",
            "rig",
            RIG6,
            replace(BASE, one_wire="stiff", me_errors=True),
        ),
        Row(
            "rig6h_flex_me",
            "paper rig S1-S6, one flexible wire, L = 300 mm, one ME drawn, ≤ 10°",
            "rig",
            RIG6,
            replace(BASE, one_wire="flexible", me_errors=True),
        ),
        Row(
            "cubesat_ih_flex_me",
            "3U CubeSat, plan --for inertia's 6 hangs, one flexible wire, one ME drawn, "
            "weighed, ≤ 10°",
            "setup",
            CUBESAT_INERTIA_PLAN6,
            replace(BASE, one_wire="flexible", me_errors=True),
            weighed=True,
        ),
        # a short wire (issue 31: 75-100 mm), and the air's quadratic drag on the body (C_dA
        # of the proof mass's mean face, 0.013 m², and the ME: 0.015; of a 3U CubeSat, 0.03)
        Row(
            "rig6h_L75_flex_me",
            "paper rig S1-S6, one flexible wire, L = 75 ± 0.5 mm, one ME drawn, ≤ 10°",
            "rig",
            RIG6,
            replace(
                BASE,
                one_wire="flexible",
                wire_length_mm=75.0,
                wire_length_sigma_mm=0.5,
                me_errors=True,
            ),
        ),
        Row(
            "rig6h_flex_me_air",
            "paper rig S1-S6, one flexible wire, L = 300 mm, one ME drawn, air drag, ≤ 10°",
            "rig",
            RIG6,
            replace(BASE, one_wire="flexible", me_errors=True, drag_area_m2=0.015),
        ),
        Row(
            "cubesat_ih_flex_me_air",
            "3U CubeSat, plan --for inertia's 6 hangs, one flexible wire, one ME drawn, "
            "air drag, weighed, ≤ 10°",
            "setup",
            CUBESAT_INERTIA_PLAN6,
            replace(BASE, one_wire="flexible", me_errors=True, drag_area_m2=0.03),
            weighed=True,
        ),
        # ten times the air: a CubeSat with its panels deployed (C_dA 0.3 m²)
        Row(
            "cubesat_ih_flex_me_air10",
            "3U CubeSat, plan --for inertia's 6 hangs, one flexible wire, one ME drawn, "
            "10× air drag, weighed, ≤ 10°",
            "setup",
            CUBESAT_INERTIA_PLAN6,
            replace(BASE, one_wire="flexible", me_errors=True, drag_area_m2=0.3),
            weighed=True,
        ),
        Row(
            "rig6h_stiff",
            "paper rig S1-S6, one stiff wire (EI 30 N·mm²), L = 300 mm, ≤ 10°",
            "rig",
            RIG6,
            replace(BASE, one_wire="stiff"),
        ),
        Row(
            "rig6h_small",
            "paper rig S1-S6, L = 300 mm, ≤ 2°",
            "rig",
            RIG6,
            replace(BASE, amplitude_deg=2.0),
        ),
        Row(
            "cubesat_h",
            "3U CubeSat, plan's 4 hangs, L = 300 mm, ≤ 10°",
            "setup",
            CUBESAT_PLAN,
            BASE,
        ),
        Row(
            "cubesat_ih",
            "3U CubeSat, plan --for inertia's 5 hangs, L = 300 mm, ≤ 10°",
            "setup",
            CUBESAT_INERTIA_PLAN,
            BASE,
        ),
        Row(
            "rig12h",
            "paper rig, 12 hangs (S1-S6 twice), L = 300 mm, ≤ 10°",
            "rig",
            RIG6 + RIG6,
            BASE,
            tuple(f"{p}a" for p in RIG6) + tuple(f"{p}b" for p in RIG6),
        ),
        Row(
            "rig6h_pivot",
            "paper rig S1-S6, pivot (L = 0)",
            "rig",
            RIG6,
            replace(BASE, wire_length_mm=0.0, wire_length_sigma_mm=0.0),
        ),
        Row(
            "rig6h_pivot_small",
            "paper rig S1-S6, pivot (L = 0), ≤ 2°",
            "rig",
            RIG6,
            replace(BASE, wire_length_mm=0.0, wire_length_sigma_mm=0.0, amplitude_deg=2.0),
        ),
        Row(
            "rig6h_L100",
            "paper rig S1-S6, L = 100 mm",
            "rig",
            RIG6,
            replace(BASE, wire_length_mm=100.0),
        ),
        Row(
            "rig6h_L1000",
            "paper rig S1-S6, L = 1000 mm",
            "rig",
            RIG6,
            replace(BASE, wire_length_mm=1000.0),
        ),
        # the same with the hinge exactly at the nominal wire exit (no play, no wire offset)
        Row("rig6", "exact exit: paper rig S1-S6, L = 300 mm, ≤ 10°", "rig", RIG6, EXACT),
        Row(
            "rig6_small",
            "exact exit: paper rig S1-S6, L = 300 mm, ≤ 2°",
            "rig",
            RIG6,
            replace(EXACT, amplitude_deg=2.0),
        ),
        Row(
            "cubesat_plan",
            "exact exit: 3U CubeSat, plan's 4 hangs, L = 300 mm",
            "setup",
            CUBESAT_PLAN,
            EXACT,
        ),
        Row(
            "rig6_pivot",
            "exact exit: paper rig S1-S6, pivot (L = 0)",
            "rig",
            RIG6,
            replace(EXACT, wire_length_mm=0.0, wire_length_sigma_mm=0.0),
        ),
        Row(
            "rig6_L1000",
            "exact exit: paper rig S1-S6, L = 1000 mm",
            "rig",
            RIG6,
            replace(EXACT, wire_length_mm=1000.0),
        ),
    )
}
ROWS.update(
    (r.name, r)
    for r in map(
        _off_row,
        [("me",), ("play",), ("floor",), ("play", "floor"), ("wire-length",), ("lambda",)],
    )
)
