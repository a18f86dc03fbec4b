"""The batched generic kinematics against Pinocchio and against the sequential solver."""

from __future__ import annotations

import re
import shutil
import warnings

import numpy as np
import pinocchio as pin
import pytest

from placement import load_robot
from placement.__main__ import main
from placement.kinematics import SOLVERS, TaskTrajectory, solver_for
from placement.kinematics.base import task_error
from placement.kinematics.batched import SOLVE_TOLERANCE, Targets, step_lengths
from placement.kinematics.tree import frame_kinematics, log3
from placement.path import load_path
from placement.placing.transform import placed_task
from placement.robot.closures import closure_residuals
from placement.search.space import default_space
from placement.workshop.gepetto import EstimatesWarning
from placement.workshop.load import edit_redundancy
from tests.support.paths import DATA

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
ROBOTS = ["orthoglide", "fivebar", "ur5", "panda"]


def unaligned_model() -> pin.Model:
    """A chain with joints about and along tilted axes, and tilted joint placements."""
    model = pin.Model()
    rng = np.random.default_rng(3)
    parent = 0
    joints = [pin.JointModelRevoluteUnaligned(*np.array([1.0, 2.0, 2.0]) / 3.0),
              pin.JointModelPrismaticUnaligned(*np.array([0.0, 0.6, 0.8])),
              pin.JointModelRX(), pin.JointModelPY(),
              pin.JointModelRevoluteUnaligned(*np.array([0.6, 0.0, -0.8]))]
    for i, joint in enumerate(joints):
        placement = pin.SE3(pin.exp3(rng.normal(size=3)), rng.normal(size=3) * 0.2)
        parent = model.addJoint(parent, joint, placement, f"j{i}")
        model.appendBodyToJoint(parent, pin.Inertia.Random(), pin.SE3.Identity())
    model.addFrame(pin.Frame("tip", parent, pin.SE3(pin.exp3(rng.normal(size=3)), rng.normal(size=3) * 0.1),
                             pin.FrameType.OP_FRAME))
    return model


def models() -> list[tuple[str, pin.Model]]:
    return [(name, load_robot(name).model) for name in ROBOTS] + [("unaligned", unaligned_model())]


@pytest.mark.parametrize(("name", "model"), models(), ids=lambda x: x if isinstance(x, str) else "")
def test_tree_matches_pinocchio(name, model):
    """Frame placements, LWA Jacobians and classical accelerations (J̇·v) of every frame, to 1e-12."""
    rng = np.random.default_rng(0)
    q = rng.uniform(-2.0, 2.0, (7, model.nq))
    v = rng.normal(0.0, 2.0, (7, model.nv))
    rotations, origins, jacobians, drifts = frame_kinematics(model, range(model.nframes), q, v)
    data = model.createData()
    for frame_id in range(model.nframes):
        rotation, origin = rotations[:, frame_id], origins[:, frame_id]
        jacobian, drift = jacobians[:, frame_id], drifts[:, frame_id]
        for k in range(len(q)):
            pin.forwardKinematics(model, data, q[k], v[k], np.zeros(model.nv))
            pin.computeJointJacobians(model, data, q[k])
            pin.updateFramePlacements(model, data)
            np.testing.assert_allclose(rotation[k], data.oMf[frame_id].rotation, atol=1e-12)
            np.testing.assert_allclose(origin[k], data.oMf[frame_id].translation, atol=1e-12)
            np.testing.assert_allclose(jacobian[k], pin.getFrameJacobian(model, data, frame_id, LWA), atol=1e-12)
            np.testing.assert_allclose(drift[k], pin.getFrameClassicalAcceleration(model, data, frame_id, LWA).vector,
                                       atol=1e-12)


