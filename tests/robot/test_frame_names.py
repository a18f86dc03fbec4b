"""A URDF that gives one name to a link and a joint (the Unitree Z1's 'gripperStator'): the link is the
frame meant, and holding joints, which Pinocchio then refuses, is an error that says why."""

import pinocchio as pin
from example_robot_data.robots_loader import ROBOTS

from placement.__main__ import main
from placement.robot.tool import find_frame
from tests.support.robot_copies import edited_copy

ELBOW = '<parent link="prox1"/><child link="dist1"/>'


def test_a_name_shared_by_a_link_and_a_joint_finds_the_link():
    model = pin.buildModelFromUrdf(ROBOTS["z1"]().df_path)
    assert sum(f.name == "gripperStator" for f in model.frames) > 1  # the case this test is about
    assert model.frames[find_frame(model, "gripperStator")].type == pin.FrameType.BODY
    assert find_frame(model, "no such frame") is None


def test_holding_joints_of_a_urdf_with_shared_names_is_a_located_error(tmp_path, capsys):
    """The five-bar with its first distal link renamed to the name of a joint, one joint locked."""
    def lock_b2(document):
        document["locked_joints"] = {"b2": document["reference_configuration"].pop("b2")}

    sidecar = edited_copy("fivebar", tmp_path, lock_b2)
    urdf = sidecar.parent / "fivebar.urdf"
    text = urdf.read_text()
    assert ELBOW in text
    urdf.write_text(text.replace('link name="dist1"', 'link name="a1"').replace(ELBOW, ELBOW.replace("dist1", "a1"))
                    .replace('<parent link="dist1"/>', '<parent link="a1"/>'))
    assert main(["check", str(sidecar)]) == 2
    error = capsys.readouterr().err
    assert "locked_joints" in error and "'a1' to both a link and a joint" in error and "Traceback" not in error
