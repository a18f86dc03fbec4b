"""Link compliance as 6×6 springs (the sidecar's ``link_springs``, the virtual-joint method), proven by physics: a
cantilever's tip compliance carried to a tool beyond the tip (beam theory by hand), and the full nonlinear static
equilibrium of the same robot with the spring as six sprung virtual joints (tests/support/static_equilibrium.py)."""

from types import SimpleNamespace

import numpy as np
import pinocchio as pin
import pytest

from placement import load_robot
from placement.kinematics import joint_trajectory
from placement.robot.exceptions import RobotFileError
from placement.stiffness import joint_springs, tool_compliance
from placement.workshop.checks import demo_trajectory
from tests.support.robot_copies import edited_copy
from tests.support.static_equilibrium import settle

E_I = 2.1e11 * 2.0e-8  # steel, a hollow section of 2e-8 m⁴ (N·m²)
BEAM_M, REACH_M = 0.3, 0.08  # the beam's length, and the tool's distance beyond its tip
VIRTUAL_STIFFNESS = [2.0e6, 3.0e6, 5.0e6, 4.0e4, 6.0e4, 8.0e4]  # N/m, N·m/rad: as soft as the UR5's joints matter


def with_link_spring(tmp_path, link: str, stiffness, origin_m) -> object:
    def edit(document):
        document["link_springs"] = {link: {"stiffness": stiffness, "origin_m": [float(x) for x in origin_m]}}
        document["sources"][f"link_springs.{link}"] = "EST: a test spring"
    return load_robot(edited_copy("ur5", tmp_path, edit))


def cantilever_tip_compliance(length_m: float) -> np.ndarray:
    """(6, 6) a cantilever's compliance at its free tip, x along the beam: bending in y and z with its coupling to the
    tip's rotation (L³/3EI, L²/2EI, L/EI), axial and torsion stiff (a tenth of the bending ones)."""
    c = np.zeros((6, 6))
    c[1, 1] = c[2, 2] = length_m**3 / (3 * E_I)
    c[5, 5] = c[4, 4] = length_m / E_I
    c[1, 5] = c[5, 1] = length_m**2 / (2 * E_I)  # a force along +y turns the tip about +z
    c[2, 4] = c[4, 2] = -length_m**2 / (2 * E_I)  # a force along +z turns it about −y
    c[0, 0], c[3, 3] = 0.1 * c[1, 1], 0.1 * c[5, 5]
    return c


def test_a_cantilever_carries_its_tip_compliance_to_the_tool_as_beam_theory_says(tmp_path):
    """The UR5's last link as a beam whose tip lies REACH_M behind the tool point along the link's x axis: the tool's
    compliance grows by (L³/3 + a·L² + a²·L)/EI across the beam (tip deflection plus the tip's rotation times a), in
    both bending planes; L³/3EI itself at a = 0."""
    rigid = load_robot("ur5")
    model = rigid.model
    tool = model.frames[rigid.end_effector_frame_id]
    link = next(f for f in model.frames if f.type == pin.FrameType.BODY and f.parentJoint == tool.parentJoint)
    tool_in_link = (link.placement.inverse() * tool.placement).translation
    joints = joint_trajectory(rigid, demo_trajectory(rigid)(np.array([0.13, 0.4])))
    for reach in (REACH_M, 0.0):
        stiffness = np.linalg.inv(cantilever_tip_compliance(BEAM_M)).tolist()
        robot = with_link_spring(tmp_path / str(reach), link.name, stiffness, tool_in_link - [reach, 0.0, 0.0])
        added = tool_compliance(joint_springs(robot), joints) - tool_compliance(joint_springs(rigid), joints)
        data = model.createData()
        for sample, q in enumerate(joints.q):
            pin.framesForwardKinematics(model, data, q)
            axes = data.oMf[model.getFrameId(link.name)].rotation
            across = [(BEAM_M**3 / 3 + reach * BEAM_M**2 + reach**2 * BEAM_M) / E_I] * 2
            in_link = axes.T @ added[sample, :3, :3] @ axes
            np.testing.assert_allclose(np.diag(in_link)[1:], across, rtol=1e-9)


