"""The tool's compliance (placement.stiffness) proven by physics: the Orthoglide's analytic stiffness k_a·JᵀJ, the
full nonlinear static equilibrium of every robot's springs (tests/support/static_equilibrium.py) under small loads,
and a closed-loop machine with a single leg against the serial formula."""

import numpy as np
import pytest

from placement import TaskTrajectory, load_robot
from placement.kinematics import joint_trajectory
from placement.stiffness import JointSprings, joint_springs, tool_compliance, tool_deflection
from placement.workshop.checks import demo_trajectory
from tests.support.static_equilibrium import settle

L_M = 0.2 / (1 / np.sqrt(6) + 1 / np.sqrt(18))  # the Orthoglide's leg length (robots/orthoglide/README.md)
EQUILIBRIUM_RELATIVE = 1e-6  # linear compliance against the nonlinear equilibrium's response to small loads


def orthoglide_jacobian(p: np.ndarray) -> np.ndarray:
    """J with ρ̇ = J·ṗ from the inverse kinematics ρ_i = p_i + sqrt(L² − p_j² − p_k²) (parameters.md), by hand."""
    x, y, z = p
    s = np.sqrt(L_M**2 - np.array([y * y + z * z, x * x + z * z, x * x + y * y]))
    return np.array([[1, -y / s[0], -z / s[0]], [-x / s[1], 1, -z / s[1]], [-x / s[2], -y / s[2], 1]])


def still_at(points_m: np.ndarray) -> TaskTrajectory:
    zero = np.zeros_like(points_m)
    return TaskTrajectory(points_m, zero, zero)


@pytest.fixture(scope="module")
def orthoglide():
    return load_robot("orthoglide")


def orthoglide_compliance(robot, points_m):
    joints = joint_trajectory(robot, still_at(np.atleast_2d(points_m)))
    return tool_compliance(joint_springs(robot), joints)


def test_orthoglide_stiffness_is_k_a_times_JtJ_at_its_named_points(orthoglide):
    """k_a·I at the isotropic point O_b; at Q⁺ (transmission factor 1/2 along the diagonal) the diagonal eigenvalue
    is k_a/4, at Q⁻ (factor 2 across it) the two across are k_a/4; k_a·δ for the paper's force (stiffness.md)."""
    k_a = orthoglide.actuators[0].stiffness
    points = orthoglide.workspace.points_m
    diagonal = np.ones(3) / np.sqrt(3)
    stiffness = np.linalg.inv(orthoglide_compliance(orthoglide, np.array([points["O_b"], points["Q_plus"],
                                                                           points["Q_minus"]])))
    np.testing.assert_allclose(stiffness[0], k_a * np.eye(3), rtol=1e-12, atol=1e-12 * k_a)
    plus, minus = stiffness[1] / k_a, stiffness[2] / k_a
    np.testing.assert_allclose(diagonal @ plus @ diagonal, 0.25, rtol=1e-9)
    np.testing.assert_allclose(np.linalg.eigvalsh(plus), [0.25, 1.5625, 1.5625], rtol=1e-9)
    np.testing.assert_allclose(diagonal @ minus @ diagonal, 4.0, rtol=1e-9)
    np.testing.assert_allclose(np.linalg.eigvalsh(minus), [0.25, 0.25, 4.0], rtol=1e-9)
    force = np.array([10.0, 215.0, 25.0])
    np.testing.assert_allclose(k_a * np.linalg.inv(stiffness[1:]) @ force,
                               [[286.4, 417.6, 296.0], [-272.5, 547.5, -212.5]], atol=0.05)


def test_orthoglide_stiffness_is_k_a_times_JtJ_throughout_its_cube(orthoglide):
    points = np.random.default_rng(7).uniform(orthoglide.workspace.min_m, orthoglide.workspace.max_m, (40, 3))
    k_a = orthoglide.actuators[0].stiffness
    expected = np.array([k_a * orthoglide_jacobian(p).T @ orthoglide_jacobian(p) for p in points])
    np.testing.assert_allclose(np.linalg.inv(orthoglide_compliance(orthoglide, points)), expected, rtol=1e-9)


