"""The robot contract: every built-in robot and every test robot obeys the same physics.

Each robot follows a smooth demonstration motion (:func:`placement.workshop.checks.demo_trajectory`: a
Lissajous figure of the end effector about its reference position, in every direction the mechanism
can move it there, DEMO_SCALE times the ``check`` command's amplitude, over DEMO_DURATION_S) while the
environment pushes on its end effector (:func:`tool_load`). Along that motion, for every kinematics
solver that serves the robot:

- every loop closure stays closed, and the end effector on the path;
- the efforts of the library's inverse dynamics (projected RNEA), applied in Pinocchio's constrained
  forward dynamics (``constraintDynamics``), give back the prescribed accelerations;
- the actuators' power Σ F·q̇ plus the load's power equals d(T + V)/dt (rotor inertia included);

and the ``check`` command passes on it. Where a robot has a lumped analytic model (LUMPED), its
efforts with massless legs equal that model's.

A new built-in robot (a folder of ``robots/``) is picked up by :func:`placement.robot.robot_names`;
a new test robot is a builder in ``tests/robot_copies.py`` and an entry of TEST_ROBOTS.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from placement import Robot, load_robot, robot_names
from placement.dynamics.inverse import ActuatorTrajectory, inverse_dynamics
from placement.kinematics import TaskTrajectory
from placement.kinematics.base import SOLVERS
from placement.robot.closures import closure_residuals
from placement.workshop.checks import check_robot, default_amplitude, demo_trajectory, energy_rate, forward_accelerations
from placement.workshop.estimates import load_erd_robot
from tests.support import delta_analytic, fivebar_analytic, robot_copies

DEMO_SCALE = 4.0  # times the check command's amplitude (5 % of the workspace's smallest side): 20 % of it
DEMO_DURATION_S = 1.0  # period of the motion's slowest component
SAMPLES = 60
LOAD_DIRECTION = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])  # oblique to every axis
LOAD_ARM_M = np.array([0.05, 0.0, 0.0])  # a pose task's load: the force applied this far off the tool point

CLOSURE_TOLERANCE = 1e-9  # m and rad, largest closure residual
PATH_TOLERANCE = 1e-9  # m and rad, largest distance of the end effector from the path
ROUND_TRIP_TOLERANCE = 1e-8  # m/s² and rad/s², largest joint acceleration error
POWER_TOLERANCE = 1e-6  # of the peak actuator power |F·q̇|
LUMPED_TOLERANCE = 1e-9  # of the peak effort

# Test robots: name -> builder (a folder of its own to write into -> the robot).
TEST_ROBOTS: dict[str, Callable[[Path], Robot]] = {
    "gepetto_fivebar": lambda folder: load_robot(robot_copies.assembled_gepetto_fivebar(folder)),
    "fivebar_vertical": lambda folder: load_robot(robot_copies.vertical_fivebar(folder)),
    "fivebar_spin_locked": lambda folder: load_robot(robot_copies.spinning_rods_fivebar(folder, locked=True)),
    "planar_arm": lambda folder: load_robot(robot_copies.planar_arm(folder)),
    "universal_shoulder_arm": lambda folder: load_robot(robot_copies.universal_shoulder_arm(folder)),
    "gantry": lambda folder: load_robot(robot_copies.gantry(folder)),
    "ur5_continuous": lambda folder: load_robot(robot_copies.continuous_ur5(folder)),
    "ur5_tool_offset": lambda folder: load_robot(robot_copies.edited_copy(
        "ur5", folder, robot_copies.with_tool(robot_copies.TOOL_OFFSET_M, robot_copies.TOOL_RPY_RAD))),
    "ur5_gripper": lambda folder: load_robot(robot_copies.edited_copy("ur5", folder, robot_copies.with_gripper)),
    "erd_ur5": lambda folder: load_erd_robot("ur5", "tool0"),
}
BUILTIN = robot_names()
assert not set(BUILTIN) & set(TEST_ROBOTS), "a test robot is named like a built-in one"
ROBOTS = [*BUILTIN, *TEST_ROBOTS]


def tool_load(robot: Robot, samples: int) -> np.ndarray:
    """(samples, task_dim) constant load of the environment on the end effector: a force of the robot's weight
    (total mass × 9.81 N) along LOAD_DIRECTION, then for a pose task its moment about the tool point, the force
    being applied LOAD_ARM_M off it (base frame)."""
    force = sum(inertia.mass for inertia in robot.model.inertias) * 9.81 * LOAD_DIRECTION
    wrench = force if robot.task == "position" else np.concatenate([force, np.cross(LOAD_ARM_M, force)])
    return np.tile(wrench, (samples, 1))


def solvers(robot: Robot) -> list[str]:
    """Every kinematics solver that serves the robot (closed form, batched generic, sequential, ...)."""
    return [name for name in SOLVERS.names() if SOLVERS.get(name).unsuitable(robot) is None]


@dataclasses.dataclass(frozen=True)
class Demo:
    """A robot on its demonstration motion (SI units).

    Attributes:
        robot: The robot as loaded (tests copy its model before changing it).
        path: The end-effector motion, a function of time (s), with exact derivatives.
        t: (SAMPLES,) sample times (s).
        task: path(t).
        load: (SAMPLES, task_dim) load of the environment on the end effector (N, N·m).
        solved: Solver name -> the inverse dynamics along the motion under the load.
    """

    robot: Robot
    path: Callable[[np.ndarray], TaskTrajectory]
    t: np.ndarray
    task: TaskTrajectory
    load: np.ndarray
    solved: dict[str, ActuatorTrajectory]


@pytest.fixture(scope="module")
def demo(request, tmp_path_factory) -> Demo:
    """The robot named by the parameter, loaded (or built) once per module, on its demonstration motion."""
    name = request.param
    robot = TEST_ROBOTS[name](tmp_path_factory.mktemp(name)) if name in TEST_ROBOTS else load_robot(name)
    path = demo_trajectory(robot, DEMO_SCALE * default_amplitude(robot)[0], DEMO_DURATION_S)
    t = np.linspace(0.0, DEMO_DURATION_S, SAMPLES)
    task, load = path(t), tool_load(robot, SAMPLES)
    solved = {method: inverse_dynamics(robot, task, load, method) for method in solvers(robot)}
    return Demo(robot, path, t, task, load, solved)


every_robot = pytest.mark.parametrize("demo", ROBOTS, indirect=True)


def with_model(robot: Robot, edit: Callable[[pin.Model], None]) -> Robot:
    """The robot on a copy of its model, changed by ``edit``."""
    model = pin.Model(robot.model)
    edit(model)
    return dataclasses.replace(robot, model=model)


@every_robot
def test_every_loop_stays_closed_and_the_end_effector_on_the_path(demo):
    """A serial robot has no loop to close: for it, only the end effector's pose is checked."""
    robot, data = demo.robot, demo.robot.model.createData()
    for method, solved in demo.solved.items():
        for k, q in enumerate(solved.joints.q):
            pin.framesForwardKinematics(robot.model, data, q)
            tool = data.oMf[robot.end_effector_frame_id]
            closure_gap = np.abs(closure_residuals(robot, data, q)).max(initial=0.0)
            path_gap = np.abs(tool.translation - demo.task.position_m[k]).max()
            if demo.task.is_pose:
                path_gap = max(path_gap, np.abs(pin.log3(tool.rotation @ demo.task.rotation[k].T)).max())
            assert closure_gap <= CLOSURE_TOLERANCE and path_gap <= PATH_TOLERANCE, (method, k, closure_gap, path_gap)


