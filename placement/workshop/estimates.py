"""Serial arms of example-robot-data by name, with estimated drives: ``erd:NAME`` and a tool frame.

``load_erd_robot("ur10", "tool0")`` builds the sidecar of example-robot-data's robot NAME in
memory and loads it, so that any serial arm it ships can be tried without writing a file. Every
number the URDF does not give is an estimate, labelled ``EST`` in the sidecar's ``sources``:

- **Joints.** The joints from the base to the tool frame move; every other movable joint (a
  gripper's fingers) is locked at example-robot-data's reference posture ``q0``, clipped into its
  limits. Of a 7-joint chain, the third joint is redundant, as the built-in ``panda``'s
  ``panda_joint3`` (on the usual shoulder-elbow-wrist arms, the upper arm's redundant rotation): it
  follows a profile along the path with ``REDUNDANT_KNOTS`` knots that the search chooses
  (:mod:`placement.placing.profiles`; ``--lock`` holds it instead). Chains of 3 to 7 joints are
  taken: six or seven moving joints follow a pose task, three a position task. Of a chain of 4 or 5 joints
  (SCARAs, 5-axis arms such as the SO-101) the tool's position is the task, and the joints after the third
  (the wrist) are redundant, profiled along the path as a 7-joint chain's third; others need a sidecar.
- **Drives** (one per joint): a gear of ratio ``GEAR_RATIO`` = 100 (revolute joint) or a ball
  screw of lead ``SCREW_LEAD_M`` = 10 mm (prismatic joint), efficiency 1, speed ratio k; a motor
  whose peak torque is the URDF's effort limit / k and top speed the URDF's velocity limit · k,
  so that the drive reaches exactly the URDF's limits. The motor's other constants follow one
  3-phase servo family scaled by its peak torque tau (N·m), fitted to the built-in UR5 and Panda
  estimates: K_t = 0.1·sqrt(tau) N·m/A (peak current 10·sqrt(tau) A), K_e = K_t/3,
  R = 0.5/sqrt(tau) Ω and L = 0.5/sqrt(tau) mH per phase, and a rotor inertia proportional to the
  torque, J = tau / 20 000 rad/s² (the same peak acceleration for every size).
- **Workspace.** L is the kinematic chain length: the sum of the distances between successive
  joint origins from the base to the tool frame (m). The box is a cube of side 0.25·L centred at
  (0.4·L, 0, 0.15·L), in front of the base (its +x) above its floor; it is shrunk about its
  centre by 20 % steps (at most 5) until the tool reaches its 8 corners pointing down.
- **Reference configuration and tool orientation.** The tool is brought to the box's centre with
  its z axis pointing down (−Z_b), its rotation about that axis free, by damped least squares (:mod:`placement.workshop.posture`)
  from ``q0`` first, then from ``REFERENCE_SEEDS`` seeded random postures within the joint
  limits. The first posture whose task Jacobian (linear rows divided by L) has a condition number
  below ``GOOD_CONDITION``, with every joint at least ``GOOD_LIMIT_MARGIN`` of its range from its
  limits, is kept, else the best-conditioned one if below ``MAX_CONDITION``.
  ``tool_rpy_in_path_rad`` is the tool's orientation in that posture: its z axis along −Z_p, into
  the workpiece, as the built-in ``ur5`` sidecar has it.
- Gravity is −9.81 m/s² along the base's z; the search is over x, y, z and φ, and for a pose task
  θ and ψ too, within ±0.35 rad (20°).
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin
import yaml
from pydantic import ValidationError

from placement.exceptions import listed
from placement.robot.build import PRISMATIC_JOINTS, reduced_model
from placement.robot.exceptions import ExampleRobotError
from placement.robot.formats import YAML_NAME, DescriptionOptions, is_gepetto
from placement.robot.mjcf import MjcfJoint, is_mjcf, mjcf_model, qpos0, read_mjcf
from placement.robot.model import Robot
from placement.robot.plausibility import model_links_without_inertia
from placement.robot.sidecar import Sidecar
from placement.robot.tool import find_frame
from placement.robot.urdf import ERD_PREFIX, closing_pairs, erd_urdf_path, pinocchio_model, urdf_limits_missing
from placement.robot.xacro import expand_xacro, is_xacro
from placement.workshop.catalog import ERD_FORM, erd_names
from placement.workshop.efforts import GIVEN_ON_COMMAND_LINE, give_efforts, with_effort_sources
from placement.workshop.load import robot_from_sidecar, write_if_it_loads
from placement.workshop.loops import (
    JOINT_SPEED_M_S,
    JOINT_SPEED_RAD_S,
    PASSIVE,
    LoopDescription,
    description_name,
    loop_sidecar,
)
from placement.workshop.posture import MAX_CONDITION, PostureSolver

GEAR_RATIO = 100.0
SCREW_LEAD_M = 0.01
MOTOR_SCALING = ("3-phase servo scaled by peak torque tau: K_t = 0.1 sqrt(tau), K_e = K_t/3, R = 0.5/sqrt(tau), "
                 "L = 0.5e-3/sqrt(tau)")  # the motor estimate, as the sources say it
BOX_CENTRE_OF_REACH = (0.4, 0.0, 0.15)
BOX_SIDE_OF_REACH = 0.25
BOX_SHRINK, BOX_SHRINKS = 0.8, 5
TILT_RAD = 0.35
REDUNDANT_KNOTS = 3  # knots of a seven-axis arm's redundant (third) joint's profile


def erd_name(text: str) -> str | None:
    """The example-robot-data name in ``erd:NAME``, or None for any other robot argument."""
    return text.removeprefix(ERD_FORM) if text.startswith(ERD_FORM) else None


def estimate_warning(robot: Robot) -> str:
    """The one warning an ``erd:`` robot deserves: its drives and workspace are estimates."""
    count = sum(text.startswith("EST") for text in robot.sources.values())
    locked = f"; joints held fixed: {', '.join(robot.locked_joints)}" if robot.locked_joints else ""
    if robot.redundant_joints:
        locked += (f"; redundant joints profiled along the path by the search: {', '.join(robot.redundant_joints)} "
                   "(--lock JOINT=VALUE holds one)")
    kind = "MJCF" if is_mjcf(robot.urdf_path) else "URDF"
    limits = ("MJCF's actuator force ranges and a joint speed of 180 deg/s" if kind == "MJCF"
              else "URDF's effort and velocity limits")
    if any(GIVEN_ON_COMMAND_LINE in text for text in robot.sources.values()):
        limits = limits.replace(" and ", ", the --effort bounds and ", 1)
    drives = (f"3000 rpm motors geared down to the joints' speeds, sized from the {limits}" if robot.closures
              else f"gear {GEAR_RATIO:g}:1, motor constants scaled from the {limits}")
    return (f"{robot.name}: the drives ({drives}), the "
            f"workspace box and the reference posture are estimates ({count} EST sources)"
            f"{locked}; absolute energies are only as good as they are (write a sidecar: docs/adding_a_robot.md)")


def load_erd_robot(name: str, tool: str | None, *, allow_massless: bool = False) -> Robot:
    """Load example-robot-data's robot ``name`` with ``tool`` following the path (rules: module docstring).

    Args:
        name: An example-robot-data name, e.g. "ur10".
        tool: The frame (link or joint) that follows the path, e.g. "tool0".
        allow_massless: As for :func:`placement.workshop.load.load_robot`.

    Raises:
        ExampleRobotError: Unknown name, missing or unknown tool, or an arm the rules cannot estimate.
        RobotFileError: Its physics is implausible (:mod:`placement.robot.plausibility`).
    """
    return robot_from_sidecar(Path(ERD_FORM + name), erd_sidecar(name, tool), allow_massless=allow_massless)


def erd_sidecar(name: str, tool: str | None) -> Sidecar:
    """The estimated sidecar of example-robot-data's robot ``name`` with ``tool`` following the path."""
    return _estimated_sidecar(_Arm.read(name, tool), ERD_FORM + name, ERD_PREFIX + name,
                              f"example-robot-data '{name}', tool {tool}: drives and workspace estimated")


