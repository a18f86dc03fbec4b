"""Profiles of redundant coordinates along a path: their knots are placement variables.

A robot with redundant joints (a seven-axis arm's elbow rotation, a track's position,
``Robot.redundant_joints``) leaves them to the search: each follows a profile along the path, a natural
cubic spline through ``knots`` values at equal shares of the path's arc length (one knot: a constant,
two: a straight line). The
knots are placement variables named ``JOINT@K`` (K from 0, at share K/(knots − 1) of the path),
appended to the six of :mod:`placement.placing.transform`, so a placement vector is
[x, y, z, φ, θ, ψ, knots of the first redundant joint, knots of the second, ...] (m, rad): a revolute
joint's knots are angles, a prismatic joint's lengths (:func:`length_variables`).

A robot may also leave the spin of its tool about the tool's own axis (z) to the search (the sidecar's
``redundancy.spin``): a constant angle, the placement variable ``spin`` (rad; deg on the command line),
which comes right after the six, before the knots. For a tool along the last joint's axis the spin
costs nothing (that joint absorbs it); for a spindle mounted across the flange it moves the arm.

A closed path (its tool ends where and as it starts) is worked cycle after cycle, so its profiles
close too: the knots stand at shares K/knots and a periodic cubic spline joins them, back to the first
knot's value at the end. Without this, a search would end the pass with the arm lower than it began
and count the potential energy released as saved, which the next pass pays back.

Along the path, the share of arc length σ(t) = s(t)/L runs from 0 to 1 with σ̇ = (v·t̂)/L and
σ̈ = (a·t̂)/L (t̂ the unit feed direction), s the time integral of v·t̂ (trapezoids); a joint's value
is q(σ), its rate q'(σ)·σ̇, its acceleration q''(σ)·σ̇² + q'(σ)·σ̈: the spline is C², so the joint
accelerations are continuous and the energy is that of a smooth motion. A path that does not move
its tool point (a pose list turning in place) runs its share on time instead.
"""

from __future__ import annotations

import functools

import numpy as np
from scipy.interpolate import CubicSpline

from placement.path.samples import PathSamples
from placement.robot.model import Robot

KNOT_SEPARATOR = "@"
SPIN = "spin"


def knot_names(robot: Robot) -> tuple[str, ...]:
    """The placement variables of the robot's redundant joints' knots, ``JOINT@K``, joint after joint."""
    return tuple(f"{joint}{KNOT_SEPARATOR}{k}" for joint in robot.redundant_joints for k in range(robot.profile_knots))


def redundant_variables(robot: Robot) -> tuple[str, ...]:
    """The placement variables after the six: the tool's spin (if the robot leaves it free), then the knots."""
    return ((SPIN,) if robot.tool_spin else ()) + knot_names(robot)


def knot_joint(name: str) -> str:
    """The joint whose profile a knot variable (``JOINT@K``) shapes."""
    return name.rsplit(KNOT_SEPARATOR, 1)[0]


def prismatic_joints(robot: Robot) -> frozenset[str]:
    """The robot's prismatic actuated joints: their values, and their knots, are lengths."""
    return frozenset(actuator.joint for actuator in robot.actuators if actuator.prismatic)


def length_variables(robot: Robot) -> frozenset[str]:
    """The redundant variables that are lengths (m; mm on the command line): the knots of prismatic joints (a
    track's position). Every other variable after the six is an angle (rad; deg on the command line)."""
    prismatic = prismatic_joints(robot)
    return frozenset(name for name in knot_names(robot) if knot_joint(name) in prismatic)


def redundant_bounds(robot: Robot) -> dict[str, tuple[float, float]]:
    """Each redundant variable's bounds, by name: the spin's whole turn, a knot's joint range (m or rad): its
    actuator's (the sidecar's, or a continuous joint's turn about the reference), else the URDF's limits."""
    model = robot.model
    ranges = {actuator.joint: (actuator.position_min, actuator.position_max) for actuator in robot.actuators}
    bounds = {SPIN: (-np.pi, np.pi)} if robot.tool_spin else {}
    for name in knot_names(robot):
        joint = knot_joint(name)
        q = model.joints[model.getJointId(joint)].idx_q
        low, high = ranges.get(joint, (model.lowerPositionLimit[q], model.upperPositionLimit[q]))
        bounds[name] = (float(low), float(high))
    return bounds


def redundant_defaults(robot: Robot) -> dict[str, float]:
    """Each redundant variable's value when none is given: no spin, a knot its joint's value at the reference
    configuration (m or rad)."""
    knots = {name: float(robot.reference_q[q]) for name, q in
             zip(knot_names(robot), np.repeat(robot.redundant_q_indices, robot.profile_knots), strict=True)}
    return {SPIN: 0.0, **knots} if robot.tool_spin else knots


