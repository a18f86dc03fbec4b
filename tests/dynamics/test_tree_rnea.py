"""The compiled Newton–Euler passes (placement.dynamics.tree_rnea) are Pinocchio's RNEA: at every state,
joint_torques(q, v, a) = rnea(q, v, a), and the path dynamics' C = rnea(q, 0, 0), C + A = rnea(q, 0, q') and
C + B = rnea(q, q', q''), on the robots and on random trees of every joint kind they take, over several blocks of
samples, times any basis; a tree they do not take goes to Pinocchio, and both routes give the same efforts."""

import numpy as np
import pinocchio as pin
import pytest

from placement import load_robot
from placement.dynamics import inverse as inverse_module
from placement.dynamics.inverse import actuator_efforts
from placement.dynamics.path_dynamics import path_dynamics
from placement.dynamics.tree_rnea import BLOCK, _sine_versine, joint_torques, path_torques, tree_inertias
from placement.kinematics import joint_trajectory
from tests.support.trajectories import orthoglide_path

JOINT_KINDS = (pin.JointModelRX, pin.JointModelRY, pin.JointModelRZ, pin.JointModelPX, pin.JointModelPY,
               pin.JointModelPZ, "revolute unaligned", "prismatic unaligned")


def random_tree(rng: np.random.Generator, joints: int = 12) -> pin.Model:
    """A branching tree of every joint kind, at random placements, with random inertias and armatures."""
    model = pin.Model()
    for j in range(1, joints + 1):
        kind = JOINT_KINDS[j % len(JOINT_KINDS)]
        if isinstance(kind, str):
            axis = rng.standard_normal(3)
            axis /= np.linalg.norm(axis)
            joint = (pin.JointModelRevoluteUnaligned if kind.startswith("revolute") else pin.JointModelPrismaticUnaligned)(axis)
        else:
            joint = kind()
        parent = int(rng.integers(0, j))
        added = model.addJoint(parent, joint, pin.SE3(pin.exp3(rng.standard_normal(3)), rng.standard_normal(3) * 0.3),
                               f"joint_{j}")
        model.appendBodyToJoint(added, pin.Inertia.Random(), pin.SE3.Identity())
    model.armature = rng.uniform(0.0, 2.0, model.nv)
    return model


def identities(model: pin.Model, n: int) -> np.ndarray:
    """(n, nv, nv) identity bases: the kernels' torques themselves."""
    return np.ascontiguousarray(np.broadcast_to(np.eye(model.nv), (n, model.nv, model.nv)))


def random_states(model: pin.Model, rng: np.random.Generator, n: int) -> tuple[np.ndarray, ...]:
    return rng.uniform(-np.pi, np.pi, (n, model.nq)), rng.standard_normal((n, model.nv)), rng.standard_normal((n, model.nv))


def assert_pinocchios(model: pin.Model, q: np.ndarray, rate: np.ndarray, curvature: np.ndarray) -> None:
    tree = tree_inertias(model)
    assert tree is not None
    identity = identities(model, len(q))
    torques, moving = path_torques(tree, q, rate, curvature, identity), joint_torques(tree, q, rate, curvature, identity)
    data, rest = model.createData(), np.zeros(model.nv)
    for n in range(len(q)):
        wanted = [pin.rnea(model, data, q[n], rest, rest).copy(), pin.rnea(model, data, q[n], rest, rate[n]).copy(),
                  pin.rnea(model, data, q[n], rate[n], curvature[n]).copy()]
        got = [torques[n, 0], torques[n, 0] + torques[n, 1], torques[n, 0] + torques[n, 2]]
        wanted.append(wanted[2])
        got.append(moving[n])
        scale = max(1.0, max(np.abs(w).max() for w in wanted))
        for found, want in zip(got, wanted):
            np.testing.assert_allclose(found, want, rtol=0.0, atol=1e-12 * scale)


