"""Smooth analytic end-effector trajectories with exact derivatives, for tests."""

from __future__ import annotations

import numpy as np

from placement.kinematics import TaskTrajectory


def lissajous(t_s: np.ndarray, center_m, amplitude_m, frequency_hz, phase_rad=(0.0, 0.0, 0.0)) -> TaskTrajectory:
    """p_c(t) = center_c + amplitude_c·sin(2π·f_c·t + phase_c) on each axis, with exact derivatives."""
    t = np.asarray(t_s, dtype=float)[:, None]
    w = 2 * np.pi * np.asarray(frequency_hz, dtype=float)
    angle = w * t + np.asarray(phase_rad)
    amplitude = np.asarray(amplitude_m, dtype=float)
    return TaskTrajectory(position_m=np.asarray(center_m) + amplitude * np.sin(angle),
                          velocity_m_s=amplitude * w * np.cos(angle),
                          acceleration_m_s2=-amplitude * w**2 * np.sin(angle))


def orthoglide_path(t_s: np.ndarray) -> TaskTrajectory:
    """A 3-D path of the Orthoglide's platform inside its cube, peak speed about 0.9 m/s."""
    return lissajous(t_s, center_m=(-0.02, -0.03, -0.01), amplitude_m=(0.08, 0.06, 0.05),
                     frequency_hz=(1.1, 1.7, 0.9), phase_rad=(0.3, 1.1, 2.0))
