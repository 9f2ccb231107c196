"""``cadcog setup init``: a set-up file and a materials file drafted from one's own STEP."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from cadcog.cli import main
from cadcog.mass.materials import load_materials
from cadcog.spacecraft.setup_draft import guess_form_factor
from support.stepfixtures import Assembly, Part, Place, write_step


@pytest.fixture(scope="module")
def sat_step(tmp_path_factory):
    """A 3U-sized frame (100 × 100 × 340.5 mm) holding two copies of a board and a battery."""
    top = Assembly("sat")
    top.add(Part("frame", [((100.0, 100.0, 5.0), (0.0, 0.0, 0.0))]))
    top.add(Part("lid", [((100.0, 100.0, 5.0), (0.0, 0.0, 335.5))]))
    board = Part("board", [((90.0, 90.0, 1.6), (5.0, 5.0, 0.0))])
    top.add(board, Place((0.0, 0.0, 100.0)))
    top.add(board, Place((0.0, 0.0, 200.0)))
    top.add(Part("battery", [((60.0, 60.0, 40.0), (20.0, 20.0, 20.0))]))
    return write_step(top, tmp_path_factory.mktemp("init") / "sat.step")


def test_the_draft_loads_as_a_set_up_and_lists_every_part(sat_step, tmp_path, capsys):
    from cadcog.spacecraft.setup import load_setup

    out = tmp_path / "mine_setup.toml"
    assert main(["setup", "init", str(sat_step), "--out", str(out)]) == 0
    assert "cadcog plan" in capsys.readouterr().out
    text = out.read_text(encoding="utf-8")
    assert 'form_factor = "3U"' in text
    materials = (tmp_path / "mine_materials.toml").read_text(encoding="utf-8")
    rules = [line for line in materials.splitlines() if line.startswith('# "') and "= ?" in line]
    # one commented rule per part name, the largest volume first (the frame and the lid tie)
    assert rules[0].split('"')[1] == "battery"
    assert sorted(r.split('"')[1] for r in rules) == ["battery", "board", "frame", "lid"]
    assert "2 bodies" in next(r for r in rules if '"board"' in r)
    load_materials(tmp_path / "mine_materials.toml")  # valid TOML with one default rule
    setup = load_setup(out)
    lo, hi = setup.bbox_mm
    np.testing.assert_allclose(hi - lo, [100.0, 100.0, 340.5], atol=1e-6)
    # the ME base at the centre of the +z face; candidates on the four side faces only
    np.testing.assert_allclose(setup.me_volumes[0].center_mm[2] >= hi[2] - 1e-6, True)
    normals = {tuple(np.round(c.normal).astype(int)) for c in setup.candidates}
    assert normals == {(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0)}
    # Every candidate is a point of the model, not of its box: short ids, the face named, the
    # grid point moved inward to the first solid (the battery spans 20..80 in x and y, the
    # boards 5..95; the frame and the lid reach the box).
    assert all(
        c.listed and len(c.id) <= 4 and c.id[:2] in ("+x", "-x", "+y", "-y")
        for c in setup.candidates
    )
    for c in setup.candidates:
        axis = int(np.argmax(np.abs(c.normal)))
        depth = hi[axis] - c.position_mm[axis] if c.normal[axis] > 0 else c.position_mm[axis]
        z = c.position_mm[2] - lo[2]
        solids_here = [  # (depth of the solid's face from the box face, its z span)
            (0.0, (0.0, 5.0)),
            (0.0, (335.5, 340.5)),
            (5.0, (100.0, 101.6)),
            (5.0, (200.0, 201.6)),
            (20.0, (20.0, 60.0)),
        ]
        assert any(
            abs(depth - d) < 1e-3 and a - 1e-3 <= z <= b + 1e-3 for d, (a, b) in solids_here
        ), (c.id, depth, z)
    ids = [c.id for c in setup.candidates]
    assert len(ids) == len(set(ids))
    # a draft never replaces a file, unless --force
    assert main(["setup", "init", str(sat_step), "--out", str(out)]) == 2
    assert "--force" in capsys.readouterr().err
    assert main(["setup", "init", str(sat_step), "--out", str(out), "--force"]) == 0


@pytest.mark.parametrize(
    ("extent", "expected"),
    [
        ((100, 100, 113.5), "1U"),
        ((104, 98, 230), "2U"),  # a little larger: rails, deployables
        ((226.3, 100, 366), "6U"),
        ((100, 100, 290), None),  # between 2U and 3U
        ((340.5, 100, 100), None),  # the long axis along x: not guessed
    ],
)
def test_form_factor_guess(extent, expected):
    assert guess_form_factor([0, 0, 0], extent) == expected


def test_the_loop_accepts_the_points_it_drafted(sat_step, tmp_path, capsys):
    """Points inside the box (on the model) go through campaign and estimate, their positions
    rounded to the files' 3 decimals, and are never refused as lying inside the body."""
    out = tmp_path / "loop_setup.toml"
    assert main(["setup", "init", str(sat_step), "--out", str(out)]) == 0
    text = out.read_text(encoding="utf-8")
    deep = [i for i in ("+x", "-x", "+y", "-y") if f'id = "{i}1"' in text]
    assert len(deep) == 4
    points = "+x1,-x1,+y1,-y1"
    readings = tmp_path / "r.csv"
    args = ["campaign", "--setup", str(out), f"--points={points}", "--out", str(readings)]
    assert main(args) == 0
    capsys.readouterr()
    assert main(["estimate", str(readings), "--setup", str(out), "--json"]) == 0
    est = json.loads(capsys.readouterr().out)
    assert len(est["suspensions"]) == 4