@pytest.mark.parametrize("name", ["orthoglide", "ur5", "delta", "fivebar", "panda"])
def test_the_three_torques_of_a_robot_are_pinocchios(name):
    """Random states of the robot (its drives' armature included), over two and a half blocks: the torques to 1e-12
    of the largest."""
    model = load_robot(name).model
    assert model.armature.any()
    assert_pinocchios(model, *random_states(model, np.random.default_rng(7), 5 * BLOCK // 2))


def test_the_three_torques_of_a_random_tree_of_every_joint_kind_are_pinocchios():
    """Aligned and unaligned revolute and prismatic joints, in branches, at random placements."""
    rng = np.random.default_rng(11)
    for _ in range(5):
        model = random_tree(rng)
        assert_pinocchios(model, *random_states(model, rng, 30))


def test_threads_share_the_samples_without_changing_a_torque():
    model = load_robot("ur5").model
    tree = tree_inertias(model)
    assert tree is not None
    states = random_states(model, np.random.default_rng(5), 3 * BLOCK + 5)
    identity = identities(model, len(states[0]))
    np.testing.assert_array_equal(path_torques(tree, *states, identity, threads=3), path_torques(tree, *states, identity))
    np.testing.assert_array_equal(joint_torques(tree, *states, identity, threads=3),
                                  joint_torques(tree, *states, identity))


def test_the_torques_times_a_basis_are_its_projection():
    """A random (N, nv, 2) basis: the kernels' products equal their torques' times it, to 1e-12 of the largest."""
    model = load_robot("orthoglide").model
    tree = tree_inertias(model)
    assert tree is not None
    rng = np.random.default_rng(9)
    states = random_states(model, rng, 2 * BLOCK + 3)
    basis, identity = rng.standard_normal((len(states[0]), model.nv, 2)), identities(model, len(states[0]))
    for kernel in (joint_torques, path_torques):
        want = np.einsum("n...v,nvc->n...c", kernel(tree, *states, identity), basis)
        np.testing.assert_allclose(kernel(tree, *states, basis), want, rtol=0.0, atol=1e-12 * np.abs(want).max())


def test_a_tree_with_another_joint_kind_is_left_to_pinocchio():
    model = pin.Model()
    model.addJoint(0, pin.JointModelSpherical(), pin.SE3.Identity(), "ball")
    assert tree_inertias(model) is None


def test_pinocchios_route_gives_the_same_efforts(orthoglide, monkeypatch):
    """The Orthoglide along a path under a load: its actuator efforts, and A, B and C, through the compiled passes
    and through batched RNEA calls agree to 1e-12 of the largest."""
    joints = joint_trajectory(orthoglide, orthoglide_path(np.linspace(0.0, 1.0, 120)))
    force = np.random.default_rng(2).normal(0.0, 50.0, (len(joints), 3))
    compiled, efforts = path_dynamics(orthoglide, joints, force, 2), actuator_efforts(orthoglide, joints, force)
    monkeypatch.setattr(inverse_module, "tree_inertias", lambda model: None)
    pinocchio = path_dynamics(orthoglide, joints, force, 2)
    np.testing.assert_allclose(efforts, actuator_efforts(orthoglide, joints, force), rtol=0.0,
                               atol=1e-12 * np.abs(efforts).max())
    for name in ("inertia", "centripetal", "static"):
        want = getattr(pinocchio, name)
        np.testing.assert_allclose(getattr(compiled, name), want, rtol=0.0, atol=1e-12 * np.abs(want).max())
    assert np.abs(compiled.inertia).max() > 1.0 and np.abs(compiled.centripetal).max() > 1.0


def test_the_path_dynamics_keep_each_placement_s_samples_and_lay_each_actuator_out_along_them(orthoglide):
    """Sample n of placement k is row k·N + n of the joints' motion and of the compiled pass's torques, and each
    actuator's (K, N) numbers are contiguous (numpy's loops on them then run along the samples)."""
    joints = joint_trajectory(orthoglide, orthoglide_path(np.linspace(0.0, 1.0, 120)))
    dynamics = path_dynamics(orthoglide, joints, np.zeros((len(joints), 3)), 3)
    torques = path_torques(tree_inertias(orthoglide.model), joints.q, joints.v, joints.a, joints.basis)
    act, shape = orthoglide.actuated_v_indices, (3, 40, 3)
    for name, want in (("velocity", joints.v[:, act]), ("curvature", joints.a[:, act]), ("static", torques[:, 0]),
                       ("inertia", torques[:, 1]), ("centripetal", torques[:, 2])):
        values = getattr(dynamics, name)
        np.testing.assert_array_equal(values, want.reshape(shape), err_msg=name)
        assert all(values[..., column].flags.c_contiguous for column in range(3)), name


def test_the_sine_and_versine_are_the_c_librarys_to_two_units_in_the_last_place():
    """Random angles to 1e5 rad, the quadrants' edges (multiples of π/4) and tiny angles: sin within 2 ulp of
    numpy's (or 4e-30, where it is as small as sin(k·π) of a float near k·π), 1 − cos within 2.3e-16."""
    rng = np.random.default_rng(3)
    angles = np.concatenate([rng.uniform(-1e5, 1e5, 4000), rng.uniform(-7.0, 7.0, 4000),
                             np.arange(-64, 65) * np.pi / 4, [0.0, 1e-300, -1e-20, 1e-8]])
    sine, versine = np.array([_sine_versine(angle) for angle in angles]).T
    np.testing.assert_array_less(np.abs(sine - np.sin(angles)), 2.01 * np.spacing(np.abs(np.sin(angles))) + 4e-30)
    np.testing.assert_array_less(np.abs(versine - (1.0 - np.cos(angles))), 2.3e-16)


def test_a_serial_arm_s_efforts_are_pinocchios_and_a_closed_loop_robot_s_compiled():
    """The UR5's six joints take Pinocchio's RNEA (bit for bit its projection), the Orthoglide's eighteen the
    compiled pass (TreeDynamics.compiled_efforts)."""
    from placement.dynamics.inverse import TreeDynamics, rnea_batch

    arm, legs = TreeDynamics(load_robot("ur5").model), TreeDynamics(load_robot("orthoglide").model)
    assert not arm.compiled_efforts and legs.compiled_efforts
    q, v, a = random_states(arm.model, np.random.default_rng(4), 50)
    basis = np.random.default_rng(5).standard_normal((50, arm.model.nv, 2))
    np.testing.assert_array_equal(arm.efforts(q, v, a, basis),
                                  np.matmul(rnea_batch(arm.model, q, v, a)[:, None, :], basis)[:, 0])
