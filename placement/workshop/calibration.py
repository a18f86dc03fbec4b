"""Drive constants fitted to a machine's own measurements.

The drive constants of a robot file are often estimates; the absolute energies are only as good
as they are. Given a measured log of a motion (times, tool positions or joint positions, and per
actuator the motor current or the electric power), :func:`calibrate` fits chosen drive constants
by bounded least squares (scipy), with the exact model computing the efforts of the logged
motion once and the drive and motor models predicting the logged quantity for each trial. The
log is split in time: the fit uses the first part, and the error on the rest (held out) says how
well the fitted model predicts what it has not seen.

Log (CSV, header row, SI units): ``t`` (s); either ``x, y, z`` (tool point in the base frame, m;
robots with a position task) or ``q_JOINT`` for every actuated joint (serial robots); and per
actuator ``power_JOINT`` (W, electric), ``current_JOINT`` (A), or both. Power alone determines the
resistance only together with the torque constant's square (the Joule power is n·R·τ²/K_t²), and
current alone does not see the resistance: fit both constants from a log of both.

A log of a cut carries the process force on the tool from the workpiece, in the base frame:
``tool_force_x, tool_force_y, tool_force_z`` (N); the efforts it asks of the actuators are then
part of the prediction.

The motion's rates are the log's own where it carries them: ``qd_JOINT`` (m/s or rad/s) and
``qdd_JOINT`` (m/s² or rad/s²) for every actuated joint, as ``placement --trace`` writes them. A
log with them may repeat an instant: two rows of one time are the motion just before and just
after a step of its acceleration (a timing law's segment end or switch), which no curve through
the positions can follow. Without them, the rates are the derivatives of a quintic spline through
the logged positions, and the times must increase.
"""

from __future__ import annotations

import csv
import dataclasses
import io
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin
from ruamel.yaml import YAML
from ruamel.yaml.comments import CommentedMap
from scipy.interpolate import make_interp_spline
from scipy.optimize import least_squares

from placement.dynamics.inverse import actuator_efforts
from placement.energy.integration import sample_power
from placement.energy.trace import MotorTrace, motor_trace
from placement.exceptions import SettingsError
from placement.kinematics import joint_trajectory
from placement.kinematics.base import task_jacobian
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory
from placement.robot.model import Robot
from placement.robot.sidecar import Drive
from placement.workshop.exceptions import CalibrationError, LogFileError

# Constants a fit may free: where they sit in a drive, their bounds and a typical size (SI).
FITTABLE: dict[str, tuple[str, tuple[float, float], float]] = {
    "resistance_ohm": ("motor", (0.0, 1e3), 1.0),
    "torque_constant_Nm_per_A": ("motor", (1e-5, 1e2), 0.1),
    "rotor_inertia_kg_m2": ("motor", (0.0, 10.0), 1e-5),
    "coulomb": ("friction", (0.0, 1e5), 10.0),
    "viscous": ("friction", (0.0, 1e6), 10.0),
    "efficiency": ("transmission", (0.05, 1.0), 1.0),
}
UNITS = {"power": "W", "current": "A"}
MAX_LOG_ROWS = 1_000_000
MAX_LOG_BYTES = 200_000_000
SPLINE_ORDER = 5  # the logged positions' interpolation, whose derivatives are the motion's rates
TOOL_FORCE_COLUMNS = ("tool_force_x", "tool_force_y", "tool_force_z")  # N, on the tool from the workpiece, base frame
MAX_LOG_VALUE = 1e9  # beyond any time (s), position (m, rad), power (W) or current (A) of a machine


@dataclass(frozen=True)
class MeasuredLog:
    """A measured motion and the drives' measured current or power (SI units).

    Attributes:
        t_s: (N,) times, increasing.
        tool_position_m: (N, 3) tool point in the base frame, or None.
        joint_position: (N, n_act) actuated joint positions (m or rad), or None.
        measured: {"power" (W) and/or "current" (A): (N, n_act), actuator order}.
        joint_velocity: (N, n_act) actuated joint velocities (m/s or rad/s), or None: read off the positions.
        joint_acceleration: (N, n_act) their accelerations (m/s² or rad/s²), given with the velocities.
        tool_force_N: (N, 3) process force on the tool from the workpiece, in the base frame, or None.
    """

    t_s: np.ndarray
    tool_position_m: np.ndarray | None
    joint_position: np.ndarray | None
    measured: dict[str, np.ndarray]
    joint_velocity: np.ndarray | None = None
    joint_acceleration: np.ndarray | None = None
    tool_force_N: np.ndarray | None = None


