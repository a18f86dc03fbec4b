"""Shaking objectives: the peak force and moment the moving robot exerts on its base.

The shaking force and moment are the rate of change of the linear and angular momentum of every
moving body (Arakelian and Briot's definition, gravity's static load left out): F = m·a_G and
M = dH_O/dt about the base frame origin O. They excite the machine's frame and its foundation,
and matter most for fast parallel robots. The process force is left out too: the workpiece is
fixed to the same base, so it closes on itself.

Both are computed exactly and batched with one RNEA call: the robot's tree is carried by a
massless free-flyer joint held at rest at the base frame, with gravity off. The free-flyer's
six efforts are then the wrench [F, M_O] the base must apply to keep it still, expressed in the
base frame.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from placement.contract.batch import EvaluatedBatch
from placement.contract.objective import OBJECTIVES, Objective
from placement.dynamics.inverse import rnea_batch
from placement.robot.model import Robot

FREE_FLYER_NQ, FREE_FLYER_NV = 7, 6


def floating_model(robot: Robot) -> pin.Model:
    """The robot's tree (joints and inertias) on a massless free-flyer joint at the base frame, without gravity."""
    tree, model = robot.model, pin.Model()
    carrier = model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "base_reaction")
    for joint in range(1, tree.njoints):
        parent = tree.parents[joint]
        added = model.addJoint(parent + 1 if parent else carrier, tree.joints[joint], tree.jointPlacements[joint],
                               tree.names[joint])
        model.appendBodyToJoint(added, tree.inertias[joint], pin.SE3.Identity())
    model.gravity = pin.Motion.Zero()
    return model


def base_wrench(robot: Robot, q: np.ndarray, v: np.ndarray, a: np.ndarray, threads: int | None = None) -> np.ndarray:
    """(M, 6) rate of change of the moving bodies' momentum: force (N), then moment about O (N·m), base frame.

    Args:
        robot: The robot.
        q, v, a: (M, nq), (M, nv), (M, nv) motion of the spanning tree's joints.
        threads: Most threads of the batched RNEA.
    """
    model = floating_model(robot)
    rest = np.zeros((len(q), FREE_FLYER_NV))
    at_origin = np.tile(pin.neutral(model)[:FREE_FLYER_NQ], (len(q), 1))
    tau = rnea_batch(model, np.hstack([at_origin, q]), np.hstack([rest, v]), np.hstack([rest, a]), threads)
    return tau[:, :FREE_FLYER_NV]


def _peak(batch: EvaluatedBatch, part: slice) -> np.ndarray:
    k, n = batch.reachable.shape
    wrench = base_wrench(batch.robot, batch.joints.q, batch.joints.v, batch.joints.a)
    return np.linalg.norm(wrench[:, part], axis=1).reshape(k, n).max(axis=1)


class ShakingForce(Objective):
    """Peak magnitude of the shaking force m·a_G on the base along the path."""

    title = "peak shaking force"
    unit = "N"

    def __call__(self, batch: EvaluatedBatch) -> np.ndarray:
        return _peak(batch, slice(0, 3))


class ShakingMoment(Objective):
    """Peak magnitude of the shaking moment dH_O/dt about the base frame origin along the path."""

    title = "peak shaking moment"
    unit = "N m"

    def __call__(self, batch: EvaluatedBatch) -> np.ndarray:
        return _peak(batch, slice(3, 6))


OBJECTIVES.add("shaking_force", ShakingForce())
OBJECTIVES.add("shaking_moment", ShakingMoment())
