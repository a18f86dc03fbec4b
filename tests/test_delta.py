"""The Delta (ABB IRB 340 dimensions), solved by the generic closed-loop machinery, proved by physics.

The reference for the kinematics is Williams' closed form ("The Delta Parallel Robot: Kinematics
Solutions", Ohio University, 2016), written here from his equations: for each leg i,
E_i cos(theta_i) + F_i sin(theta_i) + G_i = 0, solved by the tangent half-angle substitution, with
rates and accelerations by differentiating that equation in time. Nothing here uses the
placement kinematics to compute the reference.
"""

import importlib.util
import json
import math
import subprocess
import sys

import numpy as np
import pinocchio as pin
import pytest
from trajectories import lissajous

from placement import Evaluator, EvaluatorSettings, load_path
from placement.dynamics.inverse import inverse_dynamics
from placement.kinematics import joint_trajectory
from placement.robot import load_robot
from placement.robot.catalog import builtin_robots_dir
from placement.robot.checks import energy_rate, forward_accelerations

DELTA_DIR = builtin_robots_dir() / "delta"
CIRCLE = DELTA_DIR.parents[1] / "examples" / "circle.yaml"

# Williams' IRB 340 example (m).
S_B, S_P, L, ROD = 0.567, 0.076, 0.524, 1.244
W_B, W_P, U_P = math.sqrt(3) / 6 * S_B, math.sqrt(3) / 6 * S_P, math.sqrt(3) / 3 * S_P
A, B, C = W_B - U_P, S_P / 2 - math.sqrt(3) / 2 * W_B, W_P - W_B / 2
SQ3 = math.sqrt(3)

TOOL_FORCE_N = np.array([5.0, -8.0, 20.0])
LEG_BODIES = ("arm", "elbow", "rod1", "rod2", "far")  # joints whose bodies are the legs' moving parts


@pytest.fixture
def delta():
    """A freshly loaded Delta (tests may modify its model)."""
    return load_robot("delta")


def platform_path(t_s):
    """A 3-D platform path inside the workspace box, peak speed about 1.7 m/s."""
    return lissajous(t_s, center_m=(0.05, -0.08, -1.0), amplitude_m=(0.25, 0.2, 0.08),
                     frequency_hz=(1.1, 1.7, 0.9), phase_rad=(0.3, 1.1, 2.0))


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


def test_generic_solver_equals_williams_closed_form(delta):
    task = platform_path(np.linspace(0.0, 2.0, 120))
    joints = joint_trajectory(delta, task, "numeric")
    theta, theta_dot, theta_ddot, _ = williams_inverse_kinematics(task.position_m, task.velocity_m_s,
                                                                  task.acceleration_m_s2)
    act = delta.actuated_v_indices
    assert np.ptp(theta, axis=0).min() > 0.3  # the path moves every arm
    np.testing.assert_allclose(joints.q[:, delta.actuated_q_indices], theta, rtol=0, atol=1e-9)
    np.testing.assert_allclose(joints.v[:, act], theta_dot, rtol=0, atol=1e-9)
    np.testing.assert_allclose(joints.a[:, act], theta_ddot, rtol=0, atol=1e-8)


def test_forward_dynamics_reproduces_the_prescribed_accelerations(delta):
    # The welded wrist stubs of legs 2 and 3 carry no inertia; a tiny armature keeps the forward
    # solver's KKT system regular. The same model serves the inverse and the forward computation.
    passive = np.setdiff1d(np.arange(delta.model.nv), delta.actuated_v_indices)
    delta.model.armature[passive] += 1e-9
    task = platform_path(np.linspace(0.0, 2.0, 30))
    load = np.tile(TOOL_FORCE_N, (len(task), 1))
    result = inverse_dynamics(delta, task, load)
    accelerations = forward_accelerations(delta, result.joints, result.effort, load)
    assert np.abs(result.joints.a).max() > 10.0
    assert np.abs(accelerations - result.joints.a).max() <= 1e-8


def test_power_balance_with_gravity_drive_inertia_and_load(delta):
    t = np.linspace(0.0, 2.0, 60)
    task = platform_path(t)
    load = np.tile(TOOL_FORCE_N, (len(t), 1))
    result = inverse_dynamics(delta, task, load)
    power_in = (result.effort * result.velocity).sum(axis=1) + (load * task.velocity_m_s).sum(axis=1)
    peak = np.abs(result.effort * result.velocity).max()
    assert peak > 20.0  # the test path is dynamic enough to mean something
    assert np.abs(power_in - energy_rate(delta, platform_path, t)).max() <= 1e-6 * peak


