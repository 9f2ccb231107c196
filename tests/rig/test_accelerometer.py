"""A three-axis accelerometer: its mounting, its shared errors, and its ``[inclinometer]`` table."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from cadcog.core.errors import ParameterFileError
from cadcog.rig.accelerometer import (
    accel_angles_deg,
    accel_norms,
    accel_readings,
    accel_verticals,
    axes_matrix,
    axes_problem,
)
from cadcog.rig.file import load_rig
from support.rigtools import paper_rig_dict, write_rig

SIGNED = [s + a for s in "+-" for a in "xyz"]
ALL_AXES = [
    c for c in itertools.product(SIGNED, repeat=3) if len({a[1] for a in c}) == 3
]  # the 48 signed permutations
PROPER = [c for c in ALL_AXES if axes_problem(c) is None]


def test_exactly_the_24_rotations_among_the_48_signed_permutations_are_mountings():
    assert len(ALL_AXES) == 48
    assert len(PROPER) == 24
    for c in ALL_AXES:
        m = np.zeros((3, 3))
        for row, a in enumerate(c):
            m[row, "xyz".index(a[1])] = 1.0 if a[0] == "+" else -1.0
        # Independent of the module: a rotation has determinant +1 and is orthogonal.
        assert (c in PROPER) == (round(np.linalg.det(m)) == 1)
        if c in PROPER:
            np.testing.assert_array_equal(axes_matrix(c), m)
        else:
            with pytest.raises(ValueError, match="mirror image"):
                axes_matrix(c)


@pytest.mark.parametrize(
    ("axes", "message"),
    [
        (("+x", "+y"), "three signed axes"),
        (("x", "+y", "+z"), 'expected each axis as "\\+x"'),
        (("+x", "+y", "+w"), "expected each axis"),
        (("+x", "-x", "+z"), "each object axis must appear once"),
        ("+x+y+z", "three signed axes"),
    ],
)
def test_malformed_mountings_are_refused_with_what_was_expected(axes, message):
    problem = axes_problem(axes)
    assert problem is not None
    assert pytest.importorskip("re").search(message, problem)


def test_a_phone_lying_face_up_reads_plus_one_g_on_its_z():
    # Object level (up = +z); sensor mounted square: reads (0, 0, +1 g).
    a = accel_readings([[0.0, 0.0, 1.0]], np.zeros(15))
    np.testing.assert_allclose(a, [[0.0, 0.0, 1.0]], atol=1e-15)
    # Sensor x along object -y: with the object's +y up, the sensor's x reads -1 g.
    a = accel_readings([[0.0, 1.0, 0.0]], np.zeros(15), ("-y", "+x", "+z"))
    np.testing.assert_allclose(a, [[-1.0, 0.0, 0.0]], atol=1e-15)


unit = st.tuples(*[st.floats(-1.0, 1.0)] * 3).filter(lambda v: 0.1 < np.linalg.norm(v))
shared = st.tuples(
    *[st.floats(-0.08, 0.08)] * 3,
    *[st.floats(-0.03, 0.03)] * 3,
    *[st.floats(-2.0, 2.0)] * 3,
    *[st.floats(-0.03, 0.03)] * 6,
)


@given(unit, shared, st.sampled_from(PROPER), st.booleans())
def test_verticals_invert_readings_for_any_mounting_and_errors(v, theta, axes, turned):
    u = np.asarray(v) / np.linalg.norm(v)
    a = accel_readings([u], theta, axes, [turned])
    back = accel_verticals(a, theta, axes, [turned])
    np.testing.assert_allclose(back.u[0], u, atol=1e-12)
    assert not back.normalized.any()
    # At rest the calibrated magnitude is 1 g whatever the orientation and the errors.
    assert accel_norms(a, theta)[0] == pytest.approx(1.0, abs=1e-12)


@given(unit, st.lists(st.floats(-0.03, 0.03), min_size=6, max_size=6), st.booleans())
def test_any_coupling_matrix_is_its_symmetric_and_antisymmetric_parts(v, off, turned):
    """A datasheet's six couplings, as a full matrix I + C acting on what the sensor sees (after
    a reversal's turn: the coupling is the sensor's), are the model's k and w."""
    u = np.asarray(v) / np.linalg.norm(v)
    c = np.zeros((3, 3))
    c[0, 1], c[0, 2], c[1, 0], c[1, 2], c[2, 0], c[2, 1] = off
    seen = u * (np.array([-1.0, -1.0, 1.0]) if turned else 1.0)
    direct = (np.eye(3) + c) @ seen
    sym, anti = (c + c.T) / 2, (c - c.T) / 2
    theta = np.zeros(15)
    theta[9:12] = sym[0, 1], sym[0, 2], sym[1, 2]
    theta[12:15] = anti[2, 1], anti[0, 2], anti[1, 0]  # W v = w × v
    np.testing.assert_allclose(accel_readings([u], theta, turned=[turned])[0], direct, atol=1e-15)


@given(unit)
def test_the_angles_are_an_inclinometers_in_the_sensors_axes(v):
    u = np.asarray(v) / np.linalg.norm(v)
    x, y, up = accel_angles_deg([2.5 * u])  # any magnitude: only the direction counts
    assert np.sin(np.radians(x[0])) == pytest.approx(u[0], abs=1e-12)
    assert np.sin(np.radians(y[0])) == pytest.approx(u[1], abs=1e-12)
    assert bool(up[0]) == (u[2] > 0)


