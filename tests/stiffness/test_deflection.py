"""Deflection along a path: the objectives, the limit, the sidecar's stiffness fields and the command line.

The objectives are checked against the deflection computed by hand on the Orthoglide (k_a·JᵀJ from its inverse
kinematics, the process force turned into the base frame by the placement), not against placement's own numbers.
"""

import dataclasses
import json

import numpy as np
import pytest

from placement import load_path, load_robot
from placement.__main__ import main
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.placing.transform import rotation_zyx
from placement.robot.exceptions import RobotFileError
from placement.search.pareto import non_dominated
from tests.stiffness.test_compliance import orthoglide_jacobian
from tests.support.robot_copies import edited_copy

PLACEMENTS = np.array([[0.0, 0.0, 0.0, 0.0, 0.0, 0.0], [0.02, -0.03, 0.01, 0.7, 0.0, 0.0],
                       [-0.06, -0.05, -0.04, -1.2, 0.0, 0.0]])


@pytest.fixture(scope="module")
def evaluator():
    robot, path = load_robot("orthoglide"), load_path("examples/rect.yaml")
    with Evaluator(robot, path, EvaluatorSettings(objective=("deflection", "deflection_rms"), workers=1)) as evaluator:
        yield evaluator


def hand_deflection_m(robot, samples, placement):
    """(N,) |δ| at each sample: the force turned by the placement, δ = (k_a·JᵀJ)⁻¹·F at the placed tool point."""
    turn = rotation_zyx(*placement[3:])  # Rz(phi)·Ry(theta)·Rx(psi)
    points = samples.position_m @ turn.T + placement[:3]
    forces = samples.force_on_tool_N @ turn.T
    k_a = robot.actuators[0].stiffness
    return np.array([np.linalg.norm(np.linalg.solve(k_a * orthoglide_jacobian(p).T @ orthoglide_jacobian(p), f))
                     for p, f in zip(points, forces)])


def test_the_objectives_are_the_largest_and_rms_deflection_by_hand(evaluator):
    evaluation = evaluator.evaluate(PLACEMENTS)
    hand = [hand_deflection_m(evaluator.robot, evaluator.samples, p) for p in PLACEMENTS]
    np.testing.assert_allclose(evaluation.values[:, 0], [h.max() * 1e6 for h in hand], rtol=1e-9)
    np.testing.assert_allclose(evaluation.values[:, 1], [np.sqrt(np.mean(h**2)) * 1e6 for h in hand], rtol=1e-9)
    # the paper's 216.7 N against 75 N/µm at the isotropic point: about 2.9 µm
    assert 2.5 < evaluation.values[0, 0] < 3.5


def test_the_limit_rejects_exactly_the_placements_that_deflect_more(evaluator):
    largest_um = evaluator.evaluate(PLACEMENTS).values[:, 0]
    bound_um = float(np.median(largest_um))
    path = load_path("examples/rect.yaml")
    bounded = Evaluator(evaluator.robot, dataclasses.replace(path, max_deflection_m=bound_um * 1e-6),
                        EvaluatorSettings(workers=1))
    evaluation = bounded.evaluate(PLACEMENTS)
    column = evaluation.limits.index("tool deflection: tool")
    np.testing.assert_allclose(evaluation.margins[:, column], (bound_um - largest_um) / bound_um, rtol=1e-9, atol=1e-12)
    assert [m >= 0 for m in evaluation.margins[:, column]] == [v <= bound_um for v in largest_um]
    detail = bounded.detail(PLACEMENTS[2])
    assert not detail.feasible and any(m.kind == "tool deflection" and m.margin < 0 for m in detail.margins)


def test_a_robot_without_stiffness_names_the_field_it_needs():
    robot, path = load_robot("fivebar"), load_path("examples/rect.yaml")
    with pytest.raises(RobotFileError, match=r"actuators\.0\.stiffness"):
        Evaluator(robot, path, EvaluatorSettings(objective="deflection", workers=1)).evaluate(np.zeros((1, 6)))


