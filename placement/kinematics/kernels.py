"""Compiled per-sample kernels of the generic kinematics (numba): tree kinematics, Newton, rates.

Each kernel loops over the rows of a batch (samples of placements) and does, per row, what a
numpy formulation does with one array operation per joint. At a few microseconds per row, the
Python and LAPACK call overheads that bound a numpy version disappear; the inner loops allocate
nothing (every buffer is made once per call). numba compiles the kernels on their first use and
caches the machine code on disk beside this module (or in ``NUMBA_CACHE_DIR``), so that later
processes start at once. The batched entry points release the GIL, so that callers may run parts
of a batch on several threads. The functions that take the tree and buffer tuples and run at every
Newton iteration are compiled without numba's reference counting (``_nrt=False``; they allocate
nothing): a counted call that passes those tuples costs about 0.3 µs, as much as a forward
kinematics of a 6-axis arm, and without the counts the call costs as little as numba's inlining
(``inline='always'``) saved, at less than half its compile time. Compile time also guides the
rest: no slice assignment between arrays (its shape check compiles a formatted message) nor array
expressions or powers (each compiles a kernel of its own), no numpy constructor but ``np.empty`` and
``np.zeros`` and no reduction (``np.eye``, ``np.arange``, an array from nested lists or a ``sum`` each
compile implementations of their own, once per process), each entry point's loop in the entry
point itself (a wrapper compiles its callees' code once more), no Python wrappers for functions
only the kernels call (one unboxes the 30 arrays of the tree and buffer tuples, and is optimised
again in every caller), one set of argument types per function (rows passed as views, no literal
constants). A function with a single caller is inlined into it by numba (``_inlined``: ``_assemble``,
``_branch_scale``, ``least_squares``, ``_newton_step``, ``_model_remainder``, ``_factor_passive``,
``_task_inverse``, ``drifts``): compiled on its own, LLVM would optimise and emit it once for itself and once more
within its caller, which keeps it as a function of its own (together a tenth of the kernels' first
compile). ``passive_correction`` stays apart: inlined into ``rates``, it makes them 8 % slower.

Conventions follow Pinocchio: a joint's world placement ``oMi = oMparent · jointPlacement ·
motion(q)``; Jacobians and classical accelerations at a frame's origin in world-aligned axes
(LOCAL_WORLD_ALIGNED), linear rows before angular ones. Every joint is revolute or prismatic about
a fixed axis, with ``idx_q == idx_v``. Closures' rotation rows use the difference of the two
frames' angular Jacobians, as the residual's ``log3`` has that derivative at zero error.

This stays one file: numba's on-disk cache does not see a change to a function it calls from
another file. Its sections, in order (each opens with a ``# ---`` rule):

1. Data: ``TreeArrays`` (the tree and the solver's frames, flat) and ``_Buffers`` (per-call scratch).
2. Small dense linear algebra: ``_solve_square``, ``_cholesky`` / ``least_squares`` (damped normal
   equations), products, ``log3``.
3. Tree kinematics of one sample: ``forward`` (joint placements), ``residual`` (closures and the task),
   ``jacobians``, ``velocities``, ``drifts`` (the classical-acceleration terms J̇·v).
4. The solver's quantities of one sample: ``basis`` (G, the closures' null-space map from actuated to
   all joint rates), ``passive_correction``, the task map J_task·G.
5. Batched entry points: Newton (``_newton_one``, ``_newton_step``), ``rates`` (joint velocities and
   accelerations from the tool's twist and acceleration), ``frames``, ``placements``, ``rotation_vectors``.
6. Whole paths: ``solve_paths`` (each path sample by sample, seeded by interpolating the solved
   neighbours on a bisection schedule, with the branch test ``_left_branch`` and the joint motion a
   stretch of path can cause, ``_branch_scale``) and ``_assemble`` (a path's first configuration, by
   continuation from the reference configuration).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

PIVOT_FLOOR = 1e-300  # a pivot below this makes a square system singular
# numba's stub lacks the flags for no reference counting and no Python wrappers
_internal = njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]
_uncounted = njit(cache=True, _nrt=False, no_cpython_wrapper=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]
_inlined = njit(inline='always')  # typed and compiled within its one caller


class TreeArrays(NamedTuple):
    """Flat description of a spanning tree and of the frames the solver uses.

    Joints are numbered as in Pinocchio (0: the universe, parents before children). Frames are the
    solver's own list: the closure frames, then the end effector.
    """

    parent: np.ndarray  # (nj,) int64 parent joint
    constants: np.ndarray  # (nj, 3, 11) [rotation, rotation·[a], rotation·[a]², rotation·a, translation] per joint
    revolute: np.ndarray  # (nj,) bool
    q_index: np.ndarray  # (nj,) int64 (idx_q == idx_v)
    frame_parent: np.ndarray  # (nf,) int64 parent joint of each frame
    frame_rotation: np.ndarray  # (nf, 3, 3) placement in the parent joint
    frame_translation: np.ndarray  # (nf, 3)
    support: np.ndarray  # (nf, nj) bool: joint j moves frame f
    closure_first: np.ndarray  # (nc,) int64 frame index of each closure's first frame
    closure_second: np.ndarray  # (nc,) int64 frame index of its second frame
    closure_dimension: np.ndarray  # (nc,) int64: 3 (point) or 6 (weld)
    end_effector: int  # frame index of the end effector
    task_dimension: int  # the task's rows: 3 (position) or 6 (pose), then one per prescribed joint
    actuated: np.ndarray  # (n_act,) int64 velocity indices of the actuated joints
    passive: np.ndarray  # (n_passive,) int64 velocity indices of the other joints
    task_joints: np.ndarray  # (n_p,) int64 q indices of the joints whose values the task prescribes (a profile)


class _Buffers(NamedTuple):
    rotation: np.ndarray  # (nj, 3, 3) joint rotations
    origin: np.ndarray  # (nj, 3) joint origins (m)
    axis: np.ndarray  # (nj, 3) joint axes, world
    angular: np.ndarray  # (nj, 3) body angular velocities (rad/s)
    linear: np.ndarray  # (nj, 3) joint origin velocities (m/s)
    frame_rotation: np.ndarray  # (nf, 3, 3)
    frame_origin: np.ndarray  # (nf, 3)
    jacobian: np.ndarray  # (closure rows + task dim, nv): closure rows, then task rows
    drift: np.ndarray  # (closure rows + task dim,)
    normal: np.ndarray  # (n, n) normal equations / factor
    rhs: np.ndarray  # (n, k) right-hand sides
    turn: np.ndarray  # (3, 3) scratch rotation
    local: np.ndarray  # (3, 3) scratch of the forward kinematics: a joint's rotation in its parent
    columns: np.ndarray  # (nv,) 0, 1, ..., nv - 1
    nonzero: np.ndarray  # (nv,) scratch indices


@_internal
def _buffers(tree, nv):
    nj, nf = len(tree.parent), len(tree.frame_parent)
    rows = tree.task_dimension
    for c in range(len(tree.closure_dimension)):
        rows += tree.closure_dimension[c]
    n = max(nv, rows)
    columns = np.empty(nv, dtype=np.int64)
    for k in range(nv):
        columns[k] = k
    return _Buffers(np.empty((nj, 3, 3)), np.empty((nj, 3)), np.empty((nj, 3)), np.zeros((nj, 3)), np.zeros((nj, 3)),
                    np.empty((nf, 3, 3)), np.empty((nf, 3)), np.empty((rows, nv)), np.empty(rows), np.empty((n, n)),
                    np.empty((n, n + 1)), np.empty((3, 3)), np.empty((3, 3)), columns,
                    np.empty(nv, dtype=np.int64))


# ---------------------------------------------------------------- small dense linear algebra


@_internal
def _solve_square(matrix, rhs, n):
    """Solve ``matrix[:n, :n] · x = rhs[:n]`` in place by LU with partial pivoting: ``rhs[:n]`` (n, k) becomes x
    and ``matrix[:n, :n]`` its factors. Returns whether the matrix is regular."""
    k = rhs.shape[1]
    for col in range(n):
        pivot = col
        for row in range(col + 1, n):
            if abs(matrix[row, col]) > abs(matrix[pivot, col]):
                pivot = row
        if not abs(matrix[pivot, col]) > PIVOT_FLOOR:
            return False
        if pivot != col:
            for c in range(n):
                matrix[col, c], matrix[pivot, c] = matrix[pivot, c], matrix[col, c]
            for c in range(k):
                rhs[col, c], rhs[pivot, c] = rhs[pivot, c], rhs[col, c]
        for row in range(col + 1, n):
            factor = matrix[row, col] / matrix[col, col]
            if factor != 0.0:
                for c in range(col + 1, n):
                    matrix[row, c] -= factor * matrix[col, c]
                for c in range(k):
                    rhs[row, c] -= factor * rhs[col, c]
    for col in range(n - 1, -1, -1):
        for c in range(k):
            total = rhs[col, c]
            for j in range(col + 1, n):
                total -= matrix[col, j] * rhs[j, c]
            rhs[col, c] = total / matrix[col, col]
    return True


@_internal
def _normal_lower(jacobian, rows, columns, normal, nonzero):
    """Lower triangle of ``J[:rows, columns]ᵀ·J[:rows, columns]`` in ``normal``, row by row over each row's
    nonzero entries (closure rows touch few joints); ``nonzero`` is scratch of len(columns) ints."""
    n = len(columns)
    for i in range(n):
        for j in range(i + 1):
            normal[i, j] = 0.0
    for r in range(rows):
        count = 0
        for i in range(n):
            if jacobian[r, columns[i]] != 0.0:
                nonzero[count] = i
                count += 1
        for a in range(count):
            i = nonzero[a]
            x = jacobian[r, columns[i]]
            for b in range(a + 1):
                normal[i, nonzero[b]] += x * jacobian[r, columns[nonzero[b]]]


@_internal
def _cholesky(a, n, damping):
    """Lower Cholesky factor of ``a[:n, :n] + damping·I``, in place, from its lower triangle (semi-definite
    pivots floored at damping)."""
    for j in range(n):
        total = a[j, j] + damping
        for k in range(j):
            total -= a[j, k] * a[j, k]
        a[j, j] = np.sqrt(max(total, damping))
        for i in range(j + 1, n):
            total = a[i, j]
            for k in range(j):
                total -= a[i, k] * a[j, k]
            a[i, j] = total / a[j, j]


@_internal
def _cholesky_solve(factor, n, rhs, k):
    """Solve ``L·Lᵀ·x = rhs[:n, :k]`` in place with the factor of :func:`_cholesky`."""
    for c in range(k):
        for i in range(n):
            total = rhs[i, c]
            for j in range(i):
                total -= factor[i, j] * rhs[j, c]
            rhs[i, c] = total / factor[i, i]
        for i in range(n - 1, -1, -1):
            total = rhs[i, c]
            for j in range(i + 1, n):
                total -= factor[j, i] * rhs[j, c]
            rhs[i, c] = total / factor[i, i]


@_inlined
def least_squares(matrix, rhs, damping):
    """Solution (n, k) of ``matrix · x ≈ rhs`` (rhs (m, k), m ≥ n): exact when square and regular, else damped
    least squares."""
    n, k = matrix.shape[1], rhs.shape[1]
    if matrix.shape[0] == n:
        x = rhs.copy()
        if _solve_square(matrix.copy(), x, n):
            return x
    transposed = matrix.T.copy()
    normal = _gram(transposed)
    x = _product(transposed, rhs)
    _cholesky(normal, n, damping)
    _cholesky_solve(normal, n, x, k)
    return x


@_internal
def _gram(a):
    """``a · aᵀ`` (symmetric, by loops)."""
    n, m = a.shape
    out = np.empty((n, n))
    for i in range(n):
        for j in range(i + 1):
            total = 0.0
            for l in range(m):
                total += a[i, l] * a[j, l]
            out[i, j] = total
            out[j, i] = total
    return out


@_internal
def _product(a, b):
    """``a · b`` by loops (numba's ``@`` calls BLAS, whose overhead dominates on small matrices)."""
    n, m = a.shape
    k = b.shape[1]
    out = np.zeros((n, k))
    for i in range(n):
        for l in range(m):
            x = a[i, l]
            if x != 0.0:
                for j in range(k):
                    out[i, j] += x * b[l, j]
    return out


@_internal
def _apply_into(matrix, vector, out):
    """``out = matrix · vector`` by loops."""
    for i in range(matrix.shape[0]):
        total = 0.0
        for j in range(matrix.shape[1]):
            total += matrix[i, j] * vector[j]
        out[i] = total


@_internal
def _norm_1(matrix):
    """1-norm of a matrix: its largest column sum of absolute values."""
    largest = 0.0
    for c in range(matrix.shape[1]):
        total = 0.0
        for r in range(matrix.shape[0]):
            total += abs(matrix[r, c])
        largest = max(largest, total)
    return largest


@_internal
def log3(rotation, out):
    """Rotation vector (rad) of a rotation matrix, as ``pin.log3``, into ``out[:3]``."""
    cosine = min(1.0, max(-1.0, (rotation[0, 0] + rotation[1, 1] + rotation[2, 2] - 1.0) / 2.0))
    angle = np.arccos(cosine)
    x = rotation[2, 1] - rotation[1, 2]
    y = rotation[0, 2] - rotation[2, 0]
    z = rotation[1, 0] - rotation[0, 1]
    if angle < 1e-4:
        scale = 0.5 + angle * angle / 12.0
    elif angle < np.pi - 1e-3:
        scale = angle / (2.0 * np.sin(angle))
    else:  # sin θ vanishes: R = cos θ·I + (1 - cos θ)·a·aᵀ + sin θ·[a], take a from the symmetric part
        i = 0
        for k in range(1, 3):
            if rotation[k, k] > rotation[i, i]:
                i = k
        diagonal = np.sqrt(max(0.0, (rotation[i, i] - cosine) / (1.0 - cosine)))
        for k in range(3):  # the axis, into out[:3]
            out[k] = diagonal if k == i else (rotation[i, k] + rotation[k, i]) / (2.0 * (1.0 - cosine) * diagonal)
        sign = 1.0 if out[0] * x + out[1] * y + out[2] * z >= 0.0 else -1.0
        for k in range(3):
            out[k] *= sign * angle
        return
    out[0] = scale * x
    out[1] = scale * y
    out[2] = scale * z


# ---------------------------------------------------------------- tree kinematics of one sample


@_uncounted
def forward(tree, q, buffers):
    """World rotation, origin and axis of every joint, then placement of every solver frame, for one configuration."""
    rotation, origin, axis = buffers.rotation, buffers.origin, buffers.axis
    rotation[0] = 0.0
    for k in range(3):
        rotation[0, k, k] = 1.0
    origin[0] = 0.0
    axis[0] = 0.0
    local = buffers.local
    for j in range(1, len(tree.parent)):
        p = tree.parent[j]
        constants = tree.constants[j]
        value = q[tree.q_index[j]]
        if tree.revolute[j]:  # the joint's rotation in its parent: placement · exp(θ[a]) = C + sin θ·C[a] + (1 − cos θ)·C[a]²
            sine, versine = np.sin(value), 1.0 - np.cos(value)
            for r in range(3):
                for c in range(3):
                    local[r, c] = constants[r, c] + sine * constants[r, 3 + c] + versine * constants[r, 6 + c]
        else:
            for r in range(3):
                for c in range(3):
                    local[r, c] = constants[r, c]
        for r in range(3):  # the parent's rotation times the joint's local rotation, axis and offset
            p0, p1, p2 = rotation[p, r, 0], rotation[p, r, 1], rotation[p, r, 2]
            for c in range(3):
                rotation[j, r, c] = p0 * local[0, c] + p1 * local[1, c] + p2 * local[2, c]
            axis[j, r] = p0 * constants[0, 9] + p1 * constants[1, 9] + p2 * constants[2, 9]
            origin[j, r] = origin[p, r] + p0 * constants[0, 10] + p1 * constants[1, 10] + p2 * constants[2, 10]
        if not tree.revolute[j]:
            for r in range(3):
                origin[j, r] += axis[j, r] * value
    for f in range(len(tree.frame_parent)):
        j = tree.frame_parent[f]
        for r in range(3):
            total = origin[j, r]
            for c in range(3):
                total += rotation[j, r, c] * tree.frame_translation[f, c]
                buffers.frame_rotation[f, r, c] = rotation[j, r, 0] * tree.frame_rotation[f, 0, c] \
                    + rotation[j, r, 1] * tree.frame_rotation[f, 1, c] + rotation[j, r, 2] * tree.frame_rotation[f, 2, c]
            buffers.frame_origin[f, r] = total


@_internal
def _relative_rotation(first, second, out):
    """``first · secondᵀ`` into ``out``."""
    for r in range(3):
        for c in range(3):
            out[r, c] = first[r, 0] * second[c, 0] + first[r, 1] * second[c, 1] + first[r, 2] * second[c, 2]


@_uncounted
def residual(tree, buffers, q, target_position, target_rotation, target_joints, pose, out):
    """Closure gaps, then end-effector error (m, rad), then the prescribed joints' errors, into ``out``; returns
    its norm."""
    row = 0
    frame_rotation, frame_origin = buffers.frame_rotation, buffers.frame_origin
    for c in range(len(tree.closure_first)):
        f1, f2 = tree.closure_first[c], tree.closure_second[c]
        for k in range(3):
            out[row + k] = frame_origin[f1, k] - frame_origin[f2, k]
        if tree.closure_dimension[c] == 6:
            _relative_rotation(frame_rotation[f1], frame_rotation[f2], buffers.turn)
            log3(buffers.turn, out[row + 3:])
        row += tree.closure_dimension[c]
    e = tree.end_effector
    for k in range(3):
        out[row + k] = frame_origin[e, k] - target_position[k]
    if pose:
        _relative_rotation(frame_rotation[e], target_rotation, buffers.turn)
        log3(buffers.turn, out[row + 3:])
    row += tree.task_dimension - len(tree.task_joints)
    for i in range(len(tree.task_joints)):
        out[row + i] = q[tree.task_joints[i]] - target_joints[i]
    total = 0.0
    for k in range(len(out)):
        total += out[k] * out[k]
    return np.sqrt(total)


@_uncounted
def _add_frame_jacobian(tree, f, buffers, sign, out):
    """Add ``sign`` times the first len(out) (3 or 6) rows of frame ``f``'s Jacobian to ``out``."""
    origin, axis, dimension = buffers.origin, buffers.axis, len(out)
    px, py, pz = buffers.frame_origin[f, 0], buffers.frame_origin[f, 1], buffers.frame_origin[f, 2]
    for j in range(1, len(tree.parent)):
        if not tree.support[f, j]:
            continue
        column = tree.q_index[j]
        ax, ay, az = axis[j, 0], axis[j, 1], axis[j, 2]
        if tree.revolute[j]:
            dx, dy, dz = px - origin[j, 0], py - origin[j, 1], pz - origin[j, 2]
            out[0, column] += sign * (ay * dz - az * dy)
            out[1, column] += sign * (az * dx - ax * dz)
            out[2, column] += sign * (ax * dy - ay * dx)
            if dimension == 6:
                out[3, column] += sign * ax
                out[4, column] += sign * ay
                out[5, column] += sign * az
        else:
            out[0, column] += sign * ax
            out[1, column] += sign * ay
            out[2, column] += sign * az


@_uncounted
def jacobians(tree, buffers):
    """Closure rows, then task rows (the end effector's, then a unit row per prescribed joint), of the stacked
    Jacobian in ``buffers.jacobian``."""
    jacobian = buffers.jacobian
    jacobian[:, :] = 0.0
    row = 0
    for c in range(len(tree.closure_first)):
        dimension = tree.closure_dimension[c]
        _add_frame_jacobian(tree, tree.closure_first[c], buffers, 1.0, jacobian[row:row + dimension])
        _add_frame_jacobian(tree, tree.closure_second[c], buffers, -1.0, jacobian[row:row + dimension])
        row += dimension
    frame = tree.task_dimension - len(tree.task_joints)
    _add_frame_jacobian(tree, tree.end_effector, buffers, 1.0, jacobian[row:row + frame])
    for i in range(len(tree.task_joints)):
        jacobian[row + frame + i, tree.task_joints[i]] = 1.0


@_uncounted
def velocities(tree, v, buffers):
    """Angular velocity and origin velocity of every joint body for joint rates ``v``."""
    origin, axis, angular, linear = buffers.origin, buffers.axis, buffers.angular, buffers.linear
    angular[0] = 0.0
    linear[0] = 0.0
    for j in range(1, len(tree.parent)):
        p = tree.parent[j]
        dx, dy, dz = origin[j, 0] - origin[p, 0], origin[j, 1] - origin[p, 1], origin[j, 2] - origin[p, 2]
        wx, wy, wz = angular[p, 0], angular[p, 1], angular[p, 2]
        linear[j, 0] = linear[p, 0] + wy * dz - wz * dy
        linear[j, 1] = linear[p, 1] + wz * dx - wx * dz
        linear[j, 2] = linear[p, 2] + wx * dy - wy * dx
        rate = v[tree.q_index[j]]
        if tree.revolute[j]:
            for k in range(3):
                angular[j, k] = angular[p, k] + axis[j, k] * rate
        else:
            for k in range(3):
                angular[j, k] = angular[p, k]
                linear[j, k] += axis[j, k] * rate


@_uncounted
def _add_frame_drift(tree, f, v, buffers, sign, out):
    """Add ``sign`` times the first len(out) (3 or 6) entries of frame ``f``'s drift J̇·v to ``out``."""
    origin, axis, angular, linear, dimension = buffers.origin, buffers.axis, buffers.angular, buffers.linear, len(out)
    j0 = tree.frame_parent[f]
    p = buffers.frame_origin[f]
    rx, ry, rz = p[0] - origin[j0, 0], p[1] - origin[j0, 1], p[2] - origin[j0, 2]
    wx, wy, wz = angular[j0, 0], angular[j0, 1], angular[j0, 2]
    ux = linear[j0, 0] + wy * rz - wz * ry  # velocity of the frame's origin
    uy = linear[j0, 1] + wz * rx - wx * rz
    uz = linear[j0, 2] + wx * ry - wy * rx
    for j in range(1, len(tree.parent)):
        if not tree.support[f, j]:
            continue
        rate = sign * v[tree.q_index[j]]
        ax, ay, az = axis[j, 0], axis[j, 1], axis[j, 2]
        bx, by, bz = angular[j, 0], angular[j, 1], angular[j, 2]
        tx, ty, tz = by * az - bz * ay, bz * ax - bx * az, bx * ay - by * ax  # d(axis)/dt
        if tree.revolute[j]:
            dx, dy, dz = p[0] - origin[j, 0], p[1] - origin[j, 1], p[2] - origin[j, 2]
            ex, ey, ez = ux - linear[j, 0], uy - linear[j, 1], uz - linear[j, 2]
            out[0] += rate * (ty * dz - tz * dy + ay * ez - az * ey)
            out[1] += rate * (tz * dx - tx * dz + az * ex - ax * ez)
            out[2] += rate * (tx * dy - ty * dx + ax * ey - ay * ex)
            if dimension == 6:
                out[3] += rate * tx
                out[4] += rate * ty
                out[5] += rate * tz
        else:
            out[0] += rate * tx
            out[1] += rate * ty
            out[2] += rate * tz


@_inlined
def drifts(tree, v, buffers):
    """Closure drifts, then the task drift, into ``buffers.drift`` (velocities already propagated)."""
    drift = buffers.drift
    drift[:] = 0.0
    row = 0
    for c in range(len(tree.closure_first)):
        dimension = tree.closure_dimension[c]
        _add_frame_drift(tree, tree.closure_first[c], v, buffers, 1.0, drift[row:row + dimension])
        _add_frame_drift(tree, tree.closure_second[c], v, buffers, -1.0, drift[row:row + dimension])
        row += dimension
    _add_frame_drift(tree, tree.end_effector, v, buffers, 1.0, drift[row:row + tree.task_dimension - len(tree.task_joints)])


# ---------------------------------------------------------------- the solver's quantities of one sample


@_inlined
def _factor_passive(tree, buffers, rows, damping):
    """Cholesky factor of J_pᵀ·J_p + damping·I (passive columns of the closure rows) in ``buffers.normal``."""
    _normal_lower(buffers.jacobian, rows, tree.passive, buffers.normal, buffers.nonzero)
    _cholesky(buffers.normal, len(tree.passive), damping)


@_uncounted
def basis(tree, buffers, rows, damping, g):
    """Null-space basis G (nv, n_act) of the closure rows into ``g``: G[act] = I, G[passive] = −J_p⁺·J_a.

    Leaves the Cholesky factor of J_pᵀ·J_p in ``buffers.normal`` for :func:`passive_correction`.
    """
    n_act, passive, actuated = len(tree.actuated), tree.passive, tree.actuated
    g[:, :] = 0.0
    for k in range(n_act):
        g[actuated[k], k] = 1.0
    n = len(passive)
    if n == 0:
        return
    _factor_passive(tree, buffers, rows, damping)
    jacobian, rhs = buffers.jacobian, buffers.rhs
    for i in range(n):
        for k in range(n_act):
            total = 0.0
            for r in range(rows):
                total -= jacobian[r, passive[i]] * jacobian[r, actuated[k]]
            rhs[i, k] = total
    _cholesky_solve(buffers.normal, n, rhs, n_act)
    for i in range(n):
        for k in range(n_act):
            g[passive[i], k] = rhs[i, k]


@_uncounted
def passive_correction(tree, buffers, rows, values, out):
    """``out[passive] = −J_p⁺·values`` (closure rows), with the factor left by :func:`basis`; others 0."""
    out[:] = 0.0
    n = len(tree.passive)
    if n == 0:
        return
    jacobian, rhs, passive = buffers.jacobian, buffers.rhs, tree.passive
    for i in range(n):
        total = 0.0
        for r in range(rows):
            total -= jacobian[r, passive[i]] * values[r]
        rhs[i, 0] = total
    _cholesky_solve(buffers.normal, n, rhs, np.int64(1))  # a literal 1 would compile a second solve
    for i in range(n):
        out[passive[i]] = rhs[i, 0]


@_uncounted
def _task_map_into(buffers, rows, g, out):
    """``out = J_task·G`` (task dim, n_act)."""
    jacobian = buffers.jacobian
    for k in range(out.shape[0]):
        for c in range(out.shape[1]):
            total = 0.0
            for j in range(g.shape[0]):
                total += jacobian[rows + k, j] * g[j, c]
            out[k, c] = total


# ---------------------------------------------------------------- batched entry points


@_uncounted
def _newton_one(tree, buffers, x, target_position, target_rotation, target_joints, pose, settings, tolerance, error,
                step):
    """Newton in place on one configuration ``x``; returns whether the residual norm fell below ``tolerance``.

    A full step shorter than ``settings[8]`` whose linear model leaves less than a tenth of ``tolerance``
    ends the iteration without another evaluation: the residual after it differs from the model's by the
    order of the step squared times the mechanism's size, far below the tolerance.
    """
    nv = len(x)
    square = len(error) == nv
    for _ in range(int(settings[1]) + 1):
        forward(tree, x, buffers)
        norm = residual(tree, buffers, x, target_position, target_rotation, target_joints, pose, error)
        if norm < tolerance:
            return True
        if not np.isfinite(norm):
            return False
        jacobians(tree, buffers)
        _newton_step(buffers, error, step, square, settings[3])
        largest = 0.0
        for k in range(nv):
            largest = max(largest, abs(step[k, 0]))
        scale = min(1.0, settings[2] / largest) if largest > 0.0 else 1.0
        for k in range(nv):
            x[k] -= scale * step[k, 0]
        if largest <= settings[8] and _model_remainder(buffers.jacobian, error, step) < 0.1 * tolerance:
            return True
    return False


@_inlined
def _model_remainder(jacobian, error, step):
    """Norm of ``error − J·step``: the residual that the linear model predicts after the step."""
    total = 0.0
    for r in range(jacobian.shape[0]):
        remainder = error[r]
        for j in range(jacobian.shape[1]):
            remainder -= jacobian[r, j] * step[j, 0]
        total += remainder * remainder
    return np.sqrt(total)


@_inlined
def _newton_step(buffers, error, step, square, damping):
    """The step (nv, 1) solving J·step ≈ error: exact when square and regular, else damped least squares
    (the mobility check at load leaves at least as many rows as joints)."""
    jacobian, normal = buffers.jacobian, buffers.normal
    rows, nv = jacobian.shape
    if square:
        for r in range(nv):
            for c in range(nv):
                normal[r, c] = jacobian[r, c]
            step[r, 0] = error[r]
        if _solve_square(normal, step, nv):
            return
    for i in range(nv):
        total = 0.0
        for r in range(rows):
            total += jacobian[r, i] * error[r]
        step[i, 0] = total
    _normal_lower(jacobian, rows, buffers.columns, normal, buffers.nonzero)
    _cholesky(normal, nv, damping)
    _cholesky_solve(normal, nv, step, step.shape[1])


@_internal
def _tangent_one(tree, buffers, q, damping, g, identity):
    """(nq, task dim) first-order change of one configuration per task displacement, D = G·M⁺."""
    rows = len(buffers.drift) - tree.task_dimension
    forward(tree, q, buffers)
    jacobians(tree, buffers)
    basis(tree, buffers, rows, damping, g)
    task_map = np.empty((tree.task_dimension, g.shape[1]))
    _task_map_into(buffers, rows, g, task_map)
    return _product(g, least_squares(task_map, identity, damping))


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]
def rates(tree, q, twist, acceleration, damping):
    """Joint rates and accelerations at solved configurations.

    ``v = G·M⁺·twist``; ``a = G·M⁺·(task acceleration − task drift − J_task·a0) + a0`` with
    ``a0[passive] = −J_p⁺·closure drift``. Returns v, a (B, nv), G (B, nv, n_act), the task map
    M = J_task·G (B, dim, n_act) and its condition number (B,). A singular sample's solves use the
    identity in place of M, so that every value stays finite.
    """
    b, nv = q.shape
    dim, n_act = tree.task_dimension, len(tree.actuated)
    v_out, a_out = np.empty((b, nv)), np.empty((b, nv))
    g_out, m_out = np.empty((b, nv, n_act)), np.empty((b, dim, n_act))
    condition = np.empty(b)
    buffers = _buffers(tree, nv)
    rows = len(buffers.drift) - dim
    a0, rhs, rate, inverse = np.empty(nv), np.empty(dim), np.empty(n_act), np.empty((n_act, dim))
    square, factors, square_inverse = np.empty((n_act, n_act)), np.empty((n_act, n_act)), np.empty((n_act, n_act))
    for i in range(b):
        g = g_out[i]
        forward(tree, q[i], buffers)
        jacobians(tree, buffers)
        basis(tree, buffers, rows, damping, g)
        _task_map_into(buffers, rows, g, m_out[i])
        condition[i] = _task_inverse(m_out[i], inverse, square, factors, square_inverse)
        _apply_into(inverse, twist[i], rate)
        _apply_into(g, rate, v_out[i])
        velocities(tree, v_out[i], buffers)
        drifts(tree, v_out[i], buffers)
        passive_correction(tree, buffers, rows, buffers.drift, a0)
        task = buffers.jacobian[rows:]
        for k in range(dim):
            total = acceleration[i, k] - buffers.drift[rows + k]
            for j in range(nv):
                total -= task[k, j] * a0[j]
            rhs[k] = total
        _apply_into(inverse, rhs, rate)
        _apply_into(g, rate, a_out[i])
        for j in range(nv):
            a_out[i, j] += a0[j]
    return v_out, a_out, g_out, m_out, condition


