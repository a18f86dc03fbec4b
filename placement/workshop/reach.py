"""The workspace a closed-loop robot reaches with its actuators: a box the path search can trust.

:func:`reached_box` estimates it in four steps, for a mechanism with as many actuators as
directions its end effector moves in (two for a planar one, three for a spatial one); the constants
are this module's:

1. **The actuators' ranges, sampled by continuation.** A grid over the actuated joints' ranges
   (each actuator's ``position_min`` .. ``position_max``), anchored at the reference configuration,
   of about ``GRID_NODES`` nodes (50 per side for two actuators, 14 for three), is flooded from
   the reference: each node is solved from a solved neighbour in ``SUB_STEPS`` steps, each predicted
   to first order (``q + G·Δρ``) and corrected by Newton on the passive joints alone (the closure
   residuals, the actuators held). A step is refused, and the flood goes no further that way, when
   Newton does not converge, when its correction exceeds ``BRANCH_RATIO`` times the predicted motion
   (the passive joints jumped to another assembly mode or branch), when the passive joints' closure
   Jacobian (its translation rows per metre of the end effector's distance from the base, so that
   they weigh as its rotation rows) or the task map (actuators to end effector, in the directions it
   moves in) has a condition number beyond ``CONDITION_LIMIT``, or when the task map's determinant
   changes sign (a serial singularity crossed between two samples). The nodes reached are the
   actuator values the robot reaches from its reference configuration without leaving its branch or
   coming near a singularity.
2. **The reached set, in the directions the end effector moves in.** Each cell of the grid is cut
   into n! simplices (Kuhn's triangulation); a simplex whose corners were all reached, and whose image
   (the end effector's positions at its corners) keeps the orientation of the task map at the
   reference (it is not folded over a singularity), covers its image. The points of a raster over
   the reached positions (``RASTER`` per side, ``RASTER_3D`` for three directions) that some
   simplex covers are the reached set.
3. **The largest box inside.** The axis-aligned box, its corners raster points, whose raster points
   are all reached, of the largest area (volume).
4. **Checked by the search's own solver.** The ``numeric`` solver reaches every point of a
   ``CHECK_GRID``-per-side grid over the box (``CHECK_GRID_3D``) from the reference configuration,
   as it reaches a path's first sample (continuation on the reference's branch, not singular), with
   the actuators within their ranges. A point it misses removes the raster points around it (half
   the grid's spacing each way) and step 3 runs again, up to ``CHECK_ROUNDS`` times. (For a
   mechanism small beside the solver's 5 cm continuation step, the solver shortens its steps:
   :func:`placement.kinematics.batched.continuation_step`.)

The box need not hold the end effector's reference position: ``robot_delta`` is exported with its
arms hanging, 0.4 mm above the lowest point it reaches, where a box grown around it (the other way
to find a workspace, growing a box while the solver reaches) stays a few millimetres tall; the
check of step 4 reaches the box from there.

Costs and choices, measured on Gepetto's ``robot_delta`` and five-bars and the test five-bar (2
shared cores): the whole estimate takes 0.6 to 1.1 s for two actuators (2 401 nodes; the flood's
Newton iterations in Python most of it) and 4 s for the built-in Delta's three (2 197 nodes).
10 000 nodes grow the box's area by 2 to 7 % at 3 to 4 times the cost; 900 nodes lose 2 to 18 %.
A second flood over just the actuator ranges the first one reached grows the area by at most 4 % at
2 to 3 times the cost, and is not done. A condition limit of 1e2 stops at ``robot_delta``'s reference
configuration (its closure Jacobian's condition is 270 there); 1e4 changes the boxes by at most
1.2 %, while 1e6 lets ``robot_delta``'s grow by a quarter into poses within a hair of a singularity.
"""

from __future__ import annotations

import itertools
import math
from collections import deque
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from placement.kinematics.base import SOLVERS
from placement.kinematics.generic import null_space_basis
from placement.kinematics.trajectories import TaskTrajectory
from placement.robot.closures import LWA, closure_jacobian, closure_residuals
from placement.robot.model import Robot

GRID_NODES = 2500  # nodes of the actuator grid, about
SUB_STEPS = 4  # continuation steps from a node to its neighbour
NEWTON_TOLERANCE = 1e-10  # closure residual (m, rad) at which a step is solved
NEWTON_ITERATIONS = 15
BRANCH_RATIO = 0.5  # a Newton correction beyond this share of the predicted passive motion left the branch
CONDITION_LIMIT = 1e3  # condition number of the closure or task Jacobian at which the flood stops
RASTER = 64  # raster points per side over the reached positions, two directions (or one)
RASTER_3D = 24  # three directions
CHECK_GRID = 17  # points per side of the grid the numeric solver checks over the box, two directions (or one)
CHECK_GRID_3D = 9  # three directions
CHECK_ROUNDS = 6  # most times the box is chosen again after the numeric solver missed some of its points