def load_description_robot(path: Path, tool: str | None, *, allow_massless: bool = False,
                           options: DescriptionOptions = DescriptionOptions()) -> Robot:
    """Load a serial arm from its URDF or xacro file with ``tool`` following the path, its drives, workspace and
    posture estimated as for example-robot-data's arms (rules: module docstring; the posture starts from the
    description's neutral one, clipped into the joint limits).

    Args:
        path: The URDF (``.urdf``) or xacro (``.xacro``, ``.urdf.xacro``) file.
        tool: The frame (link or joint) that follows the path, e.g. "tool0".
        allow_massless: As for :func:`placement.workshop.load.load_robot`.
        options: Its package folders and xacro arguments (``--package-path``, ``--robot-arg``).

    Raises:
        ExampleRobotError: Missing or unknown tool, or an arm the rules cannot estimate.
        RobotFileError: The file cannot be read or expanded, or its physics is implausible.
    """
    sidecar = description_sidecar(path, tool, options)
    return robot_from_sidecar(path, sidecar, allow_massless=allow_massless, options=options)


def description_sidecar(path: Path, tool: str | None, options: DescriptionOptions = DescriptionOptions()) -> Sidecar:
    """The estimated sidecar of the robot described by the URDF, xacro or MJCF file ``path``, ``tool`` following the
    path; its ``urdf`` is ``path`` (absolute), a xacro's arguments its ``xacro_args``, its drives' sources naming
    the effort bounds given on the command line (``--effort``)."""
    path = path.resolve()
    return with_effort_sources(_estimated_description(path, tool, options), path, options.efforts)


