"""Energy model identities, regeneration modes, drives, and convergence with sampling."""

import dataclasses

import numpy as np
import pytest

from placement.drives.motors import MotorModel, Pmsm, PowerParts, register_motor_model
from placement.dynamics.inverse import inverse_dynamics
from placement.energy.integration import electric_energy, interval_widths
from placement.energy.trace import motor_trace
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.kinematics import TaskTrajectory
from placement.path.load import load_path
from placement.path.path_file import Timing
from tests.support.paths import EXAMPLE

PLACEMENTS = np.array([[0.0, 0.0, 0.0, 0.0, 0.0, 0.0], [-0.06, -0.05, -0.04, 0.7, 0.0, 0.0],
                       [-0.09, -0.09, -0.09, np.pi / 4, 0.0, 0.0], [0.02, -0.03, 0.01, -0.4, 0.0, 0.0]])


def with_drives(robot, motor=None, transmission=None, friction=None):
    """A copy of the robot whose drives have some fields replaced."""
    def change(drive):
        update = {}
        if motor:
            update["motor"] = drive.motor.model_copy(update=motor)
        if transmission:
            update["transmission"] = drive.transmission.model_copy(update=transmission)
        if friction:
            update["friction"] = drive.friction.model_copy(update=friction)
        return drive.model_copy(update=update)

    actuators = tuple(dataclasses.replace(a, drive=change(a.drive)) for a in robot.actuators)
    return dataclasses.replace(robot, actuators=actuators)


def energies(robot, mode, placements=PLACEMENTS, path=None):
    return Evaluator(robot, path or load_path(EXAMPLE), EvaluatorSettings(regeneration=mode)).evaluate(placements).value


def timed(law):
    """The example path under a timing law: the file's (paper), or the optimal one (whose current steps where
    its acceleration switches)."""
    path = load_path(EXAMPLE)
    return path if law == "paper" else dataclasses.replace(path, timing=Timing(mode=law))


TIMINGS = pytest.mark.parametrize("law", ["paper", "optimal"])


@TIMINGS
def test_lossless_motor_with_full_regeneration_draws_the_mechanical_energy(orthoglide, law):
    robot = with_drives(orthoglide, motor={"resistance_ohm": 0.0, "inductance_H": 0.0})
    evaluator = Evaluator(robot, timed(law), EvaluatorSettings(regeneration="signed"))
    for placement in PLACEMENTS:
        detail = evaluator.detail(placement)
        assert detail.energy.total_J == pytest.approx(detail.energy.mechanical_J.sum(), rel=1e-12, abs=1e-12)
        # and the shaft energy is the work of the actuator forces (ideal transmission, no friction)
        work = (detail.effort * detail.velocity)
        dt = interval_widths(detail.samples.t_s, detail.samples.piece)
        trapezoid = (((work[1:] + work[:-1]) / 2) * dt[:, None]).sum()
        assert detail.energy.mechanical_J.sum() == pytest.approx(trapezoid, rel=1e-12)


@TIMINGS
def test_regeneration_modes_are_ordered(orthoglide, law):
    e = {mode: energies(orthoglide, mode, path=timed(law)) for mode in ("absolute", "clip", "bus", "signed")}
    assert np.all(e["absolute"] >= e["clip"]) and np.all(e["clip"] >= e["bus"]) and np.all(e["bus"] >= e["signed"])
    assert np.all(e["absolute"] > e["signed"])  # the modes differ on these placements


@TIMINGS
def test_inductive_part_integrates_to_the_change_of_stored_energy(orthoglide, law):
    """Step by step where the optimal law's current steps (its acceleration switches), continuously elsewhere."""
    evaluator = Evaluator(orthoglide, timed(law))
    detail = evaluator.detail(PLACEMENTS[1])
    motor = orthoglide.actuators[0].drive.motor
    current, piece = detail.motor.current_A, detail.samples.piece
    expected = np.zeros(3)
    for k in np.unique(piece):
        rows = np.flatnonzero(piece == k)
        expected += motor.phases * motor.inductance_H / 2 * (current[rows[-1]] ** 2 - current[rows[0]] ** 2)
    np.testing.assert_allclose(detail.energy.inductive_J, expected, rtol=1e-12, atol=1e-15)
    assert np.abs(expected).max() > 1e-5  # the test means something