@dataclass(frozen=True)
class Reach:
    """The actuator grid flooded from the reference configuration.

    Attributes:
        values: Per actuator, the grid's values (m or rad).
        reached: Boolean array of the grid's shape: the nodes reached.
        positions: The end effector's position at each node (grid shape + (3,), m; NaN where not reached).
    """

    values: tuple[np.ndarray, ...]
    reached: np.ndarray
    positions: np.ndarray


@dataclass(frozen=True)
class ReachedBox:
    """The estimated workspace box.

    Attributes:
        low_m, high_m: Its corners (m); along the axes the end effector does not move along, its
            position at the reference configuration.
        text: How it was found, for the sidecar's ``sources``.
    """

    low_m: np.ndarray
    high_m: np.ndarray
    text: str


def reached_box(robot: Robot, directions: np.ndarray, axes: np.ndarray, centre: np.ndarray,
                normal: np.ndarray | None) -> ReachedBox | str:
    """The largest box inside what the actuators reach, checked by the numeric solver (the module's rule).

    Args:
        robot: A closed-loop robot at its closed reference configuration.
        directions: (3, n) orthonormal directions the end effector moves in at the reference.
        axes: The n base axes (0 x, 1 y, 2 z) the box extends along, as many as actuators.
        centre: The end effector's position at the reference (m).
        normal: The unit normal of a planar mechanism's plane, onto which the checked points are moved; None
            otherwise.

    Returns:
        The box, or why there is none (a phrase).
    """
    n = len(axes)
    ranges = np.array([[actuator.position_min, actuator.position_max] for actuator in robot.actuators])
    reach = flood(robot, directions, ranges, GRID_NODES)
    grid_text = f"{int(reach.reached.sum())} of a {' x '.join(map(str, reach.reached.shape))} grid over their ranges"
    if reach.reached.sum() < 2**n:
        return (f"the actuators reach {grid_text} from reference_configuration (its condition number is beyond "
                f"{CONDITION_LIMIT:g}, or it is singular)")
    covered, centres = reached_raster(reach, axes, _task_sign(robot, axes))
    solver = SOLVERS.get("numeric")(robot)
    side = CHECK_GRID if n <= 2 else CHECK_GRID_3D
    for _ in range(CHECK_ROUNDS):
        box = largest_box(covered)
        if box is None:
            return f"the positions reached at {grid_text} hold no box"
        low = np.array([c[i] for c, i in zip(centres, box[0])])
        high = np.array([c[i] for c, i in zip(centres, box[1])])
        grid = np.stack(np.meshgrid(*(np.linspace(a, b, side) for a, b in zip(low, high)), indexing="ij"), -1)
        grid = grid.reshape(-1, n)
        missed = ~_solver_reaches(robot, solver, grid, axes, centre, normal)
        if not missed.any():
            low_m, high_m = centre.copy(), centre.copy()
            low_m[axes], high_m[axes] = low, high
            return ReachedBox(low_m, high_m, (
                f"the largest box, along the directions the end effector moves in, inside the positions it reaches "
                f"with the actuators at {grid_text}, reached from reference_configuration by continuation short of "
                f"singularities (condition number {CONDITION_LIMIT:g}); every point of a {side}-per-side grid over it "
                "reached by the numeric solver (placement/workshop/reach.py)"))
        spacing, first = (high - low) / (side - 1), np.array([c[0] for c in centres])
        step = np.array([c[1] - c[0] for c in centres])
        for point in grid[missed]:
            start = np.maximum(np.floor((point - spacing / 2 - first) / step).astype(int), 0)
            stop = np.ceil((point + spacing / 2 - first) / step).astype(int) + 1
            covered[tuple(slice(a, b) for a, b in zip(start, stop))] = False
    return f"the numeric solver misses points of every box inside the positions reached at {grid_text}"


def _solver_reaches(robot: Robot, solver: object, grid: np.ndarray, axes: np.ndarray, centre: np.ndarray,
                    normal: np.ndarray | None) -> np.ndarray:
    """Which points of ``grid`` (m, along ``axes``) the numeric solver reaches from the reference configuration,
    each a path of one sample, with the actuators in their ranges."""
    points = np.repeat(centre[None], len(grid), axis=0)
    points[:, axes] = grid
    if normal is not None:
        points -= np.outer((points - centre) @ normal, normal)
    still = np.zeros_like(points)
    joints, reachable, _ = solver.solve(TaskTrajectory(points, still, still), len(points))  # type: ignore[attr-defined]
    for actuator in robot.actuators:
        value = joints.q[:, actuator.q_index]
        reachable &= (value >= actuator.position_min) & (value <= actuator.position_max)
    return reachable


