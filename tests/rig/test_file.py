"""Rig files: the paper rig loads, and every kind of bad input names its file and key."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from cadcog.core.errors import ParameterFileError
from cadcog.rig.file import default_rig_path, load_rig
from support.rigtools import paper_rig_dict, write_rig

MISSING = "missing required key"
UNKNOWN = "unknown key"
NOT_A_NUMBER = "expected a number"
NOT_POSITIVE = "expected a positive number"
OFF_SURFACE = "is not on face"
OFF_FACE = "is off face"
TOO_DEEP = "is not less than the part's"
HOLES_MEET = "holes of points .* meet"
ME_OVERLAP = "ME volumes .* overlap"
ME_IN_PM = "overlaps the proof mass"
ME_BELOW_TOP = r"must sit on the \+z side"
ME_FLOATING = "no ME volume rests on the"
UNDER_ME = "lies under ME volume"
DUPLICATE = "duplicate id"
RESERVED = "is reserved"


def test_paper_rig_loads_with_its_documented_values(paper_rig):
    assert paper_rig.proof_mass.size_mm == (200.0, 75.0, 78.0)
    assert paper_rig.proof_mass.mass_kg == 9.2
    assert len(paper_rig.suspension_points) == 6
    assert [v.name for v in paper_rig.me_volumes] == [
        "arduino_uno",
        "protoboard_inclinometer",
        "transmitter",
        "battery",
    ]
    # Density implied by 9.2 kg in the holed box: steel.
    assert 7800 < paper_rig.proof_mass_density_kg_mm3 * 1e9 < 7900


def test_paper_rig_keeps_every_suspension_in_the_inclinometer_range(paper_rig):
    readings = paper_rig.ideal_readings()
    for pid, r in readings.items():
        assert r.in_range(paper_rig.inclinometer_range_deg), pid


def test_paper_rig_me_masses_give_the_papers_sigma(paper_rig):
    m = np.array([v.mass_kg for v in paper_rig.me_volumes])
    edge = np.array([v.cog_uncertainty_cube_mm for v in paper_rig.me_volumes])
    sigma = np.sqrt(np.sum((m / m.sum() * edge) ** 2 / 12.0))
    assert sigma == pytest.approx(1.66, abs=0.05)


Mutation = Callable[[dict[str, Any]], Any]


def _set(path: str, value: Any) -> Mutation:
    def mutate(d: dict[str, Any]) -> None:
        *head, last = path.split(".")
        node: Any = d
        for part in head:
            node = node[int(part)] if part.isdigit() else node[part]
        if value is KeyError:
            del node[int(last) if last.isdigit() else last]
        else:
            node[int(last) if last.isdigit() else last] = value

    return mutate


CASES: list[tuple[str, Mutation, str, str]] = [
    ("missing top-level table", _set("holes", KeyError), "holes", MISSING),
    ("missing key", _set("proof_mass.mass_kg", KeyError), "proof_mass.mass_kg", MISSING),
    ("unknown key", _set("proof_mass.colour", "red"), "proof_mass.colour", UNKNOWN),
    ("unknown top-level key", _set("extra", 1), "extra", UNKNOWN),
    ("string for a number", _set("proof_mass.mass_kg", "9.2"), "proof_mass.mass_kg", NOT_A_NUMBER),
    ("boolean for a number", _set("holes.depth_mm", True), "holes.depth_mm", NOT_A_NUMBER),
    ("negative mass", _set("proof_mass.mass_kg", -1.0), "proof_mass.mass_kg", NOT_POSITIVE),
    # 0.1 g, 1e-300 kg and 9 t in the paper's 1.17 L block: no solid is that light or heavy
    ("mass of a foam", _set("proof_mass.mass_kg", 1e-4), "proof_mass.mass_kg", "0.0855 kg/m³"),
    ("mass of nothing", _set("proof_mass.mass_kg", 1e-300), "proof_mass.mass_kg", "at least 10"),
    (
        "mass of a star",
        _set("proof_mass.mass_kg", 9000.0),
        "proof_mass.mass_kg",
        "denser than any solid",
    ),
    (
        "zero size",
        _set("proof_mass.size_mm", [200.0, 0.0, 78.0]),
        "proof_mass.size_mm",
        NOT_POSITIVE,
    ),
    (
        "short vector",
        _set("proof_mass.size_mm", [200.0, 75.0]),
        "proof_mass.size_mm",
        "expected an array of 3 numbers",
    ),
    (
        "bad face",
        _set("suspension_points.0.face", "top"),
        "suspension_points[0].face",
        "expected one of",
    ),
    (
        "point off the surface",
        _set("suspension_points.0.position_mm", [45.0, 20.0, 80.0]),
        "suspension_points[0].position_mm",
        OFF_SURFACE,
    ),
    (
        "hole off its face",
        _set("suspension_points.2.position_mm", [60.0, 74.0, 0.0]),
        "suspension_points[2].position_mm",
        OFF_FACE,
    ),
    ("hole deeper than the part", _set("holes.depth_mm", 80.0), "holes.depth_mm", TOO_DEEP),
    (
        "holes that meet",
        _set("suspension_points.1.position_mm", [47.0, 20.0, 78.0]),
        "suspension_points[0].position_mm",
        HOLES_MEET,
    ),
    (
        "point under the ME",
        _set("suspension_points.0.position_mm", [100.0, 37.5, 78.0]),
        "suspension_points[0].position_mm",
        UNDER_ME,
    ),
    ("duplicate id", _set("suspension_points.1.id", "S1"), "suspension_points[1].id", DUPLICATE),
    (
        "single point",
        lambda d: d.update(suspension_points=d["suspension_points"][:1]),
        "suspension_points",
        "at least 2 entries",
    ),
    (
        "ME volumes overlap",
        _set("measurement_equipment.volumes.2.center_mm", [110.0, 37.5, 127.0]),
        "measurement_equipment.volumes[2].center_mm",
        ME_OVERLAP,
    ),
    (
        "ME inside the proof mass",
        _set("measurement_equipment.volumes.0.center_mm", [100.0, 37.5, 80.0]),
        "measurement_equipment.volumes[0].center_mm",
        ME_IN_PM,
    ),
    (
        "ME beside the proof mass",
        _set("measurement_equipment.volumes.3.center_mm", [230.0, 37.5, 60.0]),
        "measurement_equipment.volumes[3].center_mm",
        ME_BELOW_TOP,
    ),
    (
        "ME floating",
        lambda d: [
            v.update(center_mm=[v["center_mm"][0], v["center_mm"][1], v["center_mm"][2] + 5.0])
            for v in d["measurement_equipment"]["volumes"]
        ],
        "measurement_equipment.volumes[0].center_mm",
        ME_FLOATING,
    ),
    (
        "reserved name",
        _set("measurement_equipment.volumes.0.name", "assembly"),
        "measurement_equipment.volumes[0].name",
        RESERVED,
    ),
    (
        "ME mass zero",
        _set("measurement_equipment.volumes.1.mass_kg", 0.0),
        "measurement_equipment.volumes[1].mass_kg",
        NOT_POSITIVE,
    ),
    (
        "range over 90",
        _set("inclinometer.range_deg", 120.0),
        "inclinometer.range_deg",
        "at most 90",
    ),
    (
        "old inclinometer model name",
        _set("error_model.inclinometer_model", "conservative"),
        "error_model.inclinometer_model",
        "'hang-bias' \\(was 'conservative', the default\\) and 'paper-averaged'",
    ),
    (
        "unknown inclinometer model",
        _set("error_model.inclinometer_model", "averaged"),
        "error_model.inclinometer_model",
        "expected one of hang-bias, paper-averaged",
    ),
    (
        "old dither key",
        _set("error_model.dither_noise_deg", 0.1),
        "error_model.dither_noise_deg",
        "renamed sensor_noise_deg",
    ),
    (
        "negative sensor noise",
        _set("error_model.sensor_noise_deg", -0.1),
        "error_model.sensor_noise_deg",
        "expected a number >= 0, got -0.1",
    ),
    (
        "sensor offset beyond any datasheet",
        _set("inclinometer.offset_deg", 20.0),
        "inclinometer.offset_deg",
        "expected at most 5 \\(a sensor's zero offset",
    ),
    (
        "negative scale error",
        _set("inclinometer.scale_error_rel", -0.01),
        "inclinometer.scale_error_rel",
        "expected a number >= 0",
    ),
    (
        "scale error given in percent",
        _set("inclinometer.scale_error_rel", 1.0),
        "inclinometer.scale_error_rel",
        "expected at most 0.2 \\(a channel's sensitivity error, a fraction",
    ),
    (
        "mounting beyond 10 degrees",
        _set("inclinometer.mounting_misalignment_deg", 15.0),
        "inclinometer.mounting_misalignment_deg",
        "expected at most 10",
    ),
    (
        "unknown wire model",
        _set("error_model.wire_model", "string"),
        "error_model.wire_model",
        "expected one of one-wire, paper, elastica",
    ),
]


def test_shared_sensor_figures_reach_the_error_model(tmp_path):
    from cadcog.method.errormodel import ErrorModel

    data = paper_rig_dict()
    data["inclinometer"].update(offset_deg=0.3, scale_error_rel=0.01, mounting_misalignment_deg=0.6)
    m = ErrorModel.from_rig(load_rig(write_rig(tmp_path / "rig.toml", data)))
    np.testing.assert_allclose(
        m.shared_sensor_sigmas, [0.3 / 3**0.5] * 2 + [0.01 / 3**0.5] * 2 + [0.2] * 3
    )
    assert "mean of 10; one sensor for every hang: offset ±0.3°" in m.summary()
    assert m.paper().has_shared_sensor is False


@pytest.mark.parametrize(
    ("mutate", "key", "message"), [c[1:] for c in CASES], ids=[c[0] for c in CASES]
)
def test_bad_rig_files_name_file_and_key(tmp_path, mutate, key, message):
    data = paper_rig_dict()
    mutate(data)
    path = write_rig(tmp_path / "rig.toml", data)
    with pytest.raises(ParameterFileError, match=message) as info:
        load_rig(path)
    assert info.value.key == key
    assert str(path) in str(info.value)
    assert f"key '{key}'" in str(info.value)


def test_toml_syntax_error_names_the_file(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text("name = \n", encoding="utf-8")
    with pytest.raises(ParameterFileError, match=r"broken\.toml: invalid TOML.*line 1"):
        load_rig(path)


def test_missing_file(tmp_path):
    with pytest.raises(ParameterFileError, match="file not found"):
        load_rig(tmp_path / "nope.toml")


def test_round_trip_of_the_test_writer_is_faithful(tmp_path):
    """The tests' TOML writer must not change the rig (else the cases above test nothing)."""
    original = load_rig(default_rig_path())
    copy_ = load_rig(write_rig(tmp_path / "rig.toml", paper_rig_dict()))
    assert copy_.suspension_points == original.suspension_points
    assert copy_.me_volumes == original.me_volumes
    assert copy_.proof_mass == original.proof_mass
