"""Closed-form kinematics and the lumped analytic dynamic model of the Orthoglide 3-axis.

``make_closed_form(model)`` is the kinematics plug-in named in ``orthoglide.yaml``: it returns
every joint of the spanning tree as a function of the platform position, written with
:mod:`placement.kinematics.taylor` so that joint rates and accelerations come out exactly. In leg i's frame
(x along the slider axis e_i), with the platform at (x, y, z) and S = sqrt(L² - y² - z²):

    slider rho = x + S,   yoke alpha = atan2(z, S),   bar theta = atan2(-y, sqrt(L² - y²)),
    far link -theta,   second bar theta,   wrist -alpha.

``make_compiled_closed_form(model)`` is the same solver compiled (numba) over samples: the same operations in
the same order as the Taylor arithmetic, so that it gives the same numbers bit for bit, in one pass instead of
some 60 numpy operations over every sample.

``lumped_actuator_forces`` is the textbook lumped-mass model (platform mass on the platform, slider
mass on each slider, legs massless): exact when the legs are massless, an approximation otherwise.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from numba import njit

from placement.kinematics import taylor

AXES = "xyz"
LEG_JOINTS = ("slider", "yoke", "bar1", "bar2", "far", "wrist")  # each leg's joints, in the compiled solver's order


def leg_length_m(model: pin.Model) -> float:
    """Leg length L: the bar-1 to far-link joint offset of leg x in the URDF."""
    return float(-model.jointPlacements[model.getJointId("far_x")].translation[0])


def _legs(model: pin.Model) -> dict[str, list[int]]:
    """For each leg, the base coordinate of each of its frame's coordinates: leg i's coordinate c of the platform
    point R_iᵀ p is the base one ``legs[i][c]`` (R_i permutes the axes)."""
    rotations = {axis: model.jointPlacements[model.getJointId(f"slider_{axis}")].rotation for axis in AXES}
    for axis, rotation in rotations.items():
        if not np.allclose(rotation.max(axis=0), 1.0) or np.linalg.det(rotation) < 0:
            raise ValueError(f"leg {axis}: the slider frame must be a cyclic permutation of the base axes")
    return {axis: [int(np.argmax(np.abs(rotation[:, c]))) for c in range(3)] for axis, rotation in rotations.items()}


def make_closed_form(model: pin.Model):
    """Build the closed-form solver for the Orthoglide URDF ``model``.

    Args:
        model: The Pinocchio model of ``orthoglide.urdf``.

    Returns:
        A function mapping the platform position ``(x, y, z)`` (Taylor2 or arrays, m, base frame)
        to ``{joint name: value}`` for every joint (m or rad).
    """
    length = leg_length_m(model)
    legs = _legs(model)

    def solve(position):
        joints = {}
        for axis in AXES:
            x, y, z = (position[i] for i in legs[axis])
            reach = taylor.sqrt(length**2 - y * y - z * z)
            alpha = taylor.arctan2(z, reach)
            theta = taylor.arctan2(-y, taylor.sqrt(length**2 - y * y))
            joints.update({f"slider_{axis}": x + reach, f"yoke_{axis}": alpha, f"bar1_{axis}": theta,
                           f"bar2_{axis}": theta, f"far_{axis}": -theta, f"wrist_{axis}": -alpha})
        return joints

    return solve


def make_compiled_closed_form(model: pin.Model):
    """Build the compiled closed-form solver for the Orthoglide URDF ``model``: :func:`make_closed_form`'s,
    bit for bit, over many samples at once.

    Args:
        model: The Pinocchio model of ``orthoglide.urdf``.

    Returns:
        A function mapping (N, 3) platform positions (m), velocities (m/s) and accelerations (m/s²) in the base
        frame to the joints' names (J,) and their values (N, J) (m or rad), rates (N, J), accelerations (N, J) and
        gradients (N, J, 3) by the platform position (m/m or rad/m).
    """
    square_m2 = leg_length_m(model) ** 2
    legs = _legs(model)
    coordinates = np.array([legs[axis] for axis in AXES], dtype=np.int64)
    names = tuple(f"{joint}_{axis}" for axis in AXES for joint in LEG_JOINTS)

    def solve(position_m: np.ndarray, velocity_m_s: np.ndarray, acceleration_m_s2: np.ndarray):
        n = len(position_m)
        value, rate = np.empty((n, len(names))), np.empty((n, len(names)))
        acceleration, gradient = np.empty((n, len(names))), np.empty((n, len(names), 3))
        # The angles' arc tangents are numpy's, as the Taylor arithmetic's (its vectorised arctan2 can differ from
        # the C library's by an ulp): the kernel gives their arguments, (n, 3 legs, 2 angles) each.
        above, beside = np.empty((n, 3, 2)), np.empty((n, 3, 2))
        _legs_kernel(np.ascontiguousarray(position_m, dtype=float), np.ascontiguousarray(velocity_m_s, dtype=float),
                     np.ascontiguousarray(acceleration_m_s2, dtype=float), square_m2, coordinates,
                     value, rate, acceleration, gradient, above, beside)
        angles = np.arctan2(above, beside)  # yoke alpha, bar theta of each leg
        legs_values = value.reshape(n, 3, len(LEG_JOINTS))
        legs_values[:, :, 1], legs_values[:, :, 2], legs_values[:, :, 3] = angles[..., 0], angles[..., 1], angles[..., 1]
        legs_values[:, :, 4], legs_values[:, :, 5] = -angles[..., 1], -angles[..., 0]
        return names, value, rate, acceleration, gradient

    return solve


# The Taylor arithmetic of :mod:`placement.kinematics.taylor` on one sample: a quantity is (value, time derivative,
# its gradient by the platform's x, y, z, second time derivative); each operation as there, term for term.

@njit(error_model="numpy")
def _coordinate(position, velocity, acceleration, k, b):
    """Base coordinate ``b`` of the platform at sample ``k``: its gradient is the unit vector e_b."""
    return (position[k, b], velocity[k, b], 1.0 if b == 0 else 0.0, 1.0 if b == 1 else 0.0, 1.0 if b == 2 else 0.0,
            acceleration[k, b])


@njit(error_model="numpy")
def _product(a, b):
    return (a[0] * b[0], a[1] * b[0] + a[0] * b[1], a[2] * b[0] + a[0] * b[2], a[3] * b[0] + a[0] * b[3],
            a[4] * b[0] + a[0] * b[4], a[5] * b[0] + 2.0 * a[1] * b[1] + a[0] * b[5])


@njit(error_model="numpy")
def _difference(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3], a[4] - b[4], a[5] - b[5])


@njit(error_model="numpy")
def _from_constant(constant, a):
    """``constant - a``."""
    return (constant - a[0], -a[1], -a[2], -a[3], -a[4], -a[5])


@njit(error_model="numpy")
def _sqrt(a):
    c0 = np.sqrt(a[0])
    c1 = a[1] / (2.0 * c0)
    return (c0, c1, a[2] / (2.0 * c0), a[3] / (2.0 * c0), a[4] / (2.0 * c0), (a[5] - 2.0 * c1 * c1) / (2.0 * c0))


@njit(error_model="numpy")
def _arctan2_rates(y, x):
    """The arc tangent's derivatives (its value is left to numpy: see ``make_compiled_closed_form``)."""
    r2 = x[0] * x[0] + y[0] * y[0]
    c1 = (x[0] * y[1] - y[0] * x[1]) / r2
    c2 = (x[0] * y[5] - y[0] * x[5]) / r2 - 2.0 * c1 * (x[0] * x[1] + y[0] * y[1]) / r2
    return (c1, (x[0] * y[2] - y[0] * x[2]) / r2, (x[0] * y[3] - y[0] * x[3]) / r2,
            (x[0] * y[4] - y[0] * x[4]) / r2, c2)


