"""The stages of a first compile of the generic kinematics' kernels, shared between the command's process and a
helper process (see :mod:`placement.kinematics.warmup`).

The kernels' numba types do not depend on the robot, so compiling them for the argument types of a one-joint
tree compiles (or loads from numba's on-disk cache) exactly what every robot uses. numba compiles a function's
callees before the function, each loaded from the cache when another process has saved it there already. A
stage compiles some kernels for the types their callers pass (every array C-contiguous, every index int64):

- the helper compiles the low-level stage (forward kinematics, Jacobians, the null-space basis, products),
  says so on its standard output, then Newton, says so, then the rates and the rotation vectors;
- the command's process meanwhile compiles the leaves (small kernels that need no low-level one), then, once
  the helper has the low-level stage, the tangent map, and once it has Newton, the path solve.

The largest compiles, the path solve's and the rates' (each optimises its callees again with itself), then run
at once, one on each core. This module imports only numpy, numba, Pinocchio and the kernels, so that the helper
starts in a fraction of the library's import time.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numba
import numpy as np
import pinocchio as pin

from placement.kinematics import kernels
from placement.kinematics.kernels import TreeArrays, _Buffers
from placement.kinematics.tree import tree_arrays

LOW_LEVEL = "low-level"  # the helper's first stage: kernels that Newton, the tangent map and the rates call
NEWTON = "newton"  # the helper's second stage: Newton, which the path solve calls
SETTINGS_LENGTH = 9  # kernels.solve_paths' settings vector


class Sample(NamedTuple):
    """Arguments of the kernels on a one-joint tree (a revolute joint with its tip 1 m away, a position task)."""

    tree: TreeArrays
    buffers: _Buffers
    q: np.ndarray  # (1,) rad
    positions: np.ndarray  # (2, 3) m
    rotations: np.ndarray  # (2, 3, 3)

    @classmethod
    def build(cls) -> Sample:
        model = pin.Model()
        joint = model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "joint")
        tip = pin.SE3(np.eye(3), np.array([1.0, 0.0, 0.0]))
        frame = model.addFrame(pin.Frame("tip", joint, tip, pin.FrameType.OP_FRAME))
        tree = tree_arrays(model, [frame], end_effector=0, task_dimension=3, actuated=[0])
        return cls(tree, kernels._buffers.py_func(tree, 1), np.zeros(1), np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
                   np.zeros((2, 3, 3)))


def _signature(*arguments: object) -> tuple:
    """The numba types of some arguments, as the kernels that pass them type them."""
    return tuple(numba.typeof(argument) for argument in arguments)


def _compile(function: Callable, *arguments: object) -> None:
    """Compile a kernel for the types of ``arguments`` (or load it from the cache)."""
    function.compile(_signature(*arguments))  # type: ignore[attr-defined]  # a numba dispatcher


def compile_probe(sample: Sample) -> None:
    """The smallest kernel (a vector copy), compiled first: whether numba's cache had it tells whether it holds the
    rest."""
    vector = sample.q
    _compile(kernels._copy, vector, vector)


def compile_leaves(sample: Sample) -> None:
    """The command's first stage: kernels that call no low-level one (the square solve and the residual, which
    Newton and the tangent map call, the path solve's small helpers, and the buffers, which the path solve and
    the rates make)."""
    tree, buffers, vector, matrix = sample.tree, sample.buffers, np.zeros(3), np.eye(3)
    _compile(kernels._solve_square, matrix, matrix, 0)
    _compile(kernels.residual, tree, buffers, sample.q, vector, matrix, np.zeros(0), False, vector)
    _compile(kernels._exp3, vector, 0.0, matrix)
    _compile(kernels._displacement, vector, matrix, vector, matrix, False, vector, matrix)
    _compile(kernels._predict, vector, matrix, vector, vector)
    _compile(kernels._cubic, matrix, 0, np.zeros(5, dtype=np.int64), vector)
    _compile(kernels._left_branch, vector, vector, 0.0, 0.0)
    _compile(kernels._max_abs, vector)
    _compile(kernels._joint_displacement, tree, np.zeros(0), np.zeros(0), vector)
    _compile(kernels._buffers, tree, 0)


def compile_low_level(sample: Sample) -> None:
    """The helper's first stage: forward kinematics, Jacobians, the null-space basis, the task map, products."""
    tree, buffers, g = sample.tree, sample.buffers, np.empty((1, 1))
    _compile(kernels.forward, tree, sample.q, buffers)
    _compile(kernels.jacobians, tree, buffers)
    _compile(kernels.basis, tree, buffers, 0, 0.0, g)
    _compile(kernels._task_map_into, buffers, 0, g, g)
    _compile(kernels._gram, g)
    _compile(kernels._product, g, g)


def compile_newton(sample: Sample) -> None:
    """The helper's second stage: Newton on one configuration (the square solve and the residual found in the
    cache, compiled by the command's first stage)."""
    tree, buffers = sample.tree, sample.buffers
    _compile(kernels._newton_one, tree, buffers, sample.q, sample.positions[0], sample.rotations[0], np.zeros(0), False,
             np.zeros(SETTINGS_LENGTH), 0.0, buffers.drift, np.empty((1, 1)))


def compile_rates(sample: Sample) -> None:
    """The helper's last stage: velocities, the rates and the rotation vectors (entry points of their own)."""
    matrix = np.zeros((2, 3))
    _compile(kernels.velocities, sample.tree, sample.q, sample.buffers)
    _compile(kernels.rates, sample.tree, np.zeros((2, 1)), matrix, matrix, 0.0)
    _compile(kernels.rotation_vectors, sample.rotations)


def compile_tangent(sample: Sample) -> None:
    """The command's second stage (after the helper's low-level one): the tangent map."""
    _compile(kernels._tangent_one, sample.tree, sample.buffers, sample.q, 0.0, np.empty((1, 1)), np.eye(3))


def compile_paths(sample: Sample) -> None:
    """The command's last stage (after the helper's Newton): the path solve."""
    _compile(kernels.solve_paths, sample.tree, sample.q, sample.positions, sample.rotations, np.zeros((2, 0)), False, 2,
             np.zeros(2, dtype=np.int64), np.zeros((0, 5), dtype=np.int64), np.zeros(2), np.zeros(SETTINGS_LENGTH))


def helper_stages() -> None:
    """The helper process's work: its three stages, each announced on standard output when done."""
    sample = Sample.build()
    compile_low_level(sample)
    print(LOW_LEVEL, flush=True)
    compile_newton(sample)
    print(NEWTON, flush=True)
    compile_rates(sample)
