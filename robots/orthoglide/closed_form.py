"""Closed-form kinematics and the lumped analytic dynamic model of the Orthoglide 3-axis.

``make_closed_form(model)`` is the kinematics plug-in named in ``orthoglide.yaml``: it returns
every joint of the spanning tree as a function of the platform position, written with
:mod:`placement.kinematics.taylor` so that joint rates and accelerations come out exactly. In leg i's frame
(x along the slider axis e_i), with the platform at (x, y, z) and S = sqrt(L² - y² - z²):

    slider rho = x + S,   yoke alpha = atan2(z, S),   bar theta = atan2(-y, sqrt(L² - y²)),
    far link -theta,   second bar theta,   wrist -alpha.

``lumped_actuator_forces`` is the textbook lumped-mass model (platform mass on the platform, slider
mass on each slider, legs massless): exact when the legs are massless, an approximation otherwise.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from placement.kinematics import taylor

AXES = "xyz"


def leg_length_m(model: pin.Model) -> float:
    """Leg length L: the bar-1 to far-link joint offset of leg x in the URDF."""
    return float(-model.jointPlacements[model.getJointId("far_x")].translation[0])


def make_closed_form(model: pin.Model):
    """Build the closed-form solver for the Orthoglide URDF ``model``.

    Args:
        model: The Pinocchio model of ``orthoglide.urdf``.

    Returns:
        A function mapping the platform position ``(x, y, z)`` (Taylor2 or arrays, m, base frame)
        to ``{joint name: value}`` for every joint (m or rad).
    """
    length = leg_length_m(model)
    rotations = {axis: model.jointPlacements[model.getJointId(f"slider_{axis}")].rotation for axis in AXES}
    for axis, rotation in rotations.items():
        if not np.allclose(rotation.max(axis=0), 1.0) or np.linalg.det(rotation) < 0:
            raise ValueError(f"leg {axis}: the slider frame must be a cyclic permutation of the base axes")

    # Coordinates of the platform point in leg i's frame: R_iᵀ p, whose coordinate c is the base one legs[i][c]
    # (R_i permutes the axes).
    legs = {axis: [int(np.argmax(np.abs(rotation[:, c]))) for c in range(3)] for axis, rotation in rotations.items()}

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