def _estimated_description(path: Path, tool: str | None, options: DescriptionOptions) -> Sidecar:
    """:func:`description_sidecar` of the resolved ``path``, before its sources name the efforts given."""
    posture = "the description's neutral posture, clipped into its limits"
    if is_mjcf(path):
        model = mjcf_model(path)
        contents = read_mjcf(path, model)
        give_efforts(path, model, options.efforts, contents.joints)
        if contents.closures:
            closures = [{"name": c.name, "type": c.kind, "frames": list(c.frames)} for c in contents.closures]
            start = {name: joint.ref for name, joint in contents.joints.items() if joint.ref != 0.0}
            return loop_sidecar(path, tool, LoopDescription("MJCF", model, closures, list(contents.actuated),
                                                            "DERIVED: the joints the MJCF's actuators drive",
                                                            contents.joints, start))
        q0 = np.clip(qpos0(model, contents.joints), model.lowerPositionLimit, model.upperPositionLimit)
        arm = _Arm.of(str(path), model, q0, tool, "the MJCF's qpos0, clipped into its limits", given=contents.joints)
    else:
        urdf = expand_xacro(path, options.xacro_args, options.package_paths, path, "") if is_xacro(path) else path
        model = pinocchio_model(urdf)
        give_efforts(path, model, options.efforts)
        pairs = closing_pairs(urdf)
        if not pairs and is_gepetto(path.parent / YAML_NAME):
            raise ExampleRobotError(f"{path} is the tree of the Gepetto {YAML_NAME} beside it, which says where its "
                                    f"loops close: 'python -m placement assemble {path.parent} --write' closes them "
                                    f"and writes its sidecar; then give the folder, --robot {path.parent}, without "
                                    "--tool")
        if pairs and not is_xacro(path):
            closures = [{"name": name, "type": "point", "frames": [first, second]} for name, first, second in pairs]
            actuated, why = _onshape_actuated(model)
            return loop_sidecar(path, tool, LoopDescription("URDF", model, closures, actuated, why))
        arm = _Arm.of(str(path), model, _neutral(model), tool, posture)
    sidecar = _estimated_sidecar(arm, description_name(path), str(path),
                                 f"{path.name}, tool {tool}: drives and workspace estimated")
    return sidecar.model_copy(update={"xacro_args": dict(options.xacro_args)}) if is_xacro(path) else sidecar


def _onshape_actuated(model: pin.Model) -> tuple[list[str], str]:
    """The actuated joints of a URDF exported by onshape-to-robot, which does not say them, and the rule that chose
    them (:mod:`placement.workshop.loops`)."""
    movable = [j for j in range(1, model.njoints) if model.joints[j].nv == 1 and PASSIVE not in model.names[j].lower()]
    on_base = [model.names[j] for j in movable if model.parents[j] == 0]
    if on_base:
        return on_base, "EST: the joints on the base link (the URDF does not say which joints are actuated)"
    return [model.names[j] for j in movable], (f"EST: the joints not named *{PASSIVE}* (the URDF does not say which "
                                               "joints are actuated)")


