"""The rig's commands as a careless or hostile user would call them: no command, parts, estimate,
budget, simulate, campaign, validate, report."""

from __future__ import annotations

from tests.cli.catalogue.files import (
    GOOD_ROWS,
    HEADER,
    PARTS,
    RIG,
    RIG_READINGS,
    SETUP,
    Case,
    campaign_at,
    readings_with,
    rig_with,
    spec_with,
)

CASES = [
    # --- no command, unknown command ---------------------------------------------------------
    Case("no-command", [], r"the following arguments are required: COMMAND"),
    Case("unknown-command", ["frobnicate"], r"invalid choice: 'frobnicate'"),
    # --- parts -------------------------------------------------------------------------------
    Case("rig-missing", ["parts", "build", "nothere.toml"], r"nothere\.toml: file not found"),
    Case(
        "rig-adc-bits-huge",
        ["parts", "build", "r.toml", "--out", "out"],
        r"r\.toml: key 'inclinometer\.adc_bits': expected at most 32",
        {"r.toml": rig_with("adc_bits = 10 ", "adc_bits = 2000 ")},
    ),
    Case(
        "rig-me-mass-in-grams",
        ["budget", "--rig", "r.toml"],
        r"r\.toml: key 'measurement_equipment\.volumes\[0\]\.mass_kg': 25 kg in a 68\.6 × "
        r"53\.4 × 15 mm box is 4\.55e\+05 kg/m³: denser than any solid .* is its mass_kg in grams",
        {"r.toml": rig_with("mass_kg = 0.025 ", "mass_kg = 25 ")},
    ),
    Case(
        "rig-size-in-metres",
        ["budget", "--rig", "r.toml"],
        r"r\.toml: key 'proof_mass\.mass_kg': .* are its size_mm in metres\?",
        {"r.toml": rig_with("size_mm = [200.0, 75.0, 78.0]", "size_mm = [0.2, 0.075, 0.078]")},
    ),
    Case(
        "rig-size-1e300",
        ["parts", "build", "r.toml", "--out", "out"],
        r"r\.toml: key 'proof_mass\.size_mm': element 0: expected at most 20000",
        {"r.toml": rig_with("size_mm = [200.0", "size_mm = [1e300")},
    ),
    Case(
        "rig-name-path",
        ["parts", "build", "r.toml", "--out", "out"],
        r"r\.toml: key 'name': expected a name of letters",
        {"r.toml": rig_with('name = "paper_rig"', 'name = "../x/precious"')},
    ),
    Case(
        "rig-toml-syntax",
        ["parts", "build", "r.toml"],
        r"r\.toml: invalid TOML: .*line 1",
        {"r.toml": "name = = 1\n"},
    ),
    Case(
        "rig-binary",
        ["parts", "build", "r.toml"],
        r"r\.toml: (not UTF-8 text|invalid TOML)",
        {"r.toml": b"\xff\xfe\x00\x01binary"},
    ),
    Case(
        "spec-name-escapes-out",
        ["parts", "cubesat", "s.toml", "--out", "out"],
        r"s\.toml: key 'name': expected a name of letters.*'\.\./x/precious'",
        {"s.toml": spec_with('name = "cubesat_3u"', 'name = "../x/precious"')},
    ),
    Case(
        "spec-component-quote",
        ["parts", "cubesat", "s.toml", "--out", "out"],
        r"s\.toml: key 'components\[0\]\.name': expected a name",
        {"s.toml": spec_with('name = "eps_board"', 'name = "eps\\"board"')},
    ),
    Case(
        "spec-units-huge",
        ["parts", "cubesat", "s.toml", "--out", "out"],
        r"s\.toml: key 'units': expected at most 12",
        {"s.toml": spec_with("units = 3", "units = 1000000")},
    ),
    Case(
        "spec-size-inf",
        ["parts", "cubesat", "s.toml", "--out", "out"],
        r"s\.toml: key 'components\[0\]\.size_mm': element 0: expected a finite number",
        {"s.toml": spec_with("size_mm = [82.0, 82.0, 1.6]", "size_mm = [inf, 82.0, 1.6]")},
    ),
    Case(
        "spec-unknown-material",
        ["parts", "cubesat", "s.toml", "--out", "out"],
        r"s\.toml: key 'components\[0\]\.material': unknown material 'unobtainium'",
        {"s.toml": spec_with('material = "FR-4"', 'material = "unobtainium"')},
    ),
    Case(
        "parts-out-under-a-file",
        ["parts", "cubesat", "--out", "file/out"],
        r"file/out: cannot write here",
        {"file": "x"},
    ),
    # --- estimate ------------------------------------------------------------------------------
    Case("readings-missing", ["estimate", "none.csv"], r"none\.csv: file not found"),
    Case(
        "estimate-rig-is-a-setup",
        ["estimate", "r.csv", "--rig", "s.toml"],
        r"s\.toml: key 'proof_mass': missing: this is a spacecraft set-up .*give it as the set-up",
        {"s.toml": SETUP, "r.csv": HEADER + GOOD_ROWS},
    ),
    Case("readings-directory", ["estimate", "d"], r"d: is a directory", {"d/x": "x"}),
    Case(
        "readings-nan",
        ["estimate", "r.csv"],
        r"r\.csv, line 3: column y_mm: expected a finite number, got 'nan'",
        {"r.csv": HEADER + "S1,45,20,82,-50.6,-14.2,true\nS2,-45,nan,82,50,14,true\n"},
    ),
    Case(
        "readings-position-huge",
        ["estimate", "r.csv"],
        r"r\.csv, line 2: column x_mm: expected at most 20000",
        {"r.csv": HEADER + "S1,1e300,20,82,-50.6,-14.2,true\n" + GOOD_ROWS},
    ),
    Case(
        "readings-nul-in-id",
        ["estimate", "r.csv"],
        r"r\.csv, line 2: column point_id: a control character",
        {"r.csv": HEADER + "S\x001,45,20,82,-50.6,-14.2,true\n" + GOOD_ROWS},
    ),
    Case(
        "readings-comma-in-quoted-id",
        ["estimate", "r.csv"],
        r"r\.csv, line 2: column point_id: a comma",
        {"r.csv": HEADER + '"S,1",45,20,82,-50.6,-14.2,true\n' + GOOD_ROWS},
    ),
    Case(
        "readings-huge-field",
        ["estimate", "r.csv"],
        r"r\.csv, line 2: longer than 100000 characters",
        {"r.csv": HEADER + "S1," + "9" * 200_000 + ",20,82,-50.6,-14.2,true\n"},
    ),
    Case(
        "readings-field-over-csv-limit",
        ["estimate", "r.csv"],
        r"r\.csv, line \d+: not CSV \(field larger than field limit",
        {"r.csv": HEADER + '"' + "x\n" * 70_000 + '",1,2,3,4,5,true\n'},
    ),
    Case(
        "readings-form-feed-keeps-line-numbers",
        ["estimate", "r.csv"],
        r"r\.csv, line 4: column inc_x_deg: expected a number, got 'oops'",
        {
            "r.csv": HEADER + "S1,45,20,82,-50.6,-14.2,true\f\nS1\u2028,45,20,82,-50,-14,true\n"
            "S2,-45,20,82,oops,14,true\n"
        },
    ),
    Case(
        "readings-not-utf8",
        ["estimate", "r.csv"],
        r"r\.csv, line 3: not UTF-8 text \(invalid start byte at column 4\)",
        {"r.csv": HEADER.encode() + b"S1,45,20,82,-50.6,-14.2,true\nS2,\xff\xfe,1,2,3,4,true\n"},
    ),
    Case(
        "readings-one-hang",
        ["estimate", "r.csv"],
        r"r\.csv: 1 distinct suspension point\(s\); the method needs at least two",
        {"r.csv": HEADER + "S1,45,20,82,-50.6,-14.2,true\n"},
    ),
    Case(
        "readings-angle-beyond-90",
        ["estimate", "r.csv"],
        r"r\.csv, line 2: column inc_x_deg: angle 95° is beyond ±90°",
        {"r.csv": HEADER + "S1,45,20,82,95,-14.2,true\n" + GOOD_ROWS},
    ),
    Case(
        "readings-missing-column",
        ["estimate", "r.csv"],
        r"r\.csv, line 1: missing column\(s\) top_face_up",
        {"r.csv": "point_id,x_mm,y_mm,z_mm,inc_x_deg,inc_y_deg\nS1,1,2,3,4,5\n"},
    ),
    Case(
        "estimate-me-mass-inf",
        ["estimate", "r.csv", "--me-mass-kg", "inf"],
        r"estimate: --me-mass-kg inf: expected a finite number",
        {"r.csv": HEADER + GOOD_ROWS},
    ),
    Case(
        "estimate-min-angle-huge",
        ["estimate", "r.csv", "--min-angle-deg", "400"],
        r"estimate: --min-angle-deg 400\.0: expected at most 90 \(the angle between two plumb",
        {"r.csv": HEADER + GOOD_ROWS},
    ),
    Case(
        "estimate-negative-sigma",
        ["estimate", "r.csv", "--me-cog-sigma-mm", "-1"],
        r"estimate: --me-cog-sigma-mm -1\.0: expected a number >= 0",
        {"r.csv": HEADER + GOOD_ROWS},
    ),
    Case(
        "estimate-rig-bad-noise",
        ["estimate", "r.csv", "--rig", "r.toml"],
        r"r\.toml: key 'error_model\.sensor_noise_deg': expected a number >= 0",
        {
            "r.csv": HEADER + GOOD_ROWS,
            "r.toml": rig_with("sensor_noise_deg = 0.05 ", "sensor_noise_deg = -1 "),
        },
    ),
    # --- results no rigid body can have, and refusals that name their file (round 4) ----------
    Case(
        "estimate-weighed-far-below-the-object",
        ["estimate", "r.csv", "--rig", str(PARTS / "paper_rig.toml"), "--weighed-mass-kg", "0.1"],
        r"r\.csv: the object CoG \[.*\] mm is outside the object along z by 86\.0 mm",
        {"r.csv": RIG_READINGS},
    ),
    Case(
        "estimate-hang-far-off",
        ["estimate", "r.csv", "--rig", str(PARTS / "paper_rig.toml")],
        r"r\.csv: the object CoG .* is outside the object along x by .* z by",
        {"r.csv": readings_with("S1,45,20,82,", "S1,45,20,19999,")},
    ),
    Case(
        "estimate-digit-separator",
        ["estimate", "r.csv", "--rig", str(PARTS / "paper_rig.toml")],
        r"r\.csv, line \d+: column x_mm: expected a number, got '4_5'",
        {"r.csv": readings_with("S1,45,", "S1,4_5,")},
    ),
    Case(
        "estimate-object-mass-1e-300",
        [
            "estimate",
            "r.csv",
            "--object-mass-kg",
            "1e-300",
            "--me-mass-kg",
            "0.176",
            "--me-cog-mm",
            "100,37.5,112",
        ],
        r"--object-mass-kg 1e-300: expected at least 1e-06",
        {"r.csv": RIG_READINGS},
    ),
    Case(
        "estimate-me-cog-sigma-alone",
        ["estimate", "r.csv", "--me-cog-sigma-mm", "3"],
        r"--me-cog-sigma-mm goes with --me-cog-mm",
        {"r.csv": RIG_READINGS},
    ),
    Case(
        "campaign-onto-measured-readings",
        ["campaign", "--out", "r.csv"],
        r"--out r\.csv: exists and is not a virtual campaign .*a test's readings are not replaced",
        {"r.csv": RIG_READINGS},
    ),
    Case(
        "campaign-onto-swings-of-another",
        ["campaign", "--out", "new.csv", "--swings", "s.csv"],
        r"--swings s\.csv: exists, and --out is not the virtual campaign it goes with",
        {"s.csv": "point_id,t_s,inc_x_deg,inc_y_deg\nS1,0.0,1.0,2.0\n"},
    ),
    Case(
        "campaign-rig-and-setup",
        ["campaign", "--setup", "s.toml", "--rig", str(PARTS / "paper_rig.toml"), "--out", "c.csv"],
        r"give either --rig or --setup, not both",
        {"s.toml": SETUP},
    ),
    Case(
        "estimate-rig-and-setup",
        ["estimate", "r.csv", "--setup", "s.toml", "--rig", str(PARTS / "paper_rig.toml")],
        r"give either --rig or --setup, not both \(a set-up names its rig\)",
        {"s.toml": SETUP, "r.csv": RIG_READINGS},
    ),
    Case(
        "estimate-setup-and-me-mass",
        ["estimate", "r.csv", "--setup", "s.toml", "--me-mass-kg", "0.2"],
        r"--setup already gives the masses and the ME: drop --me-mass-kg \(a weighing goes",
        {"s.toml": SETUP, "r.csv": RIG_READINGS},
    ),
    Case(
        "estimate-min-angle-above-every-pair",
        ["estimate", "r.csv", "--rig", str(PARTS / "paper_rig.toml"), "--min-angle-deg", "90"],
        r"r\.csv: every pair .* less than the --min-angle-deg of 90° \(largest .*\): lower it",
        {"r.csv": RIG_READINGS},
    ),
    Case(
        "inertia-weighed-far-below-the-object",
        ["inertia", "s.csv", "--readings", "c.csv", "--weighed-mass-kg", "0.1"],
        r"c\.csv: the object CoG .* is outside the object along z",
        {"c.csv": campaign_at},
    ),
    Case(
        "inertia-mass-sigma-alone",
        ["inertia", "s.csv", "--readings", "c.csv", "--mass-sigma-kg", "0.5"],
        r"--mass-sigma-kg goes with --weighed-mass-kg",
        {"c.csv": campaign_at},
    ),
    Case(
        "inertia-wire-sigma-beyond-its-length",
        ["inertia", "s.csv", "--readings", "c.csv", "--rig", "r.toml"],
        r"r\.toml: key 'swing\.wire_length_sigma_mm': expected at most a quarter",
        {"c.csv": campaign_at, "r.toml": RIG + "\n[swing]\nwire_length_sigma_mm = 5000\n"},
    ),
    Case(
        "inertia-no-hang-usable-names-the-swings",
        ["inertia", "s.csv", "--readings", "c.csv", "--rig", "r.toml"],
        r"s\.csv: [0-2] of 6 hangs have a body mode to use, the whole tensor needs three",
        {"c.csv": campaign_at, "r.toml": RIG + "\n[swing]\nwire_length_mm = 0\n"},
    ),
    # --- budget, simulate ----------------------------------------------------------------------
    Case("budget-rig-missing", ["budget", "--rig", "no.toml"], r"no\.toml: file not found"),
    Case("cache-unknown-option", ["cache", "--purge"], r"unrecognized arguments: --purge"),
    Case(
        "simulate-trials-huge",
        ["simulate", "--trials-per-pair", "100000000"],
        r"simulate: --trials-per-pair 100000000: expected at most 10000000 \(Monte Carlo",
    ),
    Case("simulate-trials-float", ["simulate", "--trials-per-pair", "1e12"], r"invalid int value"),
    Case("simulate-points-one", ["simulate", "--points", "1"], r"--points 1: give 0"),
    Case(
        "simulate-points-huge",
        ["simulate", "--points", "5000"],
        r"--points 5000: expected at most 200",
    ),
    Case("simulate-seed-negative", ["simulate", "--seed", "-1"], r"--seed -1: expected at least 0"),
    Case(
        "simulate-workers-zero", ["simulate", "--workers", "0"], r"--workers 0: expected at least 1"
    ),
    Case(
        "simulate-plot-no-suffix",
        ["simulate", "--plot", "hist"],
        r"--plot hist: expected a file name ending in \.png, \.svg, \.pdf",
    ),
    Case(
        "simulate-plot-onto-rig",
        ["simulate", "--rig", "r.png", "--plot", "r.png"],
        r"r\.png: is the command's input \(--rig\)",
        {"r.png": RIG},
    ),
    Case(
        "simulate-samples-huge",
        ["simulate", "--samples", "2000000000"],
        r"--samples .*at most 100000 \(samples per hang\)",
    ),
    # --- campaign ------------------------------------------------------------------------------
    Case(
        "campaign-out-is-rig",
        ["campaign", "--rig", "r.toml", "--out", "r.toml"],
        r"r\.toml: is the command's input \(--rig\)",
        {"r.toml": RIG},
    ),
    Case(
        "campaign-noise-nan",
        ["campaign", "--noise-deg", "nan", "--out", "c.csv"],
        r"--noise-deg nan: expected a finite",
    ),
    Case(
        "campaign-samples-zero",
        ["campaign", "--samples", "0", "--out", "c.csv"],
        r"--samples 0: expected at least 1",
    ),
    Case(
        "campaign-points-without-setup",
        ["campaign", "--points", "S1,S2", "--out", "c.csv"],
        r"--points goes with --setup",
    ),
    Case(
        "campaign-out-under-file",
        ["campaign", "--out", "f/c.csv"],
        r"f/c\.csv: cannot write here",
        {"f": "x"},
    ),
    Case("campaign-out-is-dir", ["campaign", "--out", "d"], r"d: is a directory", {"d/keep": "x"}),
    # --- validate, report ----------------------------------------------------------------------
    Case(
        "validate-another-objects-readings",
        ["validate", "r.csv"],
        r"r\.csv: hang\(s\) S3 are from none of rig paper_rig's suspension points: these "
        "readings are another object's",
        {"r.csv": readings_with("S3,60,60,-4,", "S3,60,60,-30,")},
    ),
    Case(
        "report-another-objects-campaign",
        ["report", "--campaign", "r.csv", "--out", "rep"],
        r"r\.csv: hang\(s\) S3 are from none of rig paper_rig's suspension points",
        {"r.csv": readings_with("S3,60,60,-4,", "S3,60,60,-30,")},
    ),
    Case(
        "validate-bad-csv",
        ["validate", "c.csv"],
        r"c\.csv, line 2: column z_mm: expected a number, got 'zz'",
        {"c.csv": HEADER + "S1,45,20,zz,-50.6,-14.2,true\n"},
    ),
    Case(
        "validate-level",
        ["validate", "c.csv", "--level", "0.9"],
        r"--level 0\.9: expected at most 0\.5",
        {"c.csv": HEADER + GOOD_ROWS},
    ),
    Case(
        "validate-campaigns",
        ["validate", "c.csv", "--campaigns", "0"],
        r"--campaigns 0: expected at least 1",
        {"c.csv": HEADER + GOOD_ROWS},
    ),
    Case(
        "validate-windows",
        ["validate", "c.csv", "--windows", "a,b"],
        r"argument --windows",
        {"c.csv": HEADER + GOOD_ROWS},
    ),
    Case(
        "report-out-is-file",
        ["report", "--out", "f"],
        r"f: exists and is not a directory",
        {"f": "x"},
    ),
    Case(
        "report-campaign-missing",
        ["report", "--campaign", "no.csv", "--out", "rep"],
        r"no\.csv: file not found",
    ),
    Case(
        "report-spacecraft-campaign",
        ["report", "--campaign", "sat.csv", "--out", "rep"],
        r"sat\.csv: line 2: suspension A at \[50\.0, 30\.0, 40\.0\] mm lies inside the bounding "
        r"box of the body .*`cadcog report` runs a rig's chain .*`cadcog estimate --setup`",
        {"sat.csv": HEADER + "A,50,30,40,-10,5,true\nB,60,30,40,10,5,true\n"},
    ),
    Case(
        "report-seed", ["report", "--seed", "-5", "--out", "rep"], r"--seed -5: expected at least 0"
    ),
]
