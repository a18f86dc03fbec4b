"""Batched kinematics of a Pinocchio spanning tree, in numpy: placements, frame Jacobians and drifts.

One call covers a whole batch of configurations (every sample of every placement). Joints are
revolute or prismatic, about any fixed axis (URDF ``revolute`` and ``prismatic``; fixed joints are
merged into frames by Pinocchio). Quantities follow Pinocchio's conventions: a joint's world
placement ``oMi = oMparent · jointPlacement · motion(q)``, Jacobians and classical accelerations in
the world-aligned frame at the frame's origin (LOCAL_WORLD_ALIGNED), angular rows after linear ones.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from scipy.spatial.transform import Rotation

REVOLUTE = {"JointModelRX": (1.0, 0.0, 0.0), "JointModelRY": (0.0, 1.0, 0.0), "JointModelRZ": (0.0, 0.0, 1.0)}
PRISMATIC = {"JointModelPX": (1.0, 0.0, 0.0), "JointModelPY": (0.0, 1.0, 0.0), "JointModelPZ": (0.0, 0.0, 1.0)}


@dataclass(frozen=True)
class TreeJoint:
    """One joint of the tree: parent, fixed placement in the parent, axis (in its own frame) and kind."""

    parent: int
    rotation: np.ndarray  # (3, 3) jointPlacement rotation
    translation: np.ndarray  # (3,) jointPlacement translation (m)
    axis: np.ndarray  # (3,) unit axis in the joint frame
    revolute: bool
    index: int  # idx_q == idx_v

    @property
    def constants(self) -> np.ndarray:
        """(3, 11) columns that one product with the parent's rotation turns into this joint's frame.

        ``R_parent @ constants`` gives, side by side: the rotation before the joint's motion, its
        products with the axis' cross-product matrix [a] and [a]², the axis and the joint origin's
        offset, all in the world frame.
        """
        a = self.axis
        skew = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
        return np.hstack([self.rotation, self.rotation @ skew, self.rotation @ skew @ skew,
                          (self.rotation @ a)[:, None], self.translation[:, None]])


@dataclass
class TreeState:
    """World placements (and, after :meth:`Tree.velocities`, velocities) of every joint, batched.

    Attributes:
    Arrays are joint-major, so that one joint's batch is contiguous.

    Attributes:
        rotation: (njoints, B, 3, 3) joint frame orientations (index 0: the universe).
        origin_m: (njoints, B, 3) joint frame origins.
        axis: (njoints, B, 3) joint axes in the world frame.
        angular_rad_s: (njoints, B, 3) angular velocities of the joint bodies, or None.
        origin_m_s: (njoints, B, 3) velocities of the joint origins, or None.
    """

    rotation: np.ndarray
    origin_m: np.ndarray
    axis: np.ndarray
    angular_rad_s: np.ndarray | None = None
    origin_m_s: np.ndarray | None = None


def unsupported_joints(model: pin.Model) -> list[str]:
    """Names and kinds of the joints the batched tree cannot handle (empty when it can)."""
    return [f"{model.names[j]} ({joint.shortname()})" for j, joint in enumerate(model.joints)
            if j > 0 and not _axis_of(joint)]


def _axis_of(joint: pin.JointModel) -> tuple[tuple[float, ...], bool] | None:
    name = joint.shortname()
    if name in REVOLUTE:
        return REVOLUTE[name], True
    if name in PRISMATIC:
        return PRISMATIC[name], False
    if name in ("JointModelRevoluteUnaligned", "JointModelPrismaticUnaligned"):
        return tuple(joint.extract().axis), name.startswith("JointModelRevolute")
    return None


class Tree:
    """The batched kinematics of one Pinocchio model (revolute and prismatic joints only).

    Args:
        model: The Pinocchio model of the spanning tree.

    Raises:
        ValueError: The model has another kind of joint.
    """

    def __init__(self, model: pin.Model) -> None:
        unsupported = unsupported_joints(model)
        if unsupported:
            raise ValueError(f"joints of unsupported kind: {', '.join(unsupported)}")
        self.model = model
        self.joints: list[TreeJoint] = []
        for j in range(1, model.njoints):
            axis, revolute = _axis_of(model.joints[j])  # type: ignore[misc]
            placement = model.jointPlacements[j]
            self.joints.append(TreeJoint(model.parents[j], placement.rotation.copy(), placement.translation.copy(),
                                         np.asarray(axis, dtype=float), revolute, model.joints[j].idx_q))
        self.revolute_v = np.array([j.revolute for j in self.joints], dtype=bool)
        self._constants = [j.constants for j in self.joints]
        self._supports = {j: np.array(model.supports[j].tolist()[1:], dtype=int) for j in range(model.njoints)}

    def placements(self, q: np.ndarray) -> TreeState:
        """World placement of every joint frame for (B, nq) configurations."""
        b = len(q)
        rotation = np.empty((self.model.njoints, b, 3, 3))
        origin = np.empty((self.model.njoints, b, 3))
        axis = np.zeros((self.model.njoints, b, 3))
        rotation[0], origin[0] = np.eye(3), 0.0
        for j, joint in enumerate(self.joints, start=1):
            # one product per joint: rows of every sample's parent rotation times the joint's constants
            world = (rotation[joint.parent].reshape(-1, 3) @ self._constants[j - 1]).reshape(b, 3, 11)
            origin[j] = origin[joint.parent] + world[:, :, 10]
            axis[j] = world[:, :, 9]
            value = q[:, joint.index]
            if joint.revolute:  # before · exp(θ[a]) = before + sin θ · before[a] + (1 - cos θ) · before[a]²
                rotation[j] = world[:, :, 0:3] + np.sin(value)[:, None, None] * world[:, :, 3:6] \
                    + (1.0 - np.cos(value))[:, None, None] * world[:, :, 6:9]
            else:
                rotation[j] = world[:, :, 0:3]
                origin[j] += axis[j] * value[:, None]
        return TreeState(rotation, origin, axis)

    def velocities(self, state: TreeState, v: np.ndarray) -> TreeState:
        """Add the angular velocity and origin velocity of every joint body for (B, nv) rates."""
        angular = np.zeros_like(state.origin_m)
        linear = np.zeros_like(state.origin_m)
        for j, joint in enumerate(self.joints, start=1):
            p = joint.parent
            rate = v[:, joint.index, None]
            linear[j] = linear[p] + cross(angular[p], state.origin_m[j] - state.origin_m[p])
            if joint.revolute:
                angular[j] = angular[p] + state.axis[j] * rate
            else:
                angular[j] = angular[p]
                linear[j] += state.axis[j] * rate
        return TreeState(state.rotation, state.origin_m, state.axis, angular, linear)

    def frame(self, state: TreeState, frame_id: int) -> tuple[np.ndarray, np.ndarray]:
        """World rotation (B, 3, 3) and origin (B, 3) of a model frame."""
        frame = self.model.frames[frame_id]
        rows = state.rotation[frame.parentJoint].reshape(-1, 3)
        return ((rows @ frame.placement.rotation).reshape(-1, 3, 3),
                state.origin_m[frame.parentJoint] + (rows @ frame.placement.translation).reshape(-1, 3))

    def jacobian(self, state: TreeState, frame_id: int) -> np.ndarray:
        """(B, 6, nv) Jacobian of a frame, world-aligned at its origin: linear rows, then angular."""
        _, point = self.frame(state, frame_id)
        out = np.zeros((len(point), 6, self.model.nv))
        support = self._supports[self.model.frames[frame_id].parentJoint]
        if len(support) == 0:
            return out
        index = np.array([self.joints[j - 1].index for j in support])
        axis = state.axis[support]  # (S, B, 3)
        revolute = self.revolute_v[support - 1][:, None, None]
        lever = cross(axis, point - state.origin_m[support])
        out[:, :3, index] = np.where(revolute, lever, axis).transpose(1, 2, 0)
        out[:, 3:, index] = (axis * revolute).transpose(1, 2, 0)
        return out

    def drift(self, state: TreeState, v: np.ndarray, frame_id: int) -> np.ndarray:
        """(B, 6) classical acceleration of a frame at zero joint acceleration (J̇·v), world-aligned.

        ``state`` must come from :meth:`velocities` with the same ``v``.
        """
        assert state.angular_rad_s is not None and state.origin_m_s is not None
        frame = self.model.frames[frame_id]
        parent = frame.parentJoint
        _, point = self.frame(state, frame_id)
        point_velocity = state.origin_m_s[parent] + cross(state.angular_rad_s[parent], point - state.origin_m[parent])
        out = np.zeros((len(point), 6))
        support = self._supports[parent]
        if len(support) == 0:
            return out
        rate = v[:, [self.joints[j - 1].index for j in support]].T[:, :, None]  # (S, B, 1)
        axis = state.axis[support]
        turning = cross(state.angular_rad_s[support], axis)  # d(axis)/dt
        revolute = self.revolute_v[support - 1][:, None, None]
        lever = cross(turning, point - state.origin_m[support]) + cross(axis, point_velocity - state.origin_m_s[support])
        out[:, :3] = (np.where(revolute, lever, turning) * rate).sum(axis=0)
        out[:, 3:] = (turning * revolute * rate).sum(axis=0)
        return out


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross products along the last axis (faster than ``np.cross`` on small trailing axes)."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


def log3(rotation: np.ndarray) -> np.ndarray:
    """(B, 3) rotation vectors of (B, 3, 3) rotation matrices (rad), as ``pin.log3``."""
    vee = np.stack([rotation[:, 2, 1] - rotation[:, 1, 2], rotation[:, 0, 2] - rotation[:, 2, 0],
                    rotation[:, 1, 0] - rotation[:, 0, 1]], axis=1)  # 2 sin θ · axis
    cosine = np.clip((np.trace(rotation, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(cosine)
    small = angle < 1e-4
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = np.where(small, 0.5 + angle**2 / 12.0, angle / (2.0 * np.sin(angle)))
    out = scale[:, None] * vee
    near_half_turn = angle > np.pi - 1e-3  # sin θ vanishes: take the axis from the symmetric part
    if near_half_turn.any():
        out[near_half_turn] = Rotation.from_matrix(rotation[near_half_turn]).as_rotvec()
    return out
