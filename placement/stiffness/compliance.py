"""The tool's static compliance: its small displacement per unit load, for serial and closed-loop robots.

The model: the actuated joints are springs (stiffness k_a at the joint, N/m or N·m/rad: the sidecar's
``actuators.N.stiffness`` in series with the drive's reflected ``motor_side_stiffness_Nm_per_rad``), the passive joints
named under ``joint_springs`` are springs too (k_p), every other passive joint is free, the links are rigid and the
closures hold. A load w on the end effector (force at its origin, base frame; then the moment, for a pose task) moves
the joints by Δq, the least-potential-energy displacement

    minimise ½·Δqᵀ·K·Δq − wᵀ·J_task·Δq   subject to   J_c·Δq = 0,

J_c the closure Jacobian. Every Δq that keeps the closures is Δq = G·Δρ with G the null-space basis of the closures
in actuator coordinates (:class:`placement.kinematics.trajectories.JointTrajectory`; the identity for a serial arm),
which holds redundant closures such as the Orthoglide's parallelograms without their dependent rows. With T = J_task·G
(the task map) the problem in Δρ has the stiffness K_ρ = diag(k_a) + Gₚᵀ·diag(k_p)·Gₚ (Gₚ: G's rows of the sprung
passive joints), so

    Δρ = K_ρ⁻¹·Tᵀ·w,   δ = T·Δρ = C·w,   C = T·K_ρ⁻¹·Tᵀ.

No inverse of T is taken, so a robot with more actuators than task freedoms works too. For a serial arm C = J·K⁻¹·Jᵀ;
for the Orthoglide with rigid legs, T = J⁻¹ (J: tool to slider velocities) and C⁻¹ = k_a·JᵀJ.
Links given as 6×6 springs (the sidecar's ``link_springs``, the virtual-joint method; outside closed loops) add
their compliance in series: a spring at point s of a link, stiffness K_s in the link frame's axes, lets the link and
everything beyond it yield by a small twist ε = K_s⁻¹·J_sᵀ·w, which moves the tool by J_s·ε (J_s: the rotation of
the link frame, and the lever from s to the tool point), so C gains J_s·K_s⁻¹·J_sᵀ for each spring that carries the
tool.

The model is linear: it leaves out the change of J under load (the complementary stiffness, of relative size
|w|·(a length)/k), link compliance beyond the declared springs, contact and backlash.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from placement.kinematics.trajectories import JointTrajectory
from placement.kinematics.tree import frame_kinematics
from placement.robot.exceptions import RobotFileError
from placement.robot.model import Robot


@dataclass(frozen=True)
class LinkSprings:
    """The 6×6 springs of links that carry the tool (module docstring).

    Attributes:
        model: The robot's kinematic model.
        frame_ids: The tool's frame, then each sprung link's frame.
        origin_m: (L, 3) each spring's point in its link frame.
        compliance: (L, 6, 6) each spring's K_s⁻¹ in its link frame's axes, translation first.
    """

    model: pin.Model
    frame_ids: tuple[int, ...]
    origin_m: np.ndarray
    compliance: np.ndarray


@dataclass(frozen=True)
class JointSprings:
    """The springs of a robot, in joint units (N/m for a prismatic joint, N·m/rad for a revolute one).

    Attributes:
        actuator_stiffness: (n_act,) each actuated joint's stiffness, in actuator order.
        passive_v_indices: (p,) velocity indices of the sprung passive joints.
        passive_stiffness: (p,) their springs.
        links: The links' springs that carry the tool, or None.
    """

    actuator_stiffness: np.ndarray
    passive_v_indices: np.ndarray
    passive_stiffness: np.ndarray
    links: LinkSprings | None = None


def joint_springs(robot: Robot) -> JointSprings:
    """The robot's springs (module docstring).

    Raises:
        RobotFileError: An actuator has no stiffness (the message names the first such sidecar field).
    """
    missing = [i for i, actuator in enumerate(robot.actuators) if actuator.stiffness is None]
    if missing:
        names = ", ".join(robot.actuators[i].joint for i in missing)
        raise RobotFileError(robot.sidecar_path, f"actuators.{missing[0]}.stiffness", f"the tool's deflection needs "
                             f"every actuator's stiffness (N/m or N·m/rad at the joint), and {names} have none: give "
                             "actuators.N.stiffness (or the drive's motor_side_stiffness_Nm_per_rad) with its source")
    springs = robot.joint_springs
    return JointSprings(actuator_stiffness=np.array([a.stiffness for a in robot.actuators], dtype=float),
                        passive_v_indices=np.array([robot.model.joints[robot.model.getJointId(name)].idx_v
                                                    for name in springs], dtype=int),
                        passive_stiffness=np.array(list(springs.values()), dtype=float), links=_link_springs(robot))


def _link_springs(robot: Robot) -> LinkSprings | None:
    """The sidecar's link springs that carry the tool (a spring on a link the tool does not descend from moves it
    not), or None."""
    model = robot.model
    tool_joint = model.frames[robot.end_effector_frame_id].parentJoint
    carrying = {name: spring for name, spring in robot.link_springs.items()
                if model.frames[model.getBodyId(name)].parentJoint in model.supports[tool_joint]}
    if not carrying:
        return None
    return LinkSprings(model=model, frame_ids=(robot.end_effector_frame_id, *(model.getBodyId(n) for n in carrying)),
                       origin_m=np.array([spring.origin_m for spring in carrying.values()], dtype=float),
                       compliance=np.array([np.linalg.inv(spring.matrix) for spring in carrying.values()]))


def has_springs(robot: Robot) -> bool:
    """Whether every actuator of the robot gives a stiffness, so that its tool's deflection can be computed."""
    return all(actuator.stiffness is not None for actuator in robot.actuators)


