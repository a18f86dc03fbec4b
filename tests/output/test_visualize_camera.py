"""The scene's views: everything sees the whole robot and every path, from a 6 cm robot to a 2 m tall chain; the page
opens on the workpiece, which fills a good part of the view, seen from beyond it so that an arm is not in front."""

import numpy as np
import pinocchio as pin
import pytest

from placement import load_robot
from placement.output.camera import CAMERA_FOV_DEG
from placement.output.scene import WORKPIECE_MIN_M, Scene

HALF_VIEW = np.tan(np.radians(CAMERA_FOV_DEG / 2))  # a square window: the narrowest view meshcat gives across
NEAR_M = 0.01


def chain(folder, height_m: float):
    """A 3-joint vertical chain of ``height_m``, boxes as visuals, tip frame 'tip' (sidecar path)."""
    link = height_m / 3
    links, joints = [], []
    for k in range(3):
        links.append(f'<link name="l{k}"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" '
                     f'ixz="0" iyz="0"/></inertial><visual><origin xyz="0 0 {link / 2}"/><geometry><box size="'
                     f'{link / 8} {link / 8} {link}"/></geometry></visual></link>')
        parent, axis = "base" if k == 0 else f"l{k - 1}", "1 0 0" if k == 1 else "0 1 0"
        joints.append(f'<joint name="j{k}" type="revolute"><parent link="{parent}"/><child link="l{k}"/>'
                      f'<origin xyz="0 0 {0 if k == 0 else link}"/><axis xyz="{axis}"/>'
                      '<limit lower="-3" upper="3" effort="10" velocity="2"/></joint>')
    urdf = (f'<robot name="chain"><link name="base"/>{"".join(links)}{"".join(joints)}<link name="tip"/>'
            f'<joint name="tip_joint" type="fixed"><parent link="l2"/><child link="tip"/><origin xyz="0 0 {link}"/></joint>'
            "</robot>")
    (folder / "chain.urdf").write_text(urdf)
    sidecar = folder / "chain.yaml"
    sidecar.write_text("name: chain\nurdf: chain.urdf\ngravity_m_s2: [0, 0, -9.81]\n"
                       "end_effector: {frame: tip, task: position}\nactuators: [{joint: j0}, {joint: j1}, {joint: j2}]\n"
                       "placement: {free: [x, y], bounds: {x: [-0.1, 0.1], y: [-0.1, 0.1], z: [0, 0.1]}}\n")
    return load_robot(sidecar)


def drawn_box(robot, path_points):
    """The box of the robot's frame origins at its reference configuration, its workspace and the path."""
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, robot.reference_q)
    points = [np.array([frame.translation for frame in data.oMf]), path_points]
    workspace = robot.workspace
    if workspace is not None:
        points.append(np.array([workspace.min_m, workspace.max_m]))
    points = np.vstack(points)
    low, high = points.min(axis=0), points.max(axis=0)
    return np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])])


def in_view(position, target, points):
    """Whether every point projects inside the camera's view (Z up, square window, beyond the near plane)."""
    forward = (target - position) / np.linalg.norm(target - position)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    offset = points - position
    depth = offset @ forward
    return bool(np.all(depth > NEAR_M) and np.all(np.abs(offset @ right) <= HALF_VIEW * depth)
                and np.all(np.abs(offset @ up) <= HALF_VIEW * depth))


def circle_at(robot, radius_m):
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, robot.reference_q)
    angle = np.linspace(0, 2 * np.pi, 50)
    tip = data.oMf[robot.end_effector_frame_id].translation
    return tip + radius_m * np.column_stack([np.cos(angle), np.sin(angle), np.zeros_like(angle)])


@pytest.fixture(params=["tiny", "orthoglide", "tall"])
def robot(request, tmp_path):
    if request.param == "orthoglide":
        return load_robot("orthoglide")
    return chain(tmp_path, 0.06 if request.param == "tiny" else 2.0)


