"""Every parser against hypothesis-generated input: only cadcog's own error class escapes.

The parameter files are fuzzed by mutating the shipped examples line by line (a value replaced
by a nasty literal, a line dropped or doubled, bytes inserted), so that most examples get past
the TOML syntax and reach the validation of keys and values; readings files by rows of random
fields and by arbitrary text. A ``CadcogError`` (with its message naming the file) is the only
acceptable failure; anything else is a bug this test exists to find.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cadcog.core.errors import CadcogError
from cadcog.core.paramfile import TableReader, read_toml
from cadcog.mass.materials import load_materials
from cadcog.method.readings import read_readings
from cadcog.rig.file import default_rig_path, load_rig
from cadcog.spacecraft.requirements import load_requirements

PARTS = default_rig_path().parent

NASTY = [
    "nan",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e-320",
    "0",
    "-0.0",
    "-1",
    "2000",
    "1e300",
    "9223372036854775807",
    "-9223372036854775808",
    "true",
    '""',
    '" "',
    '"../../x"',
    '"a/b"',
    '"\\u0000"',
    '"\\u2028"',
    '"a,b"',
    '"x"',
    "[]",
    "[1, 2]",
    "[nan, 0, 0]",
    '["a"]',
    "{}",
    "{ a = 1 }",
    "[[1, 2], [3]]",
    "1979-05-27",
    '"FR-4"',
    '"*"',
    '"unobtainium"',
    "0.5",
]

DEVICES = st.sampled_from(["\x00", "\x0c", "\u2028", "\ufeff", "\r", "\x1b[31m", "é", ","])


@st.composite
def mutated(draw, text: str) -> str:
    """``text`` with a few of its lines changed."""
    lines = text.splitlines()
    for _ in range(draw(st.integers(1, 4))):
        i = draw(st.integers(0, len(lines) - 1))
        kind = draw(st.sampled_from(["value", "drop", "double", "insert", "key"]))
        line = lines[i]
        if kind == "value" and "=" in line:
            key = line.split("=", 1)[0]
            lines[i] = f"{key}= {draw(st.sampled_from(NASTY))}"
        elif kind == "drop":
            del lines[i]
        elif kind == "double":
            lines.insert(i, line)
        elif kind == "insert":
            at = draw(st.integers(0, len(line)))
            lines[i] = line[:at] + draw(DEVICES) + line[at:]
        elif kind == "key" and "=" in line:
            lines[i] = draw(st.sampled_from(["bogus_key", "name", "x_mm", "[table]"])) + " = 1"
        if not lines:
            lines = [""]
    return "\n".join(lines) + "\n"


def _only_cadcog_errors(write, parse) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "input"
        write(path)
        try:
            parse(path)
        except CadcogError as exc:
            assert str(exc), "an error without a message"


FUZZ = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@FUZZ
@given(mutated((PARTS / "paper_rig.toml").read_text(encoding="utf-8")))
def test_rig_files(text):
    _only_cadcog_errors(lambda p: p.write_text(text, encoding="utf-8"), load_rig)


@FUZZ
@given(mutated((PARTS / "cubesat_3u.toml").read_text(encoding="utf-8")))
def test_cubesat_specs(text):
    from cadcog.cad.cubesat import load_cubesat

    _only_cadcog_errors(lambda p: p.write_text(text, encoding="utf-8"), load_cubesat)


MATERIALS = """[materials]
"rail*" = "aluminium 6061-T6"
"battery*" = 2100.0
"*" = "aluminium 6061-T6"

[surfaces]
"*MLI*" = 0.45
"*kapton*" = { material = "polyimide (Kapton)", thickness_mm = 0.025 }

[mass_uncertainty]
"battery_pack" = 0.03
"*" = 0.05

[maturity_levels]
new = 0.20