def read_log(file: str | Path, robot: Robot) -> MeasuredLog:
    """Read a measured log (see the module docstring for its columns).

    Raises:
        LogFileError: The file is missing or not CSV, a column is missing, or a value is not a
            finite number (the message names the column and the row).
    """
    path = Path(file)
    if not path.is_file():
        raise LogFileError(path, "", "not found, or not a regular file")
    if path.stat().st_size > MAX_LOG_BYTES:
        raise LogFileError(path, "", f"larger than {MAX_LOG_BYTES // 1_000_000} MB")
    try:
        with path.open(newline="", encoding="utf-8-sig") as stream:  # Excel's "CSV UTF-8" starts with a BOM
            rows = list(csv.reader(stream))
    except (OSError, UnicodeDecodeError) as error:
        raise LogFileError(path, "", f"cannot be read as UTF-8 CSV: {error}") from None
    if len(rows) < 11 or len(rows) > MAX_LOG_ROWS:
        raise LogFileError(path, "", f"expected a header row and 10 to {MAX_LOG_ROWS:,} rows of samples")
    header = [name.strip() for name in rows[0]]
    twice = sorted({name for name in header if header.count(name) > 1})
    if twice:
        raise LogFileError(path, twice[0], "the column appears twice in the header")
    joints = [a.joint for a in robot.actuators]

    def columns(names: list[str]) -> np.ndarray:
        missing = [name for name in names if name not in header]
        if missing:
            raise LogFileError(path, missing[0], f"column missing; the header has {', '.join(header)[:300]}")
        index = [header.index(name) for name in names]
        values = np.empty((len(rows) - 1, len(names)))
        for r, row in enumerate(rows[1:], start=2):
            for c, (name, i) in enumerate(zip(names, index, strict=True)):
                text = row[i] if i < len(row) else ""
                try:
                    values[r - 2, c] = float(text)
                except ValueError:
                    raise LogFileError(path, name, f"row {r}: expected a number, got '{text[:30]}'") from None
        if not (np.abs(values) < MAX_LOG_VALUE).all():
            raise LogFileError(path, names[0], f"values must be finite numbers below {MAX_LOG_VALUE:g} in size (SI units)")
        return values

    t = columns(["t"])[:, 0]
    rates = [f"{rate}_{name}" for rate in ("qd", "qdd") for name in joints]
    carried = [name for name in rates if name in header]
    if carried and len(carried) < len(rates):
        missing = next(name for name in rates if name not in header)
        raise LogFileError(path, missing, f"column missing: a log with {carried[0]} carries the rates qd_JOINT and "
                           "qdd_JOINT of every actuated joint")
    if not (np.diff(t) >= 0).all():
        raise LogFileError(path, "t", "times must not decrease from row to row")
    if not carried and not (np.diff(t) > 0).all():
        raise LogFileError(path, "t", "times must increase from row to row, or the log must carry the rates "
                           "(columns qd_JOINT and qdd_JOINT) to repeat an instant")
    velocity, acceleration = (columns(rates[:len(joints)]), columns(rates[len(joints):])) if carried else (None, None)
    force = columns(list(TOOL_FORCE_COLUMNS)) if set(TOOL_FORCE_COLUMNS) & set(header) else None
    tool = joint = None
    logs_tool = {"x", "y", "z"} <= set(header)
    if logs_tool and robot.task == "position":
        tool = columns(["x", "y", "z"])
    elif robot.is_serial:  # a pose robot's trace has both: its joints say the pose
        if logs_tool and f"q_{joints[0]}" not in header:
            raise LogFileError(path, "x", f"robot '{robot.name}' follows a pose: log its joint positions q_JOINT")
        joint = columns([f"q_{name}" for name in joints])
    else:
        raise LogFileError(path, "x", "a closed-loop robot's log needs the tool position: columns x, y, z")
    measured = {quantity: columns([f"{quantity}_{name}" for name in joints])
                for quantity in UNITS if f"{quantity}_{joints[0]}" in header}
    if not measured:
        raise LogFileError(path, f"power_{joints[0]}", "columns missing: power_JOINT (W) or current_JOINT (A) "
                           "for every actuated joint")
    for quantity, values in measured.items():
        if not values.any():
            raise LogFileError(path, f"{quantity}_{joints[0]}", f"every {quantity} value is zero: nothing was measured")
    return MeasuredLog(t, tool, joint, measured, velocity, acceleration, force)


