"""The exact chain for many placements at once: path -> base frame -> kinematics -> dynamics ->
drives -> objective and limits.

Placements are evaluated in batches: the path samples of every placement are stacked and go
through the robot's kinematics solver and one batched RNEA call, so that thousands of placements
of hundreds of samples each stay cheap. A solver that is not vectorised (the sequential one), and
the optimal timing law, which times placements one by one, have their batches shared among worker
processes.
"""

from __future__ import annotations

import dataclasses
import multiprocessing
import os
from collections.abc import Callable, Sequence
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import dataclass

import numpy as np

from placement.contract.batch import EvaluatedBatch
from placement.contract.limit import LIMITS, margin_fields, tightest, worst_margins
from placement.contract.objective import OBJECTIVES, Objective
from placement.dynamics.inverse import TreeDynamics, actuator_efforts
from placement.dynamics.path_dynamics import path_dynamics, sample_rows
from placement.energy.integration import Energy, sample_power
from placement.energy.regeneration import REGENERATION
from placement.energy.trace import motor_trace
from placement.evaluation.parallel import process_pool
from placement.evaluation.results import Evaluation, PlacementDetail
from placement.evaluation.timed_motion import OptimalMotion, optimal_motion
from placement.exceptions import SettingsError
from placement.kinematics.base import solver_for
from placement.kinematics.trajectories import JointTrajectory
from placement.path.time_law import TimeLaw
from placement.path.toolpath import ToolPath
from placement.placing.profiles import redundant_variables
from placement.placing.transform import placed_task
from placement.registry import restore_runtime_members, runtime_members
from placement.robot.model import Robot
from placement.stiffness import has_springs
from placement.timing.optimal import time_optimal
from placement.timing.rules import check_timing

BATCH_SAMPLES = 60_000  # samples per batched call (memory: about 0.5 kB a sample)
UNREACHABLE_MARGIN = -1.0  # every margin of an unreachable placement: how infeasible it is, to steer the search


@dataclass(frozen=True)
class EvaluatorSettings:
    """How an :class:`Evaluator` evaluates placements: what it computes, on which samples, with which resources.

    Attributes:
        objective: Objective's name, see :mod:`placement.objectives`; or several names, the ranking
            one first, all of which :meth:`Evaluator.evaluate` computes.
        regeneration: Regeneration policy's name, see :mod:`placement.energy.regeneration`.
        time_step_s: Sampling step (default: the path file's).
        method: Kinematics solver's name, see :func:`placement.kinematics.joint_trajectory`.
        workers: Worker processes for a solver that is not vectorised or the optimal timing law, or
            chunks to cut a batch into for an executor (default: every core, or 1 in a pool's
            worker process, whose pool shares the cores already); 1 evaluates in this process.
        threads: Threads of the batched kinematics and RNEA (default: every core).
        exact: Compute every limit exactly at every sample in :meth:`Evaluator.evaluate` too (a
            re-check); :meth:`Evaluator.detail` always does.
        refine: Under the optimal timing law, cut each interval between the path geometry's
            samples in this many (:meth:`placement.path.toolpath.ToolPath.geometry`).
        margin: The share (0 to 1) of every limit a feasible placement keeps free at every sample:
            of a joint's range, of a speed or torque limit, of the workspace box's side, reachability
            and timing as they are; for a collision, the clearance beyond the required one per
            100 mm (0.05: 5 mm more than the cell's ``margin_m``). 0, the default: the limits themselves.
        feasibility_only: Only whether each placement is feasible is read from :meth:`Evaluator.evaluate`, not
            how much room a limit that holds has left (a global search, a tolerance box): a limit may then
            return, for a margin beyond ``margin``, a lower bound of it still beyond ``margin``. A
            gradient-based polish reads the margins near ``margin`` as values, and needs the default.
    """

    objective: str | tuple[str, ...] = "energy"
    regeneration: str = "clip"
    time_step_s: float | None = None
    method: str = "auto"
    workers: int | None = None
    threads: int | None = None
    exact: bool = False
    refine: int = 1
    margin: float = 0.0
    feasibility_only: bool = False

    def __post_init__(self) -> None:
        if not 0.0 <= self.margin < 1.0:
            raise SettingsError(f"the margin kept from every limit must be a share from 0 to 1, got {self.margin}")
        if not isinstance(self.objective, str):  # any sequence of names, kept as a tuple (hashable, picklable)
            object.__setattr__(self, "objective", tuple(self.objective))

    @property
    def objectives(self) -> tuple[str, ...]:
        """The objectives' names, the ranking one first."""
        return (self.objective,) if isinstance(self.objective, str) else self.objective