def tool_compliance(springs: JointSprings, joints: JointTrajectory) -> np.ndarray:
    """(M, d, d) the tool's compliance C = T·K_ρ⁻¹·Tᵀ (plus the links' J_s·K_s⁻¹·J_sᵀ) at each of M samples (module
    docstring), d the task dimension: m/N in the force block, then rad/(N·m) for a pose task."""
    task_map = joints.task_map
    if not len(springs.passive_stiffness):
        joint_part = np.matmul(task_map / springs.actuator_stiffness, np.swapaxes(task_map, 1, 2))
    else:
        joint_part = np.matmul(task_map, np.linalg.solve(_actuator_space_stiffness(springs, joints),
                                                         np.swapaxes(task_map, 1, 2)))
    return joint_part if springs.links is None else joint_part + link_compliance(springs.links, joints)


def link_compliance(links: LinkSprings, joints: JointTrajectory) -> np.ndarray:
    """(M, d, d) Σ J_s·K_s⁻¹·J_sᵀ over the link springs at each sample (module docstring)."""
    dimension = joints.task_map.shape[1]
    rotation, origin, _, _ = frame_kinematics(links.model, links.frame_ids, joints.q, np.zeros_like(joints.v))
    tool = origin[:, 0]
    total = np.zeros((len(joints), dimension, dimension))
    for index in range(len(links.origin_m)):
        turn = rotation[:, index + 1]  # (M, 3, 3) the link frame's axes in the base frame
        lever = tool - origin[:, index + 1] - turn @ links.origin_m[index]  # from the spring to the tool point
        move = np.zeros((len(joints), 6, 6))  # the tool's twist per ε: translation, then rotation (base frame)
        move[:, :3, :3] = turn
        move[:, :3, 3:] = -_skew(lever) @ turn
        move[:, 3:, 3:] = turn
        move = move[:, :dimension]
        total += move @ links.compliance[index] @ np.swapaxes(move, 1, 2)
    return total


def _skew(vector: np.ndarray) -> np.ndarray:
    """(M, 3, 3) the cross-product matrices of (M, 3) vectors."""
    out = np.zeros((len(vector), 3, 3))
    out[:, [2, 0, 1], [1, 2, 0]] = vector
    return out - np.swapaxes(out, 1, 2)


def tool_deflection(springs: JointSprings, joints: JointTrajectory, load: np.ndarray) -> np.ndarray:
    """(M, d) the tool's small displacement δ = C·w under the loads w (M, d) on the end effector (base frame, at its
    origin: force in N, then moment in N·m for a pose task): translation (m), then rotation (rad) for a pose task.
    Batched without forming C: δ = T·(K_ρ⁻¹·(Tᵀ·w))."""
    generalized = np.einsum("nta,nt->na", joints.task_map, load)  # Tᵀ·w, the actuator-space load (N or N·m)
    if len(springs.passive_stiffness):
        displacement = np.linalg.solve(_actuator_space_stiffness(springs, joints), generalized[..., None])[..., 0]
    else:
        displacement = generalized / springs.actuator_stiffness
    moved = np.einsum("nta,na->nt", joints.task_map, displacement)
    return moved if springs.links is None else moved + np.einsum("ntu,nu->nt", link_compliance(springs.links, joints),
                                                                 load)


def _actuator_space_stiffness(springs: JointSprings, joints: JointTrajectory) -> np.ndarray:
    """(M, m, m) K_ρ = diag(k_a) + Gₚᵀ·diag(k_p)·Gₚ at each sample."""
    passive = joints.basis[:, springs.passive_v_indices, :]  # (M, p, m)
    stiffness = np.matmul(np.swapaxes(passive, 1, 2) * springs.passive_stiffness, passive)
    stiffness[:, np.arange(len(springs.actuator_stiffness)), np.arange(len(springs.actuator_stiffness))] += \
        springs.actuator_stiffness
    return stiffness
