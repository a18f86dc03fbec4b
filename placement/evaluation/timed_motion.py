"""K placements' motion under the optimal timing law at the evaluated samples, from their motion at unit speed at the
path geometry's samples (:meth:`placement.evaluation.evaluator.Evaluator.batch`).

The evaluated samples are rows of the geometry's (:attr:`placement.path.samples.PathGeometry.grid_rows`), so that the
chain needs each placement's actuated joints' motion and efforts there, (K, N, n_act) arrays, which the path dynamics
give directly. Every joint's motion at those samples (:class:`TimedJoints`) serves some limits, objectives and
reports only, and is gathered when one of them first reads it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, fields

import numpy as np
from numba import njit

from placement.dynamics.path_dynamics import PathDynamics
from placement.kinematics.trajectories import JointTrajectory
from placement.path.samples import PathGeometry
from placement.path.time_law import TimeLaw, timed_rates
from placement.robot.model import Robot

PATH_TERMS = ("velocity", "curvature", "inertia", "centripetal", "static")  # the path dynamics the motion takes


@dataclass(frozen=True)
class OptimalMotion:
    """K placements under the optimal timing law, at the evaluated samples (N of them).

    Attributes:
        law: Their timing at the path geometry's samples.
        samples_law: The same at the evaluated samples.
        joints: Every joint's motion at the evaluated samples, K·N rows (:class:`TimedJoints`).
        position, velocity, acceleration: (K, N, n_act) the actuated joints' motion (m or rad, per s, per s²).
        effort: (K, N, n_act) the actuator efforts (N or N·m).
    """

    law: TimeLaw
    samples_law: TimeLaw
    joints: JointTrajectory
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    effort: np.ndarray


def optimal_motion(robot: Robot, geometry: PathGeometry, unit: JointTrajectory, dynamics: PathDynamics,
                   law: TimeLaw) -> OptimalMotion:
    """K placements timed by ``law`` (at ``geometry``'s samples) at the evaluated samples.

    Args:
        robot: The robot.
        geometry: The path geometry.
        unit: Every joint's motion at unit speed along the path at the geometry's samples, K·len(geometry) rows.
        dynamics: Their path dynamics (:func:`placement.dynamics.path_dynamics.path_dynamics`).
        law: Their timing.
    """
    k, grid = len(law.timed), geometry.grid_rows
    at_samples = law.at_samples(geometry)
    speed, acceleration = at_samples.speed_m_s, at_samples.acceleration_m_s2
    position = unit.q[:, robot.actuated_q_indices].reshape(k, len(geometry), -1)
    columns = np.empty((4, position.shape[2], k, len(grid)))  # each actuator's (K, N) numbers contiguous
    # C-contiguous (the path dynamics, laid out column by column, without a copy): one compiled version
    rate, curvature, inertia, centripetal, static = (np.moveaxis(getattr(dynamics, name), -1, 0) for name in PATH_TERMS)
    _timed_columns(np.ascontiguousarray(position), np.ascontiguousarray(rate), np.ascontiguousarray(curvature),
                   np.ascontiguousarray(inertia), np.ascontiguousarray(centripetal), np.ascontiguousarray(static),
                   np.ascontiguousarray(grid), np.ascontiguousarray(speed), np.ascontiguousarray(acceleration), columns)
    position, velocity, accelerated, effort = np.moveaxis(columns, 1, -1)
    rows = (np.arange(k)[:, None] * len(geometry) + grid).ravel()
    return OptimalMotion(law, at_samples, TimedJoints(unit, rows, speed.reshape(-1, 1), acceleration.reshape(-1, 1)),
                         position, velocity, accelerated, effort)


@njit(cache=True)
def _timed_columns(position: np.ndarray, rate: np.ndarray, curvature: np.ndarray, inertia: np.ndarray,
                   centripetal: np.ndarray, static: np.ndarray, grid: np.ndarray, speed_m_s: np.ndarray,
                   acceleration_m_s2: np.ndarray, columns: np.ndarray) -> None:
    """``columns`` (4, m, K, N): the actuated joints' position q, velocity q'·ṡ, acceleration q'·s̈ + q''·ṡ²
    (:func:`placement.path.time_law.timed_rates`) and effort A·s̈ + B·ṡ² + C
    (:class:`placement.dynamics.path_dynamics.PathDynamics`) at the evaluated samples, each the path geometry's sample
    ``grid[n]``, from q (K, len(geometry), m), the path dynamics there (m, K, len(geometry)) each, and ṡ and s̈
    (K, N)."""
    for j in range(columns.shape[1]):
        for k in range(columns.shape[2]):
            for n in range(columns.shape[3]):
                row, s_dot, s_ddot = grid[n], speed_m_s[k, n], acceleration_m_s2[k, n]
                squared = s_dot**2
                columns[0, j, k, n] = position[k, row, j]
                columns[1, j, k, n] = rate[j, k, row] * s_dot
                columns[2, j, k, n] = rate[j, k, row] * s_ddot + curvature[j, k, row] * squared
                columns[3, j, k, n] = inertia[j, k, row] * s_ddot + centripetal[j, k, row] * squared + static[j, k, row]


class TimedJoints(JointTrajectory):
    """Every joint's motion at some rows of a motion at unit speed along the path, timed by ṡ and s̈ there
    (:func:`placement.path.time_law.timed_rates`): a :class:`placement.kinematics.trajectories.JointTrajectory` whose
    fields are computed when first read (the chain needs few of them, most often none).

    Args:
        unit: The motion at unit speed (v = q', a = q'').
        rows: The rows to take.
        speed_m_s, acceleration_m_s2: (len(rows), 1) ṡ and s̈ at them.
    """

    def __init__(self, unit: JointTrajectory, rows: np.ndarray, speed_m_s: np.ndarray,  # noqa: D107
                 acceleration_m_s2: np.ndarray) -> None:
        def rates() -> dict[str, np.ndarray]:
            velocity, acceleration = timed_rates(unit.v[rows], unit.a[rows], speed_m_s, acceleration_m_s2)
            return {"v": velocity, "a": acceleration}

        def gathered(name: str) -> Callable[[], dict[str, np.ndarray]]:
            return lambda: {name: getattr(unit, name)[rows]}

        object.__setattr__(self, "_pending", {"q": gathered("q"), "v": rates, "a": rates, "basis": gathered("basis"),
                                              "task_map": gathered("task_map")})

    def __getattr__(self, name: str) -> np.ndarray:
        pending = self.__dict__.get("_pending", {})
        if name not in pending:
            raise AttributeError(name)
        for field, value in pending[name]().items():
            object.__setattr__(self, field, value)
        return self.__dict__[name]

    def __reduce__(self) -> tuple[type[JointTrajectory], tuple[np.ndarray, ...]]:
        """Pickled as the plain joint trajectory it stands for."""
        return JointTrajectory, tuple(getattr(self, f.name) for f in fields(JointTrajectory))
