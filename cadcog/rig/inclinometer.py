"""The dual-axis inclinometer: configuration, ADC sensor model and readings → vertical (eq. 2).

Sign convention (docs/method.md §1): ``sin X = u·x_b`` and ``sin Y = u·y_b``, with ``u`` the upward
vertical in body components, so X is positive when the body's +x axis points upward. A device
whose axes read the other way is described by ``sign_x = -1`` / ``sign_y = -1`` in the
configuration; readings are multiplied by the signs before anything else.

Defaults are the paper's rig: a Posital Fraba ACS-060 (±60°, ±0.1° accuracy) read by an Arduino
Uno's 10-bit ADC. The seed paper does not give the sensor's transfer function; the default
assumes 4 V of output span over 120° (1/30 V per degree) centred on 2.5 V, read against a 5 V
reference, which gives an LSB of 0.146°.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import UnsupportedSensorError
from cadcog.core.units import deg_to_rad, rad_to_deg

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class SensorModel:
    """Analog inclinometer output read by an ADC: counts ↔ degrees.

    ``angle_deg = (V - zero_v) / sensitivity_v_per_deg`` with ``V`` the centre of the ADC bin,
    ``V = (counts + 0.5) · adc_reference_v / 2**adc_bits`` (an ADC reports the bin the voltage
    falls in; the bin centre makes the quantisation error zero-mean, uniform in ±LSB/2).

    Examples
    --------
    >>> s = SensorModel()
    >>> round(s.lsb_deg, 4)
    0.1465
    >>> round(float(s.counts_to_deg(511.5)), 9)  # the 2.5 V bin boundary: 0 degrees
    0.0
    """

    adc_bits: int = 10
    adc_reference_v: float = 5.0
    sensitivity_v_per_deg: float = 4.0 / 120.0
    zero_v: float = 2.5

    @property
    def lsb_deg(self) -> float:
        """Angle step of one ADC count (degrees)."""
        return self.adc_reference_v / 2**self.adc_bits / self.sensitivity_v_per_deg

    @property
    def max_counts(self) -> int:
        return int(2**self.adc_bits - 1)

    def counts_to_deg(self, counts: npt.ArrayLike) -> FloatArray:
        volts = (np.asarray(counts, dtype=float) + 0.5) * self.adc_reference_v / 2**self.adc_bits
        return np.asarray((volts - self.zero_v) / self.sensitivity_v_per_deg)

    def count_to_deg(self, counts: float) -> float:
        """:meth:`counts_to_deg` of one reading, without numpy (the same operations in the same
        order, so the same bits): the readings reader calls it once per sample."""
        volts = (counts + 0.5) * self.adc_reference_v / 2**self.adc_bits
        return (volts - self.zero_v) / self.sensitivity_v_per_deg

    def deg_to_counts(self, angle_deg: npt.ArrayLike) -> FloatArray:
        """Inverse of :meth:`counts_to_deg` before rounding (real-valued counts)."""
        volts = np.asarray(angle_deg, dtype=float) * self.sensitivity_v_per_deg + self.zero_v
        return np.asarray(volts * 2**self.adc_bits / self.adc_reference_v - 0.5)


@dataclass(frozen=True)
class InclinometerConfig:
    """Range, accuracy, axis signs and ADC model of the inclinometer.

    Attributes
    ----------
    range_deg : float
        Each axis reads within ±range_deg (paper: 60).
    accuracy_deg : float
        Half-width of the uniform accuracy error (paper: 0.1).
    sign_x, sign_y : int
        +1 if the device follows the project convention on that axis, -1 if it reads reversed.
    sensor : SensorModel
    offset_deg : float
        Each channel's zero offset lies within ±offset_deg (uniform), the same on every hang of
        a test (one sensor). 0 (the default): the accuracy bounds every error of a hang.
    scale_error_rel : float
        Each channel's sensitivity lies within ±scale_error_rel of nominal (uniform), the same
        on every hang.
    mounting_misalignment_deg : float
        The sensor's axes lie within this angle of the object's (any axis, uniform in angle),
        the same on every hang.
    device : "inclinometer" or "accelerometer"
        What the sensor reads: two angles (the default), or the three components of the
        specific force in g (:mod:`cadcog.rig.accelerometer`; no range limit, and the angle
        figures above other than the mounting do not apply).
    axes : tuple of 3 str
        An accelerometer's nominal mounting: which object axis each sensor axis lies along
        (:func:`cadcog.rig.accelerometer.axes_matrix`).
    offset_g : float
        An accelerometer's zero offset: each axis's within ±offset_g (uniform), the same on
        every hang.
    cross_axis_rel : float
        An accelerometer's cross-axis sensitivity: each axis's response to each other axis
        within ±cross_axis_rel (uniform), the same on every hang.
    accuracy_g : float
        An accelerometer's error that the shared figures do not model (nonlinearity, drift,
        hysteresis): each axis's mean reading of a hang within ±accuracy_g (uniform),
        independent between hangs. It bounds both the vertical and the gravity norm
        (:func:`cadcog.rig.accelerometer.accel_norms`) of each hang.

    The three shared figures are what one sensor brings to every hang of a test
    (:func:`sensor_readings` is their definition); the estimator calibrates them jointly with
    the CoG where the hangs allow it (:mod:`cadcog.method.sharedfit`).
    """

    range_deg: float = 60.0
    accuracy_deg: float = 0.1
    sign_x: int = 1
    sign_y: int = 1
    sensor: SensorModel = field(default_factory=SensorModel)
    offset_deg: float = 0.0
    scale_error_rel: float = 0.0
    mounting_misalignment_deg: float = 0.0
    device: str = "inclinometer"
    axes: tuple[str, str, str] = ("+x", "+y", "+z")
    offset_g: float = 0.0
    accuracy_g: float = 0.001
    cross_axis_rel: float = 0.0

    @property
    def accelerometer(self) -> bool:
        """Whether the sensor is a three-axis accelerometer."""
        return self.device == "accelerometer"


#: The devices an ``[inclinometer]`` table may declare.
DEVICES = ("inclinometer", "accelerometer")


def require_angle_sensor(device: str, what: str) -> None:
    """Raise :class:`~cadcog.core.errors.UnsupportedSensorError` unless ``device`` is a
    dual-axis inclinometer: ``what`` (a simulation, a prediction) models only its readings.

    Examples
    --------
    >>> require_angle_sensor("inclinometer", "cadcog budget")
    >>> require_angle_sensor("accelerometer", "cadcog budget")
    Traceback (most recent call last):
    ...
    cadcog.core.errors.UnsupportedSensorError: cadcog budget models a dual-axis inclinometer ...
    """
    if device == "accelerometer":
        raise UnsupportedSensorError(
            f"{what} models a dual-axis inclinometer only, and the [inclinometer] table declares "
            'device = "accelerometer" (an accelerometer is taken by estimate, acquire --log or '
            "--port, inertia, and by budget --rig and plan SETUP, which predict its error: "
            "docs/bench.md §8)"
        )


@dataclass(frozen=True)
class Verticals:
    """Upward verticals from readings, and how many needed normalising.

    Attributes
    ----------
    u : ndarray, shape (n, 3)
        Unit upward verticals in body components.
    normalized : ndarray of bool, shape (n,)
        True where ``sin²X + sin²Y > 1`` and the sines were scaled back onto the unit circle.
    """

    u: FloatArray
    normalized: npt.NDArray[np.bool_]

    @property
    def n_normalized(self) -> int:
        return int(np.count_nonzero(self.normalized))


def verticals_from_readings(
    inc_x_deg: npt.ArrayLike,
    inc_y_deg: npt.ArrayLike,
    top_face_up: npt.ArrayLike,
    config: InclinometerConfig | None = None,
) -> Verticals:
    """Body-frame upward verticals from inclinometer readings (eq. 2).

    ``u = (sin X, sin Y, s·√(1 − sin²X − sin²Y))`` with ``s = +1`` when the top face is up. Noise
    can give ``sin²X + sin²Y > 1``; then both sines are divided by ``√(sin²X + sin²Y)`` and the z
    component is 0 (the paper's normalisation), and the sample is flagged.

    Parameters
    ----------
    inc_x_deg, inc_y_deg : array_like, shape (n,)
        Readings as the device reports them (signs applied here).
    top_face_up : array_like of bool, shape (n,)
    config : InclinometerConfig, optional

    Examples
    --------
    >>> v = verticals_from_readings([30.0], [0.0], [True])
    >>> np.round(v.u, 6).tolist()
    [[0.5, 0.0, 0.866025]]
    >>> verticals_from_readings([60.0], [60.0], [True]).n_normalized
    1
    """
    cfg = config or InclinometerConfig()
    sx = np.sin(deg_to_rad(np.atleast_1d(inc_x_deg))) * cfg.sign_x
    sy = np.sin(deg_to_rad(np.atleast_1d(inc_y_deg))) * cfg.sign_y
    s = np.where(np.atleast_1d(np.asarray(top_face_up, dtype=bool)), 1.0, -1.0)
    r2 = sx * sx + sy * sy
    over = r2 > 1.0
    scale = np.where(over, 1.0 / np.sqrt(np.where(over, r2, 1.0)), 1.0)
    sx, sy = sx * scale, sy * scale
    # After normalisation the z component is exactly 0, not the round-off of 1 − sx² − sy².
    sz = np.where(over, 0.0, s * np.sqrt(np.clip(1.0 - sx * sx - sy * sy, 0.0, None)))
    return Verticals(np.stack([sx, sy, sz], axis=-1), over)


def readings_from_verticals(
    u: npt.ArrayLike, config: InclinometerConfig | None = None
) -> tuple[FloatArray, FloatArray, npt.NDArray[np.bool_]]:
    """Device readings (X, Y in degrees, top-face-up flag) for upward verticals ``u`` (n, 3).

    The inverse of :func:`verticals_from_readings` for unit vectors.
    """
    cfg = config or InclinometerConfig()
    v = np.atleast_2d(np.asarray(u, dtype=float))
    x = rad_to_deg(np.arcsin(np.clip(v[:, 0], -1, 1))) * cfg.sign_x
    y = rad_to_deg(np.arcsin(np.clip(v[:, 1], -1, 1))) * cfg.sign_y
    return x, y, v[:, 2] > 0.0


#: The shared sensor parameters, in the order of every vector of them: each channel's zero
#: offset (degrees, in the device's own signs), each channel's sensitivity error (relative) and
#: the mounting rotation vector from object to sensor axes (degrees).
SHARED_SENSOR_PARAMETERS = (
    "offset_x_deg",
    "offset_y_deg",
    "scale_x_rel",
    "scale_y_rel",
    "mounting_x_deg",
    "mounting_y_deg",
    "mounting_z_deg",
)


def rotation_matrix(rotation_deg: npt.ArrayLike) -> FloatArray:
    """The rotation by the rotation vector ``rotation_deg`` (axis × angle, degrees): Rodrigues.

    Examples
    --------
    >>> np.round(rotation_matrix([0.0, 0.0, 90.0]) @ [1.0, 0.0, 0.0], 12).tolist()
    [0.0, 1.0, 0.0]
    """
    r = deg_to_rad(np.asarray(rotation_deg, dtype=float))
    angle = float(np.linalg.norm(r))
    if angle == 0.0:
        return np.eye(3)
    k = r / angle
    kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.asarray(np.eye(3) + np.sin(angle) * kx + (1.0 - np.cos(angle)) * (kx @ kx))


def _turn(v: FloatArray, rotation: FloatArray) -> FloatArray:
    """``rotation @ vᵢ`` for each row of ``v`` (n, 3), element-wise: no BLAS call, which would
    start its thread pool and allocate its buffers (under a memory limit OpenBLAS aborts the
    process instead of raising), and with the identity every vector comes back to the bit."""
    return np.asarray(
        v[:, 0:1] * rotation[:, 0] + v[:, 1:2] * rotation[:, 1] + v[:, 2:3] * rotation[:, 2]
    )


def sensor_readings(
    u: npt.ArrayLike,
    shared: npt.ArrayLike,
    config: InclinometerConfig | None = None,
    turned: npt.ArrayLike | None = None,
) -> tuple[FloatArray, FloatArray, npt.NDArray[np.bool_]]:
    """What a sensor with the shared errors ``shared`` reports for upward verticals ``u``.

    The definition of the shared parameters (:data:`SHARED_SENSOR_PARAMETERS`): the sensor
    sees ``v = R u`` (``R`` :func:`rotation_matrix` of the mounting), each channel's ideal
    report is ``A = sign · asin(v)`` and it reports ``(1 + s) A + b``. Per-hang errors (bias,
    noise, ADC) come on top. A hang read with the sensor **turned** 180° on its mount (about
    its own z axis: a reversal) sees ``(−vₓ, −v_y, v_z)``, with the same offsets and
    sensitivities: the two readings' mean is the zero offset.

    Parameters
    ----------
    u : array_like, shape (n, 3)
        Unit upward verticals, body components.
    shared : array_like, shape (7,)
    config : InclinometerConfig, optional
    turned : array_like of bool, shape (n,), optional
        Which hangs were read with the sensor turned (default none).

    Returns
    -------
    x_deg, y_deg : ndarray, shape (n,)
    top_face_up : ndarray of bool, shape (n,)
        From the body's own vertical (a small misalignment never turns the object over).

    Examples
    --------
    >>> u, shared = [[0.5, 0.0, 0.75**0.5]], [0.2, 0, 0.01, 0, 0, 0, 0]
    >>> x, y, _ = sensor_readings(u, shared)
    >>> round(float(x[0]), 9)  # 30° read 1 % high, plus 0.2°
    30.5
    >>> x, y, _ = sensor_readings(u, shared, turned=[True])
    >>> round(float(x[0]), 9)  # turned: −30° read 1 % high, plus the same 0.2°
    -30.1
    """
    cfg = config or InclinometerConfig()
    b = np.asarray(shared, dtype=float)
    v = np.atleast_2d(np.asarray(u, dtype=float))
    seen = _turn(v, rotation_matrix(b[4:7]))
    if turned is not None:
        seen[:, :2] *= np.where(np.asarray(turned, dtype=bool), -1.0, 1.0)[:, None]
    x, y, _ = readings_from_verticals(seen, cfg)
    return (1.0 + b[2]) * x + b[0], (1.0 + b[3]) * y + b[1], v[:, 2] > 0.0


def corrected_verticals(
    inc_x_deg: npt.ArrayLike,
    inc_y_deg: npt.ArrayLike,
    top_face_up: npt.ArrayLike,
    shared: npt.ArrayLike,
    config: InclinometerConfig | None = None,
    turned: npt.ArrayLike | None = None,
) -> Verticals:
    """Body-frame upward verticals from readings of a sensor with shared errors ``shared``.

    The inverse of :func:`sensor_readings`: offsets and sensitivities removed, a turned hang's
    angles negated, eq. 2 in the sensor's axes (the sign of its z from ``top_face_up``), then
    turned into the object's. Within the mounting angle of the horizontal (the object's z and
    the sensor's of opposite signs) two verticals read alike and the one whose sensor z has the
    flag's sign is returned: such a hang is ambiguous (``cadcog estimate`` warns).

    Examples
    --------
    >>> shared = [0.2, -0.1, 0.01, -0.02, 0.3, -0.4, 0.5]
    >>> u = np.array([[0.3, -0.2, (1 - 0.13) ** 0.5]] * 2)
    >>> x, y, top = sensor_readings(u, shared, turned=[False, True])
    >>> back = corrected_verticals(x, y, top, shared, turned=[False, True]).u
    >>> bool(np.allclose(back, u, atol=1e-12))
    True
    """
    b = np.asarray(shared, dtype=float)
    x = (np.atleast_1d(np.asarray(inc_x_deg, dtype=float)) - b[0]) / (1.0 + b[2])
    y = (np.atleast_1d(np.asarray(inc_y_deg, dtype=float)) - b[1]) / (1.0 + b[3])
    if turned is not None:
        flip = np.where(np.asarray(turned, dtype=bool), -1.0, 1.0)
        x, y = x * flip, y * flip
    seen = verticals_from_readings(x, y, top_face_up, config)
    return Verticals(_turn(seen.u, rotation_matrix(b[4:7]).T), seen.normalized)