def test_a_light_object_under_the_me_is_planned_with_its_consequence(tmp_path, capsys):
    """A 27 g block under the paper's 176 g ME: ``plan`` warns with the factor the compensation
    multiplies errors by, and ``--for both`` keeps the CoG plan while refusing the inertia, with
    the reason, exit 0 (``--for inertia`` alone: the same reason, exit 1: valid input, no
    plan)."""
    top = Assembly("block")
    top.add(Part("block", [((30.0, 30.0, 30.0), (0.0, 0.0, 0.0))], 1000.0, "ABS"))
    step = write_step(top, tmp_path / "block.step")
    out = tmp_path / "block_setup.toml"
    assert main(["setup", "init", str(step), "--out", str(out)]) == 0
    capsys.readouterr()
    args = ["plan", str(out), "--trials", "300", "--max-set", "3", "--json"]
    assert main([*args, "--for", "both"]) == 0
    plan = json.loads(capsys.readouterr().out)
    ratio = plan["me_mass_kg"] / plan["mass_kg"]
    assert ratio > 5
    heavy, useless = plan["warnings"]
    assert f"{1 + ratio:.2f}" in heavy and "lighter ME" in heavy
    assert f"{plan['recommended']['q95_mm']:.3g} mm" in useless  # above half the 30 mm block
    assert plan["recommended"]["q95_mm"] > 15.0 and "within the object" in useless
    assert plan["recommended"] is not None
    assert "lighter ME" in plan["inertia"]["refused"]
    assert main([*args, "--for", "inertia"]) == 1
    out = capsys.readouterr()
    assert "lighter ME" in json.loads(out.out)["inertia"]["refused"] and out.err == ""


def test_the_draft_names_parts_by_product_and_keeps_the_steps_materials(tmp_path, capsys):
    """KiCad's components (instances R1, R2, R3 of one product, whose body is a generic
    'COMPOUND') are one part named by their product; Inventor's copies (part:1, part:2) are one
    part; a part with its own STEP material is used as it is, a placeholder is named."""
    resistor = Assembly("R_0603_1608Metric")
    resistor.add(Part("COMPOUND", [((1.6, 0.8, 0.5), (0.0, 0.0, 0.0))], 3000.0, "Ceramic"))
    screw = Part("48-0381", [((2.0, 2.0, 8.0), (0.0, 0.0, 0.0))], 8000.0, "Stainless Steel")
    plunger = Part("plunger", [((3.0, 3.0, 6.0), (0.0, 0.0, 0.0))], 1000.0, "Generic")
    top = Assembly("board")
    top.add(Part("PCB", [((50.0, 40.0, 1.6), (0.0, 0.0, -1.6))]))
    for k, name in enumerate(("R1", "R2", "R3")):
        top.add(resistor, Place((5.0 + 5 * k, 5.0, 0.0)), name)
    for k in (1, 2):
        top.add(screw, Place((30.0 + 5 * k, 30.0, 0.0)), f"48-0381:{k}")
    top.add(plunger, Place((40.0, 10.0, 0.0)), "plunger:1")
    step = write_step(top, tmp_path / "kicad.step")
    assert main(["setup", "init", str(step), "--json"]) == 0
    draft = json.loads(capsys.readouterr().out)
    assert draft["n_parts"] == 4 and draft["n_lacking_material"] == 2  # the PCB, the plunger
    text = (tmp_path / "kicad_materials.toml").read_text(encoding="utf-8")
    rules = {
        line.split('"')[1]: line
        for line in text.splitlines()
        if line.startswith('# "') and "= ?" in line
    }
    assert set(rules) == {"PCB", "R_0603_1608Metric", "48-0381", "plunger"}
    assert "3 bodies" in rules["R_0603_1608Metric"] and "2 bodies" in rules["48-0381"]
    assert "'Stainless Steel', 8000 kg/m³ is used" in rules["48-0381"]
    assert "placeholder 'Generic'" in rules["plunger"]
    # The draft runs as written: the catch-all default fills the PCB (and the placeholder),
    # never the screws, and a rule written with a part's listed name matches it.
    assert (
        main(
            [
                "massprops",
                str(step),
                "--materials",
                str(tmp_path / "kicad_materials.toml"),
                "--json",
            ]
        )
        == 0
    )
    bodies = json.loads(capsys.readouterr().out)["bodies"]
    rho = {b["path"].split("/")[1]: b["density_kg_m3"] for b in bodies}
    assert rho["48-0381:1"] == rho["48-0381:2"] == 8000.0 and rho["PCB"] == 2700.0
    assert rho["plunger:1"] == 2700.0
    named = text.replace("[materials]\n", '[materials]\n"R_0603_1608Metric" = 4000.0\n', 1)
    (tmp_path / "named.toml").write_text(named, encoding="utf-8")
    assert (
        main(["massprops", str(step), "--materials", str(tmp_path / "named.toml"), "--json"]) == 0
    )
    bodies = json.loads(capsys.readouterr().out)["bodies"]
    assert {b["density_kg_m3"] for b in bodies if "/R" in b["path"]} == {4000.0}


