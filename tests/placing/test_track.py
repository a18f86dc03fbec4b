"""The UR5 on a linear track: a prismatic redundant joint profiled along the path, its knots lengths.

Physics, not snapshots: the track held at 0 is the plain UR5 to the last digit, moving the workpiece and the carriage
together along the rail changes no energy, and the resolved motion's efforts and energy are those Pinocchio's RNEA
gives on the same joint trajectory, the track's drive (friction, efficiency, rack) included.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import yaml

from placement import load_robot
from placement.__main__ import main
from placement.dynamics.inverse import TreeDynamics
from placement.energy.integration import electric_energy
from placement.energy.trace import motor_trace
from placement.evaluation.evaluator import Evaluator
from placement.path import load_path
from placement.placing.profiles import length_variables, redundant_variables
from placement.placing.transform import placed_task
from placement.robot.packages import description_geometry
from placement.search.space import default_space
from placement.workshop.catalog import builtin_robots_dir
from placement.workshop.load import edit_redundancy, robot_from_sidecar
from tests.support.generators import urdf_generator
from tests.support.paths import CIRCLE, EXAMPLES
from tests.support.rnea_reference import rnea_actuator_efforts

SEAM = EXAMPLES / "long_seam.yaml"
TRACK_DIR = builtin_robots_dir() / "ur5_track"
ALONG = np.array([0.45, 0.0, 0.2, np.pi / 2, 0.0, 0.0, -0.7, 0.1, 0.75])  # the carriage travelling with the torch


@pytest.fixture(scope="module")
def track():
    return load_robot("ur5_track")


def test_committed_urdf_is_what_the_generator_writes():
    module = urdf_generator(TRACK_DIR)
    assert (TRACK_DIR / "ur5_track.urdf").read_text(encoding="utf-8") == module.track_urdf()


def test_the_ur5s_drives_are_the_ur5s():
    """The arm's drives are copied from robots/ur5 (a sidecar has no include): they must stay equal."""
    own = yaml.safe_load((TRACK_DIR / "ur5_track.yaml").read_text(encoding="utf-8"))
    ur5 = yaml.safe_load((builtin_robots_dir() / "ur5" / "ur5.yaml").read_text(encoding="utf-8"))
    assert {name: own["drives"][name] for name in ur5["drives"]} == ur5["drives"]
    assert own["actuators"][1:] == ur5["actuators"]
    assert own["end_effector"] == ur5["end_effector"] and own["reference_configuration"] == {
        "track": 0.0, **ur5["reference_configuration"]}


def test_the_track_is_redundant_and_its_knots_are_lengths(track):
    assert track.redundant_joints == ("track",) and redundant_variables(track) == ("track@0", "track@1", "track@2")
    assert length_variables(track) == frozenset(redundant_variables(track))
    space = default_space(track)
    assert space.free[-3:] == redundant_variables(track)
    np.testing.assert_array_equal(space.lower[-3:], -1.0)
    np.testing.assert_array_equal(space.upper[-3:], 1.0)
    assert not space.angles[-3:].any() and space.angles[3:6].all()