class Evaluator:
    """Evaluates placements of one path on one robot.

    A solver that is not vectorised (the sequential one), and the optimal timing law, have their
    batches of placements shared among worker processes; call :meth:`close` (or use ``with``) to
    stop them.

    Args:
        robot: The robot (its actuators need drives).
        path: The tool path.
        settings: What to compute, on which samples, with which resources (default: the electric
            energy, on the path file's sampling, on every core).
        executor: Any ``concurrent.futures.Executor`` (a Dask cluster's, see
            :mod:`placement.evaluation.parallel`) that evaluates batches in chunks, whatever the solver,
            instead of this process or an own process pool.
    """

    def __init__(self, robot: Robot, path: ToolPath, settings: EvaluatorSettings = EvaluatorSettings(),
                 executor: Executor | None = None) -> None:
        REGENERATION.get(settings.regeneration)  # unknown names fail here, before any work
        self.robot = robot
        self.path = path
        self.settings = settings
        self.threads = settings.threads or os.cpu_count() or 1
        self.solver = solver_for(robot, settings.method, self.threads)
        self.dynamics = TreeDynamics(robot.model)
        self.objective_names = settings.objectives
        self.objective_name = self.objective_names[0]
        self.objectives: tuple[Objective, ...] = tuple(OBJECTIVES.get(name) for name in self.objective_names)
        self.objective = self.objectives[0]
        check_timing(self.objective_names, path)
        if path.timing.mode == "optimal" and robot.profile_knots > 1:
            raise SettingsError(f"robot '{robot.name}' profiles {', '.join(robot.redundant_joints)} along the path, which "
                                "the optimal timing law does not support yet: use another timing, a constant profile "
                                "(--knots 1) or --lock the joint(s)")
        step = settings.time_step_s
        self.geometry = path.geometry(step, settings.refine) if path.timing.mode == "optimal" else None
        self.samples = path.sample(step) if self.geometry is None else self.geometry.evaluated_samples
        self.distinct = None if self.geometry is None else np.flatnonzero(np.diff(self.geometry.grid_rows, prepend=-1))
        self.evaluations = 0  # placements evaluated so far
        spread = executor is not None or not self.solver.vectorized
        cores = (os.cpu_count() or 1) if multiprocessing.parent_process() is None else 1
        self.workers = (settings.workers or cores) if spread else 1
        self.executor = executor
        self._own_pool: ProcessPoolExecutor | None = None

    def __enter__(self) -> Evaluator:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Stop the worker processes, if any were started."""
        if self._own_pool is not None:
            self._own_pool.shutdown()
            self._own_pool = None

    def job(self, placements: np.ndarray) -> EvaluationJob:
        """Everything a worker process needs to evaluate ``placements`` as this evaluator would."""
        return EvaluationJob(self.robot, self.path, self.settings, placements,
                             runtime_members(members_used(self.robot, self.objective_names, self.settings.regeneration,
                                                          self.settings.method)))

    def batch(self, placements: np.ndarray, exact: bool | None = None, law: TimeLaw | None = None) -> EvaluatedBatch:
        """Run the exact chain on (K, 6) placements; arrays come back shaped (K, N, ...).

        Args:
            placements: (K, 6) placement vectors.
            exact: Limits computed exactly at every sample (default: the settings' ``exact``).
            law: Under the optimal timing law, the placements' timing on this evaluator's path
                geometry (:meth:`placement.path.time_law.TimeLaw.resampled`) instead of their time-optimal one.
        """
        k = len(placements)
        exact = self.settings.exact if exact is None else exact
        solved = self.samples if self.geometry is None else self.geometry.samples
        task, force = placed_task(self.robot, solved, placements)
        joints, reachable, _ = self.solver.solve(task, k)
        reachable, position_m = reachable.reshape(k, len(solved)), task.position_m.reshape(k, len(solved), 3)
        timing = None
        act_v = self.robot.actuated_v_indices
        if self.geometry is None:
            effort = actuator_efforts(self.robot, joints, force, self.threads, self.dynamics)
            shape = (k, len(self.samples), len(act_v))
            position = joints.q[:, self.robot.actuated_q_indices].reshape(shape)
            velocity, acceleration = joints.v[:, act_v].reshape(shape), joints.a[:, act_v].reshape(shape)
            effort = effort.reshape(shape)
        else:
            timing = self._time_optimally(joints, force, np.asarray(reachable.all(axis=1)), law)
            joints, position, velocity, acceleration = timing.joints, timing.position, timing.velocity, timing.acceleration
            effort = timing.effort
            reachable, position_m = reachable[:, self.geometry.grid_rows], sample_rows(position_m, self.geometry.grid_rows)
        self.evaluations += k
        return EvaluatedBatch(robot=self.robot, samples=self.samples, placements=placements, reachable=reachable,
                              tool_position_m=position_m, position=position, velocity=velocity,
                              acceleration=acceleration, effort=effort,
                              motor=motor_trace(self.robot, effort, velocity, acceleration),
                              regeneration=self.settings.regeneration, joints=joints,
                              exact=exact, required_margin=self.settings.margin,
                              feasibility_only=self.settings.feasibility_only and not exact,
                              time_law=None if timing is None else timing.samples_law,
                              path_law=None if timing is None else timing.law, distinct_samples=self.distinct,
                              max_deflection_m=self.path.max_deflection_m,
                              loaded_solver=self.solver if self.path.loaded_stiffness else None)

    def _time_optimally(self, joints: JointTrajectory, force: np.ndarray, reachable: np.ndarray,
                        given: TimeLaw | None) -> OptimalMotion:
        """Time each placement optimally (:mod:`placement.timing`), or as ``given``, from its motion at unit speed
        at the path geometry's samples; the motion comes back at the evaluated samples."""
        assert self.geometry is not None
        dynamics = path_dynamics(self.robot, joints, force, len(reachable), self.threads, self.dynamics)
        law = time_optimal(self.robot, self.geometry, dynamics, reachable) if given is None else given
        return optimal_motion(self.robot, self.geometry, joints, dynamics, law)

    def evaluate(self, placements: np.ndarray) -> Evaluation:
        """Objective and tightest margins of (K, 6) placements, or (K, 6 + R·knots) with a redundant robot's knots
        (:mod:`placement.placing.profiles`)."""
        placements = np.atleast_2d(np.asarray(placements, dtype=float))
        widths = sorted({6, 6 + len(redundant_variables(self.robot))})
        if placements.ndim != 2 or placements.shape[1] not in widths or not np.isfinite(placements).all():
            names = ", ".join(("x", "y", "z", "phi", "theta", "psi", *redundant_variables(self.robot)))
            raise SettingsError(f"placements must be finite (K, {' or '.join(map(str, widths))}) arrays [{names}], got "
                                f"shape {placements.shape}{'' if np.isfinite(placements).all() else ' with NaN or inf'}")
        if (self.executor is not None or self.workers > 1) and len(placements) >= 2:
            return self._evaluate_in_workers(placements)
        return self._in_batches(placements, self._evaluate_batch)

    def _evaluate_in_workers(self, placements: np.ndarray) -> Evaluation:
        executor = self.executor
        if executor is None:
            executor = self._own_pool = self._own_pool or process_pool(self.workers)
        chunks = np.array_split(placements, min(max(self.workers, 2), len(placements)))
        parts = list(executor.map(evaluate_job, [self.job(chunk) for chunk in chunks]))
        self.evaluations += len(placements)
        return Evaluation.concatenate(parts)

    def recheck(self, placements: np.ndarray, source: Evaluator) -> Evaluation:
        """Objective and tightest margins of (K, 6) placements moving as ``source`` (the same path sampled
        otherwise, see :func:`denser`) moves them, on this evaluator's samples: a re-check between the
        source's samples.

        Under the optimal timing law, the placements keep the timing found on the source's samples
        (:meth:`placement.path.time_law.TimeLaw.resampled`) instead of being timed anew; the other laws
        time every placement alike anyway.
        """
        placements = np.atleast_2d(np.asarray(placements, dtype=float))
        if self.geometry is None or source.geometry is None:
            return self.evaluate(placements)
        return self._in_batches(placements, lambda chunk: self._evaluate_batch(chunk, self._timing_of(chunk, source)))

    def _in_batches(self, placements: np.ndarray, evaluate: Callable[[np.ndarray], Evaluation]) -> Evaluation:
        """``evaluate`` on batches of at most BATCH_SAMPLES samples, the results one after the other."""
        batch = max(1, BATCH_SAMPLES // len(self.samples))
        return Evaluation.concatenate([evaluate(placements[i:i + batch]) for i in range(0, len(placements), batch)])

    def _timing_of(self, placements: np.ndarray, source: Evaluator) -> TimeLaw:
        """The optimal timing that ``source`` finds for the placements, at this evaluator's path geometry."""
        law = source.batch(placements).path_law
        assert law is not None and source.geometry is not None and self.geometry is not None  # both time optimally
        return law.resampled(source.geometry, self.geometry)

    def _evaluate_batch(self, placements: np.ndarray, law: TimeLaw | None = None) -> Evaluation:
        batch = self.batch(placements, law=law)
        margins, labels, reachable = batch_margins(batch)
        return Evaluation(placements=placements, objectives=self.objective_names,
                          values=batch_values(batch, self.objectives, reachable), margins=margins, limits=labels,
                          reachable=reachable, required_margin=self.settings.margin)

    def detail(self, placement: np.ndarray) -> PlacementDetail:
        """Objective, energy breakdown, margins and per-sample trace of one placement."""
        placement = np.asarray(placement, dtype=float)
        batch = self.batch(placement[None], exact=True)
        reachable = batch.reachable[0]
        motor = batch.motor[0]
        samples = self.samples if batch.time_law is None else batch.time_law.timed_samples(self.samples, 0)
        return PlacementDetail(
            placement=placement, objective=self.objective_name,
            value=float(self.objective(batch)[0]) if reachable.all() else self.objective.sign * np.inf,
            reachable=bool(reachable.all()), unreachable_samples=np.flatnonzero(~reachable),
            energy=_first(batch.energy), margins=tightest(margin_fields(batch)), samples=samples,
            tool_position_m=batch.tool_position_m[0], position=batch.position[0], velocity=batch.velocity[0],
            acceleration=batch.acceleration[0], effort=batch.effort[0], configuration=batch.joints.q, motor=motor,
            power_W=sample_power(self.robot, motor, samples.t_s, samples.piece), timing=self.path.timing.mode,
            duration_s=float(np.ptp(samples.t_s) if batch.time_law is None else batch.time_law.duration_s[0]),
            hold_effort=_hold_effort(self.robot, batch.joints), required_margin=self.settings.margin,
            deflection=batch.deflection.summary(0, samples.position_m) if reachable.all() and has_springs(self.robot)
            else None)


def batch_margins(batch: EvaluatedBatch) -> tuple[np.ndarray, tuple[str, ...], np.ndarray]:
    """(K, L) each placement's tightest margin of every limit (at most UNREACHABLE_MARGIN where a sample is out of
    reach), the limits' names, and (K,) which placements reach every sample."""
    margins, labels = worst_margins(margin_fields(batch))
    reachable = np.asarray(batch.reachable.all(axis=1))
    margins[~reachable] = np.minimum(margins[~reachable], UNREACHABLE_MARGIN)
    return margins, labels, reachable


def batch_values(batch: EvaluatedBatch, objectives: Sequence[Objective], reachable: np.ndarray) -> np.ndarray:
    """(K, n_objectives) each placement's objectives, the worst value (±inf) where it does not reach the path."""
    return np.column_stack([np.where(reachable, objective(batch), objective.sign * np.inf)
                            for objective in objectives])


def _hold_effort(robot: Robot, joints: JointTrajectory) -> np.ndarray:
    """(n_act,) actuator efforts holding the last sample's configuration still with no external load (gravity)."""
    last = slice(len(joints) - 1, len(joints))
    still = np.zeros_like(joints.v[last])
    return actuator_efforts(robot, JointTrajectory(joints.q[last], still, still, joints.basis[last],
                                                   joints.task_map[last]), threads=1)[0]


def _first(energy: Energy) -> Energy:
    """The energies of the first placement of a batch."""
    return Energy(total_J=energy.total_J[0], per_actuator_J=energy.per_actuator_J[0], joule_J=energy.joule_J[0],
                  inductive_J=energy.inductive_J[0], back_emf_J=energy.back_emf_J[0],
                  mechanical_J=energy.mechanical_J[0], regeneration=energy.regeneration)


@dataclass(frozen=True)
class EvaluationJob:
    """Placements to evaluate in another process, with all it takes (picklable).

    The robot travels as it is in memory (a plug-in module is re-loaded from its file), and so do
    the plug-in family members registered at run time in this process.
    """

    robot: Robot
    path: ToolPath
    settings: EvaluatorSettings
    placements: np.ndarray
    registered: dict[str, dict[str, object]]

    def evaluator(self) -> Evaluator:
        """An evaluator like the one the job came from, in this process on one thread (a worker shares the
        cores), with the plug-in members it uses registered here."""
        restore_runtime_members(self.registered)
        return Evaluator(self.robot, self.path, dataclasses.replace(self.settings, workers=1, threads=1))


def members_used(robot: Robot, objectives: tuple[str, ...], regeneration: str, method: str) -> dict[str, set[str]]:
    """The plug-in members an evaluation uses, by entry-point group."""
    drives = [a.drive for a in robot.actuators if a.drive is not None]
    return {"placement.objectives": set(objectives), "placement.regeneration": {regeneration},
            "placement.motor_models": {d.motor.model for d in drives},
            "placement.transmissions": {d.transmission.type for d in drives},
            "placement.kinematics": {method, robot.kinematics_name or ""}, "placement.limits": set(LIMITS.names())}


def evaluate_job(job: EvaluationJob) -> Evaluation:
    """Evaluate a job's placements (in a worker process: one RNEA thread, since workers share the cores)."""
    return job.evaluator().evaluate(job.placements)


def denser(source: Evaluator, density: int) -> Evaluator:
    """An evaluator of the same path sampled ``density`` times more densely, for :meth:`Evaluator.recheck`.

    The time step is ``density`` times shorter; under the optimal timing law, each interval of the
    source's path geometry is cut in ``density`` instead, so that a timing found on the source's
    samples switches at samples of this one. It computes every limit exactly, in this process.
    """
    settings = dataclasses.replace(source.settings, workers=1, threads=source.threads, exact=True)
    step = source.path.time_step_s if settings.time_step_s is None else settings.time_step_s
    if source.geometry is None:
        return Evaluator(source.robot, source.path, dataclasses.replace(settings, time_step_s=step / density, refine=1))
    return Evaluator(source.robot, source.path,
                     dataclasses.replace(settings, time_step_s=step, refine=settings.refine * density))