def test_log3_matches_pinocchio():
    """Rotation vectors of random rotations, of small ones and of ones within 1e-3 rad of a half turn."""
    rng = np.random.default_rng(1)
    axes = rng.normal(0.0, 1.0, (20, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    vectors = np.vstack([rng.normal(0.0, 1.0, (20, 3)), 1e-6 * axes, (np.pi - rng.uniform(0, 1e-3, (20, 1))) * axes])
    rotations = np.array([pin.exp3(w) for w in vectors])
    np.testing.assert_allclose(log3(rotations), [pin.log3(r) for r in rotations], atol=1e-9)
    np.testing.assert_allclose(log3(rotations[:40]), vectors[:40], atol=1e-12)


def placed(robot_name: str, path: str, placements: int, samples: int | None = None):
    """A robot ("panda_locked": the Panda with joint 3 held at 0, a six-axis arm) and random placements of a path."""
    robot = load_robot(robot_name.removesuffix("_locked"))
    if robot_name.endswith("_locked"):
        robot = edit_redundancy(robot, {"panda_joint3": 0.0})
    tool_path = load_path(f"examples/{path}.yaml")
    sampled = tool_path.sample()
    if samples:
        sampled = tool_path.sample(sampled.t_s[-1] / (samples - 1))
    space = default_space(robot)
    x = space.full(np.random.default_rng(0).uniform(space.lower, space.upper, (placements, len(space.free))))
    task, _ = placed_task(robot, sampled, x)
    return robot, task


@pytest.mark.parametrize(("robot_name", "path"), [("ur5", "rect"), ("panda_locked", "circle"), ("fivebar", "circle")])
def test_batched_equals_sequential_on_random_placements(robot_name, path):
    """Same reachable placements, and the same motion on them (1e-9), as the sample-by-sample solver.

    Random placements over the whole placement space include unreachable ones and ones where the
    mechanism would have to change branch: both solvers must reject the same.
    """
    robot, task = placed(robot_name, path, 24, samples=64)
    batched, ok_b, reason_b = SOLVERS.get("numeric")(robot).solve(task, 24)
    sequential, ok_s, _ = SOLVERS.get("sequential")(robot).solve(task, 24)
    per_placement_b, per_placement_s = ok_b.reshape(24, -1).all(axis=1), ok_s.reshape(24, -1).all(axis=1)
    np.testing.assert_array_equal(per_placement_b, per_placement_s)
    assert per_placement_b.any()
    rows = np.repeat(per_placement_b, len(task) // 24)
    for field in ("q", "v", "a", "basis", "task_map"):
        np.testing.assert_allclose(getattr(batched, field)[rows], getattr(sequential, field)[rows], atol=1e-9,
                                   err_msg=field)
    assert np.isfinite(batched.q).all() and np.isfinite(batched.a).all()
    assert per_placement_b.all() or "sample" in reason_b


@pytest.mark.parametrize(("robot_name", "path"), [("orthoglide", "rect"), ("ur5", "rect"), ("panda", "circle"),
                                                ("fivebar", "circle"), ("delta", "circle")])
def test_solved_samples_reach_their_targets(robot_name, path):
    """Every sample reported solved closes its loops and reaches its target within the solve tolerance, measured
    by Pinocchio (Newton may stop on a short step whose linear model converges, without evaluating again)."""
    robot, task = placed(robot_name, path, 12, samples=64)
    joints, ok, _ = SOLVERS.get("numeric")(robot).solve(task, 12)
    assert ok.sum() > len(ok) // 4
    data = robot.model.createData()
    gaps = []
    for k in np.flatnonzero(ok):
        rotation = task.rotation[k] if task.rotation is not None else None
        closure = closure_residuals(robot, data, joints.q[k])  # places the frames for task_error
        gaps.append(np.linalg.norm(np.concatenate([closure, task_error(robot, data, task.position_m[k], rotation)])))
    assert max(gaps) < SOLVE_TOLERANCE


def test_auto_picks_the_batched_solver_for_revolute_robots():
    assert type(solver_for(load_robot("ur5"))).__name__ == "BatchedSolver"
    assert type(solver_for(load_robot("orthoglide"))).__name__ == "ClosedFormSolver"


def test_branch_change_is_reported():
    """A five-bar path through the elbow singularity cannot be followed on one branch: it is reported."""
    robot = load_robot("fivebar")
    # straight out from the reference point towards full stretch of both arms and beyond
    y = np.linspace(0.30, 0.47, 200)
    position = np.column_stack([np.zeros_like(y), y, np.zeros_like(y)])
    task = TaskTrajectory(position, np.tile([0.0, 0.1, 0.0], (200, 1)), np.zeros((200, 3)))
    _, ok, reason = SOLVERS.get("numeric")(robot).solve(task)
    assert ok[0] and not ok[-1]
    assert "sample" in reason


def test_a_compile_is_announced_with_its_length_only_when_it_makes_the_command_wait(capsys):
    """A wait longer than the patience is announced once on stderr, then its length; a short one says nothing (a
    0.2 s pause stands in for the kernels' compile: in a process that has them already, loading takes no time)."""
    import time

    from placement.cli.common import compile_noticed

    waited_s = compile_noticed(lambda: time.sleep(0.2), "the kernels", "a while", patience_s=0.05)
    err = capsys.readouterr().err
    assert waited_s is not None and waited_s >= 0.2
    assert err.count("compiling the kernels for this machine (once, a while;") == 1
    assert err.count("compiled the kernels in 0 s") == 1
    assert compile_noticed(lambda: time.sleep(0.2), "the kernels", "a while", patience_s=600.0) is None
    assert capsys.readouterr().err == ""


def _fivebar_scaled(folder, scale: float):
    """The test five-bar exported in Gepetto's format (tests/data/gepetto_fivebar), every length times ``scale``,
    its loop closed by ``assemble --write``."""
    copy = folder / f"fivebar_{scale}"
    shutil.copytree(DATA / "gepetto_fivebar", copy)
    urdf = copy / "robot.urdf"
    urdf.write_text(re.sub(r'xyz="([^"]*)"', lambda m: 'xyz="' + " ".join(repr(float(v) * scale) for v in m[1].split())
                           + '"', urdf.read_text()))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EstimatesWarning)
        assert main(["assemble", str(copy), "--write"]) == 0
    return load_robot(copy)


def test_the_continuation_step_shrinks_with_the_mechanism(tmp_path):
    """Five-bars ten and twenty times smaller than the test one (arms of 2 and 1 cm) would turn their joints by
    radians over a continuation step of 5 cm: their assembly's steps shrink in proportion (a radian of joint motion
    each at the reference configuration), so that both reach the same scaled targets with the same joint angles,
    and as many as the full-size five-bar reaches with its 5 cm steps (with 5 cm steps they reached 616 and 614
    of the 692, four of them a turn away from each other)."""
    x, y = np.meshgrid(np.linspace(-0.4, 0.4, 41), np.linspace(-0.1, 0.45, 29))
    targets = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    still = np.zeros_like(targets)
    solved = []
    for scale in (1.0, 0.1, 0.05):
        robot = _fivebar_scaled(tmp_path, scale)
        joints, reachable, _ = SOLVERS.get("numeric")(robot).solve(TaskTrajectory(targets * scale, still, still),
                                                                      len(targets))
        solved.append((reachable, joints.q[:, [a.q_index for a in robot.actuators]]))
    (full, _), (tenth, tenth_q), (twentieth, twentieth_q) = solved
    assert min(tenth.sum(), twentieth.sum()) >= full.sum() > 600 and (tenth != twentieth).sum() <= 2
    both = tenth & twentieth
    np.testing.assert_allclose(tenth_q[both], twentieth_q[both], atol=1e-6)


def test_step_lengths_of_every_placement_take_the_longest():
    """A workpiece on a positioner moves the tool in the base frame differently at each placement: the coarse march
    then spaces its samples by the longest step of any placement (``every``), not the first placement's."""
    line = np.linspace(0.0, 1.0, 5)[:, None] * np.array([0.01, 0.0, 0.0])
    targets = Targets(np.vstack([line, 3.0 * line, 2.0 * line]), None)
    np.testing.assert_allclose(step_lengths(targets, 5), 0.0025, rtol=1e-12)
    np.testing.assert_allclose(step_lengths(targets, 5, every=True), 0.0075, rtol=1e-12)