def test_the_everything_view_sees_every_corner_of_the_robot_and_paths(robot):
    scene = Scene(robot)
    scene.add_workspace()
    size = float(np.ptp(drawn_box(robot, np.zeros((0, 3))), axis=0).max())
    path = circle_at(robot, 0.4 * size)  # a path reaching out beyond the robot
    scene.add_path("p", path, 0x00FF00)
    scene.html()
    target, position = scene.views_m()["everything"]
    corners = drawn_box(robot, path)
    assert in_view(position, target, corners)
    assert not in_view(target + 0.3 * (position - target), target, corners)  # closer, the box overflows the view
    # not absurdly far: the box's largest side spans at least a fifth of the view
    assert np.ptp(corners, axis=0).max() > 0.2 * 2 * HALF_VIEW * np.linalg.norm(position - target)


def test_the_page_opens_on_the_workpiece_which_fills_a_good_part_of_the_view(robot):
    scene = Scene(robot)
    scene.add_workspace()
    size = float(np.ptp(drawn_box(robot, np.zeros((0, 3))), axis=0).max())
    path = circle_at(robot, max(0.05 * size, WORKPIECE_MIN_M))  # a workpiece small beside the robot
    scene.add_path("p", path, 0x00FF00)
    scene.html()
    target, position = scene.camera_m
    assert list(scene.views_m()) == ["workpiece", *(["workspace"] if robot.workspace else []), "everything"]
    assert np.allclose((target, position), scene.views_m()["workpiece"])
    assert in_view(position, target, path)
    spans = np.ptp(path, axis=0).max()  # the circle's diameter against the view's width at its distance
    view_width = 2 * HALF_VIEW * np.linalg.norm(position - target)
    assert spans > 0.15 * view_width  # in the everything view of the Orthoglide: 0.03


def test_the_workpiece_is_seen_from_beyond_it_away_from_an_arms_base():
    ur5 = load_robot("ur5")
    scene = Scene(ur5)
    centre = np.array([0.4, 0.3, 0.2])  # reached from the base at the origin
    angle = np.linspace(0, 2 * np.pi, 40)
    scene.add_path("p", centre + 0.03 * np.column_stack([np.cos(angle), np.sin(angle), 0 * angle]), 0x00FF00)
    target, position = scene.views_m()["workpiece"]
    outwards = (position - target)[:2] @ centre[:2] / np.linalg.norm(position - target) / np.linalg.norm(centre[:2])
    assert outwards > 0.8  # the camera is on the far side of the workpiece, the arm behind it
    assert position[2] > target[2]  # looking down on it


def test_the_former_fixed_offset_misses_the_tall_chain(tmp_path):
    tall = chain(tmp_path, 2.0)
    data = tall.model.createData()
    pin.framesForwardKinematics(tall.model, data, tall.reference_q)
    target = data.oMf[tall.end_effector_frame_id].translation  # the former rule: no workspace, aim at the tool
    position = target + np.array([-0.45, -0.45, 0.35]) * (0.5 / 0.3)
    assert not in_view(position, target, drawn_box(tall, np.zeros((0, 3))))


def test_a_skipped_rapids_gap_is_not_drawn_as_a_line():
    import umsgpack
    from meshcat.servers.tree import find_node

    scene = Scene(load_robot("orthoglide"))
    x = np.concatenate([np.linspace(0.0, 0.01, 11), np.linspace(0.05, 0.06, 11)])  # 1 mm steps, one 40 mm gap
    scene.add_path("gap", np.stack([x, np.zeros_like(x), np.zeros_like(x)], axis=1), 0xFF0000)
    line = umsgpack.unpackb(find_node(scene.window.tree, ["meshcat", "paths", "gap", "line"]).object)
    vertices = np.frombuffer(line["object"]["geometries"][0]["data"]["attributes"]["position"]["array"].data,
                             np.float32)
    segments = vertices.reshape(-1, 2, 6, 3).mean(axis=2)  # a tube's piece: a ring of 6 vertices around each end
    assert len(segments) == 20  # 21 steps less the gap
    assert np.linalg.norm(segments[:, 1] - segments[:, 0], axis=1).max() < 0.0011
