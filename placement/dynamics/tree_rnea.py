"""The joint torques of a tree of revolute and prismatic joints by compiled passes of Newton–Euler (numba).

:func:`joint_torques` is Pinocchio's RNEA, rnea(q, v, a), for many samples: the efforts of the paper's and the
realistic timing laws (:func:`placement.dynamics.inverse.actuator_efforts`). Along a path under the optimal law,
:func:`placement.dynamics.path_dynamics.path_dynamics` needs, at every sample, the tree's joint torques of three motions at
the same configuration q: at rest under gravity (C), with q̈ = q' and no velocity nor gravity (A = M·q'), and with
q̇ = q', q̈ = q'' and no gravity (B = c(q, q') + M·q''). Pinocchio's RNEA gives each in its own pass (C, A + C,
B + C), computing the joints' placements three times and the velocity terms of motions that have none.
:func:`path_torques` does the three in one pass: each joint's placement in its parent once, then the recursive
Newton–Euler steps of each motion. Both follow Pinocchio's conventions (spatial quantities in each joint's frame,
linear part first, gravity as an upward acceleration of the base, the drives' ``armature`` times the joint
acceleration added to each torque), so that rnea(q, v, a) = joint_torques(q, v, a), C = rnea(q, 0, 0),
A = rnea(q, 0, q') − C and B = rnea(q, q', q'') − C to rounding.

Every joint is revolute or prismatic about a fixed axis (:func:`placement.kinematics.tree.joint_axes`);
:func:`tree_inertias` says None for another tree, whose efforts Pinocchio computes. The kernels take the samples
in blocks of BLOCK: each joint's placement, motions and forces over a block are rows of BLOCK numbers, each step
of the recursion a loop along them, which the compiler turns into vector instructions (several samples at once,
where Pinocchio takes one sample after the other; a joint's sine and cosine too, from fdlibm's polynomials rather
than the C library, within 2 units in the last place). numba compiles the kernels on their first use and caches the
machine code on disk beside this module; they release the GIL, so that threads share a batch's samples.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from typing import NamedTuple

import numpy as np
import pinocchio as pin
from numba import njit

from placement.kinematics.tree import joint_axes, joint_constants

BLOCK = 192  # samples per pass of a kernel
TWO_OVER_PI = 6.36619772367581382433e-01
HALF_PI = (1.57079632673412561417e+00, 6.07710050630396597660e-11, 2.02226624871116645580e-21)  # π/2, 33 bits each
SINE = (-1.66666666666666324348e-01, 8.33333333332248946124e-03, -1.98412698298579493134e-04,
        2.75573137070700676789e-06, -2.50507602534068634195e-08, 1.58969099521155010221e-10)  # fdlibm's __kernel_sin
COSINE = (4.16666666666666019037e-02, -1.38888888888741095749e-03, 2.48015872894767294178e-05,
          -2.75573143513906633035e-07, 2.08757232129817482790e-09, -1.13596475577881948265e-11)  # its __kernel_cos
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


def joint_torques(tree: TreeInertias, q: np.ndarray, v: np.ndarray, a: np.ndarray, basis: np.ndarray,
                  threads: int = 1) -> np.ndarray:
    """(N, m) the tree's joint torques rnea(q, v, a) at N samples, gravity and the drives' armature included, times
    ``basis``: Gᵀ·τ (N or N·m a unit of G's columns).

    Args:
        tree: The tree (:func:`tree_inertias`).
        q: (N, nq) configurations.
        v: (N, nv) joint velocities.
        a: (N, nv) joint accelerations.
        basis: (N, nv, m) G at each sample (the closure null space's basis; the identity for the torques themselves).
        threads: Threads, each on its share of the samples (the kernel releases the GIL).
    """
    out = np.empty((len(q), 1, basis.shape[2]))
    _in_threads(_joint_torques, tree, (q, v, a), basis, out, (2, 1), threads)
    return out[:, 0]


def path_torques(tree: TreeInertias, q: np.ndarray, rate: np.ndarray, curvature: np.ndarray, basis: np.ndarray,
                 threads: int = 1) -> np.ndarray:
    """(N, 3, m) the tree's joint torques C, A and B (module docstring) at N samples, times ``basis``: Gᵀ·C, Gᵀ·A
    and Gᵀ·B, each column's N numbers contiguous (as :func:`placement.dynamics.path_dynamics.path_dynamics` lays them out).

    Args:
        tree: The tree (:func:`tree_inertias`).
        q: (N, nq) configurations.
        rate: (N, nv) q', the joints' rates per unit of path.
        curvature: (N, nv) q'', their second derivatives.
        basis: (N, nv, m) G at each sample.
        threads: Threads, each on its share of the samples (the kernel releases the GIL).
    """
    out = np.empty((3, basis.shape[2], len(q))).transpose(2, 0, 1)  # each column's samples contiguous
    _in_threads(_path_torques, tree, (q, rate, curvature), basis, out, (3, 3), threads)
    return out


def touch_tree_kernels(joint: bool = True, path: bool = False) -> None:
    """Compile the kernel of :func:`joint_torques` (``joint``) and that of :func:`path_torques` (``path``), or load
    them from the disk cache, by running them on a one-joint tree: their numba types do not depend on the robot."""
    model = pin.Model()
    model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "joint")
    tree = tree_inertias(model)
    assert tree is not None
    rest, basis = np.zeros((1, 1)), np.ones((1, 1, 1))
    if joint:
        joint_torques(tree, rest, rest, rest, basis)
    if path:
        path_torques(tree, rest, rest, rest, basis)


def _in_threads(kernel, tree: TreeInertias, states: tuple[np.ndarray, ...], basis: np.ndarray, out: np.ndarray,
                tracks: tuple[int, int], threads: int) -> None:
    """``kernel`` into ``out`` (N, forces, m) for the samples' ``states`` (q and two rates, each (N, nv)) and
    ``basis`` (N, nv, m), on ``threads`` threads, each on its share of the samples with scratch for ``tracks``
    (motions, forces) per joint."""
    q, first, second, basis = (np.ascontiguousarray(x, dtype=float) for x in (*states, basis))
    bounds = np.linspace(0, len(q), max(threads, 1) + 1).astype(int)

    def run(start: int, stop: int) -> None:
        joints, nv = len(tree.parent), len(tree.armature)
        kernel(tree.parent, tree.constants, tree.axis, tree.revolute, tree.v_index, tree.mass, tree.lever,
               tree.inertia, tree.armature, tree.gravity, q, first, second, basis, out, start, stop,
               np.empty((joints, 9, BLOCK)), np.empty((joints, 3, BLOCK)), np.zeros((tracks[0], joints, 6, BLOCK)),
               np.empty((tracks[1], joints, 6, BLOCK)), np.empty((3, nv, BLOCK)), np.empty((tracks[1], nv, BLOCK)))

    if threads <= 1:
        run(0, len(q))
    else:
        with ThreadPoolExecutor(threads) as pool:
            list(pool.map(run, bounds[:-1], bounds[1:]))


@_uncounted
def _sine_versine(angle):
    """sin(angle) and 1 − cos(angle) for |angle| < 1e5 rad, within 2 units in the last place of the C library's sine
    (4e-30 near a multiple of π, where the sine is that small) and 2.3e-16, in arithmetic alone, so that a loop of
    them runs in vector instructions (a call of the C library's does not): the angle less its nearest multiple
    k·π/2 (π/2 in three parts, Cody and Waite's reduction), fdlibm's polynomials of that remainder on [−π/4, π/4],
    then the quadrant k mod 4 picks and signs them."""
    k = np.floor(angle * TWO_OVER_PI + 0.5)
    r = ((angle - k * HALF_PI[0]) - k * HALF_PI[1]) - k * HALF_PI[2]
    z = r * r
    sine = r + r * z * (SINE[0] + z * (SINE[1] + z * (SINE[2] + z * (SINE[3] + z * (SINE[4] + z * SINE[5])))))
    versine = 0.5 * z - z * z * (COSINE[0] + z * (COSINE[1] + z * (COSINE[2] + z * (COSINE[3] + z * (COSINE[4]
                                                                                                 + z * COSINE[5])))))
    quadrant = np.int64(k) & 3
    odd, low = (quadrant & 1) == 1, quadrant < 2
    picked = (1.0 - versine) if odd else sine
    return (picked if low else -picked), ((1.0 + sine if odd else versine) if low else
                                          (1.0 - sine if odd else 2.0 - versine))


@_uncounted
def _place(constants, axis, revolute, q, count, rotation, origin):
    """The joint's rotation (9, BLOCK), row-major, and origin (3, BLOCK) in its parent at the block's coordinates
    ``q[:count]`` (its row of ``constants``, its ``axis``)."""
    if revolute:
        for n in range(count):  # the sine and versine in the origin's rows, until the rotation is done
            origin[0, n], origin[1, n] = _sine_versine(q[n])
        for r in range(3):
            for c in range(3):
                for n in range(count):
                    rotation[3 * r + c, n] = constants[r, c] + origin[0, n] * constants[r, 3 + c] \
                        + origin[1, n] * constants[r, 6 + c]
        for r in range(3):
            for n in range(count):
                origin[r, n] = constants[r, 10]
        return
    for r in range(3):
        for c in range(3):
            for n in range(count):
                rotation[3 * r + c, n] = constants[r, c]
    for r in range(3):
        for n in range(count):
            origin[r, n] = constants[r, 10] + q[n] * (constants[r, 0] * axis[0] + constants[r, 1] * axis[1]
                                                              + constants[r, 2] * axis[2])


@_uncounted
def _to_child(rotation, origin, parent, child, axis, revolute, rates, count):
    """``child`` (6, BLOCK) = the motions ``parent`` (linear, angular) in the child's frame, Rᵀ·(v − t × ω) and Rᵀ·ω,
    plus the joint's own: its ``axis`` times ``rates[:count]``, angular about a revolute axis, linear along a
    prismatic one. Each sample's numbers are all read before any is written (``child`` might alias them, as far as
    the compiler knows, it would read them again after each write)."""
    shift = 3 if revolute else 0  # the rows the joint's own motion adds to
    for n in range(count):
        w0, w1, w2 = parent[3, n], parent[4, n], parent[5, n]
        d0 = parent[0, n] - (origin[1, n] * w2 - origin[2, n] * w1)
        d1 = parent[1, n] - (origin[2, n] * w0 - origin[0, n] * w2)
        d2 = parent[2, n] - (origin[0, n] * w1 - origin[1, n] * w0)
        r0, r1, r2, r3, r4, r5 = rotation[0, n], rotation[1, n], rotation[2, n], rotation[3, n], rotation[4, n], \
            rotation[5, n]
        r6, r7, r8 = rotation[6, n], rotation[7, n], rotation[8, n]
        child[0, n] = r0 * d0 + r3 * d1 + r6 * d2
        child[1, n] = r1 * d0 + r4 * d1 + r7 * d2
        child[2, n] = r2 * d0 + r5 * d1 + r8 * d2
        child[3, n] = r0 * w0 + r3 * w1 + r6 * w2
        child[4, n] = r1 * w0 + r4 * w1 + r7 * w2
        child[5, n] = r2 * w0 + r5 * w1 + r8 * w2
    for c in range(3):
        for n in range(count):
            child[shift + c, n] += axis[c] * rates[n]


@_uncounted
def _linear_to_child(rotation, parent, child, count):
    """``child``'s linear rows (3 of 6, BLOCK) = a motion of the parent's with no angular part, in the child's frame:
    Rᵀ·v (its angular rows stay zero; :func:`_to_child` gives the same)."""
    for n in range(count):
        v0, v1, v2 = parent[0, n], parent[1, n], parent[2, n]
        for c in range(3):
            child[c, n] = rotation[c, n] * v0 + rotation[3 + c, n] * v1 + rotation[6 + c, n] * v2


@_uncounted
def _mass_times(mass, lever, motion, count, out):
    """``out`` (6, BLOCK) = the spatial inertia times a motion with no angular part: m·v, then c × m·v
    (:func:`_inertia_times` gives the same)."""
    c0, c1, c2 = lever[0], lever[1], lever[2]
    for n in range(count):
        l0, l1, l2 = mass * motion[0, n], mass * motion[1, n], mass * motion[2, n]
        out[0, n], out[1, n], out[2, n] = l0, l1, l2
        out[3, n], out[4, n], out[5, n] = c1 * l2 - c2 * l1, c2 * l0 - c0 * l2, c0 * l1 - c1 * l0


@_uncounted
def _add_bias(axis, revolute, rates, count, velocity, acceleration):
    """``acceleration`` (6, BLOCK) gains v × (S·q̇), v = ``velocity`` (the joint's own motion in it), S·q̇ the axis
    times ``rates``: (ω × s_lin + v × s_ang, ω × s_ang)."""
    e0, e1, e2 = axis[0], axis[1], axis[2]
    for n in range(count):
        s = rates[n]
        w0, w1, w2 = velocity[3, n], velocity[4, n], velocity[5, n]
        x0, x1, x2 = (velocity[0, n], velocity[1, n], velocity[2, n]) if revolute else (w0, w1, w2)
        a0, a1, a2 = e0 * s, e1 * s, e2 * s
        acceleration[0, n] += x1 * a2 - x2 * a1
        acceleration[1, n] += x2 * a0 - x0 * a2
        acceleration[2, n] += x0 * a1 - x1 * a0
        if revolute:
            acceleration[3, n] += w1 * a2 - w2 * a1
            acceleration[4, n] += w2 * a0 - w0 * a2
            acceleration[5, n] += w0 * a1 - w1 * a0


@_uncounted
def _inertia_times(mass, lever, inertia, motion, count, out):
    """``out`` (6, BLOCK) = the spatial inertia (mass, lever, inertia about the centre of mass) times ``motion``
    (linear, angular): m·(v − c × ω), then I_c·ω + c × that."""
    c0, c1, c2 = lever[0], lever[1], lever[2]
    i00, i01, i02, i10, i11, i12, i20, i21, i22 = inertia[0, 0], inertia[0, 1], inertia[0, 2], inertia[1, 0], \
        inertia[1, 1], inertia[1, 2], inertia[2, 0], inertia[2, 1], inertia[2, 2]
    for n in range(count):
        w0, w1, w2 = motion[3, n], motion[4, n], motion[5, n]
        l0 = mass * (motion[0, n] - (c1 * w2 - c2 * w1))
        l1 = mass * (motion[1, n] - (c2 * w0 - c0 * w2))
        l2 = mass * (motion[2, n] - (c0 * w1 - c1 * w0))
        out[0, n], out[1, n], out[2, n] = l0, l1, l2
        out[3, n] = i00 * w0 + i01 * w1 + i02 * w2 + (c1 * l2 - c2 * l1)
        out[4, n] = i10 * w0 + i11 * w1 + i12 * w2 + (c2 * l0 - c0 * l2)
        out[5, n] = i20 * w0 + i21 * w1 + i22 * w2 + (c0 * l1 - c1 * l0)


@njit(cache=True, _nrt=False, inline="always")  # type: ignore[call-overload]
def _add_cross(force, n, v0, v1, v2, w0, w1, w2, h0, h1, h2, g0, g1, g2):
    """Sample ``n`` of ``force`` (6, BLOCK) gains v ×* h for the motion v = (v0, v1, v2, w0, w1, w2) and the momentum
    h = (h0, h1, h2, g0, g1, g2): (ω × h_lin, ω × h_ang + v × h_lin)."""
    force[0, n] += w1 * h2 - w2 * h1
    force[1, n] += w2 * h0 - w0 * h2
    force[2, n] += w0 * h1 - w1 * h0
    force[3, n] += w1 * g2 - w2 * g1 + v1 * h2 - v2 * h1
    force[4, n] += w2 * g0 - w0 * g2 + v2 * h0 - v0 * h2
    force[5, n] += w0 * g1 - w1 * g0 + v0 * h1 - v1 * h0


@_uncounted
def _add_velocity_force(mass, lever, inertia, velocity, count, force):
    """``force`` (6, BLOCK) gains v ×* (I·v), v = ``velocity``: (ω × h_lin, ω × h_ang + v × h_lin), h = I·v."""
    c0, c1, c2 = lever[0], lever[1], lever[2]
    i00, i01, i02, i10, i11, i12, i20, i21, i22 = inertia[0, 0], inertia[0, 1], inertia[0, 2], inertia[1, 0], \
        inertia[1, 1], inertia[1, 2], inertia[2, 0], inertia[2, 1], inertia[2, 2]
    for n in range(count):
        v0, v1, v2, w0, w1, w2 = velocity[0, n], velocity[1, n], velocity[2, n], velocity[3, n], velocity[4, n], velocity[5, n]
        h0 = mass * (v0 - (c1 * w2 - c2 * w1))
        h1 = mass * (v1 - (c2 * w0 - c0 * w2))
        h2 = mass * (v2 - (c0 * w1 - c1 * w0))
        g0 = i00 * w0 + i01 * w1 + i02 * w2 + (c1 * h2 - c2 * h1)
        g1 = i10 * w0 + i11 * w1 + i12 * w2 + (c2 * h0 - c0 * h2)
        g2 = i20 * w0 + i21 * w1 + i22 * w2 + (c0 * h1 - c1 * h0)
        _add_cross(force, n, v0, v1, v2, w0, w1, w2, h0, h1, h2, g0, g1, g2)


@_uncounted
def _add_momentum_force(velocity, momentum, count, force):
    """``force`` (6, BLOCK) gains v ×* h for a motion v = ``velocity`` and its momentum h = I·v = ``momentum``
    (6, BLOCK), already known (:func:`_add_velocity_force` computes it): (ω × h_lin, ω × h_ang + v × h_lin)."""
    for n in range(count):
        v0, v1, v2, w0, w1, w2 = velocity[0, n], velocity[1, n], velocity[2, n], velocity[3, n], velocity[4, n], velocity[5, n]
        h0, h1, h2, g0, g1, g2 = momentum[0, n], momentum[1, n], momentum[2, n], momentum[3, n], momentum[4, n], momentum[5, n]
        _add_cross(force, n, v0, v1, v2, w0, w1, w2, h0, h1, h2, g0, g1, g2)


@_uncounted
def _project(axis, revolute, force, count, out):
    """``out[:count]`` = the joint's torque: its axis · the force's moment (revolute) or linear part."""
    shift, e0, e1, e2 = 3 if revolute else 0, axis[0], axis[1], axis[2]
    for n in range(count):
        out[n] = e0 * force[shift, n] + e1 * force[shift + 1, n] + e2 * force[shift + 2, n]


@_uncounted
def _add_to_parent(rotation, origin, force, parent, count):
    """``parent`` (6, BLOCK) += ``force`` (linear, moment) in the child's frame, in the parent's: R·f, R·n + t × R·f.
    Each sample's numbers are all read before any is written (``parent`` might alias them, as far as the compiler
    knows, it would read them again after each write)."""
    for n in range(count):
        r0, r1, r2, r3, r4, r5 = rotation[0, n], rotation[1, n], rotation[2, n], rotation[3, n], rotation[4, n], \
            rotation[5, n]
        r6, r7, r8, t0, t1, t2 = rotation[6, n], rotation[7, n], rotation[8, n], origin[0, n], origin[1, n], origin[2, n]
        x0, x1, x2, y0, y1, y2 = force[0, n], force[1, n], force[2, n], force[3, n], force[4, n], force[5, n]
        f0, f1, f2 = r0 * x0 + r1 * x1 + r2 * x2, r3 * x0 + r4 * x1 + r5 * x2, r6 * x0 + r7 * x1 + r8 * x2
        parent[0, n] += f0
        parent[1, n] += f1
        parent[2, n] += f2
        parent[3, n] = (parent[3, n] + (r0 * y0 + r1 * y1 + r2 * y2)) + (t1 * f2 - t2 * f1)
        parent[4, n] = (parent[4, n] + (r3 * y0 + r4 * y1 + r5 * y2)) + (t2 * f0 - t0 * f2)
        parent[5, n] = (parent[5, n] + (r6 * y0 + r7 * y1 + r8 * y2)) + (t0 * f1 - t1 * f0)


@_uncounted
def _start_block(q, first, second, start, stop, gravity, state, base):
    """The block of samples from ``start`` (at most BLOCK, before ``stop``): its samples into ``state``
    (:func:`_gather`), and gravity, as an upward acceleration of the base, into ``base`` (the universe's row
    (6, BLOCK) of the acceleration that carries it). Returns the block's samples."""
    count = min(BLOCK, stop - start)
    _gather(q, first, second, start, count, state)
    for k in range(3):
        for n in range(count):
            base[k, n] = -gravity[k]
    return count


@_uncounted
def _gather(q, first, second, start, count, state):
    """``state`` (3, nv, BLOCK): the samples ``start`` to ``start + count`` of q and the two rates (N, nv), a joint's
    along each row."""
    for n in range(count):
        for i in range(q.shape[1]):
            state[0, i, n], state[1, i, n], state[2, i, n] = q[start + n, i], first[start + n, i], second[start + n, i]


@_uncounted
def _project_block(torque, basis, start, count, out):
    """``out[start:start + count]`` (N, forces, m) = the block's joint torques ``torque`` (forces, nv, BLOCK) times
    ``basis`` (N, nv, m): Gᵀ·τ at each sample."""
    for n in range(count):
        for m in range(torque.shape[0]):
            for c in range(basis.shape[2]):
                total = 0.0
                for i in range(torque.shape[1]):
                    total += torque[m, i, n] * basis[start + n, i, c]
                out[start + n, m, c] = total


@njit(cache=True, nogil=True, _nrt=False)  # type: ignore[call-overload]
def _joint_torques(parent, constants, axis, revolute, index, mass, lever, inertia, armature, gravity, q, v, a, basis,
                   out, start, stop, rotation, origin, motion, force, state, torque):
    """:func:`joint_torques` on flat arrays (q, v, a (N, nv), ``basis`` (N, nv, m), ``out`` (N, 1, m)) for the samples
    ``start`` to ``stop``; the scratch: each joint's rotation (nj, 9, BLOCK) and origin (nj, 3, BLOCK), its velocity and
    acceleration (2, nj, 6, BLOCK), zeros, and its force (1, nj, 6, BLOCK); the block's q, v and a (3, nv, BLOCK)
    and torques (1, nv, BLOCK)."""
    for first in range(start, stop, BLOCK):
        count = _start_block(q, v, a, first, stop, gravity, state, motion[1, 0])
        for j in range(1, len(parent)):
            p, i = parent[j], index[j]
            _place(constants[j], axis[j], revolute[j], state[0, i], count, rotation[j], origin[j])
            for m in range(2):  # the velocity and the acceleration
                _to_child(rotation[j], origin[j], motion[m, p], motion[m, j], axis[j], revolute[j], state[1 + m, i],
                          count)
            _add_bias(axis[j], revolute[j], state[1, i], count, motion[0, j], motion[1, j])
            _inertia_times(mass[j], lever[j], inertia[j], motion[1, j], count, force[0, j])
            _add_velocity_force(mass[j], lever[j], inertia[j], motion[0, j], count, force[0, j])
        for j in range(len(parent) - 1, 0, -1):
            p, i = parent[j], index[j]
            _project(axis[j], revolute[j], force[0, j], count, torque[0, i])
            for n in range(count):
                torque[0, i, n] += armature[i] * state[2, i, n]
            if p > 0:
                _add_to_parent(rotation[j], origin[j], force[0, j], force[0, p], count)
        _project_block(torque, basis, first, count, out)


@njit(cache=True, nogil=True, _nrt=False)  # type: ignore[call-overload]
def _path_torques(parent, constants, axis, revolute, index, mass, lever, inertia, armature, gravity, q, rate,
                  curvature, basis, out, start, stop, rotation, origin, motion, force, state, torque):
    """:func:`path_torques` on flat arrays (q, rate, curvature (N, nv), ``basis`` (N, nv, m), ``out`` (N, 3, m)) for
    the samples ``start`` to ``stop``; the scratch as :func:`_joint_torques`', with three motions per joint (C's, A's
    and B's accelerations: zeros), three forces and three torques. A's acceleration is B's velocity too (both are q'
    at every joint from a base at rest), and A's force its momentum."""
    for first in range(start, stop, BLOCK):
        count = _start_block(q, rate, curvature, first, stop, gravity, state, motion[0, 0])
        for j in range(1, len(parent)):
            p, i = parent[j], index[j]
            _place(constants[j], axis[j], revolute[j], state[0, i], count, rotation[j], origin[j])
            _linear_to_child(rotation[j], motion[0, p], motion[0, j], count)  # C: gravity alone, never turning
            for m in range(1, 3):  # A's and B's accelerations: q' and q'' at the joint
                _to_child(rotation[j], origin[j], motion[m, p], motion[m, j], axis[j], revolute[j], state[m, i], count)
            _add_bias(axis[j], revolute[j], state[1, i], count, motion[1, j], motion[2, j])
            _mass_times(mass[j], lever[j], motion[0, j], count, force[0, j])
            for m in range(1, 3):
                _inertia_times(mass[j], lever[j], inertia[j], motion[m, j], count, force[m, j])
            _add_momentum_force(motion[1, j], force[1, j], count, force[2, j])
        for j in range(len(parent) - 1, 0, -1):
            p, i = parent[j], index[j]
            for m in range(3):
                _project(axis[j], revolute[j], force[m, j], count, torque[m, i])
                if p > 0:
                    _add_to_parent(rotation[j], origin[j], force[m, j], force[m, p], count)
            for n in range(count):
                torque[1, i, n] += armature[i] * state[1, i, n]
                torque[2, i, n] += armature[i] * state[2, i, n]
        _project_block(torque, basis, first, count, out)
