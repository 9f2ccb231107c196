"""The CAD's and the spacecraft's commands: massprops, plan (set-up files), balance, check,
inertia, update, acquire."""

from __future__ import annotations

from tests.cli.catalogue.files import (
    GOOD_ROWS,
    HEADER,
    PARTS,
    REQUIREMENTS,
    RIG,
    RIG_READINGS,
    SETUP,
    Case,
    box_step,
    requirements_with,
    rig_with,
    setup_with,
)

CASES = [
    # --- massprops -----------------------------------------------------------------------------
    Case(
        "step-not-step",
        ["massprops", "m.step", "--density-kg-m3", "1000"],
        r"m\.step: cannot read as STEP \(.*Line",
        {"m.step": "ISO-10303-21;\nnot step at all\n"},
    ),
    Case(
        "step-directory",
        ["massprops", "d", "--density-kg-m3", "1000"],
        r"d: is a directory",
        {"d/x": "x"},
    ),
    Case(
        "step-missing",
        ["massprops", "no.step", "--density-kg-m3", "1000"],
        r"no\.step: file not found",
    ),
    Case(
        "step-empty",
        ["massprops", "e.step", "--density-kg-m3", "1000"],
        r"e\.step: ",
        {"e.step": ""},
    ),
    Case(
        "massprops-density-g-cm3",
        ["massprops", "m.step", "--density-kg-m3", "2.7"],
        r"--density-kg-m3 2\.7: expected at least 10 .*g/cm³",
        {"m.step": box_step},
    ),
    Case(
        "massprops-no-density",
        ["massprops", "m.step"],
        r"m\.step: no density for 1 solid\(s\): sat/box",
        {"m.step": box_step},
    ),
    Case(
        "massprops-of-a-set-up",
        ["massprops", "s.toml"],
        r"s\.toml: not a STEP file: a STEP file begins 'ISO-10303-21;', this one begins '\[name",
        {"s.toml": "[name]\nx = 1\n"},
    ),
    Case(
        "setup-model-key-misspelt",
        ["plan", "s.toml"],
        r"s\.toml: key 'model': missing: .* \(the table has 'model_stp': a misspelling\?\)",
        {"s.toml": setup_with("model = ", "model_stp = ")},
    ),
    Case(
        "plan-of-a-step-model",
        ["plan", "m.step"],
        r"m\.step: a STEP model, not a TOML parameter file \(cadcog setup init MODEL drafts",
        {"m.step": box_step},
    ),
    Case(
        "plan-of-a-readings-csv",
        ["plan", "r.csv"],
        r"r\.csv: a readings or swing CSV, not a TOML parameter file",
        {"r.csv": "# a comment\n#\n" + HEADER + GOOD_ROWS},
    ),
    Case(
        "massprops-units",
        ["massprops", "m.step", "--units", "furlong"],
        r"massprops: argument --units: invalid choice: 'furlong'",
        {"m.step": box_step},
    ),
    Case(
        "materials-misspelt-table",
        ["massprops", "m.step", "--materials", "mat.toml"],
        r"mat\.toml: key 'material': unknown key \(did you mean 'materials'\?",
        {"m.step": box_step, "mat.toml": '[material]\n"*" = "FR-4"\n'},
    ),
    Case(
        "materials-density-huge",
        ["massprops", "m.step", "--materials", "mat.toml"],
        r"mat\.toml: key 'materials\.\*': density 1e\+09 kg/m³ is implausible",
        {"m.step": box_step, "mat.toml": '[materials]\n"*" = 1e9\n'},
    ),
    Case(
        "massprops-about-two-numbers",
        ["massprops", "m.step", "--density-kg-m3", "1000", "--about", "1,2"],
        r"argument --about",
        {"m.step": box_step},
    ),
    Case(
        "massprops-report-onto-file",
        ["massprops", "m.step", "--density-kg-m3", "1000", "--report", "f"],
        r"f: exists and is not a directory",
        {"m.step": box_step, "f": "x"},
    ),
    Case(
        "massprops-total-mass-negative",
        ["massprops", "m.step", "--total-mass-kg", "-1"],
        r"--total-mass-kg -1\.0: expected at least 1e-06",
        {"m.step": box_step},
    ),
    # --- plan (set-up files) -------------------------------------------------------------------
    Case(
        "setup-spacing-tiny",
        ["plan", "s.toml"],
        r"s\.toml: key 'candidates\.spacing_mm': 1e-06 mm gives \d+ candidate points.*at most 2000",
        {"s.toml": setup_with("spacing_mm = 60.0", "spacing_mm = 1e-6")},
    ),
    Case(
        "setup-duplicate-id",
        ["plan", "s.toml"],
        r"s\.toml: key 'candidates\.points\[1\]\.id': duplicate candidate id 'Z1'",
        {
            "s.toml": SETUP
            + '\n[[candidates.points]]\nid = "Z1"\nposition_mm = [-30.0, 30.0, -170.25]\n'
        },
    ),
    Case(
        "setup-name-path",
        ["plan", "s.toml"],
        r"s\.toml: key 'name': expected a name",
        {"s.toml": setup_with('name = "cubesat_3u"', 'name = "a/../../b"')},
    ),
    Case(
        "setup-unknown-key",
        ["plan", "s.toml"],
        r"s\.toml: key 'form_facter': unknown key \(did you mean 'form_factor'\?",
        {"s.toml": setup_with('form_factor = "3U"', 'form_facter = "3U"')},
    ),
    Case(
        "setup-model-step-missing",
        ["plan", "sub/s.toml"],
        r"sub/s\.toml: key 'model_step': sub/gone\.step: file not found \(a path is read from "
        r"the folder of the file that names it\)",
        {
            "sub/s.toml": setup_with(
                f'model = "{(PARTS / "cubesat_3u.toml").as_posix()}"', 'model_step = "gone.step"'
            )
        },
    ),
    Case(
        "setup-materials-missing",
        ["plan", "s.toml"],
        r"s\.toml: key 'materials': nomat\.toml: file not found",
        {
            "s.toml": setup_with(
                f'model = "{(PARTS / "cubesat_3u.toml").as_posix()}"',
                f'model = "{(PARTS / "cubesat_3u.toml").as_posix()}"\nmaterials = "nomat.toml"',
            )
        },
    ),
    Case(
        "plan-trials",
        ["plan", "s.toml", "--trials", "1"],
        r"--trials 1: expected at least 2",
        {"s.toml": SETUP},
    ),
    Case(
        "plan-max-set",
        ["plan", "s.toml", "--max-set", "50"],
        r"--max-set 50: expected at most 8",
        {"s.toml": SETUP},
    ),
    Case("plan-no-setup", ["plan"], r"give the set-up file once: cadcog plan SETUP\.toml"),
    Case(
        "plan-setup-twice",
        ["plan", "s.toml", "--setup", "s.toml"],
        r"give the set-up file once",
        {"s.toml": SETUP},
    ),
    # --- balance -------------------------------------------------------------------------------
    Case(
        "balance-confidence",
        ["balance", "--setup", "s.toml", "--ballast", "b.toml", "--confidence", "2"],
        r"--confidence 2\.0: expected a probability from 0\.5 to 0\.9999",
    ),
    Case(
        "option-given-twice",
        ["balance", "--setup", "s.toml", "--ballast", "a.toml", "--ballast=b.toml"],
        r"balance: --ballast given 2 times: give it once",
    ),
    Case(
        "balance-ballast-missing",
        ["balance", "--setup", "s.toml", "--ballast", "nothere.toml", "--cog-limits-mm=1,1,1"],
        r"nothere\.toml: file not found",
    ),
    Case(
        "balance-ballast-negative",
        ["balance", "--setup", "s.toml", "--ballast", "b.toml"],
        r"b\.toml: key 'points\[0\]\.max_mass_kg': expected a positive number",
        {"b.toml": '[[points]]\nid = "a"\nposition_mm = [0, 0, 0]\nmax_mass_kg = -0.1\n'},
    ),
    # --- check (requirements files) ------------------------------------------------------------
    Case(
        "requirements-no-model",
        ["check", "q.toml"],
        r"q\.toml: key 'model': missing: give model",
        {"q.toml": requirements_with('model = "', 'modell = "')},
    ),
    Case(
        "check-junit-onto-requirements",
        ["check", "q.toml", "--junit", "q.toml"],
        r"q\.toml: is the command's input \(the requirements file\)",
        {"q.toml": REQUIREMENTS},
    ),
    Case(
        "requirements-margin",
        ["check", "q.toml"],
        r"q\.toml: key 'mass\.margin': a fraction below 1",
        {"q.toml": requirements_with("margin = 0.10", "margin = 1.5")},
    ),
    Case(
        "requirements-update-baseline-without-one",
        ["check", "q.toml", "--update-baseline"],
        r"q\.toml: --update-baseline needs a \[baseline\] table",
        {"q.toml": REQUIREMENTS.split("[baseline]")[0]},
    ),
    # --- inertia ---------------------------------------------------------------------------------
    Case(
        "inertia-swings-missing",
        ["inertia", "s.csv", "--readings", "r.csv"],
        r"s\.csv: file not found, expected a swing CSV file",
        {"r.csv": HEADER + GOOD_ROWS},
    ),
    Case(
        "inertia-swings-column",
        ["inertia", "s.csv", "--readings", "r.csv"],
        r"s\.csv, line 2: missing column\(s\) inc_y_deg",
        {"r.csv": HEADER + GOOD_ROWS, "s.csv": "# swings\npoint_id,t_s,inc_x_deg\nS1,0,1\n"},
    ),
    Case(
        "inertia-swing-time",
        ["inertia", "s.csv", "--readings", "r.csv"],
        r"s\.csv, line 3: column t_s: .* time must increase within a hang",
        {
            "r.csv": HEADER + GOOD_ROWS,
            "s.csv": "point_id,t_s,inc_x_deg,inc_y_deg\nS1,1,1,2\nS1,1,1,2\n",
        },
    ),
    Case(
        "inertia-rig-wire-negative",
        ["inertia", "s.csv", "--readings", "r.csv", "--rig", "g.toml"],
        r"g\.toml: key 'swing\.wire_length_mm'",
        {
            "r.csv": HEADER + GOOD_ROWS,
            "s.csv": "point_id,t_s,inc_x_deg,inc_y_deg\n",
            "g.toml": rig_with("[error_model]", "[swing]\nwire_length_mm = -1.0\n\n[error_model]"),
        },
    ),
    # --- update ----------------------------------------------------------------------------------
    Case(
        "update-another-objects-readings",
        ["update", "r.csv", "--setup", "s.toml", "--weighed-mass-kg", "2.6"],
        r"^cadcog: error: r\.csv: line 3: suspension S1 .* are these the readings of this set-up",
        {"r.csv": RIG_READINGS, "s.toml": SETUP},
    ),
    Case(
        "update-mass-zero",
        ["update", "r.csv", "--setup", "s.toml", "--weighed-mass-kg", "0"],
        r"--weighed-mass-kg 0\.0: expected at least 1e-06 \(a weighed mass",
        {"r.csv": HEADER + GOOD_ROWS, "s.toml": SETUP},
    ),
    Case(
        "update-region",
        [
            "update",
            "r.csv",
            "--setup",
            "s.toml",
            "--weighed-mass-kg",
            "2.6",
            "--unmodelled-region-mm",
            "1,2",
        ],
        r"argument --unmodelled-region-mm: expected six numbers",
        {"r.csv": HEADER + GOOD_ROWS, "s.toml": SETUP},
    ),
    # --- acquire ---------------------------------------------------------------------------------
    Case(
        "acquire-no-port",
        ["acquire", "--port", "ttyNONE", "--out", "r.csv", "--non-interactive"],
        r"ttyNONE",
    ),
    Case(
        "acquire-report-onto-file",
        ["acquire", "--simulate", "--out", "r.csv", "--report", "f"],
        r"--report f: exists and is not a directory",
        {"f": "x"},
    ),
    Case(
        "acquire-unknown-point",
        ["acquire", "--simulate", "--points", "S9", "--out", "r.csv"],
        r"unknown point\(s\) S9",
    ),
    Case(
        "acquire-baud",
        ["acquire", "--simulate", "--baud", "10", "--out", "r.csv"],
        r"--baud 10: expected at least 300",
    ),
    Case(
        "acquire-time-scale",
        ["acquire", "--simulate", "--time-scale", "0", "--out", "r.csv"],
        r"--time-scale 0\.0: expected at least 0\.01",
    ),
    Case(
        "acquire-out-is-rig",
        ["acquire", "--simulate", "--rig", "r.toml", "--out", "r.toml"],
        r"r\.toml: is the command's input \(--rig\)",
        {"r.toml": RIG},
    ),
]
