"""The generic kinematics solver (``numeric``): any closed-loop or serial robot, batched in numpy.

Every sample of every placement is solved together, by the compiled kernels of
:mod:`~placement.kinematics.kernels`:

1. **Assembly.** Each placement's first sample is reached from the reference configuration by
   continuation (small steps of the end effector), so that every placement starts on the
   reference configuration's assembly mode and branch.
2. **Coarse march.** Samples about 2 cm apart along the path follow one another, each
   seeded by the first-order prediction ``q + D·Δx`` (``D = G·M⁺``) of the previous one.
3. **Refinement.** The samples in between are filled in by bisection, level by level: each new
   sample is seeded by cubic interpolation of its solved neighbours and Newton converges in one or
   two steps for all of them at once.

Newton works on the stacked closure residuals and task error (damped least squares on the normal
equations). A sample whose Newton step moves it far from its prediction has left the branch (a
flip) and is reported, as is one that does not converge or is singular. Rates and accelerations
follow from the closure Jacobian and its drift, as for the sequential solver:
``v = G·ρ̇`` with ``G[act] = I``, ``G[passive] = −J_p⁺·J_a``, and ``a = G·ρ̈ − J_p⁺·γ`` on the
passive joints.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from scipy.spatial.transform import Rotation

from placement.kinematics import kernels
from placement.kinematics.base import SINGULAR_CONDITION, SOLVERS, KinematicsSolver
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory
from placement.kinematics.tree import log3, tree_arrays, unsupported_joints
from placement.robot.model import Robot

SOLVE_TOLERANCE = 1e-11  # residual norm (m and rad) at which Newton stops
MAX_ITERATIONS = 30
MAX_STEP = 0.2  # largest joint step of one Newton iteration (m or rad)
DAMPING = 1e-14  # Levenberg term of the normal equations (keeps rank-deficient samples finite)
CONTINUATION_STEP_M = 0.05  # assembly: end-effector step from the reference configuration (predicted)
CONTINUATION_TOLERANCE = 1e-5  # assembly: residual norm enough on the way (m and rad)
COARSE_STEP_M = 0.02  # coarse march: task displacement between marched samples (rotation counts 0.1 m/rad)
ROTATION_LENGTH_M = 0.1  # metres per radian when measuring task displacements
BRANCH_TOLERANCE = 1e-3  # a solution this far beyond twice its local motion has left the branch (m or rad)


@dataclass(frozen=True)
class Targets:
    """End-effector targets of a batch: positions (B, 3) and, for a pose task, rotations (B, 3, 3)."""

    position_m: np.ndarray
    rotation: np.ndarray | None

    def rows(self, index: np.ndarray) -> Targets:
        """The targets of some samples."""
        return Targets(self.position_m[index], None if self.rotation is None else self.rotation[index])


class BatchedKinematics:
    """Newton, tangents and rates for one robot over batches of configurations (compiled kernels)."""

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        frame_ids = [f for c in robot.closures for f in c.frame_ids] + [robot.end_effector_frame_id]
        closures = [(2 * i, 2 * i + 1, c.dimension) for i, c in enumerate(robot.closures)]
        self.dim = robot.task_dimension
        self.tree = tree_arrays(robot.model, frame_ids, closures=closures, end_effector=len(frame_ids) - 1,
                                task_dimension=self.dim, actuated=robot.actuated_v_indices)
        self.frame_ids = frame_ids

    def end_effector(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """End-effector rotation (3, 3) and position (3,) at one configuration."""
        rotation, origin, _, _ = kernels.frames(self.tree, q[None, :].astype(float), np.zeros((1, len(q))))
        return rotation[0, -1], origin[0, -1]

    def newton(self, q: np.ndarray, targets: Targets, tolerance: float = SOLVE_TOLERANCE) -> tuple[np.ndarray, np.ndarray]:
        """Newton from (B, nq) starts to a residual norm below ``tolerance``; returns the configurations and
        which converged."""
        pose = targets.rotation is not None
        rotation = targets.rotation if pose else np.zeros((len(q), 3, 3))
        return kernels.newton(self.tree, np.ascontiguousarray(q, dtype=float),
                              np.ascontiguousarray(targets.position_m, dtype=float),
                              np.ascontiguousarray(rotation, dtype=float), pose, tolerance, MAX_ITERATIONS, MAX_STEP,
                              DAMPING)

    def rates(self, q: np.ndarray, task: TaskTrajectory) -> tuple[JointTrajectory, np.ndarray]:
        """Joint motion at solved configurations, and which samples are regular (not singular)."""
        v, a, basis, task_map, condition = kernels.rates(self.tree, np.ascontiguousarray(q, dtype=float),
                                                         np.ascontiguousarray(task.twist(), dtype=float),
                                                         np.ascontiguousarray(task.acceleration(), dtype=float),
                                                         DAMPING)
        return JointTrajectory(q, v, a, basis, task_map), condition < SINGULAR_CONDITION

    def tangent(self, q: np.ndarray) -> np.ndarray:
        """(B, nq, task dim) first-order change of the configuration per task displacement, D = G·M⁺."""
        return kernels.tangent(self.tree, np.ascontiguousarray(q, dtype=float), DAMPING)


def _displacement(start: Targets, stop: Targets) -> np.ndarray:
    """(B, dim) displacement between two sets of targets: position, then rotation (world)."""
    move = stop.position_m - start.position_m
    if start.rotation is None or stop.rotation is None:
        return move
    return np.hstack([move, log3(stop.rotation @ start.rotation.transpose(0, 2, 1))])


def coarse_samples(targets: Targets, n: int) -> np.ndarray:
    """Indices (within the first placement) of samples about COARSE_STEP_M apart along the task, ends included."""
    steps = _displacement(targets.rows(np.arange(n - 1)), targets.rows(np.arange(1, n)))
    length = np.linalg.norm(steps[:, :3], axis=1)
    if steps.shape[1] == 6:
        length = length + ROTATION_LENGTH_M * np.linalg.norm(steps[:, 3:], axis=1)
    arc = np.concatenate([[0.0], np.cumsum(length)])
    marks = np.flatnonzero(np.diff(np.floor(arc / COARSE_STEP_M)) > 0) + 1
    return np.unique(np.concatenate([[0], marks, [n - 1]]))


class BatchedSolver(KinematicsSolver):
    """Newton for any robot of revolute and prismatic joints, every sample of every placement at once."""

    vectorized: ClassVar[bool] = True

    @classmethod
    def unsuitable(cls, robot: Robot) -> str | None:
        unsupported = unsupported_joints(robot.model)
        return f"joints of a kind it does not handle: {', '.join(unsupported)}" if unsupported else None

    def __init__(self, robot: Robot) -> None:
        super().__init__(robot)
        self.kinematics = BatchedKinematics(robot)

    def solve(self, task: TaskTrajectory, placements: int = 1) -> tuple[JointTrajectory, np.ndarray, str]:
        n = len(task) // placements
        targets = Targets(task.position_m, task.rotation)
        first = np.arange(placements) * n
        q = np.tile(self.robot.reference_q, (len(task), 1))
        ok = np.zeros(len(task), dtype=bool)
        q[first], ok[first] = self._assemble(targets.rows(first))
        coarse = coarse_samples(targets, n) if n > 1 else np.zeros(1, dtype=int)
        flipped = self._march(targets, q, ok, first, coarse)
        flipped |= self._refine(targets, q, ok, first, coarse, n)
        joints, regular = self.kinematics.rates(q, task)
        reachable = ok & ~flipped & regular
        bad = np.flatnonzero(~reachable)
        if len(bad):
            k = bad[0]
            where = f" at sample {k % n} ({np.round(task.position_m[k], 6).tolist()} m)"
            if not ok[k]:
                reason = "no configuration reaches the target" + where
            elif flipped[k]:
                reason = "the configuration leaves the reference assembly mode or branch" + where
            else:
                reason = "singular configuration: the actuators cannot produce the task motion" + where
            joints = _at_rest(joints, ~reachable, self.robot.reference_q)
        else:
            reason = ""
        return joints, reachable, reason

    def _assemble(self, targets: Targets) -> tuple[np.ndarray, np.ndarray]:
        """Each placement's first configuration, by continuation from the reference configuration."""
        kin, k = self.kinematics, len(targets.position_m)
        q = np.tile(self.robot.reference_q, (k, 1))
        rotation, position = kin.end_effector(self.robot.reference_q)
        distance = np.linalg.norm(targets.position_m - position, axis=1)
        turn = None
        if targets.rotation is not None:
            turn = log3(rotation.T @ targets.rotation)  # (K, 3) in the reference end-effector frame
            distance = np.maximum(distance, ROTATION_LENGTH_M * np.linalg.norm(turn, axis=1))
        steps = max(1, int(np.ceil(distance.max() / CONTINUATION_STEP_M)))
        ok = np.ones(k, dtype=bool)
        previous = Targets(np.tile(position, (k, 1)), None if turn is None else np.tile(rotation, (k, 1, 1)))
        for s in np.linspace(0.0, 1.0, steps + 1)[1:]:
            goal = Targets(position + s * (targets.position_m - position),
                           None if turn is None else rotation @ _exp3(s * turn))
            seed = q + np.einsum("kqt,kt->kq", kin.tangent(q), _displacement(previous, goal))  # first-order predictor
            q_next, converged = kin.newton(seed, goal, SOLVE_TOLERANCE if s == 1.0 else CONTINUATION_TOLERANCE)
            q[converged] = q_next[converged]
            ok &= converged
            previous = goal
        return q, ok

    def _march(self, targets: Targets, q: np.ndarray, ok: np.ndarray, first: np.ndarray,
               coarse: np.ndarray) -> np.ndarray:
        """Solve the coarse samples one after the other (batched over placements); returns flips."""
        flipped = np.zeros(len(q), dtype=bool)
        for previous, current in zip(coarse[:-1], coarse[1:]):
            before, now = first + previous, first + current
            prediction = np.einsum("kqt,kt->kq", self.kinematics.tangent(q[before]),
                                   _displacement(targets.rows(before), targets.rows(now)))
            prediction[~ok[before]] = 0.0  # after a failure, start again from the last solved configuration
            seed = q[before] + prediction
            solved, converged = self.kinematics.newton(seed, targets.rows(now))
            q[now] = np.where(converged[:, None], solved, q[before])
            flipped[now] = ok[before] & _left_branch(solved, seed, prediction)
            ok[now] = converged
        return flipped

    def _refine(self, targets: Targets, q: np.ndarray, ok: np.ndarray, first: np.ndarray, coarse: np.ndarray,
                n: int) -> np.ndarray:
        """Fill in the samples between coarse ones by bisection with cubic seeds; returns flips."""
        flipped = np.zeros(len(q), dtype=bool)
        known = np.zeros(n, dtype=bool)
        known[coarse] = True
        while not known.all():
            index = np.flatnonzero(known)
            left, right = index[:-1], index[1:]
            gap = right - left > 1
            left, right = left[gap], right[gap]
            middle = (left + right) // 2
            outer_left = index[np.maximum(np.searchsorted(index, left) - 1, 0)]
            outer_right = index[np.minimum(np.searchsorted(index, right) + 1, len(index) - 1)]
            neighbours = np.stack([outer_left, left, right, outer_right])
            rows = (first[:, None] + middle[None, :]).ravel()
            seed = _cubic(q, first, neighbours, middle)
            solved, converged = self.kinematics.newton(seed, targets.rows(rows))
            q[rows] = np.where(converged[:, None], solved, seed)
            ok[rows] = converged
            span = (q[(first[:, None] + right[None, :]).ravel()] - q[(first[:, None] + left[None, :]).ravel()])
            flipped[rows] = _left_branch(solved, seed, span)
            known[middle] = True
        return flipped