@_inlined
def _task_inverse(task_map, inverse, square, factors, square_inverse):
    """The task map's inverse, or for a tall one its left inverse (MᵀM)⁻¹·Mᵀ, (n_act, dim) into ``inverse``;
    returns its condition number: 1-norm when square; for a tall map the square root of MᵀM's (within a
    factor √n of the 2-norm figure). A singular map gives inf and the identity, so that values stay finite.
    ``square``, ``factors`` and ``square_inverse`` are (n_act, n_act) scratch."""
    dim, n_act = task_map.shape
    for r in range(n_act):
        for c in range(n_act):
            if dim == n_act:
                square[r, c] = task_map[r, c]
            else:
                total = 0.0
                for k in range(dim):
                    total += task_map[k, r] * task_map[k, c]
                square[r, c] = total
            factors[r, c] = square[r, c]
            square_inverse[r, c] = 1.0 if r == c else 0.0
    if not _solve_square(factors, square_inverse, n_act):
        for r in range(n_act):
            for c in range(dim):
                inverse[r, c] = 1.0 if r == c else 0.0
        return np.inf
    value = _norm_1(square) * _norm_1(square_inverse)
    if dim == n_act:
        for r in range(n_act):
            for c in range(dim):
                inverse[r, c] = square_inverse[r, c]
        return value
    for r in range(n_act):
        for c in range(dim):
            total = 0.0
            for k in range(n_act):
                total += square_inverse[r, k] * task_map[c, k]
            inverse[r, c] = total
    return np.sqrt(value)


