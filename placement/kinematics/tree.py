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


def joint_axes(model: pin.Model) -> tuple[np.ndarray, np.ndarray] | None:
    """(nj, 3) every joint's axis in its frame and (nj,) whether it is revolute (the universe's row 0), or None when
    a joint is neither revolute nor prismatic about a fixed axis."""
    found = [joint_axis(model.joints[j]) for j in range(1, model.njoints)]
    if any(each is None for each in found):
        return None
    axis, revolute = np.zeros((model.njoints, 3)), np.zeros(model.njoints, dtype=bool)
    for j, each in enumerate(found, start=1):
        assert each is not None
        axis[j], revolute[j] = each
    return axis, revolute


def joint_constants(model: pin.Model, axis: np.ndarray) -> np.ndarray:
    """(nj, 3, 11) each joint's placement in its parent at q, [R0, R0·[a], R0·[a]², R0·a, t0]: its rotation is
    R0 + sin(q)·R0·[a] + (1 − cos(q))·R0·[a]² about a revolute axis a, its origin t0 + q·R0·a along a prismatic
    one (R0, t0: the placement at q = 0; ``axis``: from :func:`joint_axes`)."""
    constants = np.zeros((model.njoints, 3, 11))
    for j in range(1, model.njoints):
        rotation, a = model.jointPlacements[j].rotation, axis[j]
        skew = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
        constants[j] = np.hstack([rotation, rotation @ skew, rotation @ skew @ skew, (rotation @ a)[:, None],
                                  model.jointPlacements[j].translation[:, None]])
    return constants


def tree_arrays(model: pin.Model, frame_ids: Sequence[int], *, closures: Sequence[tuple[int, int, int]] = (),
                end_effector: int = 0, task_dimension: int = 3, actuated: Sequence[int] | np.ndarray = (),
                task_joints: Sequence[int] | np.ndarray = ()) -> TreeArrays:
    """The flat description of ``model`` with the solver frames ``frame_ids`` (Pinocchio frame ids).

    Args:
        model: Pinocchio model of the spanning tree (revolute and prismatic joints only).
        frame_ids: Model frames the kernels place, in the order they are indexed.
        closures: (index of the first frame, index of the second, 3 or 6) per closure, indices into
            ``frame_ids``.
        end_effector: Index into ``frame_ids`` of the end effector.
        task_dimension: 3 (position task) or 6 (pose task), without the prescribed joints.
        actuated: Velocity indices of the actuated joints.
        task_joints: Configuration indices of joints whose values the task prescribes along the path (a redundant
            joint's profile): each adds a task row after the end effector's.

    Raises:
        ValueError: The model has another kind of joint.
    """
    unsupported = unsupported_joints(model)
    if unsupported:
        raise ValueError(f"joints of unsupported kind: {', '.join(unsupported)}")
    axes = joint_axes(model)
    assert axes is not None  # every joint is supported
    q_index = np.array([0] + [model.joints[j].idx_q for j in range(1, model.njoints)], dtype=np.int64)
    constants = joint_constants(model, axes[0])
    support = np.zeros((len(frame_ids), model.njoints), dtype=bool)
    for f, frame_id in enumerate(frame_ids):
        support[f, list(model.supports[model.frames[frame_id].parentJoint])[1:]] = True
    act = np.asarray(actuated, dtype=np.int64)
    return TreeArrays(
        parent=np.array(list(model.parents), dtype=np.int64),
        constants=constants, revolute=axes[1], q_index=q_index,
        frame_parent=np.array([model.frames[f].parentJoint for f in frame_ids], dtype=np.int64),
        frame_rotation=np.array([model.frames[f].placement.rotation for f in frame_ids]).reshape(-1, 3, 3),
        frame_translation=np.array([model.frames[f].placement.translation for f in frame_ids]).reshape(-1, 3),
        support=support,
        closure_first=np.array([c[0] for c in closures], dtype=np.int64),
        closure_second=np.array([c[1] for c in closures], dtype=np.int64),
        closure_dimension=np.array([c[2] for c in closures], dtype=np.int64),
        end_effector=int(end_effector), task_dimension=int(task_dimension) + len(task_joints),
        actuated=act, passive=np.setdiff1d(np.arange(model.nv), act).astype(np.int64),
        task_joints=np.asarray(task_joints, dtype=np.int64),
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