@dataclass(frozen=True)
class Calibration:
    """Fitted drive constants and how well they predict (SI units).

    Attributes:
        robot: The robot with the fitted constants.
        values: {drive: {constant: value}}.
        confidence_95: {drive: {constant: half-width of the 95 % interval}}.
        fit_rmse: {quantity: RMS error on the fitted part of the log (W or A)}.
        held_out_rmse: {quantity: RMS error on the held-out part}.
        t_s: The log's times.
        measured, predicted: {quantity: (N, n_act)}.
        split: Index of the first held-out sample.
        at_bounds: The constants ("drive.constant") that ended on a bound of their range.
    """

    robot: Robot
    values: dict[str, dict[str, float]]
    confidence_95: dict[str, dict[str, float]]
    fit_rmse: dict[str, float]
    held_out_rmse: dict[str, float]
    t_s: np.ndarray
    measured: dict[str, np.ndarray]
    predicted: dict[str, np.ndarray]
    split: int
    at_bounds: tuple[str, ...]


def with_drive_constants(robot: Robot, values: dict[str, dict[str, float]]) -> Robot:
    """The robot with some drive constants changed ({drive: {constant: value}}); its model is shared
    (see :meth:`Robot.with_drives`).

    A pmsm motor's back-EMF constant follows its torque constant (K_e = K_t / phases).
    """
    drives = robot.named_drives
    for name, constants in values.items():
        drive = drives[name]
        by_part: dict[str, dict[str, float]] = {"motor": {}, "friction": {}, "transmission": {}}
        for constant, value in constants.items():
            by_part[FITTABLE[constant][0]][constant] = float(value)
        motor = drive.motor.model_copy(update=by_part["motor"])  # copies are not validated again: values are in bounds
        if "torque_constant_Nm_per_A" in constants and motor.model == "pmsm":
            motor = motor.model_copy(update={"back_emf_constant_V_s_per_rad": motor.torque_constant_Nm_per_A / motor.phases})
        drives[name] = drive.model_copy(update={
            "motor": motor, "friction": drive.friction.model_copy(update=by_part["friction"]),
            "transmission": drive.transmission.model_copy(update=by_part["transmission"])})
    return robot.with_drives(drives)


@dataclass(frozen=True)
class _Motion:
    """The logged motion at the actuators, with efforts without the drives' own inertia."""

    velocity: np.ndarray
    acceleration: np.ndarray
    effort_without_drives: np.ndarray


