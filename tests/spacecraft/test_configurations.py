"""Configurations (``cadcog.spacecraft.configurations``, ``massprops --configurations``,
``balance --configurations``): closed forms, the deployed model built in CAD and integrated by
OCCT as the independent truth, and bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest

from cadcog.cli import main
from cadcog.mass.properties import box_properties
from cadcog.spacecraft.configurations import rotation_about
from support.stepfixtures import Assembly, Part, Place, rotation, write_step

HINGE = np.array([50.0, 0.0, -60.0])  # the panel's lower outer edge, along y


def _panel_place(deg: float) -> Place:
    """The panel's placement turned by ``deg`` about the hinge (x' = R (x - a) + a)."""
    r = rotation((0.0, 1.0, 0.0), deg)
    t = HINGE - r @ HINGE
    return Place(tuple(t), (0.0, 1.0, 0.0), deg)


def _sat(deg: float) -> Assembly:
    """A 100 × 100 × 120 mm body with a 2 mm panel on its +x face, hinged at its lower edge."""
    top = Assembly("sat")
    top.add(Part("bus", [((100.0, 100.0, 120.0), (-50.0, -50.0, -60.0))], 1200.0, "bus"))
    panel = Part("panel", [((2.0, 90.0, 110.0), (50.0, -45.0, -60.0))], 2700.0, "Al")
    top.add(panel, _panel_place(deg), "panel_1")
    return top


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("configs")
    stowed = write_step(_sat(0.0), tmp / "stowed.step")
    deployed = write_step(_sat(90.0), tmp / "deployed.step")
    mats = tmp / "m.toml"
    mats.write_text('[materials]\nbus = 1200\npanel = 2700\n[mass_uncertainty]\n"*" = 0.05\n')
    conf = tmp / "c.toml"
    conf.write_text(
        '[[configurations]]\nname = "deployed"\n[[configurations.moves]]\nparts = "panel*"\n'
        f"axis_point_mm = {HINGE.tolist()}\naxis_direction = [0, 1, 0]\nangle_deg = 90\n"
        '[[configurations]]\nname = "half-bus"\n[[configurations.mass_changes]]\n'
        'parts = "bus"\nmass_fraction = 0.5\n'
    )
    return stowed, deployed, mats, conf


def _requirements(tmp_path, step, mats, conf):
    """A requirements file: the CoG within ±20 mm in every configuration of ``conf``."""
    req = tmp_path / "req.toml"
    req.write_text(
        f'model_step = "{step.as_posix()}"\nmaterials = "{mats.as_posix()}"\n'
        f'configurations = "{conf.as_posix()}"\n[cog]\nlimits_mm = [20, 20, 20]\n'
        'configurations = "*"\n'
    )
    return req


def _massprops(capsys, *args: str) -> dict:
    assert main(["massprops", *args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_rotation_is_proper_and_turns_the_right_way():
    r = rotation_about([1.0, 2.0, 2.0], 37.0)
    assert np.allclose(r @ r.T, np.eye(3), atol=1e-12) and np.linalg.det(r) == pytest.approx(1)
    assert np.allclose(r @ np.array([1.0, 2.0, 2.0]), [1.0, 2.0, 2.0])  # the axis stays
    assert np.allclose(rotation_about([0, 1, 0], 90.0) @ [0, 0, 1.0], [1.0, 0, 0], atol=1e-12)


def test_a_turned_box_is_the_box_built_turned():
    """A box's mass properties moved 90° about a hinge equal the closed form of the box
    with its sides exchanged, its centre where the hinge takes it."""
    from cadcog.spacecraft.configurations import Move

    p = box_properties([2.0, 90.0, 110.0], [51.0, 0.0, -5.0], mass_kg=0.3)
    move = Move(("x",), rotation_about([0, 1, 0], 90.0), HINGE, np.zeros(3), "k")
    q = move.properties(p)
    # centre (51, 0, -5) about (50, 0, -60): (1, 0, 55) → (55, 0, -1) → (105, 0, -61)
    assert np.allclose(q.cog_mm, [105.0, 0.0, -61.0], atol=1e-12)
    expected = box_properties([110.0, 90.0, 2.0], [105.0, 0.0, -61.0], mass_kg=0.3)
    assert np.allclose(q.inertia_kg_mm2, expected.inertia_kg_mm2, atol=1e-9)


def test_the_deployed_configuration_is_the_deployed_model_integrated_by_occt(models, capsys):
    """The configuration applied to the stowed model's bodies equals, to integration precision,
    the model built deployed in CAD and integrated afresh: mass, CoG and the total inertia
    (its parallel-axis terms included)."""
    stowed, deployed, mats, conf = models
    d = _massprops(capsys, str(stowed), "--materials", str(mats), "--configurations", str(conf))
    truth = _massprops(capsys, str(deployed), "--materials", str(mats))
    c = d["configurations"]["deployed"]
    assert c["mass_kg"] == pytest.approx(truth["mass_kg"], rel=1e-9)
    assert np.allclose(c["cog_mm"], truth["cog_mm"], rtol=0, atol=1e-7)
    assert np.allclose(c["inertia_kg_mm2"], truth["inertia_kg_mm2"]["tensor"], rtol=1e-8, atol=1e-6)
    assert len(c["changed"]) == 1 and c["changed"][0].endswith("panel_1")


def test_a_mass_change_scales_the_part_and_keeps_its_cog(models, capsys):
    stowed, _, mats, conf = models
    d = _massprops(capsys, str(stowed), "--materials", str(mats), "--configurations", str(conf))
    bus = 0.1 * 0.1 * 0.12 * 1200.0
    panel = 0.002 * 0.09 * 0.11 * 2700.0
    c = d["configurations"]["half-bus"]
    assert c["mass_kg"] == pytest.approx(0.5 * bus + panel, rel=1e-9)
    moment = 0.5 * bus * np.zeros(3) + panel * np.array([51.0, 0.0, -5.0])
    assert np.allclose(c["cog_mm"], moment / (0.5 * bus + panel), atol=1e-7)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            '[[configurations]]\nname = "a"\n[[configurations.moves]]\nparts = "panel*"\n'
            "axis_point_mm = [0, 0, 0]\naxis_direction = [0, 0, 0]\nangle_deg = 90\n",
            "key 'configurations[0].moves[0].axis_direction': axis direction [0.0, 0.0, 0.0] "
            "has no direction",
        ),
        (
            '[[configurations]]\nname = "a"\n[[configurations.moves]]\nparts = "nothing*"\n'
            "translation_mm = [0, 0, 10]\n",
            "configurations[0].moves[0].parts: 'nothing*' matches no body",
        ),
        (
            '[[configurations]]\nname = "a"\n[[configurations.moves]]\nparts = "*"\n'
            "translation_mm = [0, 0, 10]\n",
            "matches every body",
        ),
        (
            '[[configurations]]\nname = "a"\n[[configurations.moves]]\nparts = "panel*"\n'
            "translation_mm = [0, 0, 10]\nangle_deg = 5\n",
            "give a rotation (axis_point_mm, axis_direction, angle_deg) or a translation",
        ),
        (
            '[[configurations]]\nname = "a"\n[[configurations]]\nname = "a"\n',
            "key 'configurations[1].name': 'a' is listed twice",
        ),
        (
            '[[configurations]]\nname = "a"\n[[configurations.mass_changes]]\nparts = "bus"\n'
            "mass_fraction = -0.5\n",
            "key 'configurations[0].mass_changes[0].mass_fraction': expected a number >= 0",
        ),
        (
            '[[configurations]]\nname = "a"\n[[configurations.moves]]\nparts = "panel*"\n'
            "translation_mm = [0, 0, 10]\nspeed = 3\n",
            "key 'configurations[0].moves[0].speed': unknown key",
        ),
    ],
)
def test_bad_configurations_exit_2_with_one_line(models, tmp_path, capsys, text, message):
    stowed, _, mats, _ = models
    conf = tmp_path / "bad.toml"
    conf.write_text(text)
    status = main(
        ["massprops", str(stowed), "--materials", str(mats), "--configurations", str(conf)]
    )
    out, err = capsys.readouterr()
    assert status == 2 and out == ""
    assert message in err, err
    assert len(err.strip().splitlines()) == 1


def test_balance_meets_the_envelope_in_every_configuration(models, tmp_path, capsys):
    """One ballast for the stowed and the deployed spacecraft: each configuration's CoG with
    it, recomputed here from the JSON's masses, is inside with its margin."""
    stowed, _, mats, conf = models
    b = tmp_path / "b.toml"
    b.write_text(
        '[[points]]\nid = "L"\nposition_mm = [-50.0, 0.0, 0.0]\n'
        '[[points]]\nid = "T"\nposition_mm = [0.0, 0.0, 60.0]\n'
    )
    args = ["balance", str(stowed), "--materials", str(mats), "--ballast", str(b)]
    status = main([*args, "--cog-limits-mm=5,20,10", "--configurations", str(conf), "--json"])
    d = json.loads(capsys.readouterr().out)
    assert status == 0 and d["feasible"]
    assert list(d["configurations"]) == ["deployed", "half-bus"]
    positions = {"L": np.array([-50.0, 0, 0]), "T": np.array([0, 0, 60.0])}
    for c in d["configurations"].values():
        before = c["before"]
        moment = before["mass_kg"] * np.asarray(before["cog_mm"])
        for item in d["ballast"]:
            moment = moment + item["mass_kg"] * positions[item["id"]]
        cog = moment / (before["mass_kg"] + d["total_ballast_kg"])
        assert np.allclose(cog, c["cog_mm"], atol=1e-9)
        assert min(c["margin_mm"]) >= -1e-9 and c["probability_inside"] >= 0.95 - 1e-6
    # the deployed configuration binds: stowed alone needs none
    assert d["total_ballast_kg"] > 0
    assert main([*args, "--cog-limits-mm=5,20,10", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["total_ballast_kg"] == 0.0


def test_a_panel_turned_into_the_bus_is_reported_with_the_volume_counted_twice(
    models, tmp_path, capsys
):
    """Turned -90° the panel lies 2 mm deep in the bus's lower face, 100 mm of its 110 mm
    inside: 100 × 90 × 2 = 18 000 mm³ counted twice, said in a note (and the JSON); turned
    +90° it only touches the hinge: nothing said."""
    stowed, _, mats, _ = models
    conf = tmp_path / "c.toml"
    conf.write_text(
        '[[configurations]]\nname = "wrong"\n[[configurations.moves]]\nparts = "panel*"\n'
        f"axis_point_mm = {HINGE.tolist()}\naxis_direction = [0, 1, 0]\nangle_deg = -90\n"
        '[[configurations]]\nname = "right"\n[[configurations.moves]]\nparts = "panel*"\n'
        f"axis_point_mm = {HINGE.tolist()}\naxis_direction = [0, 1, 0]\nangle_deg = 90\n"
    )
    d = _massprops(capsys, str(stowed), "--materials", str(mats), "--configurations", str(conf))
    (note,) = d["configurations"]["wrong"]["overlaps"]
    assert "panel_1 overlaps" in note and "bus" in note
    volume = float(note.split(" by ")[1].split(" mm³")[0])
    assert volume == pytest.approx(18000.0, rel=1e-3)
    assert d["configurations"]["right"]["overlaps"] == []
    assert (
        main(["massprops", str(stowed), "--materials", str(mats), "--configurations", str(conf)])
        == 0
    )
    assert "note: configuration 'wrong'" in capsys.readouterr().out


@pytest.fixture(scope="module")
def deployable(tmp_path_factory):
    """The example CubeSat with deployable arrays, as `cadcog parts cubesat` writes it."""
    from cadcog.rig.file import default_rig_path

    out = tmp_path_factory.mktemp("deployable")
    spec = default_rig_path().parent / "cubesat_3u_deployable.toml"
    assert main(["parts", "cubesat", str(spec), "--out", str(out)]) == 0
    name = "cubesat_3u_deployable"
    return (
        out,
        out / f"{name}.step",
        out / f"{name}_materials.toml",
        out / (f"{name}_configurations.toml"),
    )


def test_the_generator_s_deployed_arrays_stand_where_their_hinges_take_them(deployable, capsys):
    """Each 1.6 × 82 × 300 mm array, stowed centred 0.8 mm off its ±x face, hinged at its +z
    end (x = ±50, z = 150): deployed, its centre is at (±200, 0, 150.8), its long side along x;
    the spacecraft's CoG moves by the arrays' mass times that shift, its x stays (symmetric),
    and nothing deployed overlaps the structure."""
    capsys.readouterr()
    _, step, mats, conf = deployable
    d = _massprops(capsys, str(step), "--materials", str(mats), "--configurations", str(conf))
    total = d["mass_kg"]
    arrays = [b for b in d["bodies"] if "array_" in b["path"]]
    assert len(arrays) == 2
    shift = np.zeros(3)
    for b in arrays:
        stowed = np.asarray(b["cog_mm"])
        sx = np.sign(stowed[0])
        assert np.allclose(stowed, [sx * 50.8, 0, 0], atol=1e-9)
        shift += b["mass_kg"] * (np.array([sx * 200.0, 0, 150.8]) - stowed)
    c = d["configurations"]["deployed"]
    assert np.allclose(c["cog_mm"], np.asarray(d["cog_mm"]) + shift / total, atol=1e-9)
    assert c["overlaps"] == [] and d["configurations"]["stowed"]["changed"] == []
    # the arrays' own inertia turned: a 300 mm plate along x adds m (300² + 1.6²)/12 about z
    m = arrays[0]["mass_kg"]
    own_z = m * (300.0**2 + 82.0**2) / 12.0
    assert c["inertia_kg_mm2"][2][2] > own_z  # dominated by the arrays standing out


def test_check_requires_the_envelope_in_every_configuration_it_names(deployable, capsys):
    """±15 mm in z: stowed (CoG 11.6 mm) passes, deployed (19.7 mm) fails, named in the id and
    the title; the exit status is 1. A configuration the file does not have is refused."""
    out, step, mats, conf = deployable
    req = out / "req.toml"
    req.write_text(
        f'name = "dep"\nmodel_step = "{step.name}"\nmaterials = "{mats.name}"\n'
        f'configurations = "{conf.name}"\n[cog]\nlimits_mm = [20, 20, 15]\n'
        'configurations = "*"\n'
    )
    assert main(["check", str(req), "--json"]) == 1
    results = {r["id"]: r for r in json.loads(capsys.readouterr().out)["requirements"]}
    assert results["cog.envelope"]["passed"] and results["cog.envelope@stowed"]["passed"]
    assert not results["cog.envelope@deployed"]["passed"]
    assert results["cog.envelope@deployed"]["title"].endswith("(deployed)")
    req.write_text(req.read_text().replace('configurations = "*"', 'configurations = ["open"]'))
    assert main(["check", str(req)]) == 2
    assert "'open' is not a configuration of" in capsys.readouterr().err


def test_the_report_page_lists_each_configuration(deployable, capsys):
    out, step, mats, conf = deployable
    page = out / "page"
    args = ["massprops", str(step), "--materials", str(mats), "--configurations", str(conf)]
    assert main([*args, "--form-factor", "3U", "--report", str(page)]) == 0
    capsys.readouterr()
    html = (page / "index.html").read_text(encoding="utf-8")
    section = html.split('<h2 id="configurations">')[1].split("<h2")[0]
    assert "stowed" in section and "deployed" in section and "within the envelope" in section


def test_a_measured_spacecraft_changed_by_a_configuration_lands_where_the_cad_s_does(
    models, capsys
):
    """A test's figures (here the CAD's own, as if measured exactly) shifted by what the
    configuration changes in the CAD give the configuration's own CoG; the shift's covariance
    comes from the moved items only (zero for a configuration that moves nothing)."""
    import cadcog
    from cadcog.spacecraft.ballast_spec import UncertainMass
    from cadcog.spacecraft.configurations import (
        configuration_deltas,
        configuration_properties,
        load_configurations,
    )

    stowed, _, mats, conf = models
    report = cadcog.mass_properties(stowed, mats)
    bodies = report.result.bodies
    configs = load_configurations(conf)
    t = report.result.total
    measured = UncertainMass(t.mass_kg, 0.001, t.cog_mm, np.eye(3) * 0.01, np.zeros(3), "test")
    for delta, own in zip(
        configuration_deltas(bodies, configs),
        configuration_properties(bodies, configs),
        strict=True,
    ):
        moved = measured.shifted(
            delta.mass_kg, delta.moment_kg_mm, delta.moment_cov_kg2_mm2, delta.name
        )
        assert moved.mass_kg == pytest.approx(own.total.mass_kg, rel=1e-12)
        assert np.allclose(moved.cog_mm, own.total.cog_mm, atol=1e-9)
        assert np.all(np.diag(moved.cog_cov_mm2) > 0)


def test_a_part_used_up_is_gone_and_every_command_goes_on(models, tmp_path, capsys):
    """mass_fraction = 0 (propellant used): the part leaves the totals, massprops, check and
    balance run (a trial found a traceback in check and balance, a wrong message in
    massprops)."""
    stowed, _, mats, _ = models
    conf = tmp_path / "c.toml"
    conf.write_text(
        '[[configurations]]\nname = "no-panel"\n[[configurations.mass_changes]]\n'
        'parts = "panel*"\nmass_fraction = 0\n'
    )
    d = _massprops(capsys, str(stowed), "--materials", str(mats), "--configurations", str(conf))
    bus = 0.1 * 0.1 * 0.12 * 1200.0
    c = d["configurations"]["no-panel"]
    assert c["mass_kg"] == pytest.approx(bus, rel=1e-9)
    assert np.allclose(c["cog_mm"], [0, 0, 0], atol=1e-9)
    assert len(c["changed"]) == 1
    req = _requirements(tmp_path, stowed, mats, conf)
    assert main(["check", str(req)]) == 0
    capsys.readouterr()
    b = tmp_path / "b.toml"
    b.write_text('[[points]]\nid = "L"\nposition_mm = [-50.0, 0.0, 0.0]\n')
    args = ["balance", str(stowed), "--materials", str(mats), "--ballast", str(b)]
    assert main([*args, "--cog-limits-mm=20,20,20", "--configurations", str(conf)]) == 0
    capsys.readouterr()


def test_a_huge_axis_direction_is_a_direction(models, tmp_path, capsys):
    """[0, 1e200, 0] is +y: the same deployment as [0, 1, 0] (a trial found it overflowed to
    no move at all)."""
    stowed, _, mats, _ = models
    out = {}
    for label, direction in (("unit", "[0, 1, 0]"), ("huge", "[0, 1e200, 0]")):
        conf = tmp_path / f"{label}.toml"
        conf.write_text(
            f'[[configurations]]\nname = "d"\n[[configurations.moves]]\nparts = "panel*"\n'
            f"axis_point_mm = {HINGE.tolist()}\naxis_direction = {direction}\nangle_deg = 90\n"
        )
        d = _massprops(capsys, str(stowed), "--materials", str(mats), "--configurations", str(conf))
        out[label] = d["configurations"]["d"]["cog_mm"]
    assert np.allclose(out["unit"], out["huge"], atol=1e-9)
    assert not np.allclose(out["unit"], [1.0, 0.0, 0.0], atol=0.5)  # it did move


def test_every_pattern_of_a_list_must_match(models, tmp_path, capsys):
    stowed, _, mats, _ = models
    conf = tmp_path / "c.toml"
    conf.write_text(
        '[[configurations]]\nname = "d"\n[[configurations.moves]]\n'
        'parts = ["panel*", "nothing*"]\ntranslation_mm = [0, 0, 1]\n'
    )
    status = main(
        ["massprops", str(stowed), "--materials", str(mats), "--configurations", str(conf)]
    )
    err = capsys.readouterr().err
    assert status == 2 and "'nothing*' matches no body" in err


def test_an_overlap_fails_check_and_strict(models, tmp_path, capsys):
    """A panel turned into the bus: check has a failing requirement for it (exit 1), and
    --strict (check and massprops) refuses it (exit 2)."""
    stowed, _, mats, _ = models
    conf = tmp_path / "c.toml"
    conf.write_text(
        '[[configurations]]\nname = "wrong"\n[[configurations.moves]]\nparts = "panel*"\n'
        f"axis_point_mm = {HINGE.tolist()}\naxis_direction = [0, 1, 0]\nangle_deg = -90\n"
    )
    req = _requirements(tmp_path, stowed, mats, conf)
    assert main(["check", str(req), "--json"]) == 1
    results = {r["id"]: r for r in json.loads(capsys.readouterr().out)["requirements"]}
    assert not results["configuration.overlaps@wrong"]["passed"]
    assert main(["check", str(req), "--strict"]) == 2
    assert "overlaps" in capsys.readouterr().err
    args = ["massprops", str(stowed), "--materials", str(mats), "--configurations", str(conf)]
    assert main([*args, "--strict"]) == 2
    assert "(--strict)" in capsys.readouterr().err


def test_a_turned_part_s_uncertainty_turns_with_it(models, tmp_path, capsys):
    """The panel flipped 180° about its hinge: each item's mass and CoG error drawn as the
    materials file states them (in the model as it stands), the panel then turned: the
    configuration's CoG covariance is the Monte Carlo's (a review found the panel's CoG error
    left unturned: σx 0.026 mm for 0.78)."""
    import cadcog
    from cadcog.spacecraft.items import items_from_bodies

    stowed, _, mats, _ = models
    conf = tmp_path / "flip.toml"
    conf.write_text(
        '[[configurations]]\nname = "flip"\n[[configurations.moves]]\nparts = "panel*"\n'
        f"axis_point_mm = {HINGE.tolist()}\naxis_direction = [1, 1, 0]\nangle_deg = 180\n"
    )
    report = cadcog.mass_properties(stowed, mats, configurations=conf)
    c = report.configurations[0]
    items, _ = items_from_bodies(report.result.bodies)
    assert len(items) == 2
    rng = np.random.default_rng(9)
    n = 200_000
    r = rotation_about([1, 1, 0], 180.0)
    moment = np.zeros((n, 3))
    mass = np.zeros(n)
    for item in items:
        m = item.properties.mass_kg * (1 + item.sigma_rel * rng.standard_normal(n))
        cog = item.properties.cog_mm + item.cog_sigma_mm * rng.standard_normal((n, 3))
        if "panel" in item.key:
            cog = (cog - HINGE) @ r.T + HINGE
        moment += m[:, None] * cog
        mass += m
    g = moment / mass[:, None]
    mc = np.cov(g.T)
    assert np.allclose(np.sqrt(np.diag(c.cog_cov_mm2)), np.sqrt(np.diag(mc)), rtol=0.03)
    assert np.allclose(g.mean(axis=0), c.total.cog_mm, atol=0.05)