def virtual_joint_robot(robot, link: str, origin_m):
    """The robot's model with six joints (x, y, z translations, then rotations, all massless) inserted at point
    ``origin_m`` of ``link``, between the link's joint and everything it carries; the equilibrium solver's view of it
    (model, end-effector frame, no closures), the map of the old joints to the new and the virtual joints' v indices."""
    model = robot.model
    body = model.frames[model.getBodyId(link)]
    spring = body.placement * pin.SE3(np.eye(3), np.asarray(origin_m, dtype=float))  # in the link's joint frame
    new, mapping, virtual = pin.Model(), {0: 0}, []
    for j in range(1, model.njoints):
        parent, placement = mapping[model.parents[j]], model.jointPlacements[j]
        if model.parents[j] == body.parentJoint:
            parent, placement = virtual[-1], spring.inverse() * placement
        mapping[j] = new.addJoint(parent, model.joints[j], placement, model.names[j])
        if j == body.parentJoint:
            previous, at = mapping[j], spring
            for kind in (pin.JointModelPX, pin.JointModelPY, pin.JointModelPZ, pin.JointModelRX, pin.JointModelRY,
                         pin.JointModelRZ):
                previous = new.addJoint(previous, kind(), at, f"virtual_{kind.__name__}")
                virtual.append(previous)
                at = pin.SE3.Identity()
    tool = model.frames[robot.end_effector_frame_id]
    parent, placement = mapping[tool.parentJoint], tool.placement
    if tool.parentJoint == body.parentJoint:
        parent, placement = virtual[-1], spring.inverse() * placement
    frame = new.addFrame(pin.Frame("tool", parent, placement, pin.FrameType.OP_FRAME))
    view = SimpleNamespace(model=new, end_effector_frame_id=frame, closures=())
    return view, mapping, [new.joints[v].idx_v for v in virtual]


def test_a_link_spring_is_the_nonlinear_equilibrium_of_six_sprung_virtual_joints(tmp_path):
    """The UR5 with a diagonal 6×6 spring mid-arm (its forearm, off the link frame's origin): its compliance equals the
    finite-difference response of the full nonlinear equilibrium of the same arm with six virtual joints sprung as the
    spring, to 1e-6, and differs from the rigid link's by more than 10 %."""
    origin = [0.05, -0.02, 0.2]
    robot = with_link_spring(tmp_path, "forearm_link", VIRTUAL_STIFFNESS, origin)
    joints = joint_trajectory(robot, demo_trajectory(robot)(np.array([0.13])))
    compliance = tool_compliance(joint_springs(robot), joints)[0]
    rigid = tool_compliance(joint_springs(load_robot("ur5")), joints)[0]
    assert np.abs(compliance - rigid).max() > 0.1 * np.abs(rigid).max()
    view, mapping, virtual_v = virtual_joint_robot(robot, "forearm_link", origin)
    q0 = np.zeros(view.model.nq)
    for j in range(1, robot.model.njoints):
        q0[view.model.joints[mapping[j]].idx_q] = joints.q[0, robot.model.joints[j].idx_q]
    by_v = {view.model.joints[mapping[a.v_index + 1]].idx_v: a.stiffness for a in robot.actuators}
    by_v.update(zip(virtual_v, VIRTUAL_STIFFNESS))
    scale = 1e-6 / np.abs(compliance[:3, :3]).max()  # N and N·m: about a micrometre
    measured = np.column_stack([(settle(view, q0, by_v, w) - settle(view, q0, by_v, -w)) / (2 * scale)
                                for w in np.eye(6) * scale])
    assert np.abs(measured - compliance).max() <= 1e-6 * np.abs(compliance).max()


def test_a_link_spring_needs_a_link_and_its_source(tmp_path):
    def unknown(document):
        document["link_springs"] = {"no_such_link": {"stiffness": VIRTUAL_STIFFNESS}}
        document["sources"]["link_springs"] = "EST: a test spring"
    with pytest.raises(RobotFileError, match="link_springs.no_such_link"):
        load_robot(edited_copy("ur5", tmp_path / "a", unknown))

    def unsourced(document):
        document["link_springs"] = {"forearm_link": {"stiffness": VIRTUAL_STIFFNESS}}
    with pytest.raises(RobotFileError, match="needs its source"):
        load_robot(edited_copy("ur5", tmp_path / "b", unsourced))