def test_an_offset_is_a_vertical_error_that_the_hangs_share():
    # 20 mg on x: a level object reads 1.15° of tilt about y, on every hang alike.
    u = np.array([[0.0, 0.0, 1.0]])
    a = accel_readings(u, [0.02] + [0.0] * 14)
    seen = accel_verticals(a, np.zeros(15)).u[0]
    assert np.degrees(np.arcsin(seen[0])) == pytest.approx(np.degrees(np.arctan(0.02)), rel=1e-12)


def test_a_zero_reading_has_no_direction():
    with pytest.raises(ValueError, match="no direction"):
        accel_verticals([[0.0, 0.0, 0.0]], np.zeros(15))


REQUIRED = {
    "axes": ["+x", "+y", "+z"],
    "offset_g": 0.02,
    "scale_error_rel": 0.01,
    "mounting_misalignment_deg": 1.0,
}


def _accel_rig(tmp_path, drop=(), **inc):
    data = paper_rig_dict()
    table = {"device": "accelerometer", **REQUIRED, **inc}
    data["inclinometer"] = {k: v for k, v in table.items() if k not in drop}
    return write_rig(tmp_path / "rig.toml", data)


def test_an_accelerometer_table_reaches_the_error_model(tmp_path):
    from cadcog.method.errormodel import ErrorModel

    rig = load_rig(
        _accel_rig(
            tmp_path,
            axes=["-y", "+x", "+z"],
            offset_g=0.05,
            scale_error_rel=0.03,
            mounting_misalignment_deg=1.5,
            cross_axis_rel=0.02,
        )
    )
    cfg = rig.inclinometer
    assert cfg.accelerometer and cfg.axes == ("-y", "+x", "+z") and cfg.range_deg == 90.0
    m = ErrorModel.from_rig(rig)
    c = 0.02 / 6**0.5  # the symmetric and the antisymmetric coupling of each pair
    np.testing.assert_allclose(
        m.shared_sensor_sigmas,
        [0.05 / 3**0.5] * 3 + [0.03 / 3**0.5] * 3 + [0.5] * 3 + [c] * 6,
    )


@pytest.mark.parametrize(
    ("inc", "key", "message"),
    [
        ({"axes": ["+x", "+y", "-z"]}, "axes", "mirror image"),
        ({"axes": ["+x", "+y"]}, "axes", "three signed axes"),
        ({"axes": "+x+y+z"}, "axes", "array of strings"),
        ({"offset_g": 0.5}, "offset_g", "at most 0.3"),
        ({"offset_g": -0.1}, "offset_g", ">= 0"),
        ({"scale_error_rel": 0.6}, "scale_error_rel", "at most 0.2"),
        ({"mounting_misalignment_deg": 50.0}, "mounting_misalignment_deg", "at most 10"),
        ({"accuracy_g": 0.5}, "accuracy_g", "at most 0.1"),
        ({"accuracy_deg": 0.1}, "accuracy_deg", "declare accuracy_g"),
        ({"cross_axis_rel": 0.5}, "cross_axis_rel", "at most 0.1"),
        ({"accuracy_g": 0.0}, "accuracy_g", "positive"),
        ({"offset_deg": 0.3}, "offset_deg", "declare offset_g"),
        ({"range_deg": 60.0}, "range_deg", "an accelerometer has none"),
        ({"adc_bits": 12}, "adc_bits", "an accelerometer has none"),
        ({"device": "gyroscope"}, "device", "expected one of inclinometer, accelerometer"),
        ({"offset_gs": 0.1}, "offset_gs", "did you mean 'offset_g'"),
    ],
)
def test_bad_accelerometer_tables_name_the_key(tmp_path, inc, key, message):
    path = _accel_rig(tmp_path, **inc)
    with pytest.raises(ParameterFileError, match=message) as info:
        load_rig(path)
    assert info.value.key == f"inclinometer.{key}"


def test_an_accelerometer_declares_how_it_sits_and_what_it_shares(tmp_path):
    """No silent perfect sensor: axes and the three shared figures are required (0 allowed)."""
    for key in REQUIRED:
        with pytest.raises(ParameterFileError, match="missing: an accelerometer declares") as e:
            load_rig(_accel_rig(tmp_path, drop=(key,)))
        assert e.value.key == f"inclinometer.{key}"
    cfg = load_rig(_accel_rig(tmp_path, offset_g=0.0, scale_error_rel=0.0)).inclinometer
    assert cfg.offset_g == 0.0 and cfg.accuracy_g == 0.001 and cfg.cross_axis_rel == 0.0


def test_an_inclinometers_leftover_keys_are_named_at_once(tmp_path):
    path = _accel_rig(tmp_path, range_deg=60.0, sign_x=1, adc_bits=10)
    with pytest.raises(ParameterFileError, match=r"\(and sign_x, adc_bits\)") as info:
        load_rig(path)
    assert info.value.key == "inclinometer.range_deg"


def test_an_inclinometer_table_refuses_an_accelerometers_figures(tmp_path):
    data = paper_rig_dict()
    data["inclinometer"]["offset_g"] = 0.02
    with pytest.raises(ParameterFileError, match='declare device = "accelerometer"') as info:
        load_rig(write_rig(tmp_path / "rig.toml", data))
    assert info.value.key == "inclinometer.offset_g"