def test_the_deflection_is_the_compliance_times_the_load(orthoglide):
    """δ = T·K⁻¹·Tᵀ·w without forming C equals C·w, with and without a passive spring."""
    joints = joint_trajectory(orthoglide, still_at(np.array([[0.03, -0.05, 0.02], [-0.1, 0.04, 0.06]])))
    load = np.array([[10.0, 215.0, 25.0], [-40.0, 3.0, 120.0]])
    for springs in (joint_springs(orthoglide), _with_passive_spring(orthoglide)):
        np.testing.assert_allclose(tool_deflection(springs, joints, load),
                                   np.einsum("nij,nj->ni", tool_compliance(springs, joints), load), rtol=1e-12)


def _with_passive_spring(robot, joint="bar1_x", stiffness=2.0e6) -> JointSprings:
    """The robot's springs plus one on a passive joint (N·m/rad)."""
    springs = joint_springs(robot)
    v = robot.model.joints[robot.model.getJointId(joint)].idx_v
    return JointSprings(springs.actuator_stiffness, np.array([v]), np.array([stiffness]))


def _springs_of(robot) -> JointSprings:
    """The sidecar's springs, or for a robot that gives none (five-bar, Delta) stated test ones (N/m, N·m/rad)."""
    if all(a.stiffness is not None for a in robot.actuators):
        return joint_springs(robot)
    values = [3.0e6 if a.prismatic else 2.0e4 * (1 + i) for i, a in enumerate(robot.actuators)]
    return JointSprings(np.array(values), np.zeros(0, dtype=int), np.zeros(0))


def _equilibrium_compliance(robot, joints, springs: JointSprings, scale_N: float) -> np.ndarray:
    """(d, d) the columns (δ(+ε·e_j) − δ(−ε·e_j))/(2ε) of the nonlinear equilibrium at the trajectory's first
    sample: the loads' second-order effects cancel, so they differ from C by O(ε²)."""
    by_v = dict(zip(joints_v(robot), springs.actuator_stiffness))
    by_v.update(zip(springs.passive_v_indices.tolist(), springs.passive_stiffness))
    dimension = joints.task_map.shape[1]
    loads = np.eye(dimension) * scale_N
    return np.column_stack([(settle(robot, joints.q[0], by_v, w) - settle(robot, joints.q[0], by_v, -w)) / (2 * scale_N)
                            for w in loads])


def joints_v(robot):
    return [a.v_index for a in robot.actuators]


@pytest.mark.parametrize("name", ["orthoglide", "ur5", "panda", "fivebar", "delta"])
def test_compliance_is_the_nonlinear_equilibrium_response_to_small_loads(name):
    """Every robot, at a posture off its reference: C equals the finite-difference response of the full nonlinear
    static equilibrium, 1e-6 relative (loads that move the tool about a micrometre; moments too for a pose task)."""
    robot = load_robot(name)
    joints = joint_trajectory(robot, demo_trajectory(robot)(np.array([0.13, 0.2])))
    springs = _springs_of(robot)
    compliance = tool_compliance(springs, joints)[0]
    scale = 1e-6 / np.abs(compliance[:3, :3]).max()  # N (and N·m): about 1 µm
    measured = _equilibrium_compliance(robot, joints, springs, scale)
    assert np.abs(measured - compliance).max() <= EQUILIBRIUM_RELATIVE * np.abs(compliance).max()


def test_a_passive_spring_is_the_nonlinear_equilibrium_response_too(orthoglide):
    """The Orthoglide with a spring on a passive joint of a leg (K_ρ = diag(k_a) + Gₚᵀ·k_p·Gₚ): the same check."""
    joints = joint_trajectory(orthoglide, still_at(np.array([[0.03, -0.05, 0.02]])))
    springs = _with_passive_spring(orthoglide)
    compliance = tool_compliance(springs, joints)[0]
    assert np.abs(compliance - tool_compliance(joint_springs(orthoglide), joints)[0]).max() > 0.01 * np.abs(
        compliance).max()  # the spring matters
    measured = _equilibrium_compliance(orthoglide, joints, springs, 1e-6 / np.abs(compliance).max())
    assert np.abs(measured - compliance).max() <= EQUILIBRIUM_RELATIVE * np.abs(compliance).max()