def flood(robot: Robot, directions: np.ndarray, ranges: np.ndarray, nodes: int = GRID_NODES) -> Reach:
    """The actuator grid flooded from ``robot.reference_q`` (step 1 of the module's rule).

    Args:
        robot: A closed-loop robot at its closed reference configuration.
        directions: (3, n) orthonormal directions the end effector moves in at the reference (m per m).
        ranges: (n, 2) each actuator's range to sample (m or rad).
        nodes: The grid's nodes, about.
    """
    model, data = robot.model, robot.model.createData()
    passive = np.setdiff1d(np.arange(model.nv), robot.actuated_v_indices)
    n = len(robot.actuators)
    reference = robot.reference_q.copy()
    pin.framesForwardKinematics(model, data, reference)
    length = max(float(np.linalg.norm(data.oMf[robot.end_effector_frame_id].translation)), 1e-3)
    row_scale = np.concatenate([[1 / length] * 3 + [1.0] * (c.dimension - 3) for c in robot.closures])
    per_side = max(3, int(round(nodes ** (1 / n))))
    values, origin = [], []
    for actuator, (low, high) in zip(robot.actuators, ranges):
        at = float(reference[actuator.q_index])
        low, high = min(low, at), max(high, at)
        step = (high - low) / (per_side - 1) if high > low else 1.0
        first, last = math.ceil((low - at) / step - 1e-9), math.floor((high - at) / step + 1e-9)
        values.append(at + step * np.arange(first, last + 1))
        origin.append(-first)
    shape = tuple(len(v) for v in values)
    configurations = np.full((*shape, model.nq), np.nan)
    bases = np.full((*shape, model.nv, n), np.nan)
    positions = np.full((*shape, 3), np.nan)

    def measured(q: np.ndarray) -> tuple[np.ndarray, np.ndarray, float] | None:
        """G, the end effector's position and the task map's determinant at ``q``; None near a singularity."""
        jacobian = closure_jacobian(robot, data, q)
        if np.linalg.cond(row_scale[:, None] * jacobian[:, passive]) > CONDITION_LIMIT:
            return None
        basis, _, _ = null_space_basis(robot, jacobian)
        task = directions.T @ pin.getFrameJacobian(model, data, robot.end_effector_frame_id, LWA)[:3] @ basis
        if np.linalg.cond(task) > CONDITION_LIMIT:
            return None
        return basis, data.oMf[robot.end_effector_frame_id].translation.copy(), float(np.linalg.det(task))

    def closed(q: np.ndarray) -> np.ndarray | None:
        """Newton on the passive joints from ``q``: the closed configuration, or None."""
        for _ in range(NEWTON_ITERATIONS):
            residual = closure_residuals(robot, data, q)
            if np.abs(residual).max(initial=0.0) < NEWTON_TOLERANCE:
                return q
            step = np.zeros(model.nv)
            step[passive] = -np.linalg.lstsq(closure_jacobian(robot, data, q)[:, passive], residual, rcond=None)[0]
            q = pin.integrate(model, q, step)
        return None

    def solved(index: tuple[int, ...], neighbour: tuple[int, ...]) -> bool:
        """Walk from the solved ``neighbour`` to node ``index``; whether it is reached."""
        q, basis = configurations[neighbour], bases[neighbour]
        move = np.array([values[i][index[i]] - values[i][neighbour[i]] for i in range(n)]) / SUB_STEPS
        for _ in range(SUB_STEPS):
            predicted_step = basis @ move
            predicted = pin.integrate(model, q, predicted_step)
            solution = closed(predicted)
            if solution is None:
                return False
            correction = np.abs(pin.difference(model, predicted, solution)).max()
            there = measured(solution)
            if correction > BRANCH_RATIO * np.abs(predicted_step).max() or there is None or there[2] * sign <= 0:
                return False
            q, basis, position = solution, there[0], there[1]
        configurations[index], bases[index], positions[index] = q, basis, position
        return True

    home = tuple(origin)
    found = measured(reference)
    if found is None:
        return Reach(tuple(values), np.zeros(shape, bool), positions)
    sign = math.copysign(1.0, found[2])
    configurations[home], bases[home], positions[home] = reference, found[0], found[1]
    queue = deque([home])
    while queue:  # breadth first, so that each node is reached from a near neighbour
        node = queue.popleft()
        for axis, direction in itertools.product(range(n), (-1, 1)):
            index = tuple(k + direction if i == axis else k for i, k in enumerate(node))
            if 0 <= index[axis] < shape[axis] and np.isnan(positions[index][0]) and solved(index, node):
                queue.append(index)
    return Reach(tuple(values), ~np.isnan(positions[..., 0]), positions)


