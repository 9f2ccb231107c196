"""The catalogue of bad inputs: every subcommand, as a careless or hostile user would call it.

Each case runs ``main(argv)`` in-process in a fresh working folder holding the case's input
files, and asserts: exit status 2; one line on stderr, ``cadcog: error: ...``, that matches the
case's pattern (naming the file and line, the key or the option); no traceback; no file created,
changed or removed anywhere in the folder (inputs unchanged, nothing partial left behind); and
the shipped example files unchanged.
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from cadcog.cli import main
from cadcog.rig.file import default_rig_path

PARTS = default_rig_path().parent
RIG = (PARTS / "paper_rig.toml").read_text(encoding="utf-8")
SPEC = (PARTS / "cubesat_3u.toml").read_text(encoding="utf-8")
SETUP = (
    (PARTS / "cubesat_3u_setup.toml")
    .read_text(encoding="utf-8")
    .replace('"cubesat_3u.toml"', f'"{(PARTS / "cubesat_3u.toml").as_posix()}"')
    .replace('"paper_rig.toml"', f'"{(PARTS / "paper_rig.toml").as_posix()}"')
)
REQUIREMENTS = (
    (PARTS / "cubesat_3u_requirements.toml")
    .read_text(encoding="utf-8")
    .replace('"cubesat_3u.toml"', f'"{(PARTS / "cubesat_3u.toml").as_posix()}"')
    .replace('"cubesat_3u_baseline.json"', f'"{(PARTS / "cubesat_3u_baseline.json").as_posix()}"')
)
HEADER = "point_id,x_mm,y_mm,z_mm,inc_x_deg,inc_y_deg,top_face_up\n"
RIG_READINGS = (PARTS.parent / "docs" / "examples" / "paper_rig_readings.csv").read_text("utf-8")
GOOD_ROWS = "S1,45,20,82,-50.6,-14.2,true\nS2,-45,20,82,50.2,14.1,true\n"


def readings_with(old: str, new: str) -> str:
    """The example readings with ``old`` replaced on every line (every sample of a hang)."""
    assert old in RIG_READINGS, old
    return RIG_READINGS.replace(old, new)


def _campaign(path: Path) -> None:
    """A virtual campaign of the paper rig at ``path`` with its swings beside it (s.csv), its
    report lines kept out of the case's standard error."""
    import contextlib
    import io

    argv = ["campaign", "--seed", "3", "--out", str(path), "--swings", str(path.parent / "s.csv")]
    with contextlib.redirect_stderr(io.StringIO()), contextlib.redirect_stdout(io.StringIO()):
        assert main(argv) == 0


def rig_with(old: str, new: str) -> str:
    assert old in RIG, old
    return RIG.replace(old, new, 1)


def spec_with(old: str, new: str) -> str:
    assert old in SPEC, old
    return SPEC.replace(old, new, 1)


def setup_with(old: str, new: str) -> str:
    assert old in SETUP, old
    return SETUP.replace(old, new, 1)


def requirements_with(old: str, new: str) -> str:
    assert old in REQUIREMENTS, old
    return REQUIREMENTS.replace(old, new, 1)


def _step(path: Path) -> None:
    from support.stepfixtures import Assembly, Part, write_step

    top = Assembly("sat")
    top.add(Part("box", [((10.0, 10.0, 10.0), (0.0, 0.0, 0.0))]))
    write_step(top, path)


