"""Independent analytic model of the Delta (``robots/delta``, ABB IRB 340 dimensions).

The reference for the kinematics is Williams' closed form ("The Delta Parallel Robot: Kinematics
Solutions", Ohio University, 2016), written here from his equations: for each leg i,
E_i cos(theta_i) + F_i sin(theta_i) + G_i = 0, solved by the tangent half-angle substitution, with
rates and accelerations by differentiating that equation in time. Nothing here uses pinocchio or
the placement kinematics, so it can check them.
"""

import math

import numpy as np

# Williams' IRB 340 example (m).
S_B, S_P, L, ROD = 0.567, 0.076, 0.524, 1.244
W_B, W_P, U_P = math.sqrt(3) / 6 * S_B, math.sqrt(3) / 6 * S_P, math.sqrt(3) / 3 * S_P
A, B, C = W_B - U_P, S_P / 2 - math.sqrt(3) / 2 * W_B, W_P - W_B / 2
SQ3 = math.sqrt(3)

LEG_BODIES = ("arm", "elbow", "rod1", "rod2", "far")  # joints whose bodies are the legs' moving parts (suffix _1.._3)


def williams_coefficients(p):
    """Williams' E_i, F_i, G_i (N, 3) and their gradients dE/dp, dF/dp, dG/dp (N, 3 legs, 3 axes)."""
    x, y, z = p.T
    r2 = x * x + y * y + z * z
    e = np.stack([2 * L * (y + A), -L * (SQ3 * (x + B) + y + C), L * (SQ3 * (x - B) - y - C)], axis=1)
    f = np.stack([2 * z * L] * 3, axis=1)
    g = np.stack([r2 + A**2 + L**2 + 2 * y * A - ROD**2,
                  r2 + B**2 + C**2 + L**2 + 2 * (x * B + y * C) - ROD**2,
                  r2 + B**2 + C**2 + L**2 + 2 * (-x * B + y * C) - ROD**2], axis=1)
    de = np.broadcast_to(np.array([[0, 2 * L, 0], [-SQ3 * L, -L, 0], [SQ3 * L, -L, 0]]), (len(p), 3, 3))
    df = np.broadcast_to(np.array([0, 0, 2 * L]), (len(p), 3, 3))
    offsets = np.array([[0, A, 0], [B, C, 0], [-B, C, 0]])
    dg = 2 * (p[:, None, :] + offsets)
    return e, f, g, de, df, dg


def williams_inverse_kinematics(position_m, velocity_m_s, acceleration_m_s2):
    """Actuated angles (rad), their rates and accelerations, and dtheta/dp, by Williams' closed form.

    Args:
        position_m, velocity_m_s, acceleration_m_s2: (N, 3) platform centre motion, base frame.

    Returns:
        theta (N, 3) rad with the knees out, theta_dot (N, 3) rad/s, theta_ddot (N, 3) rad/s²,
        and the Jacobian dtheta/dp (N, 3, 3) rad/m.
    """
    p, v, a = position_m, velocity_m_s, acceleration_m_s2
    e, f, g, de, df, dg = williams_coefficients(p)
    theta = 2 * np.arctan((-f - np.sqrt(e * e + f * f - g * g)) / (g - e))
    c, s = np.cos(theta), np.sin(theta)
    f_theta = -e * s + f * c
    f_p = de * c[..., None] + df * s[..., None] + dg
    jacobian = -f_p / f_theta[..., None]
    theta_dot = np.einsum("nij,nj->ni", jacobian, v)
    f_theta_theta = -e * c - f * s
    f_theta_p = -de * s[..., None] + df * c[..., None]
    curvature = (f_theta_theta * theta_dot**2 + 2 * np.einsum("nij,nj->ni", f_theta_p, v) * theta_dot
                 + 2 * (v * v).sum(axis=1)[:, None] + np.einsum("nij,nj->ni", f_p, a))
    return theta, theta_dot, -curvature / f_theta, jacobian


def lumped_torques_Nm(task, platform_mass_kg, drive_inertia_kg_m2, gravity_m_s2, force_N):
    """Actuator torques of a Delta with massless legs: tau = J^-T (m_p (a - g) - F_ext) + I_m theta_ddot.

    J = dtheta/dp comes from Williams' closed form; by virtual power, tau·theta_dot equals the power
    into the platform mass and the drives' inertia less the external force's.

    Args:
        task: Platform centre motion (a :class:`placement.kinematics.TaskTrajectory`), base frame.
        platform_mass_kg: Mass of the platform (with whatever it carries).
        drive_inertia_kg_m2: (3,) drive inertia reflected at each actuated joint.
        gravity_m_s2: (3,) gravity in the base frame.
        force_N: (N, 3) or (3,) force the environment applies on the platform.

    Returns:
        (N, 3) torques in N·m.
    """
    _, _, theta_ddot, jacobian = williams_inverse_kinematics(task.position_m, task.velocity_m_s,
                                                             task.acceleration_m_s2)
    platform_force_N = platform_mass_kg * (task.acceleration_m_s2 - gravity_m_s2) - force_N
    transmitted = np.linalg.solve(np.transpose(jacobian, (0, 2, 1)), platform_force_N[..., None])[..., 0]
    return transmitted + drive_inertia_kg_m2 * theta_ddot
