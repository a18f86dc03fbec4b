"""The export formats: each read back into a transform equals the placement's, and each matches an outside reference.

A round trip alone cannot catch a wrong convention (a writer and a reader wrong the same way agree),
so every format is also checked against scipy's ``Rotation`` built in the order the vendor states:

* KUKA A, B, C: intrinsic Z-Y'-X'' (``from_euler("ZYX", [A, B, C])``), as KUKA's BASE/TOOL numeric
  input defines them (also stated at docs.baslerweb.com/stereovisard/rc_visard/en/pose_format_kuka.html);
* Fanuc W, P, R: rotations about the fixed X, Y, Z axes in that order (``from_euler("xyz", [W, P, R])``);
* ABB quaternion [q1, q2, q3, q4] = [w, x, y, z] (``as_quat(scalar_first=True)``), RAPID's ``orient``;
* UR rotation vector: axis times angle (``as_rotvec()``), URScript's pose ``p[x, y, z, rx, ry, rz]``;
* G-code: ``G10 L2 P1`` sets the G54 origin in machine coordinates (LinuxCNC's G-code reference,
  "G10 L2 Set Coordinate System"), and ``G68 R`` turns counter-clockwise about Z (``from_euler("z", R)``).

The placements are the project's: R = Rz(phi)·Ry(theta)·Rx(psi); scipy builds the same rotation from
``from_euler("ZYX", [phi, theta, psi])``, independently of :func:`placement.placing.transform.rotation_zyx`.
"""

import json
import re

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from placement.__main__ import main
from placement.exceptions import PlacementError
from placement.output.exceptions import ResultFileError
from placement.output.export import FORMATS, read_work_frame, to_gcode
from placement.placing.transform import placement_pose

NUMBER = r"(-?\d+(?:\.\d+)?(?:e-?\d+)?)"
TILTED = [0.1234, -0.2345, 0.3456, np.radians(30.0), np.radians(-20.0), np.radians(65.0)]
FLAT = [-0.0025, 0.0035, -0.033, np.radians(-12.5), 0.0, 0.0]
# Near the gimbal lock (theta near ±90°), a half turn (angle π for the rotation vector, w = 0 for the quaternion)
AWKWARD = [[0.0, 0.0, 0.0, np.radians(10.0), np.radians(90.0 - 1e-7), np.radians(5.0)],
           [0.0, 0.0, 0.0, np.pi, 0.0, 0.0], [0.01, 0.02, 0.03, np.radians(-170.0), np.radians(-60.0),
                                                  np.radians(179.0)]]


def result_file(tmp_path, placement, which="best", plane=None):
    document = {"robot": "test", "path": "test path", which: {"placement": dict(zip(
        ("x", "y", "z", "phi", "theta", "psi"), map(float, placement)))}}
    if plane is not None:
        document["plane"] = plane
    file = tmp_path / "result.json"
    file.write_text(json.dumps(document))
    return file


def numbers(pattern, text):
    match = re.search(pattern, text)
    assert match, f"{pattern} not in\n{text}"
    return np.array([float(v) for v in match.groups()])


def transform(rotation, origin_m):
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = rotation, origin_m
    return out


def read_back(name, text):
    """The 4x4 transform (m) a controller rebuilds from what was written, by the vendor's convention (scipy)."""
    if name == "gcode":
        xyz = numbers(rf"G10 L2 P1 X{NUMBER} Y{NUMBER} Z{NUMBER}", text)
        turn = numbers(rf"G68 X0 Y0 R{NUMBER}", text)[0] if "G68" in text else 0.0
        return transform(Rotation.from_euler("z", turn, degrees=True).as_matrix(), xyz / 1e3)
    if name == "abb":
        values = numbers(r"\[\[" + r",\s*".join([NUMBER] * 3) + r"\],\s*\[" + r",\s*".join([NUMBER] * 4) + r"\]\]", text)
        return transform(Rotation.from_quat(values[3:], scalar_first=True).as_matrix(), values[:3] / 1e3)
    if name == "kuka":
        values = numbers(r"BASE_DATA\[1\]=\{" + ",".join(f"{axis} {NUMBER}" for axis in "XYZABC") + r"\}", text)
        return transform(Rotation.from_euler("ZYX", values[3:], degrees=True).as_matrix(), values[:3] / 1e3)
    if name == "ur":
        values = numbers(r"p\[" + r",\s*".join([NUMBER] * 6) + r"\]", text)
        return transform(Rotation.from_rotvec(values[3:]).as_matrix(), values[:3])
    values = numbers(r"USER FRAME 1: " + " ".join(f"{axis} {NUMBER}" for axis in "XYZWPR"), text)
    return transform(Rotation.from_euler("xyz", values[3:], degrees=True).as_matrix(), values[:3] / 1e3)


@pytest.mark.parametrize("name", sorted(FORMATS))
@pytest.mark.parametrize("placement", [TILTED, FLAT, *AWKWARD])
def test_round_trip_rebuilds_the_placement(tmp_path, name, placement):
    """What each format writes, read by the vendor's convention, is the placement's transform to 1e-9."""
    if name == "gcode" and placement is not FLAT:
        return  # a G54 offset holds no tilt (refused below); a half turn about Z alone is FLAT's case
    frame = read_work_frame(result_file(tmp_path, placement))
    rotation, origin = placement_pose(np.array(placement))
    np.testing.assert_allclose(read_back(name, FORMATS[name](frame)), transform(rotation[0], origin[0]), atol=1e-9)


