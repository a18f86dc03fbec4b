"""Calibration: hidden drive constants are recovered from logs of current and power.

Logs are made by the model itself with hidden constants plus 1 % noise (the motion a smooth
Lissajous around the Orthoglide's isotropic point), and by MuJoCo: the Orthoglide driven open
loop, its simulated motion logged, and the power computed from the efforts MuJoCo applied.
"""

import csv
import re

import numpy as np
import pytest

from placement import load_robot
from placement.cli import main
from placement.dynamics.inverse import inverse_dynamics
from placement.energy.integration import sample_power
from placement.energy.trace import motor_trace
from placement.workshop.calibration import FITTABLE, MeasuredLog, calibrate, read_log
from placement.workshop.catalog import builtin_robots_dir
from placement.workshop.checks import demo_trajectory
from placement.workshop.exceptions import LogFileError
from tests.support.robot_copies import edited_copy

DRIVE = "sanyo_p30b06040d_ball_screw"
HIDDEN = {"resistance_ohm": 1.8, "torque_constant_Nm_per_A": 0.45, "rotor_inertia_kg_m2": 3.25e-5, "coulomb": 20.0,
          "viscous": 30.0, "efficiency": 0.9}  # the stock sidecar: 1.5, 0.5, 2.5e-5, 0, 0, 1.0


def hide(document: dict) -> None:
    drive = document["drives"][DRIVE]
    drive["motor"].update(resistance_ohm=1.8, torque_constant_Nm_per_A=0.45, back_emf_constant_V_s_per_rad=0.15,
                          rotor_inertia_kg_m2=3.25e-5)
    drive["friction"] = {"coulomb": 20.0, "viscous": 30.0}
    drive["transmission"]["efficiency"] = 0.9


