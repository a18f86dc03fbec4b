"""The static scene page of a robot whose workpiece rides on a positioner: the seam is drawn on the part and turns with
it, not the torch's track frozen in the base frame.

Read back from the recorded page: the seam's points as drawn (before meshcat packs them in float32), and the poses the
animation gives the workpiece's node at each frame. Checked against Pinocchio's forward kinematics of the motion: where
the torch is at a time is where the drawn seam, carried by the node's pose at that time, is; and at every frame the
node moves as the part's own visual does.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
import umsgpack
import yaml
from meshcat.servers.tree import find_node

import placement.output.scene as scene_module
from placement import load_robot
from placement.cli.place import draw
from placement.evaluation.evaluator import Evaluator
from placement.output.scene import WORKPIECE_NODE, Scene
from placement.path import load_path
from placement.robot.packages import description_geometry
from tests.support.paths import EXAMPLES
from tests.support.positioner import TURNING


@pytest.fixture(scope="module")
def positioner():
    return load_robot("ur5_positioner")


@pytest.fixture(scope="module")
def turning_detail(positioner, tmp_path_factory):
    """A 60 mm arc on the lid's centre (fast), the table turning 310° along it."""
    path = tmp_path_factory.mktemp("arc") / "arc.yaml"
    path.write_text(yaml.safe_dump({"units": "mm", "shape": {"type": "arc", "radius": 30, "sweep_deg": 270},
                                    "feed_m_s": 0.05, "time_step_s": 0.02,
                                    "timing": {"mode": "realistic", "max_acceleration_m_s2": 1, "max_jerk_m_s3": 20}}))
    detail = Evaluator(positioner, load_path(path)).detail(TURNING)
    assert detail.reachable
    return detail


def drawn_scene(robot, detail, monkeypatch) -> tuple[Scene, list[np.ndarray]]:
    """The scene the CLI draws for one placement, and the segments of every tube drawn, as the scene computed them."""
    segments = []

    def recording_tube(segments_m, radius_m, sides=6):
        segments.append(np.array(segments_m, dtype=float))
        return tube(segments_m, radius_m, sides)

    tube = scene_module.tube
    monkeypatch.setattr(scene_module, "tube", recording_tube)
    scene = Scene(robot)
    draw(scene, robot, 0, {"at": detail}, "arc", several=False)
    return scene, segments


def animated_poses(scene: Scene, node: str) -> list[pin.SE3]:
    """The placements the page's animation gives ``node`` (a path such as "/meshcat/workpiece"), frame by frame."""
    animation = umsgpack.unpackb(find_node(scene.window.tree, []).animation)
    clip = next(item["clip"] for item in animation["animations"] if item["path"] == node)
    tracks = {track["name"]: [key["value"] for key in track["keys"]] for track in clip["tracks"]}
    return [pin.SE3(pin.Quaternion(w, x, y, z).toRotationMatrix(), np.array(position))
            for position, (x, y, z, w) in zip(tracks[".position"], tracks[".quaternion"], strict=True)]


def tool_point(robot, q: np.ndarray) -> np.ndarray:
    """The torch's tip in the base frame at configuration ``q`` (Pinocchio's forward kinematics)."""
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, q)
    return data.oMf[robot.end_effector_frame_id].translation.copy()


def test_the_seam_is_drawn_on_the_part_where_the_torch_is_at_each_time(positioner, turning_detail, monkeypatch):
    scene, segments = drawn_scene(positioner, turning_detail, monkeypatch)
    assert find_node(scene.window.tree, ["meshcat", WORKPIECE_NODE, "paths", "0_at", "line"]).object is not None
    seam = segments[0]  # the path's tube, the first drawn: segment k from point k to k + 1 (an arc has no jump)
    first_m, last_m = seam[0, 0], seam[-1, 1]
    poses = animated_poses(scene, f"/meshcat/{WORKPIECE_NODE}")
    q = turning_detail.configuration
    for pose, point, sample in ((poses[0], first_m, 0), (poses[-1], last_m, len(q) - 1)):  # frames at samples
        torch = tool_point(positioner, q[sample])
        assert np.linalg.norm(pose.act(point) - torch) < 1e-9
    moved = np.linalg.norm(poses[0].act(last_m) - poses[-1].act(last_m))
    assert moved > 0.05  # the table turned the seam's end by centimetres: a seam in the base frame would not match