def test_holding_still_against_gravity_still_costs_energy(orthoglide):
    n = 101
    still = np.zeros((n, 3))
    result = inverse_dynamics(orthoglide, TaskTrajectory(still, still, still))
    trace = motor_trace(orthoglide, result.effort, result.velocity, result.acceleration)
    t = np.linspace(0.0, 1.0, n)
    energy = electric_energy(orthoglide, trace, t, np.zeros(n, dtype=int))
    motor = orthoglide.actuators[2].drive.motor
    joule = motor.phases * motor.resistance_ohm * trace.current_A[0, 2] ** 2 * 1.0
    assert energy.mechanical_J.sum() == 0.0 and trace.current_A[0, 2] > 0.1
    assert energy.total_J == pytest.approx(joule + energy.joule_J[:2].sum(), rel=1e-12)


def test_losses_in_the_transmission_and_friction_cost_energy(orthoglide):
    base = energies(orthoglide, "clip")
    assert np.all(energies(with_drives(orthoglide, transmission={"efficiency": 0.9}), "clip") > base)
    assert np.all(energies(with_drives(orthoglide, friction={"coulomb": 20.0, "viscous": 30.0}), "clip") > base)


def test_efficiency_acts_on_the_transmitted_load_not_on_the_rotor_inertia(orthoglide):
    robot = with_drives(orthoglide, transmission={"efficiency": 0.5})
    rotor = robot.actuators[0].reflected_inertia
    ratio = robot.actuators[0].drive.transmission.speed_ratio
    acceleration = np.full((1, 3), 2.0)
    velocity = np.full((1, 3), 0.3)
    only_rotor = motor_trace(robot, rotor * acceleration, velocity, acceleration)
    np.testing.assert_allclose(only_rotor.torque_Nm, rotor * acceleration / ratio, rtol=1e-12)
    driving = motor_trace(robot, rotor * acceleration + 40.0, velocity, acceleration)
    np.testing.assert_allclose(driving.torque_Nm, 40.0 / ratio / 0.5 + rotor * acceleration / ratio, rtol=1e-12)
    braking = motor_trace(robot, rotor * acceleration - 40.0, velocity, acceleration)
    np.testing.assert_allclose(braking.torque_Nm, -40.0 / ratio * 0.5 + rotor * acceleration / ratio, rtol=1e-12)


def test_sample_power_integrates_to_the_signed_energy(orthoglide):
    detail = Evaluator(orthoglide, load_path(EXAMPLE),
                       EvaluatorSettings(regeneration="signed", time_step_s=0.0005)).detail(PLACEMENTS[1])
    dt = interval_widths(detail.samples.t_s, detail.samples.piece)
    trapezoid = (((detail.power_W[1:] + detail.power_W[:-1]) / 2) * dt[:, None]).sum()
    assert trapezoid == pytest.approx(detail.energy.total_J, rel=1e-3)


class Doubled(MotorModel):
    """The paper's motor model, every power part doubled."""

    def interval_power(self, motor, speed_rad_s, current_A, dt_s):
        parts = Pmsm().interval_power(motor, speed_rad_s, current_A, dt_s)
        return PowerParts(2 * parts.joule_W, 2 * parts.inductive_W, 2 * parts.back_emf_W)


def test_a_registered_motor_model_is_used(orthoglide):
    register_motor_model("doubled", Doubled())
    robot = with_drives(orthoglide, motor={"model": "doubled"})
    np.testing.assert_allclose(energies(robot, "signed"), 2 * energies(orthoglide, "signed"), rtol=1e-12)


@pytest.mark.parametrize("mode", ["paper", "realistic"])
def test_energy_converges_as_sampling_grows(orthoglide, tmp_path, mode):
    file = tmp_path / "rect.yaml"
    file.write_text(EXAMPLE.read_text().replace("mode: paper", f"mode: {mode}"))
    path = load_path(file)
    steps = [0.002, 0.001, 0.0005, 0.00025]
    values = np.array([Evaluator(orthoglide, path, EvaluatorSettings(time_step_s=s)).evaluate(PLACEMENTS[1:2]).value[0]
                       for s in steps])
    changes = np.abs(np.diff(values))
    assert changes[-1] < 1e-3 * values[-1]
    assert changes[-1] < changes[0]  # differences shrink as the step halves
