"""The generic kinematics solver (``numeric``): any closed-loop or serial robot, in compiled batches.

Every sample of every placement is solved together, by the compiled kernels of
:mod:`~placement.kinematics.kernels`:

1. **Assembly.** Each placement's first sample is reached from the reference configuration by
   continuation (small steps of the end effector: CONTINUATION_STEP_M, shorter for a robot that
   would turn a joint by more than CONTINUATION_JOINT_STEP over one at its reference configuration,
   see :func:`continuation_step`), so that every placement starts on the reference configuration's
   assembly mode and branch.
2. **Coarse march.** Samples about 2 cm apart along the path follow one another, each
   seeded by the first-order prediction ``q + D·Δx`` (``D = G·M⁺``) of the previous one. Both
   ends of a jump (a step of at least JUMP_M and JUMP_RATIO times its neighbours, such as the gap
   a skipped rapid leaves) are coarse samples, so a jump is marched, never interpolated across.
3. **Refinement.** The samples in between are filled in by bisection, level by level: each new
   sample is seeded by cubic interpolation of its solved neighbours (none across a jump) and Newton
   converges in one or two steps for all of them at once.

Newton works on the stacked closure residuals and task error (damped least squares on the normal
equations). A sample whose Newton step moves it far from its prediction, farther than the joints
can move on one branch over the stretch of path the prediction came from, has left the branch (a
flip) and is reported, as is one that does not converge or is singular. Rates and accelerations
follow from the closure Jacobian and its drift, as for the sequential solver:
``v = G·ρ̇`` with ``G[act] = I``, ``G[passive] = −J_p⁺·J_a``, and ``a = G·ρ̈ − J_p⁺·γ`` on the
passive joints.
"""

from __future__ import annotations

import functools
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from placement.kinematics import kernels
from placement.kinematics.base import SINGULAR_CONDITION, SOLVERS, KinematicsSolver
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory, task_rows
from placement.kinematics.tree import log3, tree_arrays, unsupported_joints
from placement.robot.model import Robot

SOLVE_TOLERANCE = 1e-11  # residual norm (m and rad) at which Newton stops
MAX_ITERATIONS = 30
MAX_STEP = 0.2  # largest joint step of one Newton iteration (m or rad)
DAMPING = 1e-14  # Levenberg term of the normal equations (keeps rank-deficient samples finite)
CONTINUATION_STEP_M = 0.05  # assembly: end-effector step from the reference configuration (predicted) ...
CONTINUATION_JOINT_STEP = 1.0  # ... or shorter, where at the reference a step would turn a joint farther (rad or m)
SHORTEST_CONTINUATION_STEP_M = CONTINUATION_STEP_M / 64  # ... down to this
CONTINUATION_TOLERANCE = 1e-5  # assembly: residual norm enough on the way (m and rad)
COARSE_STEP_M = 0.02  # coarse march: task displacement between marched samples (rotation counts 0.1 m/rad)
ROTATION_LENGTH_M = 0.1  # metres per radian when measuring task displacements
JUMP_M = COARSE_STEP_M / 4  # a task step this long ...
JUMP_RATIO = 4.0  # ... and this many times as long as both its neighbours is a jump (a skipped rapid's gap)
BRANCH_TOLERANCE = 1e-3  # a solution this far beyond twice the joint motion its stretch of path allows left the branch (m, rad)
FINAL_STEP = 1e-7  # a Newton step this short (m or rad) that the linear model says converges is the last one
SETTINGS = np.array([SOLVE_TOLERANCE, MAX_ITERATIONS, MAX_STEP, DAMPING, CONTINUATION_STEP_M, CONTINUATION_TOLERANCE,
                     ROTATION_LENGTH_M, BRANCH_TOLERANCE, FINAL_STEP])  # in the order kernels.solve_paths reads them