def write_log(file, t, tool, power=None, current=None, names=("slider_x", "slider_y", "slider_z")):
    header = ["t", "x", "y", "z"] + [f"power_{n}" for n in names] * (power is not None) \
        + [f"current_{n}" for n in names] * (current is not None)
    columns = [t[:, None], tool] + [c for c in (power, current) if c is not None]
    with open(file, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(header)
        writer.writerows(np.hstack(columns).tolist())
    return file


@pytest.fixture(scope="module")
def hidden_log(tmp_path_factory):
    """3 s of the hidden robot at 1 kHz: tool positions, power and current with 1 % noise."""
    folder = tmp_path_factory.mktemp("hidden")
    hidden = load_robot(edited_copy("orthoglide", folder, hide))
    t = np.arange(0.0, 3.0, 0.001)
    task = demo_trajectory(hidden, amplitude_m=0.04)(t)
    motion = inverse_dynamics(hidden, task)
    trace = motor_trace(hidden, motion.effort, motion.velocity, motion.acceleration)
    power = sample_power(hidden, trace, t, np.zeros(len(t), dtype=int))
    rng = np.random.default_rng(7)
    noisy_power = power + rng.normal(0.0, 0.01 * np.abs(power).max(), power.shape)
    noisy_current = trace.current_A + rng.normal(0.0, 0.01 * np.abs(trace.current_A).max(), power.shape)
    return folder, t, task.position_m, noisy_power, noisy_current, 0.01 * np.abs(power).max()


def test_hidden_constants_are_recovered_within_2_percent(hidden_log):
    folder, t, tool, power, current, noise_W = hidden_log
    robot = load_robot("orthoglide")
    log = read_log(write_log(folder / "log.csv", t, tool, power, current), robot)
    result = calibrate(robot, log, list(FITTABLE))
    for constant, truth in HIDDEN.items():
        assert result.values[DRIVE][constant] == pytest.approx(truth, rel=0.02), constant
        assert result.confidence_95[DRIVE][constant] < 0.02 * truth  # and the fit knows it is that close
    assert result.held_out_rmse["power"] < 1.5 * noise_W  # the held-out part is predicted down to the noise


def model_log(robot, t):
    """The tool positions, power and current the model itself predicts for the demo motion at times ``t``."""
    task = demo_trajectory(robot, amplitude_m=0.04)(t)
    motion = inverse_dynamics(robot, task)
    trace = motor_trace(robot, motion.effort, motion.velocity, motion.acceleration)
    return task.position_m, sample_power(robot, trace, t, np.zeros(len(t), dtype=int)), trace.current_A


def test_a_noise_free_log_made_by_the_model_gives_back_the_truth(hidden_log):
    """The fit reads the motion's rates off the logged positions as exactly as the model made them (a quintic
    spline: finite differences erred by O(Δt²) in the acceleration and biased the friction well outside its
    interval), and starts the stock's zero friction inside its range."""
    folder = hidden_log[0]
    hidden = load_robot(folder / "orthoglide" / "orthoglide.yaml")
    t = np.arange(0.0, 1.0, 0.001)
    tool, power, current = model_log(hidden, t)
    robot = load_robot("orthoglide")
    result = calibrate(robot, MeasuredLog(t, tool, None, {"power": power, "current": current}), list(FITTABLE))
    for constant, truth in HIDDEN.items():
        assert result.values[DRIVE][constant] == pytest.approx(truth, rel=1e-6), constant
    friction = calibrate(robot, MeasuredLog(t, tool, None, {"power": power}), ["coulomb", "viscous"])
    assert friction.values[DRIVE]["coulomb"] != pytest.approx(HIDDEN["coulomb"], rel=1e-3)  # the motor differs too
    only = load_robot(edited_copy("orthoglide", folder / "friction", lambda d: d["drives"][DRIVE].update(
        friction={"coulomb": 15.0, "viscous": 25.0})))
    tool, power, _ = model_log(only, t)
    friction = calibrate(robot, MeasuredLog(t, tool, None, {"power": power}), ["coulomb", "viscous"])
    assert friction.values[DRIVE] == pytest.approx({"coulomb": 15.0, "viscous": 25.0}, rel=1e-6)


def test_the_95_percent_intervals_cover_the_truth_at_their_rate(tmp_path):
    """100 short logs (200 samples) of one motion, each with its own 1 % noise on the power: each 95 % interval
    holds the hidden constant in at least 90 of them (a binomial(100, 0.95) falls below 90 with probability 0.3 %)."""
    truth = {"coulomb": 15.0, "viscous": 25.0, "resistance_ohm": 1.8}

    def lossier(document: dict) -> None:
        document["drives"][DRIVE]["friction"] = {"coulomb": 15.0, "viscous": 25.0}
        document["drives"][DRIVE]["motor"]["resistance_ohm"] = 1.8

    t = np.arange(0.0, 1.0, 0.005)
    tool, power, _ = model_log(load_robot(edited_copy("orthoglide", tmp_path, lossier)), t)
    robot = load_robot("orthoglide")
    covered = dict.fromkeys(truth, 0)
    for seed in range(100):
        noisy = power + np.random.default_rng(seed).normal(0.0, 0.01 * np.abs(power).max(), power.shape)
        result = calibrate(robot, MeasuredLog(t, tool, None, {"power": noisy}), list(truth))
        for constant, value in truth.items():
            covered[constant] += abs(result.values[DRIVE][constant] - value) <= result.confidence_95[DRIVE][constant]
    assert min(covered.values()) >= 90, covered


def test_the_log_must_be_able_to_tell_the_constants_apart(hidden_log, tmp_path, capsys):
    _, t, tool, power, current, _ = hidden_log
    only_power = write_log(tmp_path / "power.csv", t, tool, power)
    assert main(["calibrate", "orthoglide", "--log", str(only_power), "--fit", "resistance_ohm,torque_constant_Nm_per_A"]) == 2
    assert "cannot both be fitted to power alone" in capsys.readouterr().err
    only_current = write_log(tmp_path / "current.csv", t, tool, current=current)
    assert main(["calibrate", "orthoglide", "--log", str(only_current), "--fit", "resistance_ohm"]) == 2
    assert "cannot be fitted to currents alone" in capsys.readouterr().err


def test_the_command_writes_a_calibrated_robot_that_loads(hidden_log, tmp_path, capsys):
    _, t, tool, power, current, _ = hidden_log
    log = write_log(tmp_path / "log.csv", t, tool, power, current)
    out, png = tmp_path / "orthoglide_shop2", tmp_path / "fit.png"
    assert main(["calibrate", "orthoglide", "--log", str(log), "--fit", ",".join(FITTABLE), "--out", str(out),
                 "--png", str(png)]) == 0
    text = capsys.readouterr().out
    assert "resistance_ohm" in text and "held out" in text and png.is_file()
    assert re.search(r"resistance_ohm +1\.5 -> +1\.8\d* +± ", text)  # before -> after
    robot = load_robot(out)  # the folder, named after the calibration; the plug-in and URDF came along
    assert robot.name == "orthoglide_shop2" and robot.sidecar_path == out / "orthoglide_shop2.yaml"
    assert sorted(p.name for p in out.glob("*.yaml")) == ["orthoglide_shop2.yaml"]
    written = robot.sidecar_path.read_text(encoding="utf-8")
    original = (builtin_robots_dir() / "orthoglide" / "orthoglide.yaml").read_text(encoding="utf-8")
    assert written.splitlines()[:3] == original.splitlines()[:3]  # the comments and layout kept
    assert "reference_configuration:      # the isotropic point O_b" in written
    assert "95 % interval ±" in written and "\\xB1" not in written
    drive = robot.named_drives[DRIVE]
    assert drive.motor.resistance_ohm == pytest.approx(1.8, rel=0.02) and drive.friction.coulomb == pytest.approx(20, rel=0.02)
    assert robot.sources[f"drives.{DRIVE}.motor.resistance_ohm"].startswith("CALIBRATED: fitted to log.csv")


@pytest.mark.parametrize("timing", ["paper", "optimal", "realistic"])
def test_a_trace_is_a_calibration_log(tmp_path, timing):
    """placement --trace writes a log calibrate reads as it is: a hidden robot's noise-free trace of the groove
    (its process forces included) gives back every hidden constant, under each timing law. The paper and optimal
    laws repeat instants where the acceleration steps (a segment's end, a switch): the fit takes the motion's rates
    from the trace's qd and qdd columns, so each of the two rows is the motion on its side of the step."""
    from placement import Evaluator, EvaluatorSettings, load_path
    from placement.output.report import write_trace
    from placement.timing.rules import override_timing

    hidden = load_robot(edited_copy("orthoglide", tmp_path, hide))
    path = override_timing(load_path("examples/rect.yaml"), timing)
    detail = Evaluator(hidden, path, EvaluatorSettings(workers=1)).detail(
        np.array([0.0, 0.0, -0.03, 0.3, 0.0, 0.0]))  # turned: every slider moves (Coulomb friction needs a sign)
    write_trace(tmp_path / "trace.csv", hidden, detail)
    robot = load_robot("orthoglide")
    log = read_log(tmp_path / "trace.csv", robot)
    assert (np.diff(log.t_s) == 0).any() == (timing != "realistic")  # the instants repeated, where they are
    assert np.abs(log.tool_force_N).max() > 200  # the groove's radial force, carried
    result = calibrate(robot, log, list(FITTABLE))
    for constant, truth in HIDDEN.items():
        assert result.values[DRIVE][constant] == pytest.approx(truth, rel=1e-5), constant


def test_a_serial_arm_s_trace_is_a_calibration_log(tmp_path):
    """The UR5 follows a pose: its trace's joint positions say it, and the groove's process force reaches the joints
    through the arm's Jacobian; the hidden friction and resistance come back from the noise-free trace."""
    from placement import Evaluator, EvaluatorSettings, load_path
    from placement.output.report import write_trace

    def lossier(document: dict) -> None:
        for drive in document["drives"].values():
            drive["motor"]["resistance_ohm"] *= 1.3
            drive["friction"] = {"coulomb": 2.0, "viscous": 5.0}

    hidden = load_robot(edited_copy("ur5", tmp_path, lossier))
    placement = np.array([0.27858, -0.03713, 0.19443, *np.radians([-9.22, 20.05, -3.28])])  # its best for the groove
    detail = Evaluator(hidden, load_path("examples/rect.yaml"), EvaluatorSettings(workers=1)).detail(placement)
    write_trace(tmp_path / "trace.csv", hidden, detail)
    robot = load_robot("ur5")
    result = calibrate(robot, read_log(tmp_path / "trace.csv", robot), ["resistance_ohm", "coulomb", "viscous"])
    stock = {name: drive.motor.resistance_ohm for name, drive in robot.named_drives.items()}
    for name, values in result.values.items():
        assert values == pytest.approx({"resistance_ohm": 1.3 * stock[name], "coulomb": 2.0, "viscous": 5.0},
                                       rel=1e-5), name


def test_a_log_whose_motion_mujoco_simulated(tmp_path):
    mujoco = pytest.importorskip("mujoco", reason="the optional test extra 'mujoco' is not installed")
    from placement.kinematics import joint_trajectory
    from tests.support import mujoco_model

    hidden = load_robot(edited_copy("orthoglide", tmp_path, hide))
    simulation = mujoco_model.Simulation(hidden)
    dt, steps_per_sample = simulation.timestep_s, 100  # simulate at 10 µs, log at 1 kHz
    path = demo_trajectory(hidden, amplitude_m=0.04)
    t = np.arange(0.0, 1.0, dt)
    efforts = inverse_dynamics(hidden, path(t + dt / 2)).effort
    start = joint_trajectory(hidden, path(t[:1]))
    simulation.set_state(start.q[0], start.v[0])
    act = hidden.actuated_v_indices
    logged_t, tool, velocity, acceleration, applied = [], [], [], [], []
    for k, effort in enumerate(efforts):
        simulation.data.ctrl[:] = effort
        mujoco.mj_step(simulation.model, simulation.data)
        if (k + 1) % steps_per_sample == 0:  # the state at the end of the step, and what drove it
            logged_t.append(simulation.data.time)
            tool.append(simulation.data.site_xpos[simulation.tool].copy())
            velocity.append(simulation.data.qvel[simulation.qvel[act]].copy())
            acceleration.append(simulation.data.qacc[simulation.qvel[act]].copy())
            applied.append(effort)
    velocity, acceleration, applied = np.array(velocity), np.array(acceleration), np.array(applied)
    trace = motor_trace(hidden, applied, velocity, acceleration)
    logged_t = np.array(logged_t)
    power = sample_power(hidden, trace, logged_t, np.zeros(len(logged_t), dtype=int))
    robot = load_robot("orthoglide")
    log = read_log(write_log(tmp_path / "mujoco.csv", logged_t, np.array(tool), power, trace.current_A), robot)
    result = calibrate(robot, log, list(FITTABLE))
    for constant, truth in HIDDEN.items():
        assert result.values[DRIVE][constant] == pytest.approx(truth, rel=0.02), constant


def test_a_serial_arm_logged_in_joint_positions(tmp_path):
    def lossier(document: dict) -> None:
        for drive in document["drives"].values():
            drive["motor"]["resistance_ohm"] *= 1.3
            drive["friction"] = {"coulomb": 2.0, "viscous": 5.0}

    hidden = load_robot(edited_copy("ur5", tmp_path, lossier))
    t = np.arange(0.0, 4.0, 0.002)
    motion = inverse_dynamics(hidden, demo_trajectory(hidden, amplitude_m=0.05, duration_s=2.0)(t))
    trace = motor_trace(hidden, motion.effort, motion.velocity, motion.acceleration)
    power = sample_power(hidden, trace, t, np.zeros(len(t), dtype=int))
    names = [a.joint for a in hidden.actuators]
    file = tmp_path / "ur5.csv"
    with open(file, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["t"] + [f"q_{n}" for n in names] + [f"power_{n}" for n in names])
        writer.writerows(np.column_stack([t, motion.position, power]).tolist())
    robot = load_robot("ur5")
    result = calibrate(robot, read_log(file, robot), ["resistance_ohm", "coulomb", "viscous"])
    shoulder = result.values["size3"]  # the big joints, well excited by the motion
    assert shoulder["resistance_ohm"] == pytest.approx(0.4 * 1.3, rel=0.01)
    assert shoulder["coulomb"] == pytest.approx(2.0, rel=0.01) and shoulder["viscous"] == pytest.approx(5.0, rel=0.01)


def test_changed_drives_reach_the_actuators_that_name_them_and_travel_to_workers():
    import pickle

    robot = load_robot("orthoglide")
    drive = robot.named_drives[DRIVE]
    changed = drive.model_copy(update={"motor": drive.motor.model_copy(update={"rotor_inertia_kg_m2": 1e-4})})
    new = robot.with_drives({DRIVE: changed})
    assert new.named_drives[DRIVE] is changed and robot.named_drives[DRIVE] is drive
    for before, after in zip(robot.actuators, new.actuators, strict=True):
        assert after.drive is (changed if before.drive_name == DRIVE else before.drive)
        assert after.reflected_inertia == after.drive.reflected_inertia
    assert new.model is robot.model
    copy = pickle.loads(pickle.dumps(new))
    assert copy.named_drives[DRIVE] == changed and copy.actuators == new.actuators and copy.closed_form is not None
    with pytest.raises(KeyError, match="unknown drive"):
        robot.with_drives({"no_such_drive": changed})


def test_a_repeated_instant_needs_the_logged_rates(hidden_log, tmp_path):
    """Without the rates, the motion's are read off the positions, which cannot step: a repeated time is refused,
    and so is a log that carries some rate columns but not all."""
    _, t, tool, power, _, _ = hidden_log
    stepped = t.copy()
    stepped[5] = stepped[4]
    robot = load_robot("orthoglide")
    with pytest.raises(LogFileError, match="carry the rates"):
        read_log(write_log(tmp_path / "repeated.csv", stepped, tool, power), robot)
    partial = tmp_path / "partial.csv"
    with open(partial, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["t", "x", "y", "z", "qd_slider_x", "qd_slider_y", "qd_slider_z", "qdd_slider_x"]
                        + [f"power_{n}" for n in ("slider_x", "slider_y", "slider_z")])
        writer.writerows(np.hstack([t[:, None], tool, np.zeros((len(t), 4)), power]).tolist())
    with pytest.raises(LogFileError, match="qdd_slider_y.*column missing"):
        read_log(partial, robot)