@njit(cache=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]
def frames(tree, q, v):
    """Every solver frame's rotation (B, nf, 3, 3), origin (B, nf, 3), Jacobian (B, nf, 6, nv) and drift
    (B, nf, 6) for configurations q and rates v (B, nv)."""
    b, nv = q.shape
    nf = len(tree.frame_parent)
    rotation_out = np.empty((b, nf, 3, 3))
    origin_out = np.empty((b, nf, 3))
    jacobian_out = np.zeros((b, nf, 6, nv))
    drift_out = np.zeros((b, nf, 6))
    buffers = _buffers(tree, nv)
    for i in range(b):
        forward(tree, q[i], buffers)
        velocities(tree, v[i], buffers)
        rotation_out[i] = buffers.frame_rotation
        origin_out[i] = buffers.frame_origin
        for f in range(nf):
            _add_frame_jacobian(tree, f, buffers, 1.0, jacobian_out[i, f])
            _add_frame_drift(tree, f, v[i], buffers, 1.0, drift_out[i, f])
    return rotation_out, origin_out, jacobian_out, drift_out


@njit(cache=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]
def placements(tree, q):
    """Every solver frame's rotation (B, nf, 3, 3) and origin (B, nf, 3) for configurations q (B, nq), without
    Jacobians: the placements of many bodies (collision shapes, say) in one call."""
    b, nv = q.shape
    nf = len(tree.frame_parent)
    rotation_out = np.empty((b, nf, 3, 3))
    origin_out = np.empty((b, nf, 3))
    buffers = _buffers(tree, nv)
    for i in range(b):
        forward(tree, q[i], buffers)
        rotation_out[i] = buffers.frame_rotation
        origin_out[i] = buffers.frame_origin
    return rotation_out, origin_out


