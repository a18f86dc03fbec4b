"""The exact chain for many placements at once: path -> base frame -> kinematics -> dynamics ->
drives -> energy and margins.

Placements are evaluated in batches: the path samples of every placement are stacked and go
through the robot's batched kinematics and one batched RNEA call, so that thousands of placements
of hundreds of samples each stay cheap.
"""

from __future__ import annotations

import os
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass

import numpy as np

from placement.constraints import Margin, margin_fields, tightest, worst_margins
from placement.drives import MotorTrace, motor_trace
from placement.dynamics import actuator_efforts
from placement.energy import Energy, electric_energy, sample_power
from placement.exceptions import PlacementError
from placement.frames import placed_task
from placement.kinematics import try_joint_trajectory
from placement.path import PathSamples, ToolPath
from placement.robot import Robot

BATCH_SAMPLES = 60_000  # samples per batched call (memory: about 0.5 kB a sample)
UNREACHABLE_MARGIN = -1.0  # below every real margin: how infeasible an unreachable placement is


@dataclass(frozen=True)
class Evaluation:
    """K placements evaluated with the exact model.

    Attributes:
        placements: (K, 6) placement vectors (m, rad).
        energy_J: (K,) electric energy under the regeneration mode (inf where unreachable).
        margins: (K, n_limits) tightest normalised margin of each limit (kind and actuator or axis).
        limits: Labels of the margin columns.
        reachable: (K,) whether every sample has a configuration.
    """

    placements: np.ndarray
    energy_J: np.ndarray
    margins: np.ndarray
    limits: tuple[str, ...]
    reachable: np.ndarray

    @property
    def feasible(self) -> np.ndarray:
        """(K,) every sample reachable and every margin >= 0."""
        return self.reachable & (self.margins >= 0).all(axis=1)


@dataclass(frozen=True)
class PlacementDetail:
    """Everything about one placement: energy, margins and the per-sample trace (SI units).

    Attributes:
        placement: (6,) placement vector.
        reachable: Whether every sample has a configuration.
        unreachable_samples: Indices of samples without one.
        energy: Energies (scalars, per-actuator arrays).
        margins: Tightest point of each limit kind.
        samples: The path samples in the path frame.
        tool_position_m: (N, 3) tool point in the base frame.
        position, velocity, acceleration, effort: (N, n_act) actuator motion and effort.
        motor: Motor speed, torque and current, (N, n_act).
        power_W: (N, n_act) signed electric power of each drive at each sample (the mean of the
            adjacent intervals' power, by the drive's motor model).
    """

    placement: np.ndarray
    reachable: bool
    unreachable_samples: np.ndarray
    energy: Energy
    margins: list[Margin]
    samples: PathSamples
    tool_position_m: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    effort: np.ndarray
    motor: MotorTrace
    power_W: np.ndarray

    @property
    def feasible(self) -> bool:
        """Reachable and within every limit."""
        return self.reachable and all(m.margin >= 0 for m in self.margins)


