"""The batched solver's branch test (kernels._left_branch): small motions are not flips.

A refined sample counts as having left its branch when Newton moves it from its interpolated seed
by more than twice the joint motion its stretch of path allows. Measured, as it once was, by the
change between its solved neighbours, a small closed motion traced between two coarse samples
(its ends nearly equal, the joints moving in between) was a flip at 0.15 to 4 mm on a five-bar and
not at 6 mm: a smaller motion failing where a larger one passed.
"""

import numpy as np
import pinocchio as pin
import pytest

from placement import load_robot
from placement.kinematics.base import SOLVERS
from placement.kinematics.exceptions import UnreachableError
from placement.kinematics.trajectories import TaskTrajectory
from placement.workshop.checks import check_robot, default_amplitude
from tests.support.gepetto_weld import assembled_weld_fivebar
from tests.support.trajectories import lissajous


@pytest.fixture(scope="module")
def weld_fivebar(tmp_path_factory):
    return load_robot(assembled_weld_fivebar(tmp_path_factory.mktemp("weld")))


def test_check_passes_at_every_amplitude_up_to_the_default(weld_fivebar):
    """From 0.1 mm to the default amplitude, the check motion stays on the branch: no amplitude fails where a
    larger one passes (the old test failed from 0.15 to 4 mm and passed at 0.1 and 6 mm)."""
    top, _ = default_amplitude(weld_fivebar)
    verdicts = []
    for amplitude in np.geomspace(1e-4, top, 10):
        try:
            check_robot(weld_fivebar, amplitude_m=amplitude)
            verdicts.append(True)
        except UnreachableError:
            verdicts.append(False)
    passing = np.flatnonzero(verdicts)
    assert len(passing) and not (~np.array(verdicts))[: passing.max()].any(), verdicts
    assert all(verdicts), verdicts


def _in_plane_motion(robot, rng, amplitude_m: float, n: int) -> TaskTrajectory:
    """A random closed Lissajous motion (n samples over 1 s) of the end effector in the robot's plane, around its
    reference position."""
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, robot.reference_q)
    center = data.oMf[robot.end_effector_frame_id].translation
    normal = np.asarray(robot.plane.normal if robot.plane is not None else (0.0, 0.0, 1.0), dtype=float)
    first = np.cross(normal, [0.0, 0.0, 1.0] if abs(normal[2]) < 0.9 else [1.0, 0.0, 0.0])
    first /= np.linalg.norm(first)
    second = np.cross(normal, first)
    t = np.linspace(0.0, 1.0, n)
    frequency = rng.integers(1, 4, 2).astype(float)
    phase = rng.uniform(0, 2 * np.pi, 2)
    task = lissajous(t, (0.0, 0.0, 0.0), (amplitude_m, amplitude_m, 0.0), (*frequency, 1.0), (*phase, 0.0))
    axes = np.column_stack([first, second, normal])
    return TaskTrajectory(center + task.position_m @ axes.T, task.velocity_m_s @ axes.T, task.acceleration_m_s2 @ axes.T)


@pytest.mark.parametrize("name", ["weld", "fivebar"])
def test_branch_verdict_agrees_with_a_fine_continuation(name, weld_fivebar):
    """On random smooth closed motions of 0.05 mm to 3 cm, the batched solver (100 samples, bisection between
    coarse samples) accepts exactly the motions that Pinocchio's Gauss-Newton, stepped ten times as finely from
    sample to sample (a continuation that follows the motion), tracks with a regular task map, and finds the
    same configurations there."""
    robot = weld_fivebar if name == "weld" else load_robot("fivebar")
    rng = np.random.default_rng(7)
    batched, sequential = SOLVERS.get("numeric")(robot), SOLVERS.get("sequential")(robot)
    accepted = 0
    for amplitude in np.geomspace(5e-5, 0.03, 12):
        fine = _in_plane_motion(robot, np.random.default_rng(rng.integers(1 << 32)), amplitude, 991)
        coarse = TaskTrajectory(fine.position_m[::10], fine.velocity_m_s[::10], fine.acceleration_m_s2[::10])
        q_fine, ok_fine, _ = sequential.solve(fine)
        q, ok, reason = batched.solve(coarse)
        assert ok.all() == ok_fine.all(), f"{amplitude:.2e} m: batched says '{reason}'"
        if ok.all():
            accepted += 1
            np.testing.assert_allclose(q.q, q_fine.q[::10], atol=1e-8, err_msg=f"{amplitude:.2e} m")
    assert accepted >= 10