@njit(cache=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]
def rotation_vectors(rotation):
    """(B, 3) rotation vectors of (B, 3, 3) rotation matrices."""
    out = np.empty((rotation.shape[0], 3))
    for i in range(rotation.shape[0]):
        log3(rotation[i], out[i])
    return out


# ---------------------------------------------------------------- whole paths


@_internal
def _exp3(vector, scale, out):
    """Rotation matrix of the rotation vector ``scale · vector`` (rad), into ``out``."""
    x, y, z = scale * vector[0], scale * vector[1], scale * vector[2]
    angle = np.sqrt(x * x + y * y + z * z)
    sine, versine = (np.sin(angle) / angle, (1.0 - np.cos(angle)) / (angle * angle)) if angle > 1e-12 else (1.0, 0.5)
    skew = np.empty((3, 3))  # filled entry by entry: an array from nested lists compiles list building
    skew[0, 0], skew[0, 1], skew[0, 2] = 0.0, -z, y
    skew[1, 0], skew[1, 1], skew[1, 2] = z, 0.0, -x
    skew[2, 0], skew[2, 1], skew[2, 2] = -y, x, 0.0
    square = _product(skew, skew)
    for r in range(3):
        for c in range(3):
            out[r, c] = (1.0 if r == c else 0.0) + sine * skew[r, c] + versine * square[r, c]