def _left_branch(solved: np.ndarray, seed: np.ndarray, motion: np.ndarray) -> np.ndarray:
    """Whether Newton moved each sample farther from its seed than twice the motion around it.

    A seed errs by less than the local motion, even across a corner of the path; another branch
    or assembly mode lies a finite distance away.
    """
    return np.abs(solved - seed).max(axis=1) > 2.0 * np.abs(motion).max(axis=1) + BRANCH_TOLERANCE


def _cubic(q: np.ndarray, first: np.ndarray, nodes: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Lagrange interpolation at ``at`` through the solved samples ``nodes`` (4, M), per placement.

    An outer node equal to its inner neighbour (at the ends of the path) is left out.
    """
    x = nodes.astype(float)
    used = np.stack([x[0] != x[1], np.ones(len(at), bool), np.ones(len(at), bool), x[3] != x[2]])
    seed = np.zeros((len(first) * len(at), q.shape[1]))
    for i in range(4):
        weight = used[i].astype(float)
        for j in range(4):
            if j != i:
                factor = (at - x[j]) / np.where(x[i] != x[j], x[i] - x[j], 1.0)
                weight *= np.where(used[j], factor, 1.0)
        seed += np.tile(weight, len(first))[:, None] * q[(first[:, None] + nodes[i][None, :]).ravel()]
    return seed


def _exp3(rotation_vectors: np.ndarray) -> np.ndarray:
    return Rotation.from_rotvec(rotation_vectors).as_matrix()


def _at_rest(joints: JointTrajectory, rows: np.ndarray, reference_q: np.ndarray) -> JointTrajectory:
    """The joint motion with some samples replaced by the reference configuration at rest."""
    q, v, a = joints.q.copy(), joints.v.copy(), joints.a.copy()
    basis, task_map = joints.basis.copy(), joints.task_map.copy()
    q[rows], v[rows], a[rows] = reference_q, 0.0, 0.0
    basis[rows] = np.nan_to_num(basis[rows])
    task_map[rows] = np.nan_to_num(task_map[rows])
    return JointTrajectory(q, v, a, basis, task_map)


SOLVERS.add("numeric", BatchedSolver)