def _neutral(model: pin.Model) -> np.ndarray:
    """The model's neutral configuration clipped into its joints' limits."""
    return np.clip(pin.neutral(model), model.lowerPositionLimit, model.upperPositionLimit)


def _estimated_sidecar(arm: _Arm, name: str, urdf: str, description: str) -> Sidecar:
    """The sidecar of an arm with every number its description does not give estimated (module docstring)."""
    arm.refuse_without_limits()
    box_low, box_high, q_ref = arm.workspace_and_reference()
    drives = {arm.drive_name(j): arm.drive(j) for j in arm.active}
    end_effector: dict[str, object] = {"frame": arm.tool, "task": arm.task}
    if arm.pose:  # the reference posture's tool orientation, z along -Z_p
        end_effector["tool_rpy_in_path_rad"] = [float(v) for v in pin.rpy.matrixToRpy(arm.tool_rotation(q_ref))]
    document = {
        "name": name,
        "description": description,
        "urdf": urdf,
        "gravity_m_s2": [0.0, 0.0, -9.81],
        "end_effector": end_effector,
        "reference_configuration": {arm.model.names[j]: float(q_ref[arm.q_index(j)]) for j in arm.active},
        "locked_joints": arm.locked,
        **({"redundancy": {"joints": [arm.model.names[j] for j in arm.redundant], "knots": REDUNDANT_KNOTS}}
           if arm.redundant else {}),
        "actuators": [arm.actuator(j, q_ref) for j in arm.active],
        "drives": drives,
        "workspace": {"type": "box", "min_m": box_low.tolist(), "max_m": box_high.tolist(),
                      "points_m": {"reference": arm.tool_point(q_ref).tolist()}},
        "placement": {"free": ["x", "y", "z", "phi", "theta", "psi"] if arm.pose else ["x", "y", "z", "phi"],
                      "bounds": {"theta": [-TILT_RAD, TILT_RAD], "psi": [-TILT_RAD, TILT_RAD]} if arm.pose else {}},
        "sources": arm.sources(drives),
    }
    try:
        return Sidecar.model_validate(document)
    except ValidationError as error:
        problem = error.errors()[0]
        raise ExampleRobotError(f"{arm.label}: cannot estimate {'.'.join(map(str, problem['loc']))}: "
                                f"{problem['msg']}; write a sidecar (docs/adding_a_robot.md)") from None