@every_robot
def test_forward_dynamics_with_the_efforts_gives_back_the_accelerations(demo):
    # Massless bodies cut from a loop (the weld stubs of the Orthoglide's and the Delta's wrists) make the forward
    # KKT system singular; a tiny armature on the passive joints, in both directions, keeps it regular.
    def passive_armature(model):
        model.armature[np.setdiff1d(np.arange(model.nv), demo.robot.actuated_v_indices)] += 1e-9

    regular = with_model(demo.robot, passive_armature)
    for method in demo.solved:
        result = inverse_dynamics(regular, demo.task, demo.load, method)
        accelerations = forward_accelerations(regular, result.joints, result.effort, demo.load)
        assert np.abs(result.joints.a).max() > 1.0, method  # the motion accelerates
        assert np.abs(accelerations - result.joints.a).max() <= ROUND_TRIP_TOLERANCE, method


@every_robot
def test_actuator_and_load_power_is_the_rate_of_mechanical_energy(demo):
    def weightless(model):
        model.gravity = pin.Motion.Zero()

    kinetic_rate = energy_rate(with_model(demo.robot, weightless), demo.path, demo.t)
    for method, solved in demo.solved.items():
        actuator_power = solved.effort * solved.velocity
        power_in = actuator_power.sum(axis=1) + (demo.load * demo.task.twist()).sum(axis=1)
        peak = np.abs(actuator_power).max()
        assert np.abs(kinetic_rate).max() > 0.01 * peak, method  # inertia, not only gravity, takes the power
        error = np.abs(power_in - energy_rate(demo.robot, demo.path, demo.t, method=method)).max()
        assert error <= POWER_TOLERANCE * peak, method