@njit(cache=True, error_model="numpy")
def _legs_kernel(position, velocity, acceleration, square, coordinates, value, rate, second, gradient, above, beside):
    """Every leg's joints at every sample (module docstring), into ``value`` (but the angles' values: their arc
    tangents' arguments into ``above`` and ``beside``), ``rate``, ``second`` and ``gradient``."""
    for k in range(len(position)):
        for leg in range(3):
            x = _coordinate(position, velocity, acceleration, k, coordinates[leg, 0])
            y = _coordinate(position, velocity, acceleration, k, coordinates[leg, 1])
            z = _coordinate(position, velocity, acceleration, k, coordinates[leg, 2])
            y2 = _product(y, y)
            reach = _sqrt(_difference(_from_constant(square, y2), _product(z, z)))
            alpha = _arctan2_rates(z, reach)
            minus_y = (-y[0], -y[1], -y[2], -y[3], -y[4], -y[5])
            bar_reach = _sqrt(_from_constant(square, y2))
            theta = _arctan2_rates(minus_y, bar_reach)
            above[k, leg, 0], beside[k, leg, 0], above[k, leg, 1], beside[k, leg, 1] = z[0], reach[0], -y[0], bar_reach[0]
            j = 6 * leg
            value[k, j] = x[0] + reach[0]
            rate[k, j], second[k, j] = x[1] + reach[1], x[5] + reach[5]
            for c in range(3):
                gradient[k, j, c] = x[2 + c] + reach[2 + c]
            for offset, angle, sign in ((1, alpha, 1.0), (2, theta, 1.0), (3, theta, 1.0), (4, theta, -1.0),
                                        (5, alpha, -1.0)):
                rate[k, j + offset], second[k, j + offset] = sign * angle[0], sign * angle[4]
                for c in range(3):
                    gradient[k, j + offset, c] = sign * angle[1 + c]


