"""A three-axis accelerometer as the test's sensor: how it sits on the object, what it shares
across the hangs, and its readings → the body-frame vertical.

At rest an accelerometer reads the specific force ``g·u``: gravity's reaction, along the upward
vertical ``u``, in its own axes. It therefore gives the whole vertical (which face is up
included) with no range limit, where a dual-axis inclinometer gives two angles within ±60°.
Readings are in units of standard gravity (g); a log in m/s² is converted where it is read.

How it sits on the object: ``axes = ("+x", "+y", "+z")`` says which object axis each sensor axis
lies along (sensor x, y, z in that order), any signed permutation that is a rotation (a mirror
cannot be mounted). On top of that nominal mounting, the sensor's axes are turned by a small
rotation (``mounting_misalignment_deg``).

The shared parameters (:data:`ACCEL_SHARED_PARAMETERS`, the same on every hang of a test: one
sensor) are each axis's zero offset ``b`` (g), each axis's sensitivity error ``s`` (relative),
the misalignment rotation ``r`` (degrees) and the cross-axis coupling, a symmetric part ``k``
and an antisymmetric part ``w`` (relative). :func:`accel_readings` is their definition: the
sensor sees ``v = R(r) A u`` and reports ``a = (1 + s) ∘ ((I + K + W) v) + b``, with ``K`` the
symmetric matrix of zero diagonal whose ``xy``, ``xz``, ``yz`` entries are ``k`` and ``W`` the
antisymmetric one of the rotation vector ``w``: a datasheet's six couplings within ±c each.
The coupling belongs to the sensor: a hang read with the sensor turned 180° about its own z
axis on its mount (a reversal) sees ``(−vₓ, −v_y, v_z)`` before it, where the mounting ``R``
acts after. (Without a reversal ``W`` and ``R`` act alike, and their priors share them.)

Because the magnitude of a settled reading is 1 g whatever the orientation, every hang also
says something about the offsets and sensitivities independently of the CoG:
``|(a − b)/(1 + s)| = 1`` (:func:`accel_norms`). The estimator uses that (a gravity-norm
calibration, :mod:`cadcog.method.sharedfit`) together with the plumb lines.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from cadcog.core.units import rad_to_deg
from cadcog.rig.inclinometer import Verticals, rotation_matrix

FloatArray = npt.NDArray[np.float64]

#: The shared parameters of an accelerometer, in the order of every vector of them.
ACCEL_SHARED_PARAMETERS = (
    "offset_x_g",
    "offset_y_g",
    "offset_z_g",
    "scale_x_rel",
    "scale_y_rel",
    "scale_z_rel",
    "mounting_x_deg",
    "mounting_y_deg",
    "mounting_z_deg",
    "cross_xy_rel",
    "cross_xz_rel",
    "cross_yz_rel",
    "cross_skew_x_rel",
    "cross_skew_y_rel",
    "cross_skew_z_rel",
)

#: The nominal mounting: sensor x, y, z along object x, y, z.
SQUARE_AXES = ("+x", "+y", "+z")

_AXIS_INDEX = {"x": 0, "y": 1, "z": 2}


def axes_problem(axes: object) -> str | None:
    """What is wrong with a mounting ``axes`` (None when it is a proper signed permutation).

    Examples
    --------
    >>> axes_problem(("-y", "+x", "+z")) is None
    True
    >>> axes_problem(("+x", "+y", "-z")).split(":")[0]
    'a mirror image, which no sensor can be mounted as (its determinant is -1)'
    >>> axes_problem(("+x", "+x", "+z"))
    'each object axis must appear once, got +x, +x, +z'
    """
    if not isinstance(axes, (list, tuple)) or len(axes) != 3:
        return 'expected three signed axes such as ["+x", "+y", "+z"] (sensor x, y, z)'
    for a in axes:
        if not isinstance(a, str) or len(a) != 2 or a[0] not in "+-" or a[1] not in _AXIS_INDEX:
            return f'expected each axis as "+x", "-x", "+y", "-y", "+z" or "-z", got {a!r}'
    if len({a[1] for a in axes}) != 3:
        return f"each object axis must appear once, got {', '.join(axes)}"
    if np.linalg.det(_matrix(tuple(axes))) < 0:
        return (
            "a mirror image, which no sensor can be mounted as (its determinant is -1): flip the "
            "sign of one more axis"
        )
    return None


def _matrix(axes: tuple[str, ...]) -> FloatArray:
    m = np.zeros((3, 3))
    for row, a in enumerate(axes):
        m[row, _AXIS_INDEX[a[1]]] = 1.0 if a[0] == "+" else -1.0
    return m


def axes_matrix(axes: tuple[str, str, str]) -> FloatArray:
    """``A`` with ``v_sensor = A u_object`` for the nominal mounting ``axes``.

    Raises
    ------
    ValueError
        If ``axes`` is not a proper signed permutation (:func:`axes_problem`).

    Examples
    --------
    >>> axes_matrix(("-y", "+x", "+z")) @ [0.0, 1.0, 0.0]  # object +y is sensor −x
    array([-1.,  0.,  0.])
    """
    problem = axes_problem(axes)
    if problem is not None:
        raise ValueError(problem)
    return _matrix(axes)


def _coupling(k: FloatArray, w: FloatArray) -> FloatArray:
    """``I + K + W``: the cross-axis coupling, symmetric ``k`` (xy, xz, yz) and antisymmetric
    ``w`` (a rotation vector, radians)."""
    return np.array(
        [
            [1.0, k[0] - w[2], k[1] + w[1]],
            [k[0] + w[2], 1.0, k[2] - w[0]],
            [k[1] - w[1], k[2] + w[0], 1.0],
        ]
    )


def _flip(turned: npt.ArrayLike | None, k: int) -> FloatArray:
    f = np.ones((k, 3))
    if turned is not None:
        f[:, :2] *= np.where(np.asarray(turned, dtype=bool), -1.0, 1.0)[:, None]
    return f


def accel_readings(
    u: npt.ArrayLike,
    shared: npt.ArrayLike,
    axes: tuple[str, str, str] = SQUARE_AXES,
    turned: npt.ArrayLike | None = None,
) -> FloatArray:
    """What an accelerometer with the shared errors ``shared`` reads at rest for upward
    verticals ``u`` (g, the sensor's axes): the definition of :data:`ACCEL_SHARED_PARAMETERS`.

    Parameters
    ----------
    u : array_like, shape (k, 3)
        Unit upward verticals, object axes.
    shared : array_like, shape (15,)
    axes : tuple of 3 str
    turned : array_like of bool, shape (k,), optional

    Returns
    -------
    ndarray, shape (k, 3)

    Examples
    --------
    >>> a = accel_readings([[0.0, 0.0, 1.0]], [0.01, 0, 0, 0, 0, 0.02] + [0.0] * 9)
    >>> np.round(a, 12).tolist()  # level: z reads 1 g, 2 % high; x its 10 mg offset
    [[0.01, 0.0, 1.02]]
    """
    b = np.asarray(shared, dtype=float)
    v = np.atleast_2d(np.asarray(u, dtype=float))
    rot = rotation_matrix(b[6:9]) @ axes_matrix(axes)
    seen = (v @ rot.T) * _flip(turned, len(v))  # what reaches the sensor, in its axes
    return np.asarray((1.0 + b[3:6]) * (seen @ _coupling(b[9:12], b[12:15]).T) + b[0:3])


def _calibrated(acc: npt.ArrayLike, shared: npt.ArrayLike) -> FloatArray:
    """``(I + K + W)⁻¹ ((a − b)/(1 + s))``: what the sensor saw, in its own (turned) axes."""
    b = np.asarray(shared, dtype=float)
    w = (np.atleast_2d(np.asarray(acc, dtype=float)) - b[0:3]) / (1.0 + b[3:6])
    if not np.any(b[9:15]):
        return np.asarray(w)
    return np.asarray(np.linalg.solve(_coupling(b[9:12], b[12:15]), w.T).T)


def accel_norms(acc: npt.ArrayLike, shared: npt.ArrayLike) -> FloatArray:
    """``|(a − b)/(1 + s)|`` of each reading (g): 1 at rest once the offsets and sensitivities
    are right, whatever the orientation.

    Examples
    --------
    >>> shared = [0.02, -0.01, 0.03, 0.01, -0.02, 0.005, 0, 0, 0, 0.01, -0.02, 0.005, 0.01, 0, 0]
    >>> a = accel_readings([[0.6, 0.0, 0.8], [0.0, -1.0, 0.0]], shared)
    >>> np.round(accel_norms(a, shared), 12).tolist()
    [1.0, 1.0]
    """
    return np.asarray(np.linalg.norm(_calibrated(acc, shared), axis=1))


def accel_verticals(
    acc: npt.ArrayLike,
    shared: npt.ArrayLike,
    axes: tuple[str, str, str] = SQUARE_AXES,
    turned: npt.ArrayLike | None = None,
) -> Verticals:
    """Upward verticals in object axes from accelerometer readings: the inverse of
    :func:`accel_readings` (offsets and sensitivities removed, a turned hang's x and y negated,
    normalised, then turned into the object's axes). Nothing is ever normalised onto a circle
    (``Verticals.normalized`` is all False): the reading is the whole vector.

    Raises
    ------
    ValueError
        If a reading is (nearly) zero once corrected: no direction.

    Examples
    --------
    >>> shared = [0.02, -0.01, 0.03, 0.01, -0.02, 0.005, 0.3, -0.2, 0.5, 0.01, -0.02, 0.005]
    >>> shared += [0.01, -0.005, 0.002]
    >>> u = np.array([[0.3, -0.2, (1 - 0.13) ** 0.5], [0.0, 0.6, -0.8]])
    >>> a = accel_readings(u, shared, ("-y", "+x", "+z"), turned=[False, True])
    >>> back = accel_verticals(a, shared, ("-y", "+x", "+z"), turned=[False, True]).u
    >>> bool(np.allclose(back, u, atol=1e-12))
    True
    """
    b = np.asarray(shared, dtype=float)
    w = _calibrated(acc, b)
    w = w * _flip(turned, len(w))
    norm = np.linalg.norm(w, axis=1)
    if np.any(~(norm > 1e-6)):
        raise ValueError("a reading with no direction (a zero or non-finite acceleration)")
    rot = rotation_matrix(b[6:9]) @ axes_matrix(axes)
    u = (w / norm[:, None]) @ rot
    return Verticals(np.asarray(u), np.zeros(len(u), dtype=bool))


def accel_angles_deg(acc: npt.ArrayLike) -> tuple[FloatArray, FloatArray, npt.NDArray[np.bool_]]:
    """The readings as a dual-axis inclinometer in the sensor's own axes would give them:
    ``X = asin(âₓ)``, ``Y = asin(â_y)`` (degrees) and whether ``â_z > 0`` (``â`` the unit
    reading). For display and the readings file's angle columns; the estimate uses the vector.

    Examples
    --------
    >>> x, y, up = accel_angles_deg([[0.5, 0.0, 0.75**0.5]])
    >>> round(float(x[0]), 9), round(float(y[0]), 9), bool(up[0])
    (30.0, 0.0, True)
    """
    a = np.atleast_2d(np.asarray(acc, dtype=float))
    unit = a / np.linalg.norm(a, axis=1)[:, None]
    x = rad_to_deg(np.arcsin(np.clip(unit[:, 0], -1.0, 1.0)))
    y = rad_to_deg(np.arcsin(np.clip(unit[:, 1], -1.0, 1.0)))
    return np.asarray(x), np.asarray(y), np.asarray(unit[:, 2] > 0.0)


def swing_angles_deg(acc: npt.ArrayLike, axes: tuple[str, str, str]) -> FloatArray:
    """A swing's readings as the swing fit takes them: the samples turned into object axes by
    the nominal mounting ``axes``, then ``X = asin(âₓ)``, ``Y = asin(â_y)`` (degrees, ``â`` the
    unit reading). The swing model (:mod:`cadcog.dynamics.hungbody`) is an accelerometer's: the
    direction of the specific force at the sensing point in object axes. The shared errors
    (offsets, sensitivities, misalignment) move the angles by a fixed amount and scale them by
    about 1 %: the frequencies, which carry the inertia, do not see them.

    Parameters
    ----------
    acc : array_like, shape (n, 3)
        Samples (g or any unit, sensor axes).
    axes : tuple of 3 str
        The mounting (:func:`axes_matrix`).

    Returns
    -------
    ndarray, shape (n, 2)

    Examples
    --------
    >>> swing_angles_deg([[0.0, 0.5, 0.75**0.5]], ("-y", "+x", "+z")).round(9).tolist()
    [[30.0, 0.0]]

    (sensor y lies along object x, and reads half of gravity: the object's +x is tilted 30° up.)
    """
    a = np.atleast_2d(np.asarray(acc, dtype=float)) @ axes_matrix(axes)  # (Aᵀ v)ᵀ = vᵀ A
    x, y, _ = accel_angles_deg(a)
    return np.column_stack([x, y])
