"""A Pinocchio spanning tree as flat arrays, for the compiled kernels of :mod:`placement.kinematics.kernels`.

Joints are revolute or prismatic about any fixed axis (URDF ``revolute``, ``continuous`` and
``prismatic``, a continuous joint read as a revolute one by :func:`placement.robot.urdf.one_angle_urdf`;
fixed joints are merged into frames). The solver works on a short list of frames: the two frames
of every loop closure, then the end effector.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from placement.kinematics import kernels
from placement.kinematics.kernels import TreeArrays

REVOLUTE = {"JointModelRX": (1.0, 0.0, 0.0), "JointModelRY": (0.0, 1.0, 0.0), "JointModelRZ": (0.0, 0.0, 1.0)}
PRISMATIC = {"JointModelPX": (1.0, 0.0, 0.0), "JointModelPY": (0.0, 1.0, 0.0), "JointModelPZ": (0.0, 0.0, 1.0)}


def unsupported_joints(model: pin.Model) -> list[str]:
    """Names and kinds of the joints the compiled tree cannot handle (empty when it can)."""
    return [f"{model.names[j]} ({joint.shortname()})" for j, joint in enumerate(model.joints)
            if j > 0 and not joint_axis(joint)]


def joint_axis(joint: pin.JointModel) -> tuple[tuple[float, ...], bool] | None:
    """The axis of a revolute or prismatic joint about a fixed axis, in its frame, and whether it is revolute;
    None for another kind of joint."""
    name = joint.shortname()
    if name in REVOLUTE:
        return REVOLUTE[name], True
    if name in PRISMATIC:
        return PRISMATIC[name], False
    if name in ("JointModelRevoluteUnaligned", "JointModelPrismaticUnaligned"):
        return tuple(joint.extract().axis), name.startswith("JointModelRevolute")
    return None


def tree_arrays(model: pin.Model, frame_ids: Sequence[int], *, closures: Sequence[tuple[int, int, int]] = (),
                end_effector: int = 0, task_dimension: int = 3, actuated: Sequence[int] | np.ndarray = ()) -> TreeArrays:
    """The flat description of ``model`` with the solver frames ``frame_ids`` (Pinocchio frame ids).

    Args:
        model: Pinocchio model of the spanning tree (revolute and prismatic joints only).
        frame_ids: Model frames the kernels place, in the order they are indexed.
        closures: (index of the first frame, index of the second, 3 or 6) per closure, indices into
            ``frame_ids``.
        end_effector: Index into ``frame_ids`` of the end effector.
        task_dimension: 3 (position task) or 6 (pose task).
        actuated: Velocity indices of the actuated joints.

    Raises:
        ValueError: The model has another kind of joint.
    """
    unsupported = unsupported_joints(model)
    if unsupported:
        raise ValueError(f"joints of unsupported kind: {', '.join(unsupported)}")
    nj = model.njoints
    axis = np.zeros((nj, 3))
    revolute = np.zeros(nj, dtype=bool)
    q_index = np.zeros(nj, dtype=np.int64)
    for j in range(1, nj):
        found, revolute[j] = joint_axis(model.joints[j])  # type: ignore[misc]
        axis[j] = found
        q_index[j] = model.joints[j].idx_q
    constants = np.zeros((nj, 3, 11))
    for j in range(1, nj):
        rotation, a = model.jointPlacements[j].rotation, axis[j]
        skew = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
        constants[j] = np.hstack([rotation, rotation @ skew, rotation @ skew @ skew, (rotation @ a)[:, None],
                                  model.jointPlacements[j].translation[:, None]])
    support = np.zeros((len(frame_ids), nj), dtype=bool)
    for f, frame_id in enumerate(frame_ids):
        support[f, list(model.supports[model.frames[frame_id].parentJoint])[1:]] = True
    act = np.asarray(actuated, dtype=np.int64)
    return TreeArrays(
        parent=np.array(list(model.parents), dtype=np.int64),
        constants=constants, revolute=revolute, q_index=q_index,
        frame_parent=np.array([model.frames[f].parentJoint for f in frame_ids], dtype=np.int64),
        frame_rotation=np.array([model.frames[f].placement.rotation for f in frame_ids]).reshape(-1, 3, 3),
        frame_translation=np.array([model.frames[f].placement.translation for f in frame_ids]).reshape(-1, 3),
        support=support,
        closure_first=np.array([c[0] for c in closures], dtype=np.int64),
        closure_second=np.array([c[1] for c in closures], dtype=np.int64),
        closure_dimension=np.array([c[2] for c in closures], dtype=np.int64),
        end_effector=int(end_effector), task_dimension=int(task_dimension),
        actuated=act, passive=np.setdiff1d(np.arange(model.nv), act).astype(np.int64),
    )


def frame_kinematics(model: pin.Model, frame_ids: Sequence[int], q: np.ndarray,
                     v: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Rotations (B, F, 3, 3), origins (B, F, 3), world-aligned Jacobians (B, F, 6, nv) and drifts J̇·v
    (B, F, 6) of the frames ``frame_ids`` for configurations q and rates v (B, nv)."""
    tree = tree_arrays(model, frame_ids)
    return kernels.frames(tree, np.ascontiguousarray(q, dtype=float), np.ascontiguousarray(v, dtype=float))


def log3(rotation: np.ndarray) -> np.ndarray:
    """(B, 3) rotation vectors of (B, 3, 3) rotation matrices (rad), as ``pin.log3``."""
    return kernels.rotation_vectors(np.ascontiguousarray(rotation, dtype=float))