def _motion(robot: Robot, log: MeasuredLog) -> _Motion:
    model = robot.model.copy()
    for actuator in robot.actuators:
        model.armature[actuator.v_index] -= actuator.reflected_inertia
    bare = dataclasses.replace(robot, model=model)
    t = log.t_s
    if log.tool_position_m is not None:
        joints = joint_trajectory(bare, _tool_motion(bare, log))
    else:
        assert log.joint_position is not None  # read_log gives one or the other
        q = np.tile(robot.reference_q, (len(t), 1))
        q[:, robot.actuated_q_indices] = log.joint_position
        v, a = np.zeros((len(t), model.nv)), np.zeros((len(t), model.nv))
        v[:, robot.actuated_v_indices], a[:, robot.actuated_v_indices] = (
            _rates(t, log.joint_position) if log.joint_velocity is None else (log.joint_velocity, log.joint_acceleration))
        basis = np.broadcast_to(np.eye(model.nv)[:, robot.actuated_v_indices], (len(t), model.nv, len(robot.actuators)))
        task_map = (np.zeros((len(t), 0, len(robot.actuators))) if log.tool_force_N is None  # not needed
                    else _serial_task_map(bare, q))
        joints = JointTrajectory(q, v, a, basis, task_map)
    act = robot.actuated_v_indices
    load = None
    if log.tool_force_N is not None:  # a force on the tool, no moment
        load = np.zeros((len(t), joints.task_map.shape[1]))
        load[:, :3] = log.tool_force_N
    velocity, acceleration = joints.v[:, act], joints.a[:, act]
    if log.joint_velocity is not None and log.joint_acceleration is not None:
        velocity, acceleration = log.joint_velocity, log.joint_acceleration  # as logged: a speed of 0 has no sign
    return _Motion(velocity, acceleration, actuator_efforts(bare, joints, load))


def _serial_task_map(robot: Robot, q: np.ndarray) -> np.ndarray:
    """(N, task_dim, n_act) tool velocity per unit actuator velocity of a serial robot at configurations (N, nq)."""
    data = robot.model.createData()
    task_map = np.empty((len(q), robot.task_dimension, len(robot.actuators)))
    for k, configuration in enumerate(q):
        pin.computeJointJacobians(robot.model, data, configuration)
        pin.updateFramePlacements(robot.model, data)
        task_map[k] = task_jacobian(robot, data, robot.task_dimension)[:, robot.actuated_v_indices]
    return task_map


def _tool_motion(robot: Robot, log: MeasuredLog) -> TaskTrajectory:
    """The logged tool motion: its rates read off the positions, or mapped from the actuators' logged rates.

    The tool's velocity is M·ρ̇, with M = J_task·G the task map at the logged position and ρ̇ the
    actuators' velocities. Their acceleration is affine in the tool's, ρ̈ = ρ̈₀ + M⁻¹·ẍ, where ρ̈₀
    is theirs when the tool moves at that velocity without accelerating; hence ẍ = M·(ρ̈ − ρ̈₀).
    """
    position = log.tool_position_m
    assert position is not None  # a tool log
    if log.joint_velocity is None or log.joint_acceleration is None:
        return TaskTrajectory(position, *_rates(log.t_s, position))
    at_rest = np.zeros_like(position)
    task_map = joint_trajectory(robot, TaskTrajectory(position, at_rest, at_rest)).task_map
    velocity = np.einsum("nij,nj->ni", task_map, log.joint_velocity)
    unaccelerated = joint_trajectory(robot, TaskTrajectory(position, velocity, at_rest)).a[:, robot.actuated_v_indices]
    return TaskTrajectory(position, velocity, np.einsum("nij,nj->ni", task_map, log.joint_acceleration - unaccelerated))