def test_the_sidecar_wants_a_source_for_each_stiffness_and_springs_on_passive_joints(tmp_path):
    def unsourced(document):
        document["actuators"][0]["stiffness"] = 1e7
        del document["sources"]["actuators.stiffness"]

    with pytest.raises(RobotFileError, match=r"actuators\.0\.stiffness.*needs its source"):
        load_robot(edited_copy("orthoglide", tmp_path / "a", unsourced))

    def actuated_spring(document):
        document["joint_springs"] = {"slider_y": 1e7}
        document["sources"]["joint_springs"] = "EST: test"

    with pytest.raises(RobotFileError, match=r"slider_y.*actuated.*actuators\.1\.stiffness"):
        load_robot(edited_copy("orthoglide", tmp_path / "b", actuated_spring))

    def motor_side(document):
        drive = next(iter(document["drives"].values()))
        drive["motor_side_stiffness_Nm_per_rad"] = 400.0
        document["sources"]["drives.sanyo_p30b06040d_ball_screw.motor_side_stiffness_Nm_per_rad"] = "EST: test"

    robot = load_robot(edited_copy("orthoglide", tmp_path / "c", motor_side))
    reflected = 400.0 * (2 * np.pi / 0.020) ** 2  # N·m/rad on the motor shaft times the screw's speed ratio squared
    np.testing.assert_allclose(robot.actuators[0].stiffness, 1 / (1 / 7.5e7 + 1 / reflected), rtol=1e-12)


def test_the_command_line_reports_deflection_and_names_a_binding_bound(tmp_path, capsys):
    out, trace = tmp_path / "r.json", tmp_path / "trace.csv"
    assert main(["--robot", "orthoglide", "--path", "examples/rect.yaml", "--json", str(out), "--quiet",
                 "--max-deflection-um", "3.0", "--trace", str(trace)]) == 0
    document = json.loads(out.read_text())
    table = np.genfromtxt(trace, delimiter=",", names=True)
    along = np.linalg.norm([table["deflection_x"], table["deflection_y"], table["deflection_z"]], axis=0)
    np.testing.assert_allclose(along.max() * 1e6, document["best"]["deflection"]["largest_um"], rtol=1e-8)
    for which in ("best", "worst"):
        bend = document[which]["deflection"]
        assert bend["largest_um"] <= 3.0 + 1e-9 and 0 < bend["rms_um"] <= bend["largest_um"]
        assert 0 <= bend["where"]["arc_length_m"] <= 0.18 + 1e-9 and abs(np.linalg.norm(bend["direction"]) - 1) < 1e-12
    assert "tool deflection under the process forces: largest" in capsys.readouterr().out
    assert main(["--robot", "orthoglide", "--path", "examples/rect.yaml", "--max-deflection-um", "1", "--quiet"]) == 2
    assert "tool deflection (tool) is exceeded" in capsys.readouterr().err


def test_energy_and_deflection_make_a_front(tmp_path, capsys):
    out = tmp_path / "front.json"
    assert main(["--robot", "orthoglide", "--path", "examples/rect.yaml", "--objectives", "energy,deflection",
                 "--population", "24", "--generations", "10", "--json", str(out), "--quiet"]) == 0
    members = json.loads(out.read_text())["members"]
    values = np.array([[m["values"]["energy"], m["values"]["deflection"]] for m in members])
    assert len(members) >= 5 and non_dominated(values).all()
    capsys.readouterr()


def test_a_path_without_process_force_reports_no_deflection_and_no_direction(tmp_path, capsys):
    """A weld seam has no process force: the tool does not deflect, and the report says so rather than a direction."""
    path = tmp_path / "no_force.yaml"
    path.write_text("name: a line without process force\nunits: mm\nshape: {type: polyline, points: [[-10, 0], [10, 0]]}\n"
                    "feed_m_s: 0.05\n")
    assert main(["--robot", "orthoglide", "--path", str(path), "--at", "x=0,y=0,z=0"]) == 0
    printed = capsys.readouterr().out
    assert "tool deflection: none (the path has no process force)" in printed
    assert "tool deflection under the process forces" not in printed