@dataclass
class _Arm:
    """A serial arm's model (example-robot-data's, or a description file's), its moving chain and the estimates
    made on it."""

    label: str  # the robot as the user named it (erd:NAME, or the file), in messages
    tool: str
    model: pin.Model
    frame_id: int
    q0: np.ndarray
    chain: list[int]
    active: list[int]
    locked: dict[str, float]
    unlimited: list[int]  # chain joints without position limits in the URDF (continuous ones)
    posture: str = "example-robot-data's q0"  # where q0 comes from, for the sources
    given: dict[str, MjcfJoint] | None = None  # an MJCF's joints: effort bounds' origin, armature, friction
    speeds: dict[int, float] = dataclasses.field(default_factory=dict)  # joint speeds estimated (none given)

    @classmethod
    def read(cls, name: str, tool: str | None) -> _Arm:
        """example-robot-data's robot ``name``, from its reference posture ``q0``."""
        from example_robot_data.robots_loader import ROBOTS

        if name not in ROBOTS:
            raise ExampleRobotError(f"example-robot-data has no robot '{name[:40]}' ({ERD_FORM}{name[:40]}); "
                                    f"its robots: {', '.join(erd_names())}")
        loader = ROBOTS[name]()
        model = pinocchio_model(erd_urdf_path(ROBOTS[name]))
        return cls.of(ERD_FORM + name, model, _reference_posture(model, loader.robot.model, loader.robot.q0), tool)

    @classmethod
    def of(cls, label: str, model: pin.Model, q0: np.ndarray, tool: str | None,
           posture: str = "example-robot-data's q0", given: dict[str, MjcfJoint] | None = None) -> _Arm:
        """The arm of ``model`` whose chain ends at ``tool``, from the posture ``q0`` (rules: module docstring); an
        MJCF's joint data ``given``, its joints' speeds estimated."""
        frame_id = _tool_frame(model, label, tool)
        chain = [int(j) for j in model.supports[model.frames[frame_id].parentJoint][1:]]
        odd = [model.names[j] for j in chain if model.joints[j].nq != 1 or model.joints[j].nv != 1]
        if odd:
            raise ExampleRobotError(f"{label}: joints {odd} between the base and '{tool}' are not revolute, "
                                    "continuous or prismatic joints of one coordinate; write a sidecar "
                                    "(docs/adding_a_robot.md)")
        unlimited = [j for j in chain if urdf_limits_missing(model, j)]  # continuous, or revolute without bounds
        for j in unlimited:  # free while the reference posture is sought, a full turn about it in the sidecar
            index = model.joints[j].idx_q
            model.lowerPositionLimit[index], model.upperPositionLimit[index] = -np.inf, np.inf
        if len(chain) not in (3, 4, 5, 6, 7):
            raise ExampleRobotError(f"{label}: {len(chain)} joint(s) from the base to '{tool}'; a path needs "
                                    "3 to 5 (a position task, joints after the third redundant), 6 (a pose task) or 7 "
                                    "(the third redundant): choose another "
                                    "--tool, or write a sidecar that locks the joints the path should not move "
                                    "(docs/adding_a_robot.md)")
        active = list(chain)
        locked = {model.names[j]: float(_clip(model, j, q0[model.joints[j].idx_q]))
                  for j in range(1, model.njoints) if j not in active}
        speeds = {}
        if given is not None:  # an MJCF gives no speed limits
            for j in active:
                prismatic = model.joints[j].shortname() in PRISMATIC_JOINTS
                speeds[j] = JOINT_SPEED_M_S if prismatic else JOINT_SPEED_RAD_S
                model.velocityLimit[model.joints[j].idx_v] = speeds[j]
        return cls(label, str(tool), model, frame_id, q0, chain, active, locked, unlimited, posture, given, speeds)

    @property
    def pose(self) -> bool:
        """Whether the tool's orientation is prescribed too (six moving joints)."""
        return len(self.active) >= 6

    @property
    def redundant(self) -> list[int]:
        """The joints profiled along the path: a seven-joint chain's third, a 4- or 5-joint chain's after the third."""
        if len(self.active) == 7:
            return [self.chain[2]]
        return self.active[3:] if len(self.active) in (4, 5) else []

    @property
    def task(self) -> str:
        """The sidecar's task."""
        return "pose" if self.pose else "position"

    @property
    def reach_m(self) -> float:
        """Kinematic chain length L: distances between successive joint origins, base to tool (m)."""
        model = self.model
        steps = [model.jointPlacements[j].translation for j in self.chain]
        steps.append(model.frames[self.frame_id].placement.translation)
        return float(sum(np.linalg.norm(step) for step in steps))

    def q_index(self, joint: int) -> int:
        """The configuration index of a joint of the full model."""
        return int(self.model.joints[joint].idx_q)

    def drive_name(self, joint: int) -> str:
        """The drive of a joint is named after it (dots would break the sources' dotted paths)."""
        return self.model.names[joint].replace(".", "_")

    def actuator(self, joint: int, q_ref: np.ndarray) -> dict:
        """The sidecar's actuator of a joint: its drive, and where the URDF gives no range, a full turn about the
        reference posture ``q_ref`` (full model)."""
        entry: dict[str, object] = {"joint": self.model.names[joint], "drive": self.drive_name(joint)}
        if joint in self.unlimited:
            centre = float(q_ref[self.q_index(joint)])
            entry.update(position_min=centre - np.pi, position_max=centre + np.pi)
        if joint in self.speeds:
            entry["velocity_max"] = self.speeds[joint]
        return entry

    def refuse_without_limits(self) -> None:
        """Refuse a URDF that gives a moving joint no effort or velocity limit, naming every such joint and, since
        such descriptions (ROS-Industrial's) give no inertia either, every moving link without inertia.

        Raises:
            ExampleRobotError: Some joint's drive cannot be estimated; the message says what a sidecar must give.
        """
        if self.given is not None:  # an MJCF: its efforts are checked joint by joint (drive)
            return
        limits = {"effort": self.model.effortLimit, "velocity": self.model.velocityLimit}
        missing = {kind: [self.model.names[j] for j in self.active if not 0 < values[self.model.joints[j].idx_v] < np.inf]
                   for kind, values in limits.items()}
        if not any(missing.values()):
            return
        said = " and ".join(f"no {kind} limit for joint(s) {listed(names, 8)}" for kind, names in missing.items()
                            if names)
        massless = model_links_without_inertia(self.reduced())
        without = (f"; nor any inertia for its moving link(s) {listed(massless, 8)} (no <inertial>): every energy "
                   "would leave out their weight and inertia" if massless else "")
        links = (f", and each link's mass_kg, com_m (m) and inertia_kg_m2 under links (e.g. links.{massless[0]}, "
                 "each with a sources entry)" if massless else "")
        raise ExampleRobotError(f"{self.label}: its URDF gives {said} (<limit effort=... velocity=...>), so their "
                                f"drives cannot be estimated{without}. Write a sidecar that gives a drive for each "
                                f"actuator (its motor's max_torque_Nm and max_speed_rad_s from the data sheet){links}: "
                                "docs/adding_a_robot.md, '3. A robot written by hand'")

    def drive(self, joint: int) -> dict:
        """The estimated drive of one joint (rules: module docstring)."""
        joint_name, v = self.model.names[joint], self.model.joints[joint].idx_v
        effort, speed = float(self.model.effortLimit[v]), float(self.model.velocityLimit[v])
        if self.given is not None and not 0 < effort < np.inf:
            raise ExampleRobotError(f"{self.label}: nothing in the MJCF bounds the effort of joint '{joint_name}', so "
                                    f"its drive cannot be estimated: give its peak torque (N m; N for a sliding joint) "
                                    f"with --effort {joint_name}=VALUE, or its actuator a forcerange (the joint an "
                                    "actuatorfrcrange) in a copy of the file, or write a sidecar "
                                    "(docs/adding_a_robot.md)")
        prismatic = self.model.joints[joint].shortname().startswith("JointModelP")
        k = 2 * np.pi / SCREW_LEAD_M if prismatic else GEAR_RATIO
        transmission = ({"type": "ball_screw", "lead_m": SCREW_LEAD_M, "efficiency": 1.0} if prismatic
                        else {"type": "gear", "ratio": GEAR_RATIO, "efficiency": 1.0})
        torque = effort / k
        root = np.sqrt(torque)
        given = self.given.get(joint_name) if self.given is not None else None
        armature = given.armature if given is not None else 0.0
        motor = {"torque_constant_Nm_per_A": 0.1 * root, "back_emf_constant_V_s_per_rad": 0.1 * root / 3,
                 "resistance_ohm": 0.5 / root, "inductance_H": 5e-4 / root, "phases": 3,
                 "rotor_inertia_kg_m2": armature / k**2 if armature > 0 else torque / 20_000.0,
                 "max_torque_Nm": torque, "max_speed_rad_s": speed * k}
        drive: dict[str, object] = {"transmission": transmission, "motor": motor}
        if given is not None and (given.frictionloss > 0 or given.damping > 0):
            drive["friction"] = {"coulomb": given.frictionloss, "viscous": given.damping}
        return drive

    def sources(self, drives: dict) -> dict[str, str]:
        """An EST (or DERIVED) entry for every estimate."""
        entries = {
            "gravity_m_s2": "EST: floor-mounted, base z up",
            "reference_configuration": f"EST: tool pointing down at the workspace centre, solved from {self.posture} "
                                       "(else seeded postures) with a well-conditioned task Jacobian",
            "workspace": f"EST: a cube of side {BOX_SIDE_OF_REACH} L centred at {list(BOX_CENTRE_OF_REACH)} L, L = "
                         f"{self.reach_m:.3f} m the chain length, shrunk until the tool reaches its corners",
            "placement": f"EST: the workpiece may be tilted by up to {np.degrees(TILT_RAD):.0f} degrees",
        }
        if self.locked:
            entries["locked_joints"] = f"EST: joints off the base-to-tool chain held at {self.posture}"
        if len(self.active) == 7:
            entries["redundancy"] = (f"EST: the chain's third joint profiled along the path with {REDUNDANT_KNOTS} "
                                     "knots, as the built-in panda's joint 3")
        elif self.redundant:
            entries["redundancy"] = (f"EST: a position task, the chain's joints after the third profiled along the path "
                                     f"with {REDUNDANT_KNOTS} knots (a 4- or 5-axis arm's wrist)")
        for i, joint in enumerate(self.active):
            if joint in self.unlimited:
                for field in ("position_min", "position_max"):
                    entries[f"actuators.{i}.{field}"] = ("EST: the URDF gives no position limits (a continuous joint, "
                                                         "say); a full turn about the reference posture")
        if self.pose:
            entries["end_effector.tool_rpy_in_path_rad"] = "DERIVED: tool z along -Z_p, yaw of the reference posture"
        for drive, spec in drives.items():
            kind = "gear ratio" if spec["transmission"]["type"] == "gear" else "screw lead"
            entries[f"drives.{drive}.transmission"] = f"EST: a typical {kind} (the {self.kind} gives none)"
            entries[f"drives.{drive}.motor"] = (f"EST: {MOTOR_SCALING}, J = tau/20000; max_torque and max_speed "
                                               "DERIVED from the URDF's effort and velocity limits through the "
                                               "transmission")
        if self.given is not None:
            for i, joint in enumerate(self.active):
                entries.update(self._mjcf_sources(joint, drives[self.drive_name(joint)]))
                entries[f"actuators.{i}.velocity_max"] = "EST: the MJCF gives no speed limits; a typical joint speed"
        return entries

    @property
    def kind(self) -> str:
        """The kind of description, in the sources: URDF or MJCF."""
        return "URDF" if self.given is None else "MJCF"

    def _mjcf_sources(self, joint: int, drive: dict) -> dict[str, str]:
        """The sources of an MJCF joint's drive: the effort bound, armature and friction it gives, the speed
        estimated."""
        assert self.given is not None  # an MJCF's arm
        name, given = self.drive_name(joint), self.given[self.model.names[joint]]
        speed = self.speeds[joint]
        unit = "m/s" if self.model.joints[joint].shortname() in PRISMATIC_JOINTS else "rad/s"
        rotor = (f"J DERIVED from the MJCF's armature {given.armature:g} divided by the transmission's speed ratio "
                 "squared" if given.armature > 0 else "J = tau/20000")
        entries = {f"drives.{name}.motor": (
            f"EST: {MOTOR_SCALING}, {rotor}; max_torque DERIVED from the MJCF ({given.effort_from}) through the "
            f"transmission; max_speed EST from a joint speed of {speed:g} {unit} (the MJCF gives none)")}
        if "friction" in drive:
            entries[f"drives.{name}.friction"] = (f"DERIVED: the MJCF's joint frictionloss {given.frictionloss:g} "
                                                  f"(Coulomb) and damping {given.damping:g} (viscous)")
        return entries

    def reduced(self) -> pin.Model:
        """The model with the locked joints held (what the solvers move)."""
        q = self.q0.copy()
        ids = [self.model.getJointId(n) for n in self.locked]
        for name, value in self.locked.items():
            q[self.model.joints[self.model.getJointId(name)].idx_q] = value
        if not ids:
            return self.model
        try:
            return reduced_model(self.model, ids, q)
        except ValueError as error:
            raise ExampleRobotError(f"{self.label}: {error}") from None

    def tool_point(self, q_full: np.ndarray) -> np.ndarray:
        """The tool frame's origin at a configuration of the full model (m)."""
        data = self.model.createData()
        pin.framesForwardKinematics(self.model, data, q_full)
        return data.oMf[self.frame_id].translation.copy()

    def tool_rotation(self, q_full: np.ndarray) -> np.ndarray:
        """The tool frame's rotation at a configuration of the full model."""
        data = self.model.createData()
        pin.framesForwardKinematics(self.model, data, q_full)
        return data.oMf[self.frame_id].rotation.copy()

    def workspace_and_reference(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The workspace box (min, max, m) and the reference configuration (full model)."""
        reach = self.reach_m
        centre, half = np.array(BOX_CENTRE_OF_REACH) * reach, BOX_SIDE_OF_REACH * reach / 2
        solver = PostureSolver(self.reduced(), self.tool, self.pose, reach)
        q_ref = solver.reference(centre, solver.from_full(self.model, self.q0), np.random.default_rng(0))
        if q_ref is None:
            raise ExampleRobotError(f"{self.label}: '{self.tool}' cannot reach {np.round(centre, 3).tolist()} m "
                                    f"(the estimated workspace centre) {'pointing down ' if self.pose else ''}with a "
                                    f"condition number below {MAX_CONDITION:g}; write a sidecar (docs/adding_a_robot.md)")
        for _ in range(BOX_SHRINKS):
            corners = centre + half * np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)])
            if all(solver.solve(corner, q_ref) is not None for corner in corners):
                break
            half *= BOX_SHRINK
        else:
            raise ExampleRobotError(f"{self.label}: '{self.tool}' cannot reach the corners of a box around "
                                    f"{np.round(centre, 3).tolist()} m; write a sidecar (docs/adding_a_robot.md)")
        return centre - half, centre + half, solver.to_full(self.model, self.q0, q_ref)


def _reference_posture(model: pin.Model, erd_model: pin.Model, erd_q0: np.ndarray) -> np.ndarray:
    """example-robot-data's ``q0`` on this model, joint by joint (neutral where it has none)."""
    q = pin.neutral(model)
    for j in range(1, model.njoints):
        name = model.names[j]
        if not erd_model.existJointName(name) or model.joints[j].nq != 1:
            continue
        erd_joint = erd_model.joints[erd_model.getJointId(name)]
        at = erd_q0[erd_joint.idx_q:erd_joint.idx_q + erd_joint.nq]
        q[model.joints[j].idx_q] = at[0] if erd_joint.nq == 1 else np.arctan2(at[1], at[0])  # continuous: (cos, sin)
    return q


def _clip(model: pin.Model, joint: int, value: float) -> float:
    """A joint's value within its limits, if it has any."""
    if urdf_limits_missing(model, joint):
        return value
    index = model.joints[joint].idx_q
    return float(np.clip(value, model.lowerPositionLimit[index], model.upperPositionLimit[index]))


def _tool_frame(model: pin.Model, label: str, tool: str | None) -> int:
    """The id of the tool frame (a link, else a joint), or an error listing the candidates."""
    parents = {frame.parentFrame for frame in model.frames}
    leaves = [f.name for i, f in enumerate(model.frames) if f.type in (pin.FrameType.BODY, pin.FrameType.OP_FRAME)
              and i not in parents]  # an MJCF's sites are frames too
    if tool is None:
        raise ExampleRobotError(f"{label} needs --tool FRAME, the frame that follows the path; candidates "
                                f"(the leaves of its tree): {', '.join(leaves)}")
    frame_id = find_frame(model, tool)
    if frame_id is not None:
        return frame_id
    links = [f.name for f in model.frames if f.type == pin.FrameType.BODY]
    raise ExampleRobotError(f"--tool: {label} has no frame '{tool[:40]}'; the leaves of its tree: "
                            f"{', '.join(leaves)}; its links: {', '.join(links)}")


def write_estimated_sidecar(path: Path, robot: Robot) -> Robot:
    """Write the estimated sidecar of ``robot`` (loaded from a description file or as erd:NAME) to ``path``, for its
    user to refine: its URDF and package folders relative to ``path``, every estimate marked EST under ``sources``.

    Returns:
        The robot loaded from the file written (it is written only if it loads).

    Raises:
        AssemblyError: The file would not load (nothing is written).
    """
    path = path.resolve()
    document = robot.sidecar_document()
    if not robot.urdf_source.startswith(ERD_PREFIX):
        document["urdf"] = os.path.relpath(robot.urdf_source, path.parent)
    if robot.package_paths:
        document["package_paths"] = [os.path.relpath(folder, path.parent) for folder in robot.package_paths]
    header = (f"# Written by 'placement --write-sidecar' from {robot.sidecar_path}: the drives, the workspace and the\n"
              "# reference posture are estimates (EST under sources). Replace them with the robot's own values\n"
              "# (docs/adding_a_robot.md) and load this file with --robot.\n")
    return write_if_it_loads(path, header + yaml.safe_dump(document, sort_keys=False, default_flow_style=None, width=120))
