"""Cases the second audit found (issue 11), across commands."""

from __future__ import annotations

import os

from tests.cli.catalogue.files import (
    GOOD_ROWS,
    HEADER,
    PARTS,
    REQUIREMENTS,
    SETUP,
    SPEC,
    Case,
    box_step,
    requirements_with,
    rig_with,
    spec_with,
)

CASES = [
    # --- found by the second audit (issue 11) --------------------------------------------------
    Case(
        "rig-adc-step-too-coarse",
        ["budget", "--rig", "r.toml"],
        r"r\.toml: key 'inclinometer\.sensitivity_v_per_deg': the ADC step is 4\.88e\+297°",
        {
            "r.toml": rig_with(
                "sensitivity_v_per_deg = 0.0333333333333333", "sensitivity_v_per_deg = 1e-300"
            )
        },
    ),
    Case(
        "spec-panel-thinner-than-a-solid",
        ["parts", "cubesat", "sp.toml", "--out", "o"],
        r"sp\.toml: key 'structure\.panel_mm': expected at least 0\.01, got 1e-300",
        {"sp.toml": spec_with("panel_mm = 1.5", "panel_mm = 1e-300")},
    ),
    Case(
        "simulate-min-angle-negative",
        ["simulate", "--min-angle-deg", "-5"],
        r"--min-angle-deg -5\.0: expected at least 0 \(the angle between two plumb lines\)",
    ),
    Case(
        "massprops-about-huge",
        ["massprops", "m.step", "--density-kg-m3", "1000", "--about", "1e308,0,0"],
        r"argument --about: expected at most 20000 \(lengths and positions within 20 m\)",
        {"m.step": box_step},
    ),
    Case(
        "massprops-exclude-everything",
        ["massprops", "m.step", "--density-kg-m3", "1000", "--exclude", "*"],
        r"--exclude '\*': excludes every body of m\.step",
        {"m.step": box_step},
    ),
    Case(
        "materials-pattern-control-character",
        ["massprops", "m.step", "--materials", "mat.toml"],
        r"mat\.toml: key 'materials': pattern 'a\\x00b' holds a control character",
        {"m.step": box_step, "mat.toml": '[materials]\n"a\\u0000b" = 2700.0\n'},
    ),
    Case(
        "requirements-min-above-max",
        ["check", "q.toml"],
        r"q\.toml: key 'mass\.min_kg': 5 is above max_kg 3\.2: no model can pass",
        {"q.toml": requirements_with("min_kg = 1.0", "min_kg = 5.0")},
    ),
    Case(
        "check-update-baseline-onto-requirements",
        ["check", "q.toml", "--update-baseline"],
        r"q\.toml: is the command's input \(a parameter file it reads\)",
        {
            "q.toml": REQUIREMENTS.replace(
                f'"{(PARTS / "cubesat_3u_baseline.json").as_posix()}"', '"q.toml"'
            )
        },
    ),
    Case(
        "campaign-setup-one-point",
        ["campaign", "--setup", "s.toml", "--points", "Z1", "--out", "o.csv"],
        r"--points: give at least two distinct point ids",
        {"s.toml": SETUP},
    ),
    Case(
        "campaign-setup-repeated-point",
        ["campaign", "--setup", "s.toml", "--points", "Z1,Z1", "--out", "o.csv"],
        r"--points: Z1 given more than once: each point once",
        {"s.toml": SETUP},
    ),
    Case(
        "update-region-flat",
        [
            "update",
            "r.csv",
            "--setup",
            "s.toml",
            "--weighed-mass-kg",
            "2.6",
            "--unmodelled-region-mm=0,0,0,0,10,10",
            "--unmodelled-sigma-kg",
            "0.05",
        ],
        r"--unmodelled-region-mm: the box has no extent along x",
        {"r.csv": HEADER + GOOD_ROWS, "s.toml": SETUP},
    ),
    Case(
        "acquire-out-not-a-regular-file",
        ["acquire", "--simulate", "--out", "/dev/zero", "--non-interactive"],
        r"/dev/zero: exists and is not a regular file",
    ),
    # issue 21, the second adversarial round
    Case(
        "estimate-duplicated-column",
        ["estimate", "r.csv"],
        r"r\.csv, line 1: column 'x_mm' appears twice \(fields 2 and 8\): expected each "
        r"column once",
        {"r.csv": HEADER.rstrip("\n") + ",x_mm\n" + GOOD_ROWS.replace("true\n", "true,0\n")},
    ),
    Case(
        "setup-init-missing-step",
        ["setup", "init", "none.step"],
        r"none\.step: file not found",
    ),
    Case(
        "setup-init-out-not-toml",
        ["setup", "init", "none.step", "--out", "s.txt"],
        r"--out s\.txt: expected a file name ending in \.toml",
    ),
    Case(
        "setup-init-refuses-to-overwrite",
        ["setup", "init", "none.step", "--out", "s_setup.toml"],
        r"s_setup\.toml: exists; --force \(force=True from Python\) replaces it",
        {"s_setup.toml": "name = 'x'\n"},
    ),
    Case(
        "massprops-collapse-out-of-range",
        ["massprops", "none.step", "--collapse-below-percent", "100"],
        r"--collapse-below-percent: expected a number from 0 to under 100, got 100",
    ),
    Case(
        "massprops-fifo-step",
        ["massprops", "pipe.step", "--density-kg-m3", "2700"],
        r"pipe\.step: is a FIFO \(named pipe\), expected a regular file",
        {"pipe.step": lambda p: os.mkfifo(p)},
    ),
    Case(
        "report-fifo-campaign",
        ["report", "--campaign", "pipe.csv", "--out", "rep"],
        r"pipe\.csv: is a FIFO \(named pipe\), expected a regular file",
        {"pipe.csv": lambda p: os.mkfifo(p)},
    ),
    Case(
        "parts-cubesat-duplicate-component-name",
        ["parts", "cubesat", "spec.toml", "--out", "o"],
        r"spec\.toml: key 'components\[1\]\.name': 'eps_board' is also the name of "
        r"components\[0\]",
        {"spec.toml": spec_with('name = "battery_pack"', 'name = "eps_board"')},
    ),
    Case(
        "massprops-10000-character-value-capped",
        ["massprops", "m.step", "--units", "x" * 10_000],
        r"invalid choice: 'x{30,}…\(10002 characters\)…x{30,}' \(choose from",
    ),
    Case("report-empty-out", ["report", "--out", ""], r"report: --out: expected a value"),
    Case("campaign-empty-out-equals", ["campaign", "--out="], r"campaign: --out: expected a"),
    Case("report-out-dash", ["report", "--out", "-"], r"-: this output is a folder"),
    Case("parts-build-out-dash", ["parts", "build", "--out", "-"], r"-: this output is a folder"),
    Case(
        "parts-cubesat-out-fifo",
        ["parts", "cubesat", "spec.toml", "--out", "pipe"],
        r"pipe: exists and is not a directory",
        {"spec.toml": SPEC, "pipe": lambda p: os.mkfifo(p)},
    ),
    Case(
        "campaign-out-existing-folder",
        ["campaign", "--out", "d"],
        r"d: is a directory, expected a file name",
        {"d/keep.txt": "kept"},
    ),
    Case(
        "campaign-samples-huge-value-capped",
        ["campaign", "--out", "c.csv", "--samples", "9" * 5000],
        r"--samples: invalid int value: '9+…\(5002 characters\)…9+'",
    ),
]