def test_a_draft_read_with_units_loads_at_the_same_scale(sat_step, tmp_path, capsys):
    """``--units cm`` on a file declared in mm: the draft says so, and loads (its points and
    its ME base are in the scaled mm the set-up's model is read in)."""
    from cadcog.spacecraft.setup import load_setup

    out = tmp_path / "cm_setup.toml"
    assert main(["setup", "init", str(sat_step), "--out", str(out), "--units", "cm"]) == 0
    assert 'units = "cm"' in out.read_text(encoding="utf-8")
    setup = load_setup(out)
    lo, hi = setup.bbox_mm
    np.testing.assert_allclose(hi - lo, [1000.0, 1000.0, 3405.0], rtol=1e-9)


@pytest.mark.parametrize(
    ("point", "message"),
    [
        (
            'id = "a"\nface = "+x"\nposition_mm = [60.0, 0.0, 0.0]',
            "outside the model's bounding box",
        ),
        ('id = "a"\nposition_mm = [40.0, 0.0, 0.0]', 'name its face, face = "+x"'),
        (
            'id = "a"\nface = "+q"\nposition_mm = [40.0, 0.0, 0.0]',
            "key 'candidates.points[0].face': expected one of",
        ),
        (
            'id = "a"\nface = "+x"\nposition_mm = [40.0, 0.0, 0.0]\n\n[[candidates.points]]\n'
            'id = "b"\nface = "+y"\nposition_mm = [40.005, 0.0, 0.0]',
            "is the point of candidate 'a'",
        ),
    ],
)
def test_listed_points_are_checked_naming_the_key(tmp_path, point, message):
    """A point with a face must lie within the box; one without must sit on a box face; two
    listed points at one place (their bolt axes would be ambiguous) are refused."""
    from cadcog.core.errors import ParameterFileError
    from cadcog.spacecraft.setup import load_setup

    top = Assembly("b")
    top.add(Part("b", [((100.0, 100.0, 100.0), (-50.0, -50.0, -50.0))], 2700.0, "Al"))
    write_step(top, tmp_path / "b.step")
    (tmp_path / "s.toml").write_text(
        'name = "b"\nmodel_step = "b.step"\n\n[measurement_equipment]\n'
        "base_center_mm = [0, 0, 50]\n\n[candidates]\n\n[[candidates.points]]\n"
        f'{point}\n\n[[candidates.points]]\nid = "z"\nposition_mm = [0.0, 50.0, 20.0]\n',
        encoding="utf-8",
    )
    with pytest.raises(ParameterFileError, match=re.escape(message)):
        load_setup(tmp_path / "s.toml")


