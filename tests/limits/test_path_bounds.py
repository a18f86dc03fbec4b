"""Limits on how fast a path runs give their bounds along the path (``Limit.path_bounds``) from the same drive
equations as their margins.

On a lossy Orthoglide (transmission efficiency 0.8, Coulomb and viscous friction, a bus voltage and joint
acceleration bounds, so that every built-in bound is there), timed by the optimal law: each bound's form,
evaluated at the law's ṡ and s̈, is the quantity the exact chain computes for that limit (joint speed and
acceleration, motor speed, motor torque driving or braking, R·I + K_e·ω), and the rows the law is given
never allow a motion that breaks a bound.
"""

import numpy as np
import pytest

from placement import Evaluator, EvaluatorSettings, load_path, load_robot
from placement.contract.limit import path_bounds
from placement.dynamics.path_dynamics import path_dynamics
from placement.energy.trace import Drives
from placement.placing.transform import placed_task
from placement.timing.optimal import SAFETY, bound_rows, speed_bound
from tests.support.paths import EXAMPLE
from tests.support.robot_copies import edited_copy

PLACEMENT = np.array([0.0, 0.0, -0.033, 0.0, 0.0, 0.0])


def lossy(document: dict) -> None:
    drive = next(iter(document["drives"].values()))
    drive["transmission"]["efficiency"] = 0.8
    drive["friction"] = {"coulomb": 15.0, "viscous": 25.0}
    drive["motor"]["bus_voltage_V"] = 80.0
    for actuator in document["actuators"]:
        actuator["acceleration_max"] = 20.0


@pytest.fixture(scope="module")
def timed(tmp_path_factory):
    """The robot, its path bounds along the path at one placement, the law's motion there, and the exact chain's
    batch at the evaluated samples."""
    folder = tmp_path_factory.mktemp("lossy")
    robot = load_robot(edited_copy("orthoglide", folder, lossy))
    path_file = folder / "rect.yaml"
    path_file.write_text(EXAMPLE.read_text(encoding="utf-8").replace("mode: paper", "mode: optimal"), encoding="utf-8")
    with Evaluator(robot, load_path(path_file), EvaluatorSettings(time_step_s=0.004, workers=1)) as evaluator:
        batch = evaluator.batch(PLACEMENT[None])
        geometry = evaluator.geometry
        task, force = placed_task(robot, geometry.samples, PLACEMENT[None])
        joints, reachable, _ = evaluator.solver.solve(task, 1)
    assert reachable.all() and batch.path_law is not None and batch.path_law.timed.all()
    dynamics = path_dynamics(robot, joints, force, 1).rows(geometry.grid_rows)
    law = batch.path_law
    speed, acceleration = law.speed_m_s[:, geometry.grid_rows], law.acceleration_m_s2[:, geometry.interval_rows]
    return robot, path_bounds(robot, dynamics), speed, acceleration, batch


def bound(bounds, kind, index=0):
    return [b for b in bounds if b.kind == kind][index]


def test_every_built_in_bound_is_there(timed):
    _, bounds, *_ = timed
    assert sorted(b.kind for b in bounds) == ["drive voltage", "drive voltage", "joint acceleration", "joint speed",
                                              "motor speed", "motor torque", "motor torque"]  # driving and braking


def test_joint_and_motor_rates_along_the_path_are_the_chains(timed):
    robot, bounds, speed, acceleration, batch = timed
    np.testing.assert_allclose(bound(bounds, "joint speed").form(speed, acceleration), batch.velocity, atol=1e-12)
    np.testing.assert_allclose(bound(bounds, "joint acceleration").form(speed, acceleration), batch.acceleration,
                               atol=1e-9)
    np.testing.assert_allclose(bound(bounds, "motor speed").form(speed, acceleration), batch.motor.speed_rad_s,
                               atol=1e-9)


def test_the_motor_torque_is_the_driving_form_where_the_motor_drives_and_the_braking_one_elsewhere(timed):
    """Where a joint moves. At rest (the path's ends and corners) the bound counts Coulomb friction against the
    motion about to start, sign(q'), and the motor trace none, sign(0): the timing law is the stricter there."""
    robot, bounds, speed, acceleration, batch = timed
    drives = Drives.of(robot)
    driving, braking = (b.form(speed, acceleration) for b in bounds if b.kind == "motor torque")
    transmitted = drives.transmitted(batch.effort, batch.velocity, batch.acceleration, np.sign(batch.velocity))
    motoring = transmitted * batch.velocity >= 0
    assert motoring.any() and (~motoring).any()
    torque, moving = batch.motor.torque_Nm, batch.velocity != 0
    assert moving.mean() > 0.9
    np.testing.assert_allclose(np.where(motoring, driving, braking)[moving], torque[moving],
                               atol=1e-9 * np.abs(torque).max())
    at_rest = np.where(motoring, driving, braking)[~moving] - torque[~moving]
    coulomb = drives.coulomb_friction * np.broadcast_to(drives.driving_gain, torque.shape)
    assert (np.abs(at_rest) <= np.abs(coulomb[~moving]) * (1 + 1e-9)).all()
    assert not np.allclose(driving, braking)  # the two gains differ with a lossy transmission


def test_the_voltage_form_is_the_resistive_and_back_emf_voltage(timed):
    robot, bounds, speed, acceleration, batch = timed
    drives = Drives.of(robot)
    driving = bound(bounds, "drive voltage").form(speed, acceleration)
    torque_driving = bound(bounds, "motor torque").form(speed, acceleration)
    np.testing.assert_allclose(driving, drives.resistive_voltage(torque_driving, batch.motor.speed_rad_s), atol=1e-9)


def test_the_timed_motion_keeps_every_bound(timed):
    _, bounds, speed, acceleration, _ = timed
    for each in bounds:
        assert (np.abs(each.form(speed, acceleration)) <= SAFETY * each.top * (1 + 1e-6)).all(), each.kind


def test_the_rows_never_allow_what_a_bound_forbids(timed):
    """Random (ṡ, s̈) within the speed bound that satisfy every row a·s̈ + b·ṡ² + c ≤ 0 keep every bound: the
    tangent and chord of the terms in ṡ are on the safe side."""
    _, bounds, speed, _, _ = timed
    k, n = speed.shape
    feed = np.full(n, 0.66)
    top_speed = speed_bound(bounds, feed, k)
    a, b, c = bound_rows(bounds, top_speed)
    rng = np.random.default_rng(0)
    kept = 0
    for _ in range(200):
        s_dot = rng.uniform(0.0, 1.0, (k, n)) * top_speed
        s_ddot = rng.uniform(-30.0, 30.0, (k, n))
        allowed = ((a * s_ddot[..., None] + b * s_dot[..., None] ** 2 + c) <= 0).all(axis=-1)
        for each in bounds:
            value = np.abs(each.form(s_dot, s_ddot))
            assert (value[allowed] <= SAFETY * each.top * (1 + 1e-9) + 1e-12).all(), each.kind
        kept += allowed.sum()
    assert kept > 1000  # the check saw many allowed motions
