"""The compiled kernels, built once before pytest-xdist's workers start (``python -m pytest -n 2``).

On a fresh numba cache each worker would otherwise compile every kernel its first tests call (some 35 s of CPU
each, and as much again in each command-line process a test starts before the cache is filled). Built once in
the controlling process, they are in numba's disk cache (``NUMBA_CACHE_DIR``, else ``__pycache__`` beside the
modules), where the workers and their command-line processes load them. A warm cache is loaded in about a second.

The work is shared by three processes, so that it takes about half its CPU time: the generic kinematics'
(:func:`placement.kinematics.warmup.touch_kernels`, itself in two processes), then the frames' and placements'
kernels here, while another process compiles the dynamics', the optimal timing law's, the collision
bounds' and the closed-form kinematics'.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pinocchio as pin

from placement.collision.bounds import SPHERE, pair_bounds
from placement.contract.limit import PathBound
from placement.dynamics.path_dynamics import PathForm
from placement.dynamics.tree_rnea import touch_tree_kernels
from placement.evaluation.timed_motion import _timed_columns
from placement.kinematics import kernels
from placement.kinematics.closed_form import touch_joint_motion_kernel
from placement.kinematics.tree import tree_arrays
from placement.kinematics.warmup import touch_kernels
from placement.timing.optimal import bound_rows
from placement.timing.topp import time_placements
from tests.support.paths import ROOT


def compile_kernels() -> None:
    """Compile (or load from the cache) every kernel the library calls, for the argument types it passes them."""
    other = subprocess.Popen([sys.executable, "-c", f"from {__name__} import compile_others; compile_others()"],
                             cwd=ROOT, env={**os.environ, "PYTHONPATH": os.pathsep.join(entry or os.getcwd()
                                                                                        for entry in sys.path)},
                             stdin=subprocess.DEVNULL)
    touch_kernels()
    tree, q = _one_joint_tree(), np.zeros((1, 1))
    kernels.frames(tree, q, q)
    kernels.placements(tree, q)
    if other.wait() != 0:  # its error was printed; here it is raised
        compile_others()


def compile_others() -> None:
    """The dynamics', the optimal timing law's, the collision bounds' and the closed-form kinematics' kernels."""
    touch_tree_kernels(path=True)
    touch_joint_motion_kernel()
    rows = np.array([[[1.0], [-1.0]]])  # one placement, two samples: -1 <= s̈ <= 1
    time_placements(np.array([0.0, 1.0]), np.array([0, 2]), np.array([False]), rows, np.zeros((1, 2, 1)),
                    -np.ones((1, 2, 1)), np.ones((1, 2)), np.array([True]))
    column = np.moveaxis(np.ones((1, 1, 2)), 0, -1)  # one placement's two samples, laid out as the path dynamics
    bound_rows([PathBound("motor torque", PathForm(a=column, b=column, c=column, w=column), np.ones(1))], np.ones((1, 2)))
    _timed_columns(np.ones((1, 2, 1)), *[np.ones((1, 1, 2))] * 5, np.array([0, 1, 1]), np.ones((1, 3)), np.ones((1, 3)),
                   np.empty((4, 1, 1, 3)))
    rotation, centre_m = np.eye(3)[None, None], np.zeros((1, 1, 3))  # one shape, in one configuration
    shape = np.array([0], dtype=np.int64)
    pair_bounds(rotation, centre_m, shape, shape, np.array([False]), np.full(1, SPHERE, dtype=np.int64),
                np.ones(1), np.ones((1, 3)), np.zeros((1, 3)), 0.0)


def _one_joint_tree() -> kernels.TreeArrays:
    """The compiled tree of a revolute joint with one frame on it (the kernels' types do not depend on the robot)."""
    model = pin.Model()
    joint = model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "joint")
    frame = model.addFrame(pin.Frame("tip", joint, pin.SE3.Identity(), pin.FrameType.OP_FRAME))
    return tree_arrays(model, [frame])
