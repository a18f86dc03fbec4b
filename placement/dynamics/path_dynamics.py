"""Actuator efforts along a path, affine in the path motion: F(s) = A(s)·s̈ + B(s)·ṡ² + C(s).

Along a path p(s), every joint moves as q(s), so its velocity and acceleration are q'·ṡ and
q'·s̈ + q''·ṡ², and the projected RNEA (linear in the accelerations, quadratic in the velocities)
gives the efforts exactly in this form: A, B and C are the efforts of three motions at each
sample's configuration (:func:`path_dynamics`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from placement.dynamics.inverse import TreeDynamics, load_efforts
from placement.kinematics.trajectories import JointTrajectory
from placement.robot.model import Robot


@dataclass(frozen=True)
class PathDynamics:
    """What limits the motion along the path of K placements, per sample, in the actuators' units.

    Attributes:
        velocity: (K, N, n_act) q' of the actuated joints (per metre of path).
        curvature: (K, N, n_act) q'' of the actuated joints (per metre² of path).
        inertia, centripetal, static: (K, N, n_act) A, B and C of the efforts (module docstring).
    """

    velocity: np.ndarray
    curvature: np.ndarray
    inertia: np.ndarray
    centripetal: np.ndarray
    static: np.ndarray

    def rows(self, index: np.ndarray) -> PathDynamics:
        """The same at some samples (an index into the sample axis), laid out column by column
        (:func:`sample_rows`)."""
        return PathDynamics(*(sample_rows(getattr(self, f.name), index) for f in dataclasses.fields(PathDynamics)))

    @property
    def shape(self) -> tuple[int, ...]:
        """(K, N, n_act)."""
        return self.velocity.shape

    @property
    def joint_velocity(self) -> PathForm:
        """q̇ = q'·ṡ of the actuated joints."""
        return PathForm(w=self.velocity)

    @property
    def joint_acceleration(self) -> PathForm:
        """q̈ = q'·s̈ + q''·ṡ² of the actuated joints."""
        return PathForm(a=self.velocity, b=self.curvature)

    @property
    def effort(self) -> PathForm:
        """The actuator efforts A·s̈ + B·ṡ² + C."""
        return PathForm(a=self.inertia, b=self.centripetal, c=self.static)


def sample_rows(values: np.ndarray, index: np.ndarray) -> np.ndarray:
    """(K, len(index), m) ``values`` (K, N, m) at some samples, laid out column by column: each column's (K,
    len(index)) numbers contiguous, so that numpy's elementwise operations and reductions on them run along the
    samples (on rows of m numbers, m = 3 actuators, each of its loops runs about six times slower) and a
    placement's values do not depend on the other placements of its batch."""
    return np.moveaxis(np.take(np.moveaxis(values, -1, 0), index, axis=-1), 0, -1)


class PathForm:
    """A quantity along the path, affine in the path motion: a·s̈ + b·ṡ² + c + w·ṡ.

    Each term is an array broadcastable to (K, N, m): K placements, N samples, m columns (actuators,
    or some of them). Forms add, subtract and scale by arrays, so that an equation written once for
    a motion sampled in time (arrays) gives the same quantity along the path (forms): the drives'
    equations (:class:`placement.energy.trace.Drives`) serve the motor trace and the optimal timing
    law alike.
    """

    __array_ufunc__ = None  # ndarray ⊙ PathForm defers to PathForm's reflected operators

    def __init__(self, a: np.ndarray | float = 0.0, b: np.ndarray | float = 0.0, c: np.ndarray | float = 0.0,
                 w: np.ndarray | float = 0.0) -> None:
        self.a, self.b, self.c, self.w = a, b, c, w

    @property
    def terms(self) -> tuple[np.ndarray | float, ...]:
        """(a, b, c, w)."""
        return self.a, self.b, self.c, self.w

    def __add__(self, other: PathForm | np.ndarray | float) -> PathForm:
        if isinstance(other, PathForm):
            return PathForm(*(x + y for x, y in zip(self.terms, other.terms)))
        return PathForm(self.a, self.b, self.c + other, self.w)

    __radd__ = __add__

    def __neg__(self) -> PathForm:
        return PathForm(*(-x for x in self.terms))

    def __sub__(self, other: PathForm | np.ndarray | float) -> PathForm:
        return self + (-other)

    def __rsub__(self, other: np.ndarray | float) -> PathForm:
        return -self + other

    def __mul__(self, scale: np.ndarray | float) -> PathForm:
        if isinstance(scale, PathForm):
            return NotImplemented  # a product of two forms is not affine
        return PathForm(*(x * scale for x in self.terms))

    __rmul__ = __mul__

    def __truediv__(self, scale: np.ndarray | float) -> PathForm:
        return PathForm(*(x / scale for x in self.terms))

    def __call__(self, speed: np.ndarray, acceleration: np.ndarray) -> np.ndarray:
        """The quantity for ṡ and s̈ of shape (K, N): (K, N, m)."""
        s_dot, s_ddot = speed[..., None], acceleration[..., None]
        return self.a * s_ddot + self.b * s_dot**2 + self.c + self.w * s_dot

    @property
    def speed_only(self) -> bool:
        """Whether only the term in ṡ is there (a bound on the speed along the path)."""
        return not any(np.any(term) for term in (self.a, self.b, self.c))

    def columns(self, index: np.ndarray | list[int], shape: tuple[int, ...]) -> PathForm:
        """Some columns of the form, its terms broadcast to ``shape`` (K, N, m) first."""
        return PathForm(*(np.broadcast_to(term, shape)[..., index] for term in self.terms))


def path_dynamics(robot: Robot, joints: JointTrajectory, force: np.ndarray, placements: int,
                  threads: int | None = None, dynamics: TreeDynamics | None = None) -> PathDynamics:
    """The efforts along the path of K placements, from their joints' motion at unit speed along the path.

    Args:
        robot: The robot.
        joints: Every joint's motion at unit speed along the path (v = q', a = q''), K·N rows.
        force: (K·N, 3 or 6) load on the end effector, as for :func:`placement.dynamics.inverse.actuator_efforts`.
        placements: K.
        threads: Most threads (default: every core; fewer on small batches).
        dynamics: The robot's tree dynamics, where the caller keeps them (default: built from ``robot.model``).

    Returns:
        A, B and C: the tree's torques at rest under gravity, with q̈ = q' alone and with q̇ = q', q̈ = q''
        without gravity (:meth:`TreeDynamics.path_efforts`), projected on the actuators; C less the load's share.
        Each array is laid out column by column, as :func:`sample_rows` says why.
    """
    act = robot.actuated_v_indices
    shape = (placements, len(joints.q) // placements, len(act))
    efforts = (dynamics or TreeDynamics(robot.model)).path_efforts(joints.q, joints.v, joints.a, joints.basis,
                                                                   threads)  # (K·N, 3, n_act): C, A, B
    static = np.subtract(efforts[:, 0], load_efforts(joints, force), order="F")  # laid out as the torques are
    return PathDynamics(*(np.moveaxis(np.ascontiguousarray(x.T).reshape(shape[::-1][:1] + shape[:2]), 0, -1)
                          for x in (joints.v[:, act], joints.a[:, act], efforts[:, 1], efforts[:, 2], static)))