def path_share(samples: PathSamples) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The share of arc length σ (N,) from 0 to 1 at each sample, and its first and second time derivatives (1/s,
    1/s²); on time where the tool point does not move (module docstring)."""
    speed = np.einsum("ij,ij->i", samples.velocity_m_s, samples.tangent)
    tangential = np.einsum("ij,ij->i", samples.acceleration_m_s2, samples.tangent)
    arc = np.concatenate([[0.0], np.cumsum(np.diff(samples.t_s) * (speed[1:] + speed[:-1]) / 2)])
    length = arc[-1]
    if not length > 0.0:
        duration = max(float(np.ptp(samples.t_s)), np.finfo(float).tiny)
        t = samples.t_s - samples.t_s[0]
        return t / duration, np.full(len(t), 1.0 / duration), np.zeros(len(t))
    return arc / length, speed / length, tangential / length


CLOSED_TOLERANCE = 1e-9  # m and rad: a path whose tool ends this near its start pose is closed


def is_closed(samples: PathSamples) -> bool:
    """Whether the tool ends where and as it starts (to CLOSED_TOLERANCE): a closed path, worked cycle after cycle."""
    if np.abs(samples.position_m[-1] - samples.position_m[0]).max() > CLOSED_TOLERANCE:
        return False
    return samples.rotation is None or np.abs(samples.rotation[-1] - samples.rotation[0]).max() <= CLOSED_TOLERANCE


def knot_shares(knots: int, closed: bool) -> np.ndarray:
    """The share of arc length each knot stands at: K/(knots − 1), or K/knots on a closed path (0 for one knot)."""
    if knots == 1:
        return np.zeros(1)
    return np.arange(knots) / (knots if closed else knots - 1)


@functools.lru_cache(maxsize=8)
def _spline_basis(knots: int, closed: bool) -> tuple[CubicSpline, ...]:
    """The cubic spline through ``knots`` unit values at :func:`knot_shares`, natural, or periodic on a closed path,
    and its first two derivatives."""
    if knots == 1:
        raise ValueError("a single knot is a constant")
    if closed:
        values = np.vstack([np.eye(knots), np.eye(knots)[:1]])
        spline = CubicSpline(np.linspace(0.0, 1.0, knots + 1), values, bc_type="periodic")
    else:
        spline = CubicSpline(knot_shares(knots, False), np.eye(knots), bc_type="natural")
    return spline, spline.derivative(1), spline.derivative(2)


def joint_profiles(knots: np.ndarray, samples: PathSamples) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The redundant joints' values, rates and accelerations along the path.

    Args:
        knots: (K, R, n) each placement's knots of each redundant joint (m or rad).
        samples: The path's samples (N).

    Returns:
        Positions, velocities and accelerations, each (K·N, R), placement-major (as the task's samples).
    """
    k, r, n = knots.shape
    sigma, rate, rate_change = path_share(samples)
    if n == 1:
        position = np.broadcast_to(knots[:, None, :, 0], (k, len(sigma), r))
        still = np.zeros_like(position)
        return position.reshape(-1, r), still.reshape(-1, r), still.reshape(-1, r)
    value, slope, bend = (basis(sigma) for basis in _spline_basis(n, is_closed(samples)))  # (N, n) each
    position = np.einsum("sn,krn->ksr", value, knots)
    first, second = np.einsum("sn,krn->ksr", slope, knots), np.einsum("sn,krn->ksr", bend, knots)
    velocity = first * rate[None, :, None]
    acceleration = second * (rate ** 2)[None, :, None] + first * rate_change[None, :, None]
    return position.reshape(-1, r), velocity.reshape(-1, r), acceleration.reshape(-1, r)


def knots_of(robot: Robot, placements: np.ndarray) -> np.ndarray | None:
    """(K, R, n) the knots in placement vectors (K, 6 [+ 1] + R·n), or None for a robot without redundant joints
    or placements of the six variables only (the redundant joints then stay at the reference configuration)."""
    if not robot.redundant_joints or placements.shape[1] == 6:
        return None
    start = 6 + robot.tool_spin
    return placements[:, start:].reshape(len(placements), len(robot.redundant_joints), robot.profile_knots)


def spin_of(robot: Robot, placements: np.ndarray) -> np.ndarray | None:
    """(K,) the tool's spin in placement vectors (rad), or None: a robot that keeps its tool's spin, or placements of
    the six variables only (no spin)."""
    if not robot.tool_spin or placements.shape[1] == 6:
        return None
    return placements[:, 6]