@dataclass(frozen=True)
class Targets:
    """End-effector targets of a batch: positions (B, 3) and, for a pose task, rotations (B, 3, 3); and the
    redundant joints' values (B, R) (m or rad; R = 0 for a robot without)."""

    position_m: np.ndarray
    rotation: np.ndarray | None
    joints: np.ndarray | None = None

    def rows(self, index: np.ndarray) -> Targets:
        """The targets of some samples."""
        return Targets(self.position_m[index], None if self.rotation is None else self.rotation[index],
                       None if self.joints is None else self.joints[index])


class BatchedKinematics:
    """Path solves and joint rates for one robot over batches of placements (compiled kernels)."""

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        frame_ids = [f for c in robot.closures for f in c.frame_ids] + [robot.end_effector_frame_id]
        closures = [(2 * i, 2 * i + 1, c.dimension) for i, c in enumerate(robot.closures)]
        self.dim = robot.task_dimension
        self.tree = tree_arrays(robot.model, frame_ids, closures=closures, end_effector=len(frame_ids) - 1,
                                task_dimension=self.dim, actuated=robot.actuated_v_indices,
                                task_joints=robot.redundant_q_indices)
        self.settings = SETTINGS.copy()
        self.settings[4] = continuation_step(self.tree, robot.reference_q)

    def solve_paths(self, targets: Targets, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Configurations of every sample of placements of ``n`` samples each, which converged and which
        left the branch."""
        pose = targets.rotation is not None
        rotation = targets.rotation if pose else np.zeros((len(targets.position_m), 3, 3))
        steps = step_lengths(targets, n, every=self.robot.workpiece_frame is not None)
        jumps = jump_steps(steps)
        coarse = coarse_samples(steps, jumps) if n > 1 else np.zeros(1, dtype=np.int64)
        arc = np.concatenate([[0.0], np.cumsum(steps)])
        joints = self.joint_targets(targets.joints, len(targets.position_m))
        return kernels.solve_paths(self.tree, self.robot.reference_q.astype(float),
                                   np.ascontiguousarray(targets.position_m, dtype=float),
                                   np.ascontiguousarray(rotation, dtype=float), joints, pose, n, coarse.astype(np.int64),
                                   bisection_schedule(coarse, n, jumps), arc, self.settings)

    def joint_targets(self, values: np.ndarray | None, rows: int) -> np.ndarray:
        """(rows, R) the redundant joints' values: ``values``, or their reference values where None."""
        if values is None:
            values = np.broadcast_to(self.robot.reference_q[self.tree.task_joints], (rows, len(self.tree.task_joints)))
        return np.ascontiguousarray(values, dtype=float)

    def rates(self, q: np.ndarray, task: TaskTrajectory) -> tuple[JointTrajectory, np.ndarray]:
        """Joint motion at solved configurations, and which samples are regular (not singular).

        The redundant joints' rates are rows of the task; the task map returned keeps the end effector's rows
        (J_task·G), as the dynamics needs it.
        """
        twist, acceleration = task.twist(), task.acceleration()
        redundant = len(self.tree.task_joints)
        if redundant:
            still = np.zeros((len(q), redundant))
            twist = np.hstack([twist, still if task.joint_velocity is None else task.joint_velocity])
            acceleration = np.hstack([acceleration, still if task.joint_acceleration is None else task.joint_acceleration])
        v, a, basis, task_map, condition = kernels.rates(self.tree, np.ascontiguousarray(q, dtype=float),
                                                         np.ascontiguousarray(twist, dtype=float),
                                                         np.ascontiguousarray(acceleration, dtype=float), DAMPING)
        return JointTrajectory(q, v, a, basis, task_map[:, :self.dim]), condition < SINGULAR_CONDITION


def continuation_step(tree: kernels.TreeArrays, reference_q: np.ndarray) -> float:
    """The assembly's continuation step for one robot (m): CONTINUATION_STEP_M, or the step that turns a joint by
    CONTINUATION_JOINT_STEP at the reference configuration where CONTINUATION_STEP_M would turn it farther (a
    mechanism small beside CONTINUATION_STEP_M, or one whose reference is near a singularity), but no shorter than
    SHORTEST_CONTINUATION_STEP_M.

    The joint motion per metre of task motion is the largest row norm of D = G·M⁺ (rotation columns per
    ROTATION_LENGTH_M), as the branch test measures it; a first-order prediction that turns joints by radians lands
    Newton on another branch, or a turn away.
    """
    q = np.ascontiguousarray(reference_q, dtype=float)[None]
    still = np.zeros((1, tree.task_dimension))
    _, _, basis, task_map, _ = kernels.rates(tree, q, still, still, DAMPING)
    weights = np.where(np.arange(tree.task_dimension) < 3, 1.0, 1.0 / ROTATION_LENGTH_M)
    largest = float(np.linalg.norm(basis[0] @ np.linalg.pinv(task_map[0]) * weights, axis=1).max(initial=0.0))
    if not np.isfinite(largest) or largest * CONTINUATION_STEP_M <= CONTINUATION_JOINT_STEP:
        return CONTINUATION_STEP_M
    return max(CONTINUATION_JOINT_STEP / largest, SHORTEST_CONTINUATION_STEP_M)


def _displacement(start: Targets, stop: Targets) -> np.ndarray:
    """(B, dim) displacement between two sets of targets: position, then rotation (world)."""
    move = stop.position_m - start.position_m
    if start.rotation is None or stop.rotation is None:
        return move
    return np.hstack([move, log3(stop.rotation @ start.rotation.transpose(0, 2, 1))])


def step_lengths(targets: Targets, n: int, every: bool = False) -> np.ndarray:
    """(n - 1,) task displacements between the first placement's successive samples (rotation counted at
    ROTATION_LENGTH_M per radian), m; with ``every``, the longest of every placement's (a workpiece on a positioner:
    the tool's motion in the base frame then differs from placement to placement, as the profiles do)."""
    if n < 2:
        return np.zeros(0)
    rows = np.arange(len(targets.position_m) if every else n).reshape(-1, n)
    steps = _displacement(targets.rows(rows[:, :-1].ravel()), targets.rows(rows[:, 1:].ravel()))
    length = np.linalg.norm(steps[:, :3], axis=1)
    if steps.shape[1] == 6:
        length = length + ROTATION_LENGTH_M * np.linalg.norm(steps[:, 3:], axis=1)
    return length.reshape(-1, n - 1).max(axis=0)


def jump_steps(steps: np.ndarray) -> np.ndarray:
    """Indices k of the steps k -> k + 1 that jump: at least JUMP_M long and JUMP_RATIO times as long as the steps
    on either side (the gap a skipped rapid leaves, not a coarsely sampled path)."""
    before = np.concatenate([steps[:1], steps[:-1]])
    after = np.concatenate([steps[1:], steps[-1:]])
    return np.flatnonzero((steps >= JUMP_M) & (steps > JUMP_RATIO * np.maximum(before, after)))


def coarse_samples(steps: np.ndarray, jumps: np.ndarray) -> np.ndarray:
    """Indices (within the first placement) of samples about COARSE_STEP_M apart along the task, ends included,
    and both ends of every jump (``steps`` and ``jumps`` as in :meth:`BatchedKinematics.solve_paths`)."""
    arc = np.concatenate([[0.0], np.cumsum(steps)])
    marks = np.flatnonzero(np.diff(np.floor(arc / COARSE_STEP_M)) > 0) + 1
    return np.unique(np.concatenate([[0], marks, jumps, jumps + 1, [len(steps)]]))


class BatchedSolver(KinematicsSolver):
    """Newton for any robot of revolute and prismatic joints, every sample of every placement at once."""

    vectorized: ClassVar[bool] = True

    @classmethod
    def unsuitable(cls, robot: Robot) -> str | None:
        unsupported = unsupported_joints(robot.model)
        return f"joints of a kind it does not handle: {', '.join(unsupported)}" if unsupported else None

    def __init__(self, robot: Robot, threads: int | None = None) -> None:
        super().__init__(robot, threads)
        self.kinematics = BatchedKinematics(robot)

    def solve(self, task: TaskTrajectory, placements: int = 1) -> tuple[JointTrajectory, np.ndarray, str]:
        n = len(task) // placements
        parts = [(p[0] * n, (p[-1] + 1) * n) for p in np.array_split(np.arange(placements), min(self.threads, placements))]
        if len(parts) == 1:
            solved = [self._solve_rows(task, n, 0, len(task))]
        else:  # the kernels release the GIL: one chunk of placements per thread
            with ThreadPoolExecutor(len(parts)) as pool:
                solved = list(pool.map(lambda part: self._solve_rows(task, n, *part), parts))
        joints = solved[0][0] if len(solved) == 1 else JointTrajectory.concatenate([part[0] for part in solved])
        ok, flipped, regular = (np.concatenate([part[k] for part in solved]) for k in (1, 2, 3))
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
            _put_at_rest(joints, ~reachable, self.robot.reference_q)
        else:
            reason = ""
        return joints, reachable, reason

    def _solve_rows(self, task: TaskTrajectory, n: int, start: int,
                    stop: int) -> tuple[JointTrajectory, np.ndarray, np.ndarray, np.ndarray]:
        """Joint motion of the placements in rows ``start:stop``, which samples converged, left the branch
        and are regular."""
        rows = task_rows(task, start, stop)
        q, ok, flipped = self.kinematics.solve_paths(Targets(rows.position_m, rows.rotation, rows.joint_position), n)
        joints, regular = self.kinematics.rates(q, rows)
        return joints, ok, flipped, regular


def bisection_schedule(coarse: np.ndarray, n: int, jumps: np.ndarray | None = None) -> np.ndarray:
    """(L, 5) order in which the samples between coarse ones are solved: middle, outer left, left, right,
    outer right, level after level (a level's middles only use samples known before it). An outer node across
    a jump (step k -> k + 1 for k in ``jumps``, both ends coarse) is left out (set to its inner neighbour).

    Every placement of a path has the same schedule, so recent ones are kept (and copied out)."""
    jumps = np.asarray(jumps if jumps is not None else [], dtype=np.int64)
    return _schedule(np.asarray(coarse, dtype=np.int64).tobytes(), n, jumps.tobytes()).copy()


@functools.lru_cache(maxsize=16)
def _schedule(coarse_bytes: bytes, n: int, jumps_bytes: bytes) -> np.ndarray:
    """:func:`bisection_schedule` of coarse samples and jumps given as int64 bytes."""
    coarse, jumps = np.frombuffer(coarse_bytes, dtype=np.int64), np.frombuffer(jumps_bytes, dtype=np.int64)
    jump = np.zeros(n + 1, dtype=bool)
    jump[jumps] = True
    known = np.zeros(n, dtype=bool)
    known[coarse] = True
    levels = []
    while not known.all():
        index = np.flatnonzero(known)
        left, right = index[:-1], index[1:]
        gap = right - left > 1
        left, right = left[gap], right[gap]
        middle = (left + right) // 2
        outer_left = index[np.maximum(np.searchsorted(index, left) - 1, 0)]
        outer_right = index[np.minimum(np.searchsorted(index, right) + 1, len(index) - 1)]
        outer_left = np.where(jump[outer_left] & (outer_left == left - 1), left, outer_left)
        outer_right = np.where(jump[right] & (outer_right == right + 1), right, outer_right)
        levels.append(np.stack([middle, outer_left, left, right, outer_right], axis=1))
        known[middle] = True
    return np.concatenate(levels).astype(np.int64) if levels else np.zeros((0, 5), dtype=np.int64)


def _put_at_rest(joints: JointTrajectory, rows: np.ndarray, reference_q: np.ndarray) -> None:
    """Replace some samples of a freshly solved joint motion, in place, by the reference configuration at rest."""
    joints.q[rows], joints.v[rows], joints.a[rows] = reference_q, 0.0, 0.0
    joints.basis[rows] = np.nan_to_num(joints.basis[rows])
    joints.task_map[rows] = np.nan_to_num(joints.task_map[rows])


SOLVERS.add("numeric", BatchedSolver)
