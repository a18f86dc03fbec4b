"""The three efforts of the path dynamics in one compiled pass of Newton–Euler over the tree (numba).

Along a path, :func:`placement.dynamics.path.path_dynamics` needs, at every sample, the tree's
joint torques of three motions at the same configuration q: at rest under gravity (C), with
q̈ = q' and no velocity nor gravity (A = M·q'), and with q̇ = q', q̈ = q'' and no gravity
(B = c(q, q') + M·q''). Pinocchio's RNEA gives each in its own pass (C, A + C, B + C), computing
the joints' placements three times and the velocity terms of motions that have none.
:func:`path_torques` does the three in one pass per sample: each joint's placement in its parent
once, then the recursive Newton–Euler steps of each motion, in Pinocchio's conventions (spatial
quantities in each joint's frame, linear part first, gravity as an upward acceleration of the
base, the drives' ``armature`` times the joint acceleration added to each torque), so that
C = rnea(q, 0, 0), A = rnea(q, 0, q') − C and B = rnea(q, q', q'') − C to rounding.

Every joint is revolute or prismatic about a fixed axis (:func:`placement.kinematics.tree.joint_axes`);
:func:`tree_inertias` says None for another tree, whose efforts Pinocchio computes. numba compiles
the kernel on its first use and caches the machine code on disk beside this module; the kernel
releases the GIL, so that threads share a batch's samples.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from typing import NamedTuple

import numpy as np
import pinocchio as pin
from numba import njit

from placement.kinematics.tree import joint_axes, joint_constants

_uncounted = njit(cache=True, _nrt=False)  # type: ignore[call-overload]  # allocates nothing: no reference counting (compiles faster)


class TreeInertias(NamedTuple):
    """A spanning tree of revolute and prismatic joints as flat arrays, with its inertias.

    Joints are numbered as in Pinocchio (0: the universe, parents before children).
    """

    parent: np.ndarray  # (nj,) int64 parent joint
    constants: np.ndarray  # (nj, 3, 11) [R0, R0·[a], R0·[a]², R0·a, t0]: the placement in the parent (joint_constants)
    axis: np.ndarray  # (nj, 3) joint axis in the joint's frame
    revolute: np.ndarray  # (nj,) bool
    v_index: np.ndarray  # (nj,) int64 the joint's configuration and velocity index (equal)
    mass: np.ndarray  # (nj,) kg
    lever: np.ndarray  # (nj, 3) centre of mass in the joint's frame (m)
    inertia: np.ndarray  # (nj, 3, 3) rotational inertia about the centre of mass (kg·m²)
    armature: np.ndarray  # (nv,) rotor inertia at each joint (kg·m² or kg)
    gravity: np.ndarray  # (3,) m/s², in the universe's frame


def tree_inertias(model: pin.Model) -> TreeInertias | None:
    """The flat tree of ``model``, or None when a joint is neither revolute nor prismatic about a fixed axis (or has
    a configuration index other than its velocity index)."""
    axes = joint_axes(model)
    if axes is None or any(model.joints[j].idx_q != model.joints[j].idx_v for j in range(1, model.njoints)):
        return None
    axis, revolute = axes
    return TreeInertias(parent=np.array(list(model.parents), dtype=np.int64), constants=joint_constants(model, axis), axis=axis,
                        revolute=revolute, v_index=np.array([max(joint.idx_v, 0) for joint in model.joints],
                                                          dtype=np.int64),
                        mass=np.array([inertia.mass for inertia in model.inertias]),
                        lever=np.array([inertia.lever for inertia in model.inertias]),
                        inertia=np.array([inertia.inertia for inertia in model.inertias]),
                        armature=np.array(model.armature, dtype=float), gravity=np.array(model.gravity.linear))


def path_torques(tree: TreeInertias, q: np.ndarray, rate: np.ndarray, curvature: np.ndarray,
                 threads: int = 1) -> np.ndarray:
    """(N, 3, nv) the tree's joint torques C, A and B (module docstring) at N samples.

    Args:
        tree: The tree (:func:`tree_inertias`).
        q: (N, nq) configurations.
        rate: (N, nv) q', the joints' rates per unit of path.
        curvature: (N, nv) q'', their second derivatives.
        threads: Threads, each on its share of the samples (the kernel releases the GIL).
    """
    q, rate, curvature = (np.ascontiguousarray(x, dtype=float) for x in (q, rate, curvature))
    out = np.empty((len(q), 3, len(tree.armature)))

    def run(rows: slice) -> None:
        _path_torques(tree.parent, tree.constants, tree.axis, tree.revolute, tree.v_index, tree.mass, tree.lever,
                      tree.inertia, tree.armature, tree.gravity, q[rows], rate[rows], curvature[rows], out[rows],
                      *_scratch(len(tree.parent)))

    bounds = np.linspace(0, len(q), max(threads, 1) + 1).astype(int)
    parts = [slice(start, stop) for start, stop in zip(bounds[:-1], bounds[1:])]
    if len(parts) == 1:
        run(parts[0])
    else:
        with ThreadPoolExecutor(len(parts)) as pool:
            list(pool.map(run, parts))
    return out


def touch_path_torques() -> None:
    """Compile the kernel (or load it from the disk cache) by running it on a one-joint tree: its numba types do
    not depend on the robot."""
    model = pin.Model()
    model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "joint")
    tree = tree_inertias(model)
    assert tree is not None
    path_torques(tree, np.zeros((1, 1)), np.zeros((1, 1)), np.zeros((1, 1)))


def _scratch(joints: int) -> tuple[np.ndarray, ...]:
    """The kernel's scratch for a tree of ``joints`` joints: each joint's rotation (3, 3) and origin (3,) in its
    parent; per joint, in its frame, the linear and angular parts (4, joints, 3) of C's, A's and B's accelerations and
    B's velocity, in that order; the three motions' forces (3, joints, 6); one spatial vector (6,)."""
    return (np.empty((joints, 3, 3)), np.empty((joints, 3)), np.zeros((4, joints, 3)), np.zeros((4, joints, 3)),
            np.zeros((3, joints, 6)), np.empty(6))


@_uncounted
def _inertia_times(mass, lever, inertia, linear, angular, out):
    """``out`` (6,) = the spatial inertia (mass, lever, inertia about the centre of mass) times the motion
    (linear, angular): m·(v − c × ω), then I_c·ω + c × that."""
    c0, c1, c2 = lever[0], lever[1], lever[2]
    l0 = mass * (linear[0] - (c1 * angular[2] - c2 * angular[1]))
    l1 = mass * (linear[1] - (c2 * angular[0] - c0 * angular[2]))
    l2 = mass * (linear[2] - (c0 * angular[1] - c1 * angular[0]))
    out[0], out[1], out[2] = l0, l1, l2
    for r in range(3):
        out[3 + r] = inertia[r, 0] * angular[0] + inertia[r, 1] * angular[1] + inertia[r, 2] * angular[2]
    out[3] += c1 * l2 - c2 * l1
    out[4] += c2 * l0 - c0 * l2
    out[5] += c0 * l1 - c1 * l0


@_uncounted
def _act_inverse(rotation, origin, linear, angular, out_linear, out_angular):
    """The motion (linear, angular) in the parent's frame, in the child's: Rᵀ·ω and Rᵀ·(v − t × ω)."""
    d0 = linear[0] - (origin[1] * angular[2] - origin[2] * angular[1])
    d1 = linear[1] - (origin[2] * angular[0] - origin[0] * angular[2])
    d2 = linear[2] - (origin[0] * angular[1] - origin[1] * angular[0])
    for c in range(3):
        out_angular[c] = rotation[0, c] * angular[0] + rotation[1, c] * angular[1] + rotation[2, c] * angular[2]
        out_linear[c] = rotation[0, c] * d0 + rotation[1, c] * d1 + rotation[2, c] * d2


@_uncounted
def _add_act(rotation, origin, force, target):
    """``target`` (6,) += the force (linear, moment), in the child's frame, in the parent's: R·f, R·n + t × R·f."""
    f0 = rotation[0, 0] * force[0] + rotation[0, 1] * force[1] + rotation[0, 2] * force[2]
    f1 = rotation[1, 0] * force[0] + rotation[1, 1] * force[1] + rotation[1, 2] * force[2]
    f2 = rotation[2, 0] * force[0] + rotation[2, 1] * force[1] + rotation[2, 2] * force[2]
    target[0] += f0
    target[1] += f1
    target[2] += f2
    for r in range(3):
        target[3 + r] += rotation[r, 0] * force[3] + rotation[r, 1] * force[4] + rotation[r, 2] * force[5]
    target[3] += origin[1] * f2 - origin[2] * f1
    target[4] += origin[2] * f0 - origin[0] * f2
    target[5] += origin[0] * f1 - origin[1] * f0


@njit(cache=True, nogil=True, _nrt=False)  # type: ignore[call-overload]
def _path_torques(parent, constants, axis, revolute, index, mass, lever, inertia, armature, gravity, q, rate,
                  curvature, out, rotation, origin, linear, angular, force, scratch):
    """:func:`path_torques` on flat arrays, into ``out`` (N, 3, nv), with the scratch of :func:`_scratch`."""
    nj = len(parent)
    for n in range(len(q)):
        for k in range(3):
            linear[0, 0, k] = -gravity[k]
        for j in range(1, nj):
            p, i, value = parent[j], index[j], q[n, index[j]]
            sine, versine = (np.sin(value), 1.0 - np.cos(value)) if revolute[j] else (0.0, 0.0)
            for r in range(3):
                for c in range(3):
                    rotation[j, r, c] = constants[j, r, c] + sine * constants[j, r, 3 + c] \
                        + versine * constants[j, r, 6 + c]
                origin[j, r] = constants[j, r, 10]
            if not revolute[j]:
                for r in range(3):
                    origin[j, r] += value * (rotation[j, r, 0] * axis[j, 0] + rotation[j, r, 1] * axis[j, 1]
                                             + rotation[j, r, 2] * axis[j, 2])
            for m in range(4):
                _act_inverse(rotation[j], origin[j], linear[m, p], angular[m, p], linear[m, j], angular[m, j])
            joint = linear if not revolute[j] else angular
            for k in range(3):
                joint[1, j, k] += axis[j, k] * rate[n, i]
                joint[2, j, k] += axis[j, k] * curvature[n, i]
                joint[3, j, k] += axis[j, k] * rate[n, i]
            # B's acceleration gains v × (S·q̇): (ω × s_lin + v × s_ang, ω × s_ang), s = axis·q'
            s = rate[n, i]
            w0, w1, w2 = angular[3, j, 0], angular[3, j, 1], angular[3, j, 2]
            x0, x1, x2 = (w0, w1, w2) if not revolute[j] else (linear[3, j, 0], linear[3, j, 1], linear[3, j, 2])
            a0, a1, a2 = axis[j, 0] * s, axis[j, 1] * s, axis[j, 2] * s
            linear[2, j, 0] += x1 * a2 - x2 * a1
            linear[2, j, 1] += x2 * a0 - x0 * a2
            linear[2, j, 2] += x0 * a1 - x1 * a0
            if revolute[j]:
                angular[2, j, 0] += w1 * a2 - w2 * a1
                angular[2, j, 1] += w2 * a0 - w0 * a2
                angular[2, j, 2] += w0 * a1 - w1 * a0
            for m in range(3):
                _inertia_times(mass[j], lever[j], inertia[j], linear[m, j], angular[m, j], force[m, j])
            # B's force gains v ×* (I·v): (ω × h_lin, ω × h_ang + v × h_lin)
            _inertia_times(mass[j], lever[j], inertia[j], linear[3, j], angular[3, j], scratch)
            v0, v1, v2 = linear[3, j, 0], linear[3, j, 1], linear[3, j, 2]
            h0, h1, h2, g0, g1, g2 = scratch[0], scratch[1], scratch[2], scratch[3], scratch[4], scratch[5]
            force[2, j, 0] += w1 * h2 - w2 * h1
            force[2, j, 1] += w2 * h0 - w0 * h2
            force[2, j, 2] += w0 * h1 - w1 * h0
            force[2, j, 3] += w1 * g2 - w2 * g1 + v1 * h2 - v2 * h1
            force[2, j, 4] += w2 * g0 - w0 * g2 + v2 * h0 - v0 * h2
            force[2, j, 5] += w0 * g1 - w1 * g0 + v0 * h1 - v1 * h0
        for j in range(nj - 1, 0, -1):
            p, i, shift = parent[j], index[j], 3 if revolute[j] else 0
            for m in range(3):
                out[n, m, i] = axis[j, 0] * force[m, j, shift] + axis[j, 1] * force[m, j, shift + 1] \
                    + axis[j, 2] * force[m, j, shift + 2]
                if p > 0:
                    _add_act(rotation[j], origin[j], force[m, j], force[m, p])
            out[n, 1, i] += armature[i] * rate[n, i]
            out[n, 2, i] += armature[i] * curvature[n, i]