def jacobian(position_m: np.ndarray, length_m: float) -> np.ndarray:
    """Jacobian rhodot = J·pdot, (N, 3, 3): J[i] = e_iᵀ - (p_j/S_i) for j != i.

    Args:
        position_m: (N, 3) platform positions in the base frame.
        length_m: Leg length L.
    """
    p = np.atleast_2d(position_m)
    reach = np.sqrt(length_m**2 - (p**2).sum(axis=1, keepdims=True) + p**2)  # S_i, (N, 3)
    result = -p[:, None, :] / reach[:, :, None]
    result[:, np.arange(3), np.arange(3)] = 1.0
    return result


def slider_motion(position_m: np.ndarray, velocity_m_s: np.ndarray, acceleration_m_s2: np.ndarray,
                  length_m: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Slider positions (m), velocities (m/s) and accelerations (m/s²), each (N, 3), analytically.

    rho_i = p_i + S_i with S_i = sqrt(L² - p_j² - p_k²) over the two other axes j, k.
    """
    p, v, a = (np.atleast_2d(x) for x in (position_m, velocity_m_s, acceleration_m_s2))
    others = [[1, 2], [2, 0], [0, 1]]
    reach = np.sqrt(length_m**2 - np.stack([(p[:, o] ** 2).sum(axis=1) for o in others], axis=1))
    reach_rate = -np.stack([(p[:, o] * v[:, o]).sum(axis=1) for o in others], axis=1) / reach
    reach_acc = (-np.stack([(v[:, o] ** 2 + p[:, o] * a[:, o]).sum(axis=1) for o in others], axis=1)
                 - reach_rate**2) / reach
    return p + reach, v + reach_rate, a + reach_acc


def lumped_actuator_forces(position_m: np.ndarray, velocity_m_s: np.ndarray, acceleration_m_s2: np.ndarray,
                           length_m: float, platform_mass_kg: float, slider_mass_kg: float,
                           slider_inertia_kg: float, gravity_m_s2: np.ndarray,
                           external_force_N: np.ndarray | None = None) -> np.ndarray:
    """Slider forces (N, 3) of the lumped model, in newtons.

    F = J⁻ᵀ·(m_p·(a - g) - F_ext) + (m_s + m_rotor)·rhoddot - m_s·g_i, where F_ext is the force
    on the platform from the environment and m_rotor the reflected rotor and screw inertia.
    """
    platform = platform_mass_kg * (acceleration_m_s2 - gravity_m_s2)
    if external_force_N is not None:
        platform = platform - external_force_N
    transmitted = np.linalg.solve(np.transpose(jacobian(position_m, length_m), (0, 2, 1)), platform[..., None])[..., 0]
    slider_acceleration = slider_motion(position_m, velocity_m_s, acceleration_m_s2, length_m)[2]
    return (transmitted + (slider_mass_kg + slider_inertia_kg) * slider_acceleration
            - slider_mass_kg * np.asarray(gravity_m_s2))