class Evaluator:
    """Evaluates placements of one path on one robot.

    Robots solved by the generic (per-sample) kinematics share batches of placements among worker
    processes; call :meth:`close` (or use ``with``) to stop them.

    Args:
        robot: The robot (its actuators need drives).
        path: The tool path.
        regeneration: Regeneration mode, see :mod:`placement.energy`.
        time_step_s: Sampling step (default: the path file's).
        method: Kinematics method, see :func:`placement.kinematics.joint_trajectory`.
        workers: Processes for batches of placements (default: every core for the generic
            kinematics, 1 for a closed-form plug-in, whose batches are already vectorised).
    """

    def __init__(self, robot: Robot, path: ToolPath, regeneration: str = "clip", time_step_s: float | None = None,
                 method: str = "auto", workers: int | None = None) -> None:
        self.robot = robot
        self.path = path
        self.regeneration = regeneration
        self.time_step_s = time_step_s
        self.method = ("closed_form" if robot.closed_form is not None else "numeric") if method == "auto" else method
        self.samples = path.sample(time_step_s)
        self.evaluations = 0  # placements evaluated so far
        self.workers = workers or (1 if self.method == "closed_form" else os.cpu_count() or 1)
        self._pool: ProcessPoolExecutor | None = None

    def __enter__(self) -> Evaluator:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Stop the worker processes, if any were started."""
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None

    def _chain(self, placements: np.ndarray) -> dict:
        """Run the exact chain on (K, 6) placements; arrays come back shaped (K, N, ...)."""
        k, n = len(placements), len(self.samples)
        task, force = placed_task(self.robot, self.samples, placements)
        if self.method == "closed_form":
            joints, reachable = try_joint_trajectory(self.robot, task, "closed_form")
        else:  # the generic solver walks each placement from the reference configuration
            pieces = [try_joint_trajectory(self.robot, _rows(task, i * n, (i + 1) * n), self.method) for i in range(k)]
            joints = type(pieces[0][0])(*(np.concatenate([getattr(p[0], f) for p in pieces])
                                          for f in ("q", "v", "a", "basis", "task_map")))
            reachable = np.concatenate([p[1] for p in pieces])
        effort = actuator_efforts(self.robot, joints, force)
        act_q = [a.q_index for a in self.robot.actuators]
        act_v = self.robot.actuated_v_indices
        shape = (k, n, len(act_v))
        out = {"reachable": reachable.reshape(k, n), "tool": task.position_m.reshape(k, n, 3),
               "position": joints.q[:, act_q].reshape(shape), "velocity": joints.v[:, act_v].reshape(shape),
               "acceleration": joints.a[:, act_v].reshape(shape), "effort": effort.reshape(shape)}
        out["motor"] = motor_trace(self.robot, out["effort"], out["velocity"], out["acceleration"])
        self.evaluations += k
        return out

    def evaluate(self, placements: np.ndarray) -> Evaluation:
        """Energy and tightest margins of (K, 6) placements."""
        placements = np.atleast_2d(np.asarray(placements, dtype=float))
        if placements.shape[1] != 6 or not np.isfinite(placements).all():
            raise PlacementError(f"placements must be finite (K, 6) arrays [x, y, z, phi, theta, psi], got shape "
                                 f"{placements.shape}{'' if np.isfinite(placements).all() else ' with NaN or inf'}")
        if self.workers > 1 and len(placements) >= 2:
            return self._evaluate_in_workers(placements)
        batch = max(1, BATCH_SAMPLES // len(self.samples))
        parts = [self._evaluate_batch(placements[i:i + batch]) for i in range(0, len(placements), batch)]
        return Evaluation(placements=placements, energy_J=np.concatenate([p[0] for p in parts]),
                          margins=np.concatenate([p[1] for p in parts]), limits=parts[0][2],
                          reachable=np.concatenate([p[3] for p in parts]))

    def _evaluate_in_workers(self, placements: np.ndarray) -> Evaluation:
        if self._pool is None:
            self._pool = ProcessPoolExecutor(max_workers=self.workers, initializer=single_threaded_rnea)
        chunks = np.array_split(placements, min(self.workers, len(placements)))
        job = (self.robot, self.path, self.regeneration, self.time_step_s, self.method)
        parts = list(self._pool.map(evaluate_in_worker, *zip(*[(*job, chunk) for chunk in chunks])))
        self.evaluations += len(placements)
        return Evaluation(placements=placements, energy_J=np.concatenate([p.energy_J for p in parts]),
                          margins=np.concatenate([p.margins for p in parts]), limits=parts[0].limits,
                          reachable=np.concatenate([p.reachable for p in parts]))

    def _evaluate_batch(self, placements: np.ndarray) -> tuple[np.ndarray, np.ndarray, tuple[str, ...], np.ndarray]:
        chain = self._chain(placements)
        energy = electric_energy(self.robot, chain["motor"], self.samples.t_s, self.samples.piece, self.regeneration)
        fields = margin_fields(self.robot, chain["position"], chain["velocity"], chain["motor"], chain["tool"])
        margins, labels = worst_margins(fields)
        reachable = chain["reachable"].all(axis=1)
        margins[~reachable] = np.minimum(margins[~reachable], UNREACHABLE_MARGIN)
        return np.where(reachable, energy.total_J, np.inf), margins, tuple(labels), reachable

    def detail(self, placement: np.ndarray) -> PlacementDetail:
        """Energy breakdown, margins and per-sample trace of one placement."""
        placement = np.asarray(placement, dtype=float)
        chain = {key: (value[0] if isinstance(value, np.ndarray) else value)
                 for key, value in self._chain(placement[None]).items()}
        motor = MotorTrace(*(getattr(chain["motor"], f)[0] for f in ("speed_rad_s", "torque_Nm", "current_A")))
        energy = electric_energy(self.robot, motor, self.samples.t_s, self.samples.piece, self.regeneration)
        fields = margin_fields(self.robot, chain["position"], chain["velocity"], motor, chain["tool"])
        return PlacementDetail(
            placement=placement, reachable=bool(chain["reachable"].all()),
            unreachable_samples=np.flatnonzero(~chain["reachable"]), energy=energy, margins=tightest(fields),
            samples=self.samples, tool_position_m=chain["tool"], position=chain["position"],
            velocity=chain["velocity"], acceleration=chain["acceleration"], effort=chain["effort"], motor=motor,
            power_W=sample_power(self.robot, motor, self.samples.t_s, self.samples.piece))


def single_threaded_rnea() -> None:
    """Worker initialiser: one RNEA thread per process, since the processes share the cores."""
    from placement import dynamics

    dynamics.THREADS = 1


def evaluate_in_worker(robot: Robot, path: ToolPath, regeneration: str, time_step_s: float | None,
                       method: str, placements: np.ndarray) -> Evaluation:
    """Evaluate placements in a worker process (the robot arrives as it is in memory)."""
    return Evaluator(robot, path, regeneration, time_step_s, method, workers=1).evaluate(placements)


def _rows(task, start: int, stop: int):
    """Samples start:stop of a task trajectory."""
    from placement.kinematics import TaskTrajectory

    return TaskTrajectory(*(None if value is None else value[start:stop]
                            for value in (task.position_m, task.velocity_m_s, task.acceleration_m_s2,
                                          task.rotation, task.angular_velocity_rad_s, task.angular_acceleration_rad_s2)))
