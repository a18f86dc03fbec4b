"""An independent physics engine for the tests: a MuJoCo model of any robot, built from its
Pinocchio tree (joint placements, axes, inertias, drive armature, gravity) plus its closures as
MuJoCo equality constraints, driven open loop by actuator efforts.

MuJoCo simulates the closed-loop mechanism forward in time by its own formulation (soft equality
constraints, its own integrator); if the efforts computed by placement's projected RNEA are
right, the simulated tool follows the path they were computed for.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pinocchio as pin

from placement.robot.model import Robot

MASSLESS_KG = 1e-9  # MuJoCo refuses moving bodies without mass ...
MASSLESS_INERTIA_KG_M2 = 1e-3  # ... and without rotational inertia (given only to bodies that do not turn)
CONSTRAINT = 'solref="0.0001 1" solimp="0.9999 0.9999 0.001"'  # stiff: a time constant of 0.1 ms
AXES = {"X": "1 0 0", "Y": "0 1 0", "Z": "0 0 1"}


def _vector(values: np.ndarray) -> str:
    return " ".join(f"{v:.17g}" for v in values)


def _quaternion(rotation: np.ndarray) -> str:
    q = pin.Quaternion(rotation)
    return _vector([q.w, q.x, q.y, q.z])


def _joint(model: pin.Model, j: int) -> str:
    joint = model.joints[j]
    kind = joint.shortname()
    axis = AXES.get(kind[-1]) if kind[-2:] in ("RX", "RY", "RZ", "PX", "PY", "PZ") else None
    if axis is None:  # an unaligned revolute or prismatic joint
        axis = _vector(joint.extract().axis)
    slide = "Prismatic" in kind or kind[-2] == "P"
    return (f'<joint name="{model.names[j]}" type="{"slide" if slide else "hinge"}" axis="{axis}" '
            f'armature="{model.armature[joint.idx_v]:.17g}" damping="0" limited="false"/>')


def _inertial(model: pin.Model, j: int) -> str:
    inertia = model.inertias[j]
    mass, com, rotational = inertia.mass, inertia.lever, inertia.inertia
    if mass <= 0.0:
        mass, rotational = MASSLESS_KG, np.eye(3) * MASSLESS_INERTIA_KG_M2
    full = [rotational[0, 0], rotational[1, 1], rotational[2, 2], rotational[0, 1], rotational[0, 2], rotational[1, 2]]
    return f'<inertial pos="{_vector(com)}" mass="{mass:.17g}" fullinertia="{_vector(full)}"/>'


def mjcf(robot: Robot) -> str:
    """The MJCF text of the robot: one body per Pinocchio joint, a site per closure and tool frame."""
    model = robot.model
    frames = {i for closure in robot.closures for i in closure.frame_ids} | {robot.end_effector_frame_id}
    sites = {j: [] for j in range(model.njoints)}
    for i in sorted(frames):
        frame = model.frames[i]
        sites[frame.parentJoint].append(f'<site name="f{i}" pos="{_vector(frame.placement.translation)}" '
                                        f'quat="{_quaternion(frame.placement.rotation)}"/>')

    def body(j: int) -> str:
        placement = model.jointPlacements[j]
        children = "".join(body(c) for c in range(1, model.njoints) if model.parents[c] == j)
        return (f'<body name="b{j}" pos="{_vector(placement.translation)}" quat="{_quaternion(placement.rotation)}">'
                f'{_joint(model, j)}{_inertial(model, j)}{"".join(sites[j])}{children}</body>')

    roots = "".join(body(j) for j in range(1, model.njoints) if model.parents[j] == 0)
    equalities = "".join(
        f'<{"connect" if c.kind == "point" else "weld"} site1="f{c.frame_ids[0]}" site2="f{c.frame_ids[1]}" {CONSTRAINT}/>'
        for c in robot.closures)
    motors = "".join(f'<motor joint="{a.joint}" gear="1" ctrllimited="false"/>' for a in robot.actuators)
    return (f'<mujoco><compiler angle="radian" autolimits="false"/>'
            f'<option timestep="1e-5" integrator="RK4" gravity="{_vector(model.gravity.linear)}">'
            f'<flag contact="disable"/></option>'
            f'<worldbody>{"".join(sites[0])}{roots}</worldbody>'
            f'<equality>{equalities}</equality><actuator>{motors}</actuator></mujoco>')


class Simulation:
    """The robot in MuJoCo, set to a joint state and stepped with given actuator efforts."""

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        self.model = mujoco.MjModel.from_xml_string(mjcf(robot))
        self.data = mujoco.MjData(self.model)
        pin_model = robot.model
        self.qpos = np.array([self.model.jnt_qposadr[mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_JOINT, name)]
                              for name in pin_model.names[1:]])
        self.qvel = np.array([self.model.jnt_dofadr[mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_JOINT, name)]
                              for name in pin_model.names[1:]])
        self.tool = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_SITE, f"f{robot.end_effector_frame_id}")
        self.tool_body = self.model.site_bodyid[self.tool]

    @property
    def timestep_s(self) -> float:
        return float(self.model.opt.timestep)

    def set_state(self, q: np.ndarray, v: np.ndarray) -> None:
        """Positions and velocities of every joint (Pinocchio's order)."""
        self.data.qpos[self.qpos] = q
        self.data.qvel[self.qvel] = v
        self.data.time = 0.0
        mujoco.mj_forward(self.model, self.data)

    def run(self, efforts: np.ndarray, force_on_tool_N: np.ndarray | None = None) -> np.ndarray:
        """Step once per row of ``efforts`` (actuator order, held over the step), with a constant force
        on the tool point (base frame) if given; returns the tool's path (n+1, 3)."""
        path = [self.data.site_xpos[self.tool].copy()]
        for effort in efforts:
            self.data.ctrl[:] = effort
            if force_on_tool_N is not None:  # MuJoCo applies it at the body's centre of mass: add its moment
                lever = self.data.site_xpos[self.tool] - self.data.xipos[self.tool_body]
                self.data.xfrc_applied[self.tool_body] = np.concatenate([force_on_tool_N,
                                                                         np.cross(lever, force_on_tool_N)])
            mujoco.mj_step(self.model, self.data)
            path.append(self.data.site_xpos[self.tool].copy())
        return np.array(path)
