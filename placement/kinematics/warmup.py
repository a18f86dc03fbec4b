"""The generic kinematics' compiled kernels made ready before a command needs them: loaded from numba's cache, or,
on a machine's first run, compiled by two processes at once.

The kernels' numba types do not depend on the robot, so running them once on a one-joint tree compiles (or
loads) exactly what every robot uses. A first compile costs about 20 s of CPU, most of it in the path solve,
which compiles its callees before itself. It is shared with a helper process; both write numba's on-disk cache,
which each process reads before compiling a function:

- this process compiles the tangent map (``_tangent_one``: forward kinematics, Jacobians, null-space basis,
  least squares), then the path solve, whose Newton it then finds in the cache;
- the helper compiles the buffers and Newton (``_newton_one``), then the rates and the rotation vectors, which
  this process then loads from the cache.

Both compile the forward kinematics and the Jacobians, a second or so of CPU spent twice. Whatever the helper
did not leave in the cache (it could not start, say) is compiled here; when this process finds its share in
the cache, the helper is stopped at once.
"""

from __future__ import annotations

import os
import subprocess
import sys
from typing import NamedTuple

import numba
import numpy as np
import pinocchio as pin

from placement.kinematics import kernels
from placement.kinematics.batched import DAMPING, SETTINGS
from placement.kinematics.kernels import TreeArrays, _Buffers
from placement.kinematics.tree import tree_arrays

ENTRY_POINTS = (kernels.solve_paths, kernels.rates, kernels.rotation_vectors)


def touch_kernels() -> None:
    """Load or compile every kernel a robot uses (on a machine's first run about 10 s, shared with a helper
    process)."""
    if all(function.signatures for function in ENTRY_POINTS):  # this process has them already
        return
    helper = _start_helper()
    compiled = _own_share()
    if helper is not None:
        if not compiled:  # found in the cache: the helper's share is there too (or is compiled below)
            helper.terminate()
        helper.wait()
    _run_entry_points(_Sample.build(), rates=True)


def _start_helper() -> subprocess.Popen | None:
    """A Python process running :func:`helper_share` on this process's import path (None if none can start). Its
    output is discarded: if it fails, this process compiles its share."""
    path = [entry or os.getcwd() for entry in sys.path]
    try:
        return subprocess.Popen([sys.executable, "-c", f"from {__name__} import helper_share; helper_share()"],
                                env={**os.environ, "PYTHONPATH": os.pathsep.join(path)}, stdin=subprocess.DEVNULL,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    except OSError:
        return None


class _Sample(NamedTuple):
    """Arguments of the kernels on a one-joint tree (a revolute joint with its tip 1 m away, a position task)."""

    tree: TreeArrays
    buffers: _Buffers
    q: np.ndarray  # (1,)
    positions: np.ndarray  # (2, 3) m
    rotations: np.ndarray  # (2, 3, 3)

    @classmethod
    def build(cls) -> _Sample:
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


def _own_share() -> bool:
    """This process's share of a first compile (the tangent map, then the path solve); returns whether anything was
    compiled (else it was all in the cache)."""
    sample = _Sample.build()
    tree, buffers = sample.tree, sample.buffers
    kernels._tangent_one.compile(_signature(tree, buffers, sample.q, 0.0, np.empty((1, 1)), np.eye(3)))
    _run_entry_points(sample, rates=False)
    return any(function.stats.cache_misses for function in (kernels._tangent_one, kernels.solve_paths))


def helper_share() -> None:
    """The helper process's share of a first compile: the buffers and Newton, then the rates (run by
    :func:`_start_helper`'s process)."""
    sample = _Sample.build()
    tree, buffers = sample.tree, sample.buffers
    kernels._buffers.compile(_signature(tree, 1))
    kernels._newton_one.compile(_signature(tree, buffers, sample.q, sample.positions[0], sample.rotations[0], False,
                                           SETTINGS, 0.0, buffers.drift, np.empty((1, 1))))
    kernels.rates(tree, np.zeros((2, 1)), np.zeros((2, 3)), np.zeros((2, 3)), DAMPING)
    kernels.rotation_vectors(np.eye(3)[None])


def _run_entry_points(sample: _Sample, rates: bool) -> None:
    """Run the path solve, and with ``rates`` the rates and the rotation vectors, on the sample (compiling them, or
    loading them from the cache, on first use)."""
    q, _, _ = kernels.solve_paths(sample.tree, sample.q, sample.positions, sample.rotations, False, 2,
                                  np.array([0, 1], dtype=np.int64), np.zeros((0, 5), dtype=np.int64),
                                  np.array([0.0, np.sqrt(2.0)]), SETTINGS)
    if rates:
        kernels.rates(sample.tree, q, np.zeros((2, 3)), np.zeros((2, 3)), DAMPING)
        kernels.rotation_vectors(np.eye(3)[None])