@_internal
def _displacement(position_0, rotation_0, position_1, rotation_1, pose, out, scratch):
    """Task displacement from one target to another: position, then rotation (world) for a pose."""
    for k in range(3):
        out[k] = position_1[k] - position_0[k]
    if pose:
        _relative_rotation(rotation_1, rotation_0, scratch)
        log3(scratch, out[3:])


@njit(cache=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]
def _left_branch(solved, seed, local, tolerance):
    """Whether Newton moved a sample farther from its seed than twice ``local`` (m or rad), the most the
    joints can move on one branch over the stretch of path the seed was taken from, plus ``tolerance``."""
    moved = 0.0
    for k in range(len(solved)):
        moved = max(moved, abs(solved[k] - seed[k]))
    return moved > 2.0 * local + tolerance


@_inlined
def _branch_scale(tree, buffers, q, settings, g, identity):
    """Largest joint motion (m or rad) per metre of task motion at ``q`` on its branch: the largest row norm of
    D = G·M⁺, its rotation columns per ``settings[6]`` m (the length a radian counts for along the path)."""
    tangent = _tangent_one(tree, buffers, q, settings[3], g, identity)
    largest = 0.0
    for k in range(tangent.shape[0]):
        total = 0.0
        for j in range(tangent.shape[1]):
            weight = 1.0 if j < 3 else 1.0 / settings[6]
            term = weight * tangent[k, j]
            total += term * term
        largest = max(largest, np.sqrt(total))
    return largest