def kuhn_simplices(n: int) -> np.ndarray:
    """(n!, n + 1, n) corner offsets of the simplices of Kuhn's triangulation of the unit n-cube."""
    simplices = []
    for order in itertools.permutations(range(n)):
        corners = [np.zeros(n, int)]
        for axis in order:
            corner = corners[-1].copy()
            corner[axis] = 1
            corners.append(corner)
        simplices.append(corners)
    return np.array(simplices)


def reached_raster(reach: Reach, axes: np.ndarray, sign: float) -> tuple[np.ndarray, list[np.ndarray]]:
    """Step 2 of the module's rule: which raster points the reached simplices cover.

    Args:
        reach: The flooded grid.
        axes: The base axes the end effector moves along, as many as actuators.
        sign: Sign of the task map's determinant at the reference, its rows ``axes``.

    Returns:
        The covered points (a boolean array, ``RASTER`` per side), and the raster's coordinates along each axis (m).
    """
    n = len(axes)
    points = reach.positions[..., axes]
    low, high = points[reach.reached].min(axis=0), points[reach.reached].max(axis=0)
    side = RASTER if n <= 2 else RASTER_3D
    spacing = np.maximum(high - low, 1e-12) / (side - 1)
    covered = np.zeros((side,) * n, bool)
    simplices = kuhn_simplices(n)
    turns = [np.linalg.det(np.diff(corners, axis=0).T.astype(float)) for corners in simplices]
    for cell in itertools.product(*(range(k - 1) for k in reach.reached.shape)):
        for corners, turn in zip(simplices, turns):
            index = tuple((np.array(cell) + corners).T)
            if not reach.reached[index].all():
                continue
            image = points[index]  # (n + 1, n): the end effector at the simplex's corners
            edges = (image[1:] - image[0]).T
            if np.linalg.det(edges) * turn * sign <= 0:  # folded over a singularity, or flat
                continue
            first = np.maximum(np.ceil((image.min(axis=0) - low) / spacing - 1e-9).astype(int), 0)
            last = np.minimum(np.floor((image.max(axis=0) - low) / spacing + 1e-9).astype(int), side - 1)
            if (last < first).any():
                continue
            candidates = np.stack(np.meshgrid(*(np.arange(a, b + 1) for a, b in zip(first, last)), indexing="ij"), -1)
            candidates = candidates.reshape(-1, n)
            weights = np.linalg.solve(edges, (low + candidates * spacing - image[0]).T)
            inside = (weights >= -1e-9).all(axis=0) & (weights.sum(axis=0) <= 1 + 1e-9)
            covered[tuple(candidates[inside].T)] = True
    return covered, [low[i] + spacing[i] * np.arange(side) for i in range(n)]


def largest_box(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """Step 3 of the module's rule: the first and last indices, per axis, of the box of True points of ``mask``
    of the largest product of its spans (points per side less one); None when every such box is flat."""
    if mask.ndim == 1:
        padded = np.concatenate([[0], mask.astype(int), [0]])
        edges = np.flatnonzero(np.diff(padded))
        starts, lengths = edges[::2], edges[1::2] - edges[::2]
        if not len(lengths) or lengths.max() < 2:
            return None
        k = int(lengths.argmax())
        return np.array([starts[k]]), np.array([starts[k] + lengths[k] - 1])
    best: tuple[int, np.ndarray, np.ndarray] | None = None
    for first in range(mask.shape[0]):
        both = mask[first].copy()
        for last in range(first + 1, mask.shape[0]):
            both &= mask[last]
            if not both.any():
                break
            inner = largest_box(both)
            if inner is not None:
                span = (last - first) * int(np.prod(inner[1] - inner[0]))
                if best is None or span > best[0]:
                    best = (span, np.array([first, *inner[0]]), np.array([last, *inner[1]]))
    return None if best is None else (best[1], best[2])


def _task_sign(robot: Robot, axes: np.ndarray) -> float:
    """Sign of the task map's determinant at the reference configuration, its rows the base ``axes``."""
    data = robot.model.createData()
    basis, _, _ = null_space_basis(robot, closure_jacobian(robot, data, robot.reference_q))
    task = pin.getFrameJacobian(robot.model, data, robot.end_effector_frame_id, LWA)[axes] @ basis
    return math.copysign(1.0, float(np.linalg.det(task)))