def test_the_seam_turns_with_the_part_as_drawn_at_every_frame(positioner, turning_detail, monkeypatch):
    scene, _ = drawn_scene(positioner, turning_detail, monkeypatch)
    model, frame = positioner.model, positioner.model.getFrameId(positioner.workpiece_frame)
    visual = description_geometry(positioner, pin.GeometryType.VISUAL)
    part = next(item for item in visual.geometryObjects if item.parentJoint == model.frames[frame].parentJoint)
    data, geometry_data = model.createData(), visual.createData()
    pin.framesForwardKinematics(model, data, positioner.reference_q)
    pin.updateGeometryPlacements(model, data, visual, geometry_data)
    frame_in_part = geometry_data.oMg[visual.getGeometryId(part.name)].actInv(data.oMf[frame])
    workpiece = animated_poses(scene, f"/meshcat/{WORKPIECE_NODE}")
    drawn_part = animated_poses(scene, f"/meshcat/robot/visuals/{part.name}")
    assert len(workpiece) == len(drawn_part) > 100
    for seam_pose, part_pose in zip(workpiece, drawn_part, strict=True):
        assert np.abs((seam_pose.inverse() * part_pose * frame_in_part).toActionMatrix() - np.eye(6)).max() < 1e-9


def test_the_workpiece_view_frames_the_seam_wherever_the_table_carries_it(positioner, turning_detail, monkeypatch):
    scene, segments = drawn_scene(positioner, turning_detail, monkeypatch)
    low, high = scene.view_box("workpiece")
    torch = np.array([tool_point(positioner, q) for q in turning_detail.configuration[::10]])
    seam, poses = segments[0][:, 0], animated_poses(scene, f"/meshcat/{WORKPIECE_NODE}")
    carried = [seam @ pose.rotation.T + pose.translation for pose in poses[::10]]
    for points in (torch, *carried):
        assert np.all(points >= low) and np.all(points <= high)


def test_a_robot_without_a_carried_workpiece_draws_its_paths_in_the_base_frame():
    robot = load_robot("ur5")
    scene = Scene(robot)
    points = np.array([[0.4, 0.0, 0.2], [0.4, 0.1, 0.2], [0.5, 0.1, 0.2]])
    scene.add_path("p", points, 0x009E73, configuration=np.repeat(robot.reference_q[None], 3, axis=0))
    assert find_node(scene.window.tree, ["meshcat", "paths", "p", "line"]).object is not None
    assert WORKPIECE_NODE not in find_node(scene.window.tree, ["meshcat"])
    assert np.array_equal(scene.workpiece_points_m[0], points)


def test_the_workbench_refuses_a_carried_workpiece_naming_it(capsys):
    from placement.__main__ import main

    assert main(["app", "--robot", "ur5_positioner", "--path", str(EXAMPLES / "positioner_weld.yaml")]) == 2
    error = capsys.readouterr().err
    assert "workpiece_frame: workpiece" in error and "workbench" in error and "Traceback" not in error


def test_the_workbench_refuses_profiled_joints_naming_them_and_how_to_hold_them(capsys):
    """The seven-axis Panda's joint 3 is profiled along the path: the workbench, which places six variables, says so
    before it serves a page (was: 'a placement is six finite numbers' once the page was up)."""
    from placement.__main__ import main

    assert main(["app", "--robot", "panda", "--path", str(EXAMPLES / "circle.yaml")]) == 2
    error = capsys.readouterr().err
    assert "panda_joint3" in error and "--lock panda_joint3=VALUE" in error and "Traceback" not in error