[growth_allowance]
"payload*" = "new"
"*" = 0.05
"""


@FUZZ
@given(mutated(MATERIALS))
def test_materials_files(text):
    _only_cadcog_errors(lambda p: p.write_text(text, encoding="utf-8"), load_materials)


def _requirements(path: Path) -> None:
    load_requirements(TableReader(read_toml(path), path), path)


@FUZZ
@given(mutated((PARTS / "cubesat_3u_requirements.toml").read_text(encoding="utf-8")))
def test_requirements_files(text):
    _only_cadcog_errors(lambda p: p.write_text(text, encoding="utf-8"), _requirements)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated((PARTS / "cubesat_3u_setup.toml").read_text(encoding="utf-8")))
def test_setup_files(text):
    """Few examples: a set-up that passes builds the CubeSat (a second each)."""
    from cadcog.spacecraft.setup import load_setup

    def write(p: Path) -> None:
        text2 = text.replace('"cubesat_3u.toml"', f'"{(PARTS / "cubesat_3u.toml").as_posix()}"')
        text2 = text2.replace('"paper_rig.toml"', f'"{(PARTS / "paper_rig.toml").as_posix()}"')
        p.write_text(text2, encoding="utf-8")

    _only_cadcog_errors(write, load_setup)


HEADER = "point_id,x_mm,y_mm,z_mm,inc_x_deg,inc_y_deg,top_face_up"
FIELD = st.one_of(
    st.sampled_from(["S1", "S2", "0", "-1", "1e308", "nan", "inf", "true", "false", "", " "]),
    st.from_regex(r"-?[0-9]{1,3}(\.[0-9]{1,4})?", fullmatch=True),
    st.text(max_size=12),
)


@FUZZ
@given(st.lists(st.lists(FIELD, min_size=0, max_size=9), max_size=12), st.booleans())
def test_readings_rows(rows, counts):
    header = HEADER.replace("_deg", "_counts") if counts else HEADER
    text = header + "\n" + "\n".join(",".join(r) for r in rows) + "\n"
    _only_cadcog_errors(lambda p: p.write_text(text, encoding="utf-8"), read_readings)


@FUZZ
@given(st.binary(max_size=400))
def test_readings_bytes(data):
    _only_cadcog_errors(lambda p: p.write_bytes(HEADER.encode() + b"\n" + data), read_readings)


@pytest.mark.parametrize("device", ["/dev/zero", "/dev/urandom"])
def test_endless_inputs_are_refused_without_reading_them_whole(device):
    if not Path(device).exists():
        pytest.skip(f"no {device}")
    # refused up front, unread: a random first line can be short valid UTF-8 (1 run in ~200)
    with pytest.raises(CadcogError, match=r"is a character device, expected a regular file"):
        read_readings(device)
    with pytest.raises(CadcogError, match=r"is not a regular file, expected a TOML file"):
        load_rig(device)


SWING_HEADER = "point_id,t_s,inc_x_deg,inc_y_deg"
SWING_ID = st.sampled_from(["S1", "S2", "S3", "", " S1", "S1\x1b", "#S1", "S1,S2"])


@FUZZ
@given(
    st.lists(
        st.tuples(SWING_ID, FIELD, FIELD, FIELD).map(",".join)
        | st.lists(FIELD, max_size=6).map(",".join),
        max_size=40,
    )
)
def test_swing_rows(rows):
    """The swing file (issue 33): rows of ids, times and angles, valid or not, in any order;
    a hang's samples read back, or a CadcogError naming the file."""
    from cadcog.dynamics.swingfile import read_swings

    text = SWING_HEADER + "\n" + "\n".join(rows) + "\n"
    _only_cadcog_errors(lambda p: p.write_text(text, encoding="utf-8"), read_swings)


@FUZZ
@given(st.binary(max_size=400))
def test_swing_bytes(data):
    from cadcog.dynamics.swingfile import read_swings

    header = SWING_HEADER.encode() + b"\n"
    _only_cadcog_errors(lambda p: p.write_bytes(header + data), read_swings)


ENTRY_RESULT = {"mass_kg": 2.5825139, "cog_mm": [1.5, -0.25, 12.0], "bodies": ["a", "b"]}


@FUZZ
@given(
    st.data(),
    st.sampled_from(["flip", "cut", "insert", "replace"]),
)
def test_a_cache_entry_gives_back_its_result_or_nothing(data, how):
    """The cache entry (issue 33): whatever its bytes become (a character flipped, the file
    cut short, bytes inserted, replaced whole), ``load_data`` returns the stored result
    exactly or None, never another value and never an error."""
    import os

    from cadcog.cad import cachestore

    with tempfile.TemporaryDirectory() as tmp:
        old = os.environ.get("CADCOG_CACHE_DIR")
        os.environ["CADCOG_CACHE_DIR"] = tmp
        try:
            key = "k" * 64
            cachestore.store_data(key, ENTRY_RESULT)
            path = Path(tmp) / f"{key}.json"
            raw = path.read_bytes()
            at = data.draw(st.integers(0, len(raw) - 1))
            if how == "flip":
                raw = raw[:at] + bytes([raw[at] ^ data.draw(st.integers(1, 255))]) + raw[at + 1 :]
            elif how == "cut":
                raw = raw[:at]
            elif how == "insert":
                raw = raw[:at] + data.draw(st.binary(min_size=1, max_size=20)) + raw[at:]
            else:
                raw = data.draw(st.binary(max_size=200))
            path.write_bytes(raw)
            got = cachestore.load_data(key)
        finally:
            if old is None:
                os.environ.pop("CADCOG_CACHE_DIR", None)
            else:
                os.environ["CADCOG_CACHE_DIR"] = old
    assert got is None or got == ENTRY_RESULT