@every_robot
def test_the_check_command_passes(demo):
    report = check_robot(demo.robot, samples=40)
    assert report.passed and report.power_error_W <= POWER_TOLERANCE * report.peak_power_W, report


# --- the massless-leg limit: robot name -> its lumped analytic model -------------------------------------------------

@dataclasses.dataclass(frozen=True)
class Lumped:
    """A robot's lumped analytic model.

    Attributes:
        massless_legs: Changes a copy of the robot's model to the idealised mechanism the model describes.
        efforts: (robot, task, load) -> (N, n_act) actuator efforts of the model (N or N·m).
    """

    massless_legs: Callable[[Robot, pin.Model], None]
    efforts: Callable[[Robot, TaskTrajectory, np.ndarray], np.ndarray]


def orthoglide_massless(robot, model):
    for axis in "xyz":
        for body in ("yoke", "bar1", "bar2", "far"):
            model.inertias[model.getJointId(f"{body}_{axis}")] = pin.Inertia.Zero()


def orthoglide_lumped(robot, task, load):
    model, closed_form = robot.model, robot.plugin
    return closed_form.lumped_actuator_forces(
        task.position_m, task.velocity_m_s, task.acceleration_m_s2, closed_form.leg_length_m(model),
        platform_mass_kg=model.inertias[model.getJointId("wrist_x")].mass,
        slider_mass_kg=model.inertias[model.getJointId("slider_x")].mass,
        slider_inertia_kg=robot.actuators[0].reflected_inertia, gravity_m_s2=model.gravity.linear,
        external_force_N=load)


def delta_massless(robot, model):
    for i in (1, 2, 3):
        for body in delta_analytic.LEG_BODIES:
            model.inertias[model.getJointId(f"{body}_{i}")] = pin.Inertia.Zero()


def delta_lumped(robot, task, load):
    model = robot.model
    return delta_analytic.lumped_torques_Nm(task, model.inertias[model.getJointId("wrist_1")].mass,
                                            np.array([a.reflected_inertia for a in robot.actuators]),
                                            model.gravity.linear, load)


def fivebar_massless(robot, model):
    """Massless distal links; the payload a point mass at the tip."""
    tip = model.frames[robot.end_effector_frame_id].placement.translation
    model.inertias[model.getJointId("b1")] = pin.Inertia(fivebar_analytic.PAYLOAD_MASS, tip, np.zeros((3, 3)))
    model.inertias[model.getJointId("b2")] = pin.Inertia.Zero()


def fivebar_lumped(robot, task, load):
    rotor = robot.actuators[0].reflected_inertia  # the geared motor's inertia at the joint
    return fivebar_analytic.lumped_torques(task.position_m, task.velocity_m_s, task.acceleration_m_s2, load,
                                           prox_inertia_A_kg_m2=fivebar_analytic.PROX_INERTIA_A + rotor)


LUMPED = {
    "orthoglide": Lumped(orthoglide_massless, orthoglide_lumped),  # platform and sliders (robots/orthoglide)
    "delta": Lumped(delta_massless, delta_lumped),  # platform and drives, Williams' Jacobian (tests/delta_analytic.py)
    "fivebar": Lumped(fivebar_massless, fivebar_lumped),  # tip payload and proximal rods (tests/fivebar_analytic.py)
}


@pytest.mark.parametrize("demo", list(LUMPED), indirect=True)
def test_massless_legs_give_the_lumped_analytic_efforts(demo):
    lumped = LUMPED[demo.robot.name]
    idealised = with_model(demo.robot, lambda model: lumped.massless_legs(demo.robot, model))
    effort = inverse_dynamics(idealised, demo.task, demo.load).effort
    at_rest = TaskTrajectory(demo.task.position_m, 0 * demo.task.velocity_m_s, 0 * demo.task.acceleration_m_s2)
    expected, static = lumped.efforts(idealised, demo.task, demo.load), lumped.efforts(idealised, at_rest, demo.load)
    peak = np.abs(effort).max()
    assert np.abs(expected - static).max() > 0.01 * peak  # the model's inertial terms are tested, not only statics
    assert np.abs(effort - expected).max() <= LUMPED_TOLERANCE * peak