def test_worked_examples_match_scipy_in_each_vendor_convention(tmp_path):
    """The numbers of a tilted placement are scipy's for the rotation in each vendor's order."""
    frame = read_work_frame(result_file(tmp_path, TILTED))
    reference = Rotation.from_euler("ZYX", TILTED[3:])  # the project's Rz(phi)·Ry(theta)·Rx(psi)
    xyz_mm = np.array(TILTED[:3]) * 1e3
    kuka = numbers(r"\{" + ",".join(f"{axis} {NUMBER}" for axis in "XYZABC") + r"\}", FORMATS["kuka"](frame))
    np.testing.assert_allclose(kuka, [*xyz_mm, *reference.as_euler("ZYX", degrees=True)], atol=1e-6)
    np.testing.assert_allclose(kuka[3:], [30.0, -20.0, 65.0], atol=1e-7)  # A = phi, B = theta, C = psi
    fanuc = numbers(" ".join(f"{axis} {NUMBER}" for axis in "XYZWPR"), FORMATS["fanuc"](frame))
    np.testing.assert_allclose(fanuc, [*xyz_mm, *reference.as_euler("xyz", degrees=True)], atol=1e-6)
    abb = numbers(r",\s*".join([NUMBER] * 4) + r"\]\], \[\[0", FORMATS["abb"](frame))
    np.testing.assert_allclose(abb, reference.as_quat(scalar_first=True, canonical=True), atol=1e-9)
    ur = numbers(r"p\[" + r",\s*".join([NUMBER] * 6) + r"\]", FORMATS["ur"](frame))
    np.testing.assert_allclose(ur, [*TILTED[:3], *reference.as_rotvec()], atol=1e-9)


def test_hand_worked_quarter_turn():
    """A quarter turn about Z, by hand: quaternion [cos 45°, 0, 0, sin 45°], rotation vector [0, 0, π/2],
    A = R = 90°, and G68 R90 sends the programmed point (10, 0) to offset + (0, 10) mm."""
    from placement.output.export import WorkFrame

    frame = WorkFrame(Rotation.from_euler("z", 90, degrees=True).as_matrix(), np.array([0.1, 0.2, 0.0]), "r", "p",
                      "best", np.zeros(6))
    np.testing.assert_allclose(numbers(r",\s*".join([NUMBER] * 4) + r"\]\], \[\[0", FORMATS["abb"](frame)),
                               [np.sqrt(0.5), 0, 0, np.sqrt(0.5)], atol=1e-10)
    np.testing.assert_allclose(numbers(r"p\[" + r",\s*".join([NUMBER] * 6) + r"\]", FORMATS["ur"](frame))[3:],
                               [0, 0, np.pi / 2], atol=1e-10)
    assert numbers(r"A (\S+),", FORMATS["kuka"](frame))[0] == pytest.approx(90.0)
    assert numbers(r" R (\S+)$", FORMATS["fanuc"](frame).strip())[0] == pytest.approx(90.0)
    gcode = FORMATS["gcode"](frame)
    offset = numbers(rf"G10 L2 P1 X{NUMBER} Y{NUMBER} Z{NUMBER}", gcode)
    turn = numbers(rf"R{NUMBER}", gcode.splitlines()[-1])[0]
    programmed = np.array([10.0, 0.0])
    landed = offset[:2] + np.array([[np.cos(np.radians(turn)), -np.sin(np.radians(turn))],
                                    [np.sin(np.radians(turn)), np.cos(np.radians(turn))]]) @ programmed
    np.testing.assert_allclose(landed, [100.0, 210.0], atol=1e-9)


def test_a_planar_robot_placement_is_composed_with_its_plane(tmp_path):
    """A planar robot's placement is read in its plane's frame: the export is the base-frame pose."""
    plane = {"normal": [0.0, 1.0, 0.0], "point_m": [0.1, 0.0, 0.2], "x_axis": [1.0, 0.0, 0.0],
             "y_axis": [0.0, 0.0, -1.0]}
    frame = read_work_frame(result_file(tmp_path, [0.05, 0.02, 0.0, 0.3, 0.0, 0.0], plane=plane))
    # The path point (1, 0, 0) of F_p: turned by 0.3 rad about the normal, from the plane's point
    point = frame.matrix @ np.array([1.0, 0.0, 0.0, 1.0])
    u, v = np.array(plane["x_axis"]), np.array(plane["y_axis"])
    expected = np.array(plane["point_m"]) + 0.05 * u + 0.02 * v + np.cos(0.3) * u + np.sin(0.3) * v
    np.testing.assert_allclose(point[:3], expected, atol=1e-12)


def test_gcode_refuses_a_tilt(tmp_path):
    with pytest.raises(PlacementError, match="tilts the path"):
        to_gcode(read_work_frame(result_file(tmp_path, TILTED)))


def test_result_file_errors_name_the_field(tmp_path):
    with pytest.raises(ResultFileError, match="at.placement"):
        read_work_frame(result_file(tmp_path, FLAT), "at")
    bad = tmp_path / "bad.json"
    bad.write_text("{")
    with pytest.raises(ResultFileError, match="not JSON"):
        read_work_frame(bad)


def test_command_writes_every_format_and_exits_2_on_bad_input(tmp_path, capsys):
    file = result_file(tmp_path, FLAT)
    for name in FORMATS:
        out = tmp_path / f"frame.{name}"
        assert main(["export", str(file), "--to", name, "--out", str(out)]) == 0, capsys.readouterr().err
        assert "base frame F_b" in out.read_text()
    capsys.readouterr()
    assert main(["export", str(file), "--to", "abb", "--which", "worst"]) == 2
    assert "worst.placement" in capsys.readouterr().err
