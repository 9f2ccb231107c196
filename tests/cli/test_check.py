"""``cadcog check``: the example's requirements pass; a changed model fails with a readable
diff; bad requirements files are refused with exit 2."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import pytest

from cadcog.cli import main
from cadcog.rig.file import default_rig_path

PARTS = default_rig_path().parent
REQUIREMENTS = PARTS / "cubesat_3u_requirements.toml"


def test_the_example_holds_and_writes_junit(tmp_path, capsys):
    junit = tmp_path / "results.xml"
    assert main(["check", str(REQUIREMENTS), "--junit", str(junit)]) == 0
    out = capsys.readouterr().out
    assert "all requirements hold" in out and "FAIL" not in out
    suite = ET.parse(junit).getroot().find("testsuite")
    assert suite is not None and suite.get("failures") == "0"
    names = [c.get("name") for c in suite.iter("testcase")]
    assert {"mass.max", "cog.envelope", "cog.envelope_95", "baseline"} <= set(names)
    assert "inertia.ratio.xx/zz" in names and len(names) == 10


def _failing_case(tmp_path):
    """The example with a 25 % heavier battery pack and a tighter bus allocation."""
    spec = (PARTS / "cubesat_3u.toml").read_text(encoding="utf-8")
    spec = spec.replace("size_mm = [70.0, 38.0, 66.0]", "size_mm = [70.0, 47.5, 66.0]")
    (tmp_path / "cubesat_3u.toml").write_text(spec, encoding="utf-8")
    req = REQUIREMENTS.read_text(encoding="utf-8")
    req = req.replace(
        'file = "cubesat_3u_baseline.json"', f'file = "{PARTS / "cubesat_3u_baseline.json"}"'
    )
    req = req.replace("max_kg = 2.0", "max_kg = 1.9")
    path = tmp_path / "requirements.toml"
    path.write_text(req, encoding="utf-8")
    return path


def test_a_changed_model_fails_with_a_readable_diff(tmp_path, capsys):
    path = _failing_case(tmp_path)
    junit = tmp_path / "results.xml"
    assert main(["check", str(path), "--junit", str(junit), "--json"]) == 1
    out = json.loads(capsys.readouterr().out)
    failed = {r["id"]: r for r in out["requirements"] if not r["passed"]}
    assert set(failed) == {"mass.allocation.payload_and_bus", "baseline"}
    changes = out["baseline"]["changes"]
    # 25 % more battery: 0.456456 kg × 0.25 = +114.1 g; the pack grows about its fixed centre,
    # so its own CoG does not move, but the total's does.
    assert changes[0].startswith("total +114.1 g, CoG")
    assert any(c.startswith("cubesat_3u/payload_and_bus/battery_pack +114.1 g") for c in changes)
    assert changes[0] == "total +114.1 g, CoG -0.49 mm in y, -4.84 mm in z"  # docs/ci.md
    suite = ET.parse(junit).getroot().find("testsuite")
    assert suite is not None and suite.get("failures") == "2"


def test_update_baseline_then_the_change_is_accepted(tmp_path, capsys):
    path = _failing_case(tmp_path)
    text = path.read_text(encoding="utf-8").replace(
        str(PARTS / "cubesat_3u_baseline.json"), "b.json"
    )
    path.write_text(text.replace("max_kg = 1.9", "max_kg = 2.0"), encoding="utf-8")
    assert main(["check", str(path)]) == 2  # no baseline yet
    assert "write it with cadcog check --update-baseline" in capsys.readouterr().err
    assert main(["check", str(path), "--update-baseline"]) == 0
    assert main(["check", str(path)]) == 0
    assert (tmp_path / "b.json").is_file()


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (("margin = 0.10", "margin = 1.5"), "key 'mass.margin'"),
        (('node = "structure"', 'node = "nothing"'), "no budget node match 'nothing'"),
        (("at_95 = true", "at_95 = 1"), "key 'cog.at_95': expected true or false"),
        (('axes = "+x,+y,+z"', 'axes = "+x,+x,+z"'), "key 'cog.axes'"),
        (("[baseline]", '[baseline]\ncolour = "red"'), "key 'baseline.colour': unknown key"),
        (('numerator = "xx"', 'numerator = "qq"'), "key 'inertia.ratio[0].numerator'"),
    ],
)
def test_bad_requirements_are_refused_with_exit_2(tmp_path, capsys, edit, message):
    text = REQUIREMENTS.read_text(encoding="utf-8").replace(*edit)
    text = text.replace('model = "cubesat_3u.toml"', f'model = "{PARTS / "cubesat_3u.toml"}"')
    text = text.replace(
        'file = "cubesat_3u_baseline.json"', f'file = "{PARTS / "cubesat_3u_baseline.json"}"'
    )
    path = tmp_path / "req.toml"
    path.write_text(text, encoding="utf-8")
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1, err


def test_strict_makes_a_note_about_the_model_an_error(tmp_path, capsys):
    from support.stepfixtures import Assembly, Part, square_face, write_step

    top = Assembly("top")
    top.add(Part("box", [((10.0, 10.0, 10.0), (0.0, 0.0, 0.0))], 2700.0, "Al"))
    top.add(Part("sheet", [], shapes=[square_face(20.0, 30.0)]))
    write_step(top, tmp_path / "m.step")
    (tmp_path / "req.toml").write_text(
        'model_step = "m.step"\n[mass]\nmax_kg = 1.0\n', encoding="utf-8"
    )
    assert main(["check", str(tmp_path / "req.toml")]) == 0
    assert "note: 1 surface body" in capsys.readouterr().out
    assert main(["check", str(tmp_path / "req.toml"), "--strict"]) == 2
    assert "--strict: 1 note(s)" in capsys.readouterr().err


def test_near_equal_moments_can_be_declared_so_for_the_axes_requirement(tmp_path, capsys):
    """A near-cubic body (moments within a few %) whose principal axes a small off-centre
    mass turns far from the frame: the axes requirement fails as stated, and holds once
    moments within 10 % count as equal (the axes of equal moments are not defined)."""
    from support.stepfixtures import Assembly, Part, write_step

    top = Assembly("cube")
    top.add(Part("body", [((100.0, 100.0, 104.0), (-50.0, -50.0, -52.0))], 2700.0, "Al"))
    top.add(Part("lump", [((10.0, 10.0, 10.0), (30.0, 30.0, 30.0))], 2700.0, "Al"))
    write_step(top, tmp_path / "cube.step")
    base = 'model_step = "cube.step"\n[inertia]\nmax_misalignment_deg = 5.0\n'
    (tmp_path / "req.toml").write_text(base, encoding="utf-8")
    assert main(["check", str(tmp_path / "req.toml"), "--json"]) == 1
    (result,) = json.loads(capsys.readouterr().out)["requirements"]
    assert float(result["value"].rstrip("°")) > 20.0
    (tmp_path / "req.toml").write_text(base + "distinct_moments_rel = 0.1\n", encoding="utf-8")
    assert main(["check", str(tmp_path / "req.toml"), "--json"]) == 0
    (result,) = json.loads(capsys.readouterr().out)["requirements"]
    assert "within 10 %" in result["detail"]
    (tmp_path / "req.toml").write_text(
        'model_step = "cube.step"\n[inertia]\ndistinct_moments_rel = 0.1\n', encoding="utf-8"
    )
    assert main(["check", str(tmp_path / "req.toml")]) == 2
    assert "goes with max_misalignment_deg" in capsys.readouterr().err


def test_junit_is_well_formed_whatever_characters_a_body_name_holds():
    """A body name from a STEP file or a baseline may hold control characters (NUL, ESC),
    U+FFFE: the XML stays well-formed and shows them as escapes."""
    from types import SimpleNamespace as C

    from cadcog.reports.junit import junit_xml

    odd = "bolt" + "".join(map(chr, (0, 1, 27, 0xFFFE))) + "[31m"
    xml = junit_xml(
        odd, [C(id=odd, title=odd, value="1 g", limit="≤ 0 g", passed=False, detail=odd)]
    )
    root = ET.fromstring(xml.split("\n", 1)[1])  # parses: well-formed
    case = root.find("testsuite/testcase")
    assert case is not None and case.get("name") == "bolt\\x00\\x01\\x1b\\ufffe[31m"
    assert all(chr(c) not in xml for c in (0, 1, 27, 0xFFFE))