@_uncounted
def _copy(source, target):
    """``target[:] = source`` for vectors, by a loop (a slice assignment compiles a shape check with its message)."""
    for k in range(len(target)):
        target[k] = source[k]


@_internal
def _max_abs(vector):
    """Largest magnitude of a vector's entries."""
    largest = 0.0
    for k in range(len(vector)):
        largest = max(largest, abs(vector[k]))
    return largest


@_internal
def _joint_displacement(tree, before, after, out):
    """The prescribed joints' change from ``before`` to ``after`` into the task displacement's last rows."""
    row = tree.task_dimension - len(tree.task_joints)
    for i in range(len(tree.task_joints)):
        out[row + i] = after[i] - before[i]


@_internal
def _predict(q, tangent, motion, change):
    """The first-order prediction ``q + D·Δx`` of a configuration, D·Δx into ``change``."""
    _apply_into(tangent, motion, change)
    out = np.empty(len(q))
    for k in range(len(q)):
        out[k] = q[k] + change[k]
    return out


@_internal
def _cubic(q, base, row, out):
    """Lagrange interpolation at sample ``row[0]`` through the samples ``row[1:5]`` (outer left, left, right,
    outer right) of the placement starting at ``base``; an outer node equal to its inner neighbour (at the
    ends of the path) is left out."""
    at = row[0]
    used = (row[1] != row[2], True, True, row[4] != row[3])
    out[:] = 0.0
    for i in range(4):
        if not used[i]:
            continue
        weight = 1.0
        for j in range(4):
            if j != i and used[j]:
                weight *= (at - row[1 + j]) / (row[1 + i] - row[1 + j])
        for k in range(len(out)):
            out[k] += weight * q[base + row[1 + i], k]


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]
def solve_paths(tree, reference_q, positions, rotations, joint_targets, pose, n, coarse, schedule, arc, settings):
    """Every sample of every placement's path, placement after placement (see :mod:`placement.kinematics.batched`).

    Branch test (``_left_branch``): a coarse sample's Newton correction is compared with its first-order
    prediction; a refined sample's with the most the joints can move along the stretch of path its seed
    is interpolated over (outer left to outer right): ``_branch_scale`` at the solution times that
    stretch's length. Not with the change between the solved neighbours, which vanishes where the path
    comes back near where it was (a small closed curve between two coarse samples) while the joints
    move in between.

    Args:
        tree: The tree description.
        reference_q: (nq,) the reference configuration, on the assembly mode to keep.
        positions, rotations: (P·n, 3) and (P·n, 3, 3) end-effector targets, placement after placement.
        joint_targets: (P·n, n_p) the prescribed joints' values (``tree.task_joints``), m or rad.
        pose: Whether rotations are prescribed.
        n: Samples per placement.
        coarse: Indices of the coarse samples, marched one after the other (0 first, n - 1 last).
        schedule: (L, 5) bisection refinement in order: middle, outer left, left, right, outer right.
        arc: (n,) length of path from the first sample to each (m, a radian counted as ``settings[6]`` m),
            the same for every placement.
        settings: solve tolerance, most iterations, largest step, damping, continuation step (m),
            continuation tolerance, metres per radian, branch tolerance, final step.

    Returns:
        Configurations (P·n, nq), which samples converged, and which left the branch.
    """
    total, nv = len(positions), len(reference_q)
    q = np.empty((total, nv))
    ok, flipped = np.empty(total, dtype=np.bool_), np.empty(total, dtype=np.bool_)
    for i in range(total):  # a loop, as np.zeros compiles a fill of its own for each array type
        ok[i], flipped[i] = False, False
    buffers = _buffers(tree, nv)
    rows = len(buffers.drift)
    error = np.empty(rows)
    step = np.empty((max(rows, nv), 1))
    g = np.empty((nv, len(tree.actuated)))
    identity = np.zeros((tree.task_dimension, tree.task_dimension))  # np.eye compiles several implementations
    for k in range(tree.task_dimension):
        identity[k, k] = 1.0
    motion, prediction, scratch = np.empty(tree.task_dimension), np.empty(nv), np.empty((3, 3))
    forward(tree, reference_q, buffers)
    reference_position = buffers.frame_origin[tree.end_effector].copy()
    reference_rotation = buffers.frame_rotation[tree.end_effector].copy()
    for p in range(total // n):  # each placement's path
        base = p * n
        ok[base] = _assemble(tree, buffers, reference_q, reference_position, reference_rotation, positions[base],
                             rotations[base], joint_targets[base], pose, settings, q[base], error, step, g, identity,
                             motion, scratch)
        for c in range(len(coarse) - 1):
            before, now = base + coarse[c], base + coarse[c + 1]
            if ok[before]:
                _displacement(positions[before], rotations[before], positions[now], rotations[now], pose, motion, scratch)
                _joint_displacement(tree, joint_targets[before], joint_targets[now], motion)
                seed = _predict(q[before], _tangent_one(tree, buffers, q[before], settings[3], g, identity), motion,
                                prediction)
            else:  # after a failure, start again from the last solved configuration
                prediction[:] = 0.0
                seed = q[before].copy()
            solved = seed.copy()
            ok[now] = _newton_one(tree, buffers, solved, positions[now], rotations[now], joint_targets[now], pose,
                                  settings, settings[0], error, step)
            _copy(solved if ok[now] else q[before], q[now])
            flipped[now] = ok[before] and _left_branch(solved, seed, _max_abs(prediction), settings[7])
        seed = np.empty(nv)
        for r in range(len(schedule)):
            middle = base + schedule[r, 0]
            _cubic(q, base, schedule[r], seed)
            solved = q[middle]
            _copy(seed, solved)
            ok[middle] = _newton_one(tree, buffers, solved, positions[middle], rotations[middle], joint_targets[middle],
                                     pose, settings, settings[0], error, step)
            if ok[middle] and _left_branch(solved, seed, 0.0, settings[7]):  # moved beyond the tolerance: how far may it?
                stretch = arc[schedule[r, 4]] - arc[schedule[r, 1]]
                local = _branch_scale(tree, buffers, solved, settings, g, identity) * stretch
                flipped[middle] = _left_branch(solved, seed, local, settings[7])
            if not ok[middle]:
                _copy(seed, solved)
    return q, ok, flipped


@_inlined
def _assemble(tree, buffers, reference_q, reference_position, reference_rotation, target_position, target_rotation,
              target_joints, pose, settings, out, error, step, g, identity, motion, scratch):
    """The first configuration of a path, by predicted continuation from the reference configuration in
    steps of at most ``settings[4]`` (m, rotation counted at ``settings[6]`` m/rad); returns success."""
    turn = np.empty(3)
    for k in range(3):
        turn[k] = 0.0
    dx, dy, dz = (target_position[0] - reference_position[0], target_position[1] - reference_position[1],
                  target_position[2] - reference_position[2])
    distance = np.sqrt(dx * dx + dy * dy + dz * dz)
    if pose:
        _relative_rotation(reference_rotation.T.copy(), target_rotation.T.copy(), scratch)  # R_refᵀ·R_target
        log3(scratch, turn)
        distance = max(distance, settings[6] * np.sqrt(turn[0] * turn[0] + turn[1] * turn[1] + turn[2] * turn[2]))
    n_p = len(tree.task_joints)
    previous_joints, goal_joints = np.empty(n_p), np.empty(n_p)
    for i in range(n_p):
        previous_joints[i] = reference_q[tree.task_joints[i]]
        distance = max(distance, settings[6] * abs(target_joints[i] - previous_joints[i]))
    steps = max(1, int(np.ceil(distance / settings[4])))
    x = reference_q.copy()
    success = True
    previous_position, previous_rotation = reference_position.copy(), reference_rotation.copy()
    goal_rotation, change = reference_rotation.copy(), np.empty(len(x))
    for s in range(1, steps + 1):
        fraction = s / steps
        goal_position = np.empty(3)
        for k in range(3):
            goal_position[k] = reference_position[k] + fraction * (target_position[k] - reference_position[k])
        if pose:
            _exp3(turn, fraction, scratch)
            goal_rotation = _product(reference_rotation, scratch)
        for i in range(n_p):
            goal_joints[i] = reference_q[tree.task_joints[i]] + fraction * (target_joints[i] - reference_q[tree.task_joints[i]])
        _displacement(previous_position, previous_rotation, goal_position, goal_rotation, pose, motion, scratch)
        _joint_displacement(tree, previous_joints, goal_joints, motion)
        seed = _predict(x, _tangent_one(tree, buffers, x, settings[3], g, identity), motion, change)
        tolerance = settings[0] if s == steps else settings[5]
        if _newton_one(tree, buffers, seed, goal_position, goal_rotation, goal_joints, pose, settings, tolerance, error,
                       step):
            x = seed
        else:
            success = False
        previous_position, previous_rotation = goal_position, goal_rotation
        _copy(goal_joints, previous_joints)
    _copy(x, out)
    return success