def test_inertia_of_a_light_object_says_the_swings_do_not_determine_it(tmp_path, capsys):
    """A 27 g block under the 176 g ME: the tensor's moments come out negative with σ larger
    than themselves; the command refuses the unphysical tensor and says why (exit 2)."""
    top = Assembly("block")
    top.add(Part("block", [((30.0, 30.0, 30.0), (0.0, 0.0, 0.0))], 1000.0, "ABS"))
    step = write_step(top, tmp_path / "block.step")
    setup = tmp_path / "block_setup.toml"
    assert main(["setup", "init", str(step), "--out", str(setup)]) == 0
    r, s = tmp_path / "r.csv", tmp_path / "s.csv"
    points = "--points=+x2,+x3,+y4,-y4"
    assert (
        main(["campaign", "--setup", str(setup), points, "--out", str(r), "--swings", str(s)]) == 0
    )
    capsys.readouterr()
    args = ["inertia", str(s), "--readings", str(r), "--setup", str(setup)]
    assert main([*args, "--weighed-mass-kg", "0.027", "--json"]) == 2
    err = capsys.readouterr().err
    assert "principal moment that is not positive" in err and err.count("\n") == 1
    moments = re.search(r"\((.*) kg·mm²\)", err).group(1).split(", ")
    assert any(float(m.split(" ± ")[0]) <= 0 for m in moments)


@pytest.mark.parametrize(
    ("line", "key"),
    [
        ("frequency_model_rel = 10.0", "swing.frequency_model_rel"),
        ("me_inertia_rel = 1e300", "swing.me_inertia_rel"),
    ],
)
def test_swing_figures_are_bounded_naming_the_file_and_key(sat_step, tmp_path, line, key):
    """A 1000 % frequency model error or a 1e300 ME inertia fraction were a LinAlgError and an
    OverflowError deep in the swing fit: now the set-up's key, with its accepted range."""
    from cadcog.core.errors import ParameterFileError
    from cadcog.spacecraft.setup import load_setup

    out = tmp_path / "b_setup.toml"
    assert main(["setup", "init", str(sat_step), "--out", str(out)]) == 0
    out.write_text(out.read_text(encoding="utf-8") + f"\n[swing]\n{line}\n", encoding="utf-8")
    with pytest.raises(ParameterFileError, match=re.escape(f"key '{key}': expected at most")):
        load_setup(out)


def test_a_board_s_points_land_on_its_edge_not_on_the_parts_behind_it(tmp_path):
    """A 1.6 mm board with a 5 mm part under it: the box's mid-height misses the board, so
    each row is also cast at other heights and the ray meeting a solid nearest the box face
    wins: the points sit on the board's edge (depth 0), none on the part 20 mm in."""
    from cadcog.spacecraft.setup import load_setup

    top = Assembly("board")
    top.add(Part("PCB", [((50.0, 40.0, 1.6), (-25.0, -20.0, 0.0))], 1850.0, "FR4"))
    top.add(Part("can", [((10.0, 10.0, 5.0), (-5.0, -5.0, -5.0))], 2700.0, "Al"))
    step = write_step(top, tmp_path / "board.step")
    out = tmp_path / "board_setup.toml"
    assert main(["setup", "init", str(step), "--out", str(out)]) == 0
    setup = load_setup(out)
    assert len(setup.candidates) >= 8
    for c in setup.candidates:
        assert 0.0 <= c.position_mm[2] <= 1.6, (c.id, c.position_mm)
        axis = int(np.argmax(np.abs(c.normal)))
        edge = 25.0 if axis == 0 else 20.0
        assert abs(abs(c.position_mm[axis]) - edge) < 1e-3, (c.id, c.position_mm)


def test_a_second_draft_of_the_same_model_reads_no_cad(sat_step, tmp_path, monkeypatch):
    """The survey (solids, materials, points cast onto the model) is cached by the model's
    content: a second `setup init` (elsewhere, another name) reads no CAD and drafts the same."""
    import shutil

    from cadcog.cad import stepread

    a = tmp_path / "a_setup.toml"
    assert main(["setup", "init", str(sat_step), "--out", str(a)]) == 0
    copy = tmp_path / "elsewhere" / "sat.step"
    copy.parent.mkdir()
    shutil.copyfile(sat_step, copy)
    monkeypatch.setattr(stepread, "read_step", lambda *a, **k: pytest.fail("read again"))
    b = tmp_path / "b_setup.toml"
    assert main(["setup", "init", str(copy), "--out", str(b)]) == 0
    assert (tmp_path / "a_materials.toml").read_text(encoding="utf-8") == (
        tmp_path / "b_materials.toml"
    ).read_text(encoding="utf-8")
    strip = [
        line
        for line in a.read_text(encoding="utf-8").splitlines()
        if not line.startswith(("model_step", "materials", "name", "# Test set-up of"))
    ]
    assert strip == [
        line
        for line in b.read_text(encoding="utf-8").splitlines()
        if not line.startswith(("model_step", "materials", "name", "# Test set-up of"))
    ]