def test_the_track_held_at_zero_is_the_plain_ur5(track):
    """--lock track=0 leaves the UR5 of robots/ur5 (with the same torch) on a fixed base: the same efforts and
    energies, to 1e-12."""
    locked = edit_redundancy(track, {"track": 0.0})
    plain = load_robot("ur5")
    ur5 = robot_from_sidecar(plain.sidecar_path, plain.edited_sidecar(tool=track.sidecar.tool))
    placement = np.array([0.4, 0.05, 0.2, 0.3, 0.1, -0.05])
    path = load_path(CIRCLE)
    held, plain = Evaluator(locked, path).batch(placement[None]), Evaluator(ur5, path).batch(placement[None])
    assert [a.joint for a in locked.actuators] == [a.joint for a in ur5.actuators]
    np.testing.assert_allclose(held.effort[0], plain.effort[0], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(held.energy.per_actuator_J[0], plain.energy.per_actuator_J[0], rtol=1e-12)


def test_moving_the_workpiece_and_the_carriage_together_changes_no_energy(track):
    """The rail is level and its friction does not depend on where the carriage is: the same path and carriage motion
    shifted along the rail by 200 mm draw the same energy (1e-9)."""
    evaluator = Evaluator(track, load_path(SEAM))
    shifted = ALONG.copy()
    shifted[1] += 0.2
    shifted[6:] += 0.2
    batch = evaluator.batch(np.vstack([ALONG, shifted]))
    assert batch.reachable.all()
    np.testing.assert_allclose(batch.energy.per_actuator_J[1], batch.energy.per_actuator_J[0], rtol=1e-9, atol=1e-9)
    assert batch.energy.per_actuator_J[0][0] > 1.0  # the track's drive works: friction along 1.45 m of travel


def test_the_resolved_motion_keeps_the_torch_on_the_seam_and_its_rates_are_derivatives(track):
    evaluator = Evaluator(track, load_path(SEAM))
    batch = evaluator.batch(ALONG[None])
    task, _ = placed_task(track, evaluator.samples, ALONG[None])
    joints, data = batch.joints, track.model.createData()
    for k in range(0, len(joints.q), 11):
        pin.framesForwardKinematics(track.model, data, joints.q[k])
        np.testing.assert_allclose(data.oMf[track.end_effector_frame_id].translation, task.position_m[k], atol=1e-9)
    t, inner = evaluator.samples.t_s, slice(3, -3)  # the realistic law's start and stop ramps are shorter than a step
    for rates, positions, within in ((joints.v, joints.q, 1e-4), (joints.a, joints.v, 1e-2)):
        finite = np.gradient(positions, t, axis=0)[inner]
        assert (np.abs(finite - rates[inner]).max(axis=0) <= within * np.abs(rates[inner]).max(axis=0) + 1e-12).all()


def test_energy_of_the_resolved_motion_is_rnea_on_its_joint_trajectory(track):
    """Efforts by Pinocchio's RNEA, sample by sample, on the same joint trajectory (the carriage moving): the same
    efforts and the same electric energy, the track's friction and efficiency included, to 1e-9."""
    evaluator = Evaluator(track, load_path(SEAM))
    batch = evaluator.batch(ALONG[None])
    assert batch.reachable.all()
    joints = batch.joints
    _, force = placed_task(track, evaluator.samples, ALONG[None])
    efforts = rnea_actuator_efforts(track, joints, force)
    np.testing.assert_allclose(batch.effort[0], efforts, rtol=1e-9, atol=1e-9 * np.abs(efforts).max())
    compiled = TreeDynamics(track.model)  # the compiled Newton-Euler pass (the optimal law's route), forced on this arm
    compiled.compiled_efforts = True
    np.testing.assert_allclose(compiled.efforts(joints.q, joints.v, joints.a, joints.basis), efforts, rtol=1e-9,
                               atol=1e-9 * np.abs(efforts).max())
    carriage = joints.q[:, track.redundant_q_indices[0]]
    assert carriage[0] == pytest.approx(-0.7, abs=1e-12) and carriage[-1] == pytest.approx(0.75, abs=1e-12)
    v, a = joints.v[:, track.actuated_v_indices], joints.a[:, track.actuated_v_indices]
    energy = electric_energy(track, motor_trace(track, efforts, v, a), evaluator.samples.t_s, evaluator.samples.piece)
    assert energy.total_J == pytest.approx(float(batch.energy.total_J[0]), rel=1e-9)
    np.testing.assert_allclose(energy.per_actuator_J, batch.energy.per_actuator_J[0], rtol=1e-9, atol=1e-12)


def test_the_knots_are_given_in_mm_and_written_in_m(tmp_path, capsys):
    """--at reads a track knot in mm, the report prints it in mm, --json writes m (knots_m, position_m), and
    --at-json reads it back to the very same energy; the track's drive is in the energy table."""
    first, second = tmp_path / "first.json", tmp_path / "second.json"
    at = "x=450,z=200,phi=90,track@0=-700,track@1=100,track@2=0.75m"
    assert main(["--robot", "ur5_track", "--path", str(SEAM), "--at", at, "--json", str(first)]) == 0
    out = capsys.readouterr().out
    assert "track@0 = -700.00 mm, track@1 = 100.00 mm, track@2 = 750.00 mm" in out
    assert "track along the path: -700.00 mm at the start" in out
    assert any(line.split()[:1] == ["track"] and len(line.split()) == 6 for line in out.splitlines())  # energy row
    document = json.loads(first.read_text())["at"]
    assert document["placement"]["track@0"] == pytest.approx(-0.7, abs=1e-15)
    profile = document["profiles"]["track"]
    assert profile["knots_m"] == pytest.approx([-0.7, 0.1, 0.75], abs=1e-15) and "position_rad" not in profile
    assert profile["position_m"][-1] == pytest.approx(0.75, abs=1e-12)
    assert document["energy_per_actuator_J"]["track"] > 0.0
    assert main(["--robot", "ur5_track", "--path", str(SEAM), "--at-json", str(first), "--which", "at",
                 "--json", str(second)]) == 0
    assert json.loads(second.read_text())["at"]["energy_J"] == document["energy_J"]


@pytest.mark.slow
def test_the_long_seam_needs_the_track(tmp_path, capsys):
    """On its track the UR5 welds the 1.5 m seam, the carriage moving along it; held at the rail's middle, no placement
    on the table reaches it."""
    out = tmp_path / "seam.json"
    assert main(["--robot", "ur5_track", "--path", str(SEAM), "--minimize", "--json", str(out)]) == 0
    best = json.loads(out.read_text())["best"]
    assert best["feasible"] and best["recheck_holds"]
    assert np.ptp(best["profiles"]["track"]["position_m"]) > 1.0
    capsys.readouterr()
    assert main(["--robot", "ur5_track", "--path", str(SEAM), "--minimize", "--lock", "track=0"]) == 2
    assert "leaves the robot's reach at every placement" in capsys.readouterr().err


def test_the_ur5s_meshes_are_found_in_example_robot_data(track):
    """The URDF names the UR5's meshes package://example-robot-data/...: found without any --package-path."""
    geometry = description_geometry(track, pin.GeometryType.VISUAL)
    paths = {Path(item.meshPath).name for item in geometry.geometryObjects}
    assert {"base.dae", "shoulder.dae", "wrist3.dae"} <= paths