def lumped_torques_Nm(task, platform_mass_kg, drive_inertia_kg_m2, gravity_m_s2, force_N):
    """Actuator torques of a Delta with massless legs: tau = J^-T (m_p (a - g) - F_ext) + I_m theta_ddot.

    J = dtheta/dp comes from Williams' closed form; by virtual power, tau·theta_dot equals the power
    into the platform mass and the drives' inertia less the external force's.
    """
    _, _, theta_ddot, jacobian = williams_inverse_kinematics(task.position_m, task.velocity_m_s,
                                                             task.acceleration_m_s2)
    platform_force_N = platform_mass_kg * (task.acceleration_m_s2 - gravity_m_s2) - force_N
    transmitted = np.linalg.solve(np.transpose(jacobian, (0, 2, 1)), platform_force_N[..., None])[..., 0]
    return transmitted + drive_inertia_kg_m2 * theta_ddot


def test_massless_legs_equal_the_lumped_analytic_model(delta):
    model = delta.model
    for i in (1, 2, 3):
        for body in LEG_BODIES:
            model.inertias[model.getJointId(f"{body}_{i}")] = pin.Inertia.Zero()
    task = platform_path(np.linspace(0.0, 2.0, 150))
    load = np.tile(TOOL_FORCE_N, (len(task), 1))
    result = inverse_dynamics(delta, task, load)
    lumped = lumped_torques_Nm(task, model.inertias[model.getJointId("wrist_1")].mass,
                               np.array([a.reflected_inertia for a in delta.actuators]), model.gravity.linear, load)
    assert np.abs(result.effort).max() > 10.0
    assert np.abs(result.effort - lumped).max() <= 1e-9 * np.abs(result.effort).max()


def test_real_legs_differ_from_the_lumped_model(delta):
    """The arms and rods weigh: with them the efforts leave the lumped model by newton-metres."""
    model = delta.model
    task = platform_path(np.linspace(0.0, 2.0, 150))
    result = inverse_dynamics(delta, task)
    lumped = lumped_torques_Nm(task, model.inertias[model.getJointId("wrist_1")].mass,
                               np.array([a.reflected_inertia for a in delta.actuators]), model.gravity.linear,
                               np.zeros(3))
    assert np.abs(result.effort - lumped).max() > 1.0


def rotated_120_deg(placement):
    """The placement turned by +120 degrees about the base's vertical axis (leg 1 -> 2 -> 3)."""
    turn = 2 * math.pi / 3
    x, y = placement[0], placement[1]
    return np.array([math.cos(turn) * x - math.sin(turn) * y, math.sin(turn) * x + math.cos(turn) * y,
                     placement[2], placement[3] + turn, placement[4], placement[5]])


def test_a_path_turned_by_120_degrees_costs_the_same_energy_with_the_actuators_permuted(delta):
    evaluator = Evaluator(delta, load_path(CIRCLE), EvaluatorSettings(time_step_s=0.004, workers=1))
    placement = np.array([0.15, -0.10, -1.00, 0.3, 0.0, 0.0])
    energy = evaluator.detail(placement).energy.per_actuator_J
    turned = evaluator.detail(rotated_120_deg(placement)).energy.per_actuator_J
    assert energy.max() > 1.05 * energy.min()  # the placement loads the arms unequally: the permutation shows
    np.testing.assert_allclose(turned, np.roll(energy, 1), rtol=1e-6)


def test_committed_urdf_is_what_the_generator_writes():
    spec = importlib.util.spec_from_file_location("make_urdf", DELTA_DIR / "make_urdf.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert (DELTA_DIR / "delta.urdf").read_text() == module.urdf_text()


def test_the_command_line_places_the_circle_on_the_delta(tmp_path):
    # A small budget (two generations of six, a coarse sampling) runs every stage of the search.
    out = tmp_path / "result.json"
    run = subprocess.run([sys.executable, "-m", "placement", "--robot", "delta", "--path", str(CIRCLE),
                          "--minimize", "--time-step", "0.05", "--generations", "2", "--population", "6",
                          "--quiet", "--json", str(out)], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    best = json.loads(out.read_text())["best"]
    assert best["feasible"] and 0.0 < best["energy_J"] < math.inf