def _rates(t_s: np.ndarray, position: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Velocity and acceleration of logged positions (N, k), from the quintic spline through them.

    Central finite differences err by O(Δt²) in the acceleration (2.6e-2 m/s² on a 1 kHz log of the
    Orthoglide's demo motion, more at the log's ends), which biased the fitted friction well beyond its
    interval; the quintic spline errs by 7e-8 m/s² there.
    """
    spline = make_interp_spline(t_s, position, k=SPLINE_ORDER, axis=0)
    return spline.derivative(1)(t_s), spline.derivative(2)(t_s)


def predict(robot: Robot, motion: _Motion, t_s: np.ndarray, quantities: list[str]) -> dict[str, np.ndarray]:
    """The robot's prediction of the logged quantities, each (N, n_act)."""
    inertia = np.array([a.reflected_inertia for a in robot.actuators])
    trace: MotorTrace = motor_trace(robot, motion.effort_without_drives + inertia * motion.acceleration,
                                    motion.velocity, motion.acceleration)
    out = {"current": trace.current_A} if "current" in quantities else {}
    if "power" in quantities:
        out["power"] = sample_power(robot, trace, t_s, np.zeros(len(t_s), dtype=int))
    return out


def calibrate(robot: Robot, log: MeasuredLog, fit: list[str], held_out: float = 0.3) -> Calibration:
    """Fit drive constants to a measured log.

    Args:
        robot: The robot; every drive its actuators use is fitted, each drive on its own.
        log: The measured log (see :func:`read_log`).
        fit: Names of the constants to fit (keys of FITTABLE).
        held_out: Share of the log, at its end, kept out of the fit to measure the prediction.

    Returns:
        The fitted constants with 95 % intervals, the errors and the robot with them.

    Raises:
        SettingsError: An unknown constant, or a log too short to hold anything out.
        CalibrationError: Constants the log cannot determine (the resistance from currents alone, or
            with the torque constant from power alone, a log without motion, constants left loose).
    """
    unknown = sorted(set(fit) - set(FITTABLE))
    if unknown or not fit:
        raise SettingsError(f"constants to fit: expected some of {', '.join(FITTABLE)}, got {', '.join(unknown) or 'none'}")
    if "power" not in log.measured and "resistance_ohm" in fit:
        raise CalibrationError("resistance_ohm cannot be fitted to currents alone: log the electric power too")
    if "current" not in log.measured and {"resistance_ohm", "torque_constant_Nm_per_A"} <= set(fit):
        raise CalibrationError("resistance_ohm and torque_constant_Nm_per_A cannot both be fitted to power alone "
                               "(only R/K_t² shows): log the currents too, or fit one of them")
    split = int(round(len(log.t_s) * (1 - held_out)))
    if not 10 <= split <= len(log.t_s) - 10 or not 0 < held_out < 1:
        raise SettingsError(f"held-out share {held_out}: both parts of the {len(log.t_s)}-sample log need 10 samples")
    names = sorted({a.drive_name for a in robot.actuators if a.drive_name})
    keys = [(drive, constant) for drive in names for constant in fit]
    start = np.array([constant_value(robot.named_drives[d], c) for d, c in keys])
    lower, upper = (np.array([FITTABLE[c][1][k] for _, c in keys]) for k in (0, 1))
    typical = np.array([FITTABLE[c][2] for _, c in keys])
    scale = np.maximum(np.abs(start), typical)  # the search runs in these units
    motion = _motion(robot, log)
    if not np.abs(motion.velocity).max() > 0:
        raise CalibrationError("the log shows no motion of the actuators: log a motion that moves every axis")
    quantities = sorted(log.measured)
    size = {q: float(np.sqrt(np.mean(log.measured[q][:split] ** 2))) or 1.0 for q in quantities}  # weighs W against A

    def fitted(x: np.ndarray) -> Robot:
        values: dict[str, dict[str, float]] = {d: {} for d in names}
        for (d, c), value in zip(keys, x * scale, strict=True):
            values[d][c] = value
        return with_drive_constants(robot, values)

    def residuals(x: np.ndarray) -> np.ndarray:
        predicted = predict(fitted(x), motion, log.t_s, quantities)
        return np.concatenate([((predicted[q] - log.measured[q])[:split] / size[q]).ravel() for q in quantities])

    # A constant on a bound of its range (a friction of 0, the stock value) starts at its typical size instead:
    # scipy's trust region starts as large as the start vector, which is all but zero there.
    first = np.where((start <= lower) | (start >= upper), np.clip(typical, lower, upper), start)
    result = least_squares(residuals, first / scale, bounds=(lower / scale, upper / scale))
    calibrated = fitted(result.x)
    predicted = predict(calibrated, motion, log.t_s, quantities)
    error = {q: predicted[q] - log.measured[q] for q in quantities}
    dof = max(1, result.fun.size - len(keys))
    covariance = np.linalg.pinv(result.jac.T @ result.jac) * (result.fun @ result.fun) / dof
    half_width = 1.96 * np.sqrt(np.clip(np.diag(covariance), 0.0, None)) * scale
    singular, directions = np.linalg.svd(result.jac, full_matrices=False)[1:]
    unseen = directions[singular <= 1e-9 * max(singular.max(), 1e-300)]  # combinations the log does not move
    half_width[(np.abs(unseen) > 0.1).any(axis=0)] = np.inf
    values: dict[str, dict[str, float]] = {d: {} for d in names}
    intervals: dict[str, dict[str, float]] = {d: {} for d in names}
    for (d, c), value, width in zip(keys, result.x * scale, half_width, strict=True):
        values[d][c], intervals[d][c] = float(value), float(width)
    loose = [f"{d}.{c}" for (d, c), value, width in zip(keys, result.x * scale, half_width, strict=True)
             if not width <= max(abs(value), FITTABLE[c][2])]
    if loose:
        raise CalibrationError(f"the log does not determine {', '.join(loose)} (95 % intervals wider than the values): "
                               "log a richer motion of every axis, or fit fewer constants")
    return Calibration(robot=calibrated, values=values, confidence_95=intervals,
                       fit_rmse={q: float(np.sqrt(np.mean(e[:split] ** 2))) for q, e in error.items()},
                       held_out_rmse={q: float(np.sqrt(np.mean(e[split:] ** 2))) for q, e in error.items()},
                       t_s=log.t_s, measured=log.measured, predicted=predicted, split=split,
                       at_bounds=tuple(f"{d}.{c}" for (d, c), value, low, high in zip(keys, result.x * scale, lower, upper,
                                                                                       strict=True)
                                       if min(value - low, high - value) <= 1e-9 * (high - low)))


def constant_value(drive: Drive, constant: str) -> float:
    """A fittable constant's value in a drive (SI)."""
    part = getattr(drive, FITTABLE[constant][0])
    return float(getattr(part, constant))


def write_calibrated(robot: Robot, calibration: Calibration, folder: str | Path, log_name: str) -> Path:
    """Copy the robot's folder to ``folder`` with a sidecar carrying the fitted constants, named after the folder.

    The sidecar is the original, its comments and layout kept (a ruamel.yaml round trip), renamed
    ``FOLDER_NAME.yaml`` with ``name: FOLDER_NAME``, so that ``--robot FOLDER`` loads it. Each fitted
    constant gets a ``CALIBRATED`` entry under ``sources`` with its 95 % interval.

    Returns:
        The calibrated sidecar's path.

    Raises:
        SettingsError: ``folder`` exists.
    """
    target = Path(folder)
    if target.exists():
        raise SettingsError(f"--out: '{target}' exists; name a new folder")
    shutil.copytree(robot.sidecar_path.parent, target, ignore=shutil.ignore_patterns("__pycache__"))
    (target / robot.sidecar_path.name).unlink()
    sidecar = target / f"{target.name}.yaml"
    round_trip = YAML()  # keeps the original's comments, order and flow style
    round_trip.allow_unicode = True  # '±' as is
    round_trip.width = 4096  # long source entries on one line, as written
    document = round_trip.load(robot.sidecar_path.read_text(encoding="utf-8"))
    document["name"] = target.name
    if "sources" not in document:
        document["sources"] = CommentedMap()
    sources = document["sources"]
    held_out = ", ".join(f"{v:.3g} {UNITS[q]}" for q, v in calibration.held_out_rmse.items())
    for drive, constants in calibration.values.items():
        entry = document["drives"][drive]
        for constant, value in constants.items():
            part = FITTABLE[constant][0]
            if part not in entry:
                entry[part] = CommentedMap()
            entry[part][constant] = value
            sources[f"drives.{drive}.{part}.{constant}"] = (
                f"CALIBRATED: fitted to {log_name}, 95 % interval ±{calibration.confidence_95[drive][constant]:.3g}; "
                f"held-out RMS error {held_out}")
        # with_drive_constants keeps the back-EMF constant consistent with the torque constant: take it from there
        entry["motor"]["back_emf_constant_V_s_per_rad"] = \
            calibration.robot.named_drives[drive].motor.back_emf_constant_V_s_per_rad
    stream = io.StringIO()
    round_trip.dump(document, stream)
    sidecar.write_text(stream.getvalue(), encoding="utf-8")
    return sidecar