@dataclass(frozen=True)
class Case:
    id: str
    argv: list[str]
    message: str  # a regular expression the one-line message must match
    files: dict[str, str | bytes | Callable[[Path], None]] = field(default_factory=dict)


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
        "campaign-rig-and-setup",
        ["campaign", "--setup", "s.toml", "--rig", str(PARTS / "paper_rig.toml"), "--out", "c.csv"],
        r"give either --rig or --setup, not both",
        {"s.toml": SETUP},
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
        {"c.csv": _campaign},
    ),
    Case(
        "inertia-mass-sigma-alone",
        ["inertia", "s.csv", "--readings", "c.csv", "--mass-sigma-kg", "0.5"],
        r"--mass-sigma-kg goes with --weighed-mass-kg",
        {"c.csv": _campaign},
    ),
    Case(
        "inertia-wire-sigma-beyond-its-length",
        ["inertia", "s.csv", "--readings", "c.csv", "--rig", "r.toml"],
        r"r\.toml: key 'swing\.wire_length_sigma_mm': expected at most a quarter",
        {"c.csv": _campaign, "r.toml": RIG + "\n[swing]\nwire_length_sigma_mm = 5000\n"},
    ),
    Case(
        "inertia-no-hang-usable-names-the-swings",
        ["inertia", "s.csv", "--readings", "c.csv", "--rig", "r.toml"],
        r"s\.csv: [0-2] of 6 hangs have a body mode to use, the whole tensor needs three",
        {"c.csv": _campaign, "r.toml": RIG + "\n[swing]\nwire_length_mm = 0\n"},
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
        {"m.step": _step},
    ),
    Case(
        "massprops-no-density",
        ["massprops", "m.step"],
        r"m\.step: no density for 1 solid\(s\): sat/box",
        {"m.step": _step},
    ),
    Case(
        "massprops-units",
        ["massprops", "m.step", "--units", "furlong"],
        r"massprops: argument --units: invalid choice: 'furlong'",
        {"m.step": _step},
    ),
    Case(
        "materials-misspelt-table",
        ["massprops", "m.step", "--materials", "mat.toml"],
        r"mat\.toml: key 'material': unknown key \(did you mean 'materials'\?",
        {"m.step": _step, "mat.toml": '[material]\n"*" = "FR-4"\n'},
    ),
    Case(
        "materials-density-huge",
        ["massprops", "m.step", "--materials", "mat.toml"],
        r"mat\.toml: key 'materials\.\*': density 1e\+09 kg/m³ is implausible",
        {"m.step": _step, "mat.toml": '[materials]\n"*" = 1e9\n'},
    ),
    Case(
        "massprops-about-two-numbers",
        ["massprops", "m.step", "--density-kg-m3", "1000", "--about", "1,2"],
        r"argument --about",
        {"m.step": _step},
    ),
    Case(
        "massprops-report-onto-file",
        ["massprops", "m.step", "--density-kg-m3", "1000", "--report", "f"],
        r"f: exists and is not a directory",
        {"m.step": _step, "f": "x"},
    ),
    Case(
        "massprops-total-mass-negative",
        ["massprops", "m.step", "--total-mass-kg", "-1"],
        r"--total-mass-kg -1\.0: expected at least 1e-06",
        {"m.step": _step},
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
        "update-mass-zero",
        ["update", "r.csv", "--setup", "s.toml", "--weighed-mass-kg", "0"],
        r"--weighed-mass-kg must be a positive number",
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
        {"m.step": _step},
    ),
    Case(
        "massprops-exclude-everything",
        ["massprops", "m.step", "--density-kg-m3", "1000", "--exclude", "*"],
        r"--exclude '\*': excludes every body of m\.step",
        {"m.step": _step},
    ),
    Case(
        "materials-pattern-control-character",
        ["massprops", "m.step", "--materials", "mat.toml"],
        r"mat\.toml: key 'materials': pattern 'a\\x00b' holds a control character",
        {"m.step": _step, "mat.toml": '[materials]\n"a\\u0000b" = 2700.0\n'},
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


def _snapshot(root: Path) -> dict[str, str]:
    return {
        str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
        if p.is_file()
        else "dir"
        for p in sorted(root.rglob("*"))
    }


SHIPPED = {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in PARTS.glob("*.*")}


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_bad_input_is_one_line_exit_2_and_writes_nothing(case, tmp_path, monkeypatch, capsys):
    import re

    for name, content in case.files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if callable(content):
            content(path)
        elif isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content, encoding="utf-8", newline="")
    before = _snapshot(tmp_path)
    monkeypatch.chdir(tmp_path)
    status = main(case.argv)
    err = capsys.readouterr().err
    assert status == 2, (status, err)
    assert "Traceback" not in err
    lines = [line for line in err.splitlines() if not line.startswith("cadcog: warning")]
    assert len(lines) == 1 and lines[0].startswith("cadcog: error: "), err
    assert re.search(case.message, lines[0]), lines[0]
    assert _snapshot(tmp_path) == before  # nothing new, nothing changed, nothing left behind
    assert {
        p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in PARTS.glob("*.*")
    } == SHIPPED


def test_the_catalogue_covers_every_subcommand():
    from cadcog.cli._main import _subparsers, build_parser

    covered = {c.argv[0] for c in CASES if c.argv}
    assert set(_subparsers(build_parser())) <= covered
    assert len(CASES) >= 60
