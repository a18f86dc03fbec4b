"""The degrees-of-freedom error names the joints left free and proposes the locked_joints that fix it."""

import re

import numpy as np
import pytest
import yaml
from robot_copies import edited_copy

from placement.exceptions import RobotFileError
from placement.robot import load_robot

SPIN = ('<link name="dist{i}_hub"/>'
        '<joint name="spin{i}" type="revolute"><parent link="dist{i}_hub"/><child link="dist{i}"/>'
        '<origin xyz="0 0 0"/><axis xyz="1 0 0"/><limit lower="-3.14" upper="3.14" effort="1" velocity="1"/></joint>')


def spinning_rods_fivebar(folder):
    """The five-bar with each distal rod on an extra revolute joint about its own axis (x)."""
    sidecar = edited_copy("fivebar", folder, lambda document: None)
    urdf = sidecar.parent / "fivebar.urdf"
    text = urdf.read_text()
    for i in (1, 2):
        elbow = f'<parent link="prox{i}"/><child link="dist{i}"/>'
        assert elbow in text
        text = text.replace(elbow, f'<parent link="prox{i}"/><child link="dist{i}_hub"/>')
        text = text.replace("</robot>", SPIN.format(i=i) + "\n</robot>")
    urdf.write_text(text)
    return sidecar


def test_the_error_names_the_spinning_joints_and_the_proposal_makes_it_load(tmp_path):
    sidecar = spinning_rods_fivebar(tmp_path)
    with pytest.raises(RobotFileError) as caught:
        load_robot(sidecar)
    error = caught.value
    assert error.field == "actuators" and "\n" not in str(error)
    assert "the closures leave 4 degree(s) of freedom at reference_configuration for the 2 actuated joint(s)" in str(error)
    assert "joint(s) spin1, spin2 still move" in str(error)
    proposal = re.search(r"locked_joints: (\{[^}]*\})", str(error)).group(1)
    assert yaml.safe_load(proposal) == {"spin1": 0.0, "spin2": 0.0}

    document = yaml.safe_load(sidecar.read_text())
    document["locked_joints"] = yaml.safe_load(proposal)
    sidecar.write_text(yaml.safe_dump(document))
    robot = load_robot(sidecar)
    np.testing.assert_allclose(robot.reference_q, load_robot("fivebar").reference_q, atol=1e-12)