def test_a_frame_the_coarse_grid_misses_gets_its_points_on_the_model(tmp_path):
    """Three 4 mm bars bent through space (a frame, a pipe): the draft's 70 mm grid passes
    between them, so the grid is halved until enough rays meet the model (the box grid in the
    air was the old draft); every point lies on a bar's surface, its bolt axis leaving the
    model with no bar in the way, and no more than DRAFT_MAX_POINTS are kept."""
    from cadcog.spacecraft.setup import load_setup
    from cadcog.spacecraft.setup_draft import DRAFT_MAX_POINTS, DRAFT_MIN_POINTS

    bars = [
        ((150.0, 4.0, 4.0), (0.0, 0.0, 0.0)),
        ((4.0, 120.0, 4.0), (146.0, 0.0, 0.0)),
        ((4.0, 4.0, 204.0), (146.0, 116.0, 0.0)),
    ]
    top = Assembly("frame")
    top.add(Part("bars", bars, 2700.0, "Al"))
    step = write_step(top, tmp_path / "frame.step")
    out = tmp_path / "frame_setup.toml"
    assert main(["setup", "init", str(step), "--out", str(out)]) == 0
    assert "[[candidates.points]]" in out.read_text(encoding="utf-8")
    setup = load_setup(out)
    assert DRAFT_MIN_POINTS <= len(setup.candidates) <= DRAFT_MAX_POINTS
    lo = np.array([c for _, c in bars])
    hi = lo + np.array([s for s, _ in bars])

    def inside(p, eps):
        return np.all((p >= lo - eps) & (p <= hi + eps), axis=1)

    for c in setup.candidates:
        p = np.asarray(c.position_mm)
        assert inside(p, 2e-3).any(), (c.id, p)  # on a bar (the file rounds to 0.001 mm)
        n = np.asarray(c.normal)
        ray = p + np.outer(np.linspace(0.01, 300.0, 3000), n)
        assert not any(inside(q, -1e-6).any() for q in ray), (c.id, p)  # nothing in the way


def test_the_me_base_is_drafted_on_the_model_not_in_the_air(tmp_path, capsys):
    """Two blocks at opposite corners of their box (a bent part's box is mostly air): the +z
    face's centre lies over nothing, so the ME's base goes on the highest top near it (the
    taller block's, z = 30), not at the box face's centre (25, 25, 30), 21 mm from any solid;
    a plain box keeps the face's centre, which lies on it."""
    top = Assembly("frame")
    top.add(Part("low", [((10.0, 10.0, 10.0), (0.0, 0.0, 0.0))], 2700.0, "Al"))
    top.add(Part("tall", [((10.0, 10.0, 30.0), (40.0, 40.0, 0.0))], 2700.0, "Al"))
    step = write_step(top, tmp_path / "frame.step")
    out = tmp_path / "frame_setup.toml"
    assert main(["setup", "init", str(step), "--out", str(out)]) == 0
    line = next(x for x in out.read_text().splitlines() if x.startswith("base_center_mm"))
    base = np.array(json.loads(line.split("=", 1)[1].split("#")[0]))
    assert base[2] == pytest.approx(30.0)
    assert 40.0 <= base[0] <= 50.0 and 40.0 <= base[1] <= 50.0
    assert "highest surface near the centre" in line
    block = Assembly("block")
    block.add(Part("b", [((20.0, 20.0, 20.0), (0.0, 0.0, 0.0))], 2700.0, "Al"))
    out2 = tmp_path / "block_setup.toml"
    assert (
        main(["setup", "init", str(write_step(block, tmp_path / "b.step")), "--out", str(out2)])
        == 0
    )
    line = next(x for x in out2.read_text().splitlines() if x.startswith("base_center_mm"))
    assert json.loads(line.split("=", 1)[1].split("#")[0]) == [10, 10, 20]
    assert "top surface under the centre" in line


def test_a_materials_file_given_as_the_set_up_is_named_as_such(sat_step, tmp_path, capsys):
    out = tmp_path / "sat_setup.toml"
    assert main(["setup", "init", str(sat_step), "--out", str(out)]) == 0
    capsys.readouterr()
    materials = tmp_path / "sat_materials.toml"
    assert main(["plan", str(materials)]) == 2
    err = capsys.readouterr().err
    assert f"{materials}: a materials file ([materials]), not a set-up" in err
    assert len(err.strip().splitlines()) == 1
