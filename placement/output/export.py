"""A placement written as the work frame a controller takes: G-code, ABB, KUKA, Universal Robots, Fanuc.

Every format writes one rigid transform, the path frame F_p in the robot's base frame F_b (the
paper's bTp: origin [x, y, z], rotation R = Rz(phi)·Ry(theta)·Rx(psi), see
:mod:`placement.placing.transform`; for a planar robot composed with its plane's frame, which the
result file records). Only the numbers' units and the rotation's parametrisation differ:

=========  ===========================================  =====================================================
format     what is written                              units and rotation convention
=========  ===========================================  =====================================================
gcode      ``G10 L2 P1 X Y Z`` (G54) and ``G68 R``       mm; R = turn about the machine's Z (deg, counter-
                                                        clockwise seen from +Z); no tilt (theta = psi = 0)
abb        RAPID ``wobjdata`` user frame                 mm; quaternion [q1, q2, q3, q4] = [w, x, y, z], q1 ≥ 0
kuka       KRL ``BASE_DATA[n] = {X, Y, Z, A, B, C}``     mm; deg, A about Z, B about Y', C about X''
                                                        (intrinsic Z-Y'-X'': R = Rz(A)·Ry(B)·Rx(C))
ur         URScript pose ``p[x, y, z, rx, ry, rz]``      m; rotation vector axis·angle (rad), angle in [0, π]
fanuc      user frame ``X Y Z W P R``                    mm; deg, W about fixed X, then P about fixed Y, then
                                                        R about fixed Z: R = Rz(R)·Ry(P)·Rx(W)
=========  ===========================================  =====================================================

The frame the numbers are read in is F_b, the robot model's base frame (the root of its URDF).
A controller reads a work frame in its own reference frame: machine coordinates for G54, the
world frame for ABB's ``uframe``, KUKA's BASE and Fanuc's user frame, the base frame for UR.
Where that frame is not F_b (a robot mounted elsewhere in the world, a UR's controller base
turned by 180° about Z from the ``base_link`` of ur_description, a machine whose zero is not the
URDF root), the user composes the controller's frame of F_b with this transform before entering
it; every file says so in a comment.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from placement.output.exceptions import ExportError, ResultFileError
from placement.placing.transform import VARIABLES, rotation_zyx

WHICH = ("best", "worst", "at")
ZERO_TURN = 1e-12  # rad: below this a tilt or a G68 turn is written as none


@dataclass(frozen=True)
class WorkFrame:
    """The path frame F_p in the robot's base frame F_b, and where it comes from.

    Attributes:
        rotation: (3, 3) the axes of F_p in F_b.
        origin_m: (3,) the origin of F_p in F_b (m).
        robot: The robot's name in the result file.
        path: The path's name in the result file.
        which: Which placement of the file ("best", "worst" or "at").
        placement: The placement vector [x, y, z, phi, theta, psi] (m, rad), in the plane's frame for a planar robot.
    """

    rotation: np.ndarray
    origin_m: np.ndarray
    robot: str
    path: str
    which: str
    placement: np.ndarray

    @property
    def matrix(self) -> np.ndarray:
        """The 4x4 homogeneous transform bTp (m)."""
        out = np.eye(4)
        out[:3, :3], out[:3, 3] = self.rotation, self.origin_m
        return out


def read_work_frame(file: str | Path, which: str = "best") -> WorkFrame:
    """The work frame of one placement of a result file written by ``--json``.

    Args:
        file: The JSON file.
        which: "best", "worst" or "at" (the ``--at`` placement).

    Raises:
        ResultFileError: The file is missing, not JSON, holds several paths, or lacks the placement.
    """
    try:
        document = json.loads(Path(file).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as error:
        raise ResultFileError(file, "", f"cannot be read ({getattr(error, 'strerror', None) or error})") from None
    except json.JSONDecodeError as error:
        raise ResultFileError(file, "", f"is not JSON (line {error.lineno}: {error.msg})") from None
    if not isinstance(document, dict):
        raise ResultFileError(file, "", "expected a JSON object as --json writes it")
    if "paths" in document:
        raise ResultFileError(file, "paths", f"holds {len(document['paths'])} paths; export reads a file of one path "
                              "(run the main job with a single --path)")
    if document.get("workpiece_frame") is not None:
        raise ExportError(f"{file}: the placement is in the frame '{document['workpiece_frame']}' of the robot's "
                          "positioner, which moves along the path: a controller takes it as a work object carried by "
                          "the positioner (coordinated motion), not as a fixed work frame, which is all export writes")
    entry = document.get(which)
    if not isinstance(entry, dict) or not isinstance(entry.get("placement"), dict):
        present = [key for key in WHICH if isinstance(document.get(key), dict)]
        raise ResultFileError(file, f"{which}.placement", "missing; the file's placements: "
                              f"{', '.join(present) or 'none'} (give one with --which)")
    values = entry["placement"]
    try:
        placement = np.array([float(values[name]) for name in VARIABLES])
    except (KeyError, TypeError, ValueError):
        raise ResultFileError(file, f"{which}.placement", f"expected numbers {', '.join(VARIABLES)}") from None
    if not np.all(np.isfinite(placement)):
        raise ResultFileError(file, f"{which}.placement", "expected finite numbers")
    rotation, origin = rotation_zyx(*placement[3:]), placement[:3]
    plane = document.get("plane")
    if plane is not None:  # the placement is read in the plane's frame (placement.placing.transform)
        try:
            turn = np.column_stack([plane["x_axis"], plane["y_axis"], plane["normal"]]).astype(float)
            point = np.asarray(plane["point_m"], dtype=float).reshape(3)
        except (KeyError, TypeError, ValueError):
            raise ResultFileError(file, "plane", "expected x_axis, y_axis, normal and point_m, 3 numbers each") from None
        rotation, origin = turn @ rotation, point + turn @ origin
    return WorkFrame(rotation, origin, str(document.get("robot", "")), str(document.get("path", "")), which, placement)


def _header(frame: WorkFrame, comment: str, reference: str) -> list[str]:
    """The comment lines every export starts with: what the numbers are and in which frame to read them."""
    lines = [f"placement {frame.which} of '{frame.path}' on robot '{frame.robot}' (placement --json, SI in the file)",
             "the numbers below: the path frame F_p (the path file's coordinates) in the robot's base frame F_b",
             "(the paper's F_b, the root of the robot's URDF), not the flange nor the tool",
             f"the controller reads them in its {reference};",
             "if that frame is not F_b, compose its pose of F_b with these numbers before entering them"]
    return [f"{comment} {line}" for line in lines]


def to_gcode(frame: WorkFrame) -> str:
    """G54 work offset (``G10 L2 P1``, mm) and a rotation about Z (``G68``, deg) for a CNC controller.

    ``G21 G90 G10 L2 P1 X Y Z`` sets the G54 origin in machine coordinates, absolute, in mm (LinuxCNC, Fanuc, Haas);
    ``G68 X0 Y0 R`` (Fanuc, Haas; LinuxCNC has no G68) then turns programmed coordinates by R
    degrees counter-clockwise seen from +Z about the G54 origin, so a programmed point p lands at
    offset + Rz(R)·p. A G54 offset with G68 holds no tilt: a placement with theta or psi is refused.

    Raises:
        ExportError: The placement tilts the path frame (its Z is not the machine's Z).
    """
    rotation = frame.rotation
    if np.hypot(rotation[0, 2], rotation[1, 2]) > ZERO_TURN:
        raise ExportError(f"--to gcode: the {frame.which} placement tilts the path (theta or psi is not 0): a G54 "
                          "offset with G68 holds only a turn about Z; export to a robot format instead")
    turn = np.degrees(np.arctan2(rotation[1, 0], rotation[0, 0]))
    x, y, z = frame.origin_m * 1e3
    lines = _header(frame, ";", "machine coordinates (G53)")
    lines += ["; G54 origin at X Y Z (mm, machine coordinates), G90: absolute (under G91 a Fanuc control adds them",
              "; to the offset already there); G68 turns the program about the G54 origin by R degrees,",
              "; counter-clockwise seen from +Z (G17 plane); G69 cancels it. LinuxCNC has no G68: there, give",
              "; the turn as R on the G10 L2 line instead (check the sign of a turn on the machine first)",
              f"G21 G90 G10 L2 P1 X{x:.6f} Y{y:.6f} Z{z:.6f}", "G54 G17"]
    if abs(np.radians(turn)) > ZERO_TURN:
        lines.append(f"G68 X0 Y0 R{turn:.8f}")
    return "\n".join(lines) + "\n"


def quaternion_wxyz(rotation: np.ndarray) -> np.ndarray:
    """Unit quaternion [w, x, y, z] of a rotation matrix, w ≥ 0 (Shepperd's method, exact for every turn)."""
    m = rotation
    trace = np.trace(m)
    candidates = np.array([trace, m[0, 0], m[1, 1], m[2, 2]])
    k = int(np.argmax(candidates))
    if k == 0:
        w = np.sqrt(1 + trace) / 2
        q = np.array([w, (m[2, 1] - m[1, 2]) / (4 * w), (m[0, 2] - m[2, 0]) / (4 * w), (m[1, 0] - m[0, 1]) / (4 * w)])
    else:
        i, j, n = k - 1, k % 3, (k + 1) % 3
        v = np.zeros(3)
        v[i] = np.sqrt(1 + 2 * m[i, i] - trace) / 2
        v[j] = (m[j, i] + m[i, j]) / (4 * v[i])
        v[n] = (m[n, i] + m[i, n]) / (4 * v[i])
        q = np.array([(m[n, j] - m[j, n]) / (4 * v[i]), *v])
    q /= np.linalg.norm(q)
    return q if q[0] >= 0 else -q


def zyx_angles(rotation: np.ndarray) -> np.ndarray:
    """[a, b, c] (rad) with rotation = Rz(a)·Ry(b)·Rx(c), b in [−π/2, π/2] (at b = ±π/2, c = 0)."""
    cosine = np.hypot(rotation[0, 0], rotation[1, 0])
    b = np.arctan2(-rotation[2, 0], cosine)  # not arcsin: exact near ±π/2 too
    if cosine < 1e-12:  # gimbal lock: only a ∓ c is defined
        return np.array([np.arctan2(-rotation[0, 1], rotation[1, 1]), b, 0.0])
    return np.array([np.arctan2(rotation[1, 0], rotation[0, 0]), b, np.arctan2(rotation[2, 1], rotation[2, 2])])


def to_abb(frame: WorkFrame) -> str:
    """ABB RAPID ``wobjdata`` whose user frame is the placement: [x, y, z] mm, quaternion [q1..q4] = [w, x, y, z].

    The object frame is the identity, ``robhold`` FALSE and ``ufprog`` TRUE (a fixed user frame).
    """
    x, y, z = frame.origin_m * 1e3
    q = quaternion_wxyz(frame.rotation)
    lines = _header(frame, "!", "world coordinate system (wobjdata.uframe; world = base unless the robot is moved)")
    lines += ["! uframe: [[x, y, z] mm, [q1, q2, q3, q4] = quaternion [w, x, y, z]]; oframe: identity",
              f"PERS wobjdata wobj_placement := [FALSE, TRUE, \"\", [[{x:.6f}, {y:.6f}, {z:.6f}], "
              f"[{q[0]:.10f}, {q[1]:.10f}, {q[2]:.10f}, {q[3]:.10f}]], [[0, 0, 0], [1, 0, 0, 0]]];"]
    return "\n".join(lines) + "\n"


def to_kuka(frame: WorkFrame) -> str:
    """KUKA KRL ``BASE_DATA[1]``: X, Y, Z mm; A, B, C deg, intrinsic Z-Y'-X'' (R = Rz(A)·Ry(B)·Rx(C))."""
    x, y, z = frame.origin_m * 1e3
    a, b, c = np.degrees(zyx_angles(frame.rotation))
    lines = _header(frame, ";", "WORLD frame (BASE_DATA; WORLD = ROBROOT unless the robot is mounted elsewhere)")
    lines += ["; X, Y, Z mm; A about Z, then B about the new Y', then C about the new X'' (deg)",
              f"BASE_DATA[1]={{X {x:.6f},Y {y:.6f},Z {z:.6f},A {a:.8f},B {b:.8f},C {c:.8f}}}"]
    return "\n".join(lines) + "\n"


def rotation_vector(rotation: np.ndarray) -> np.ndarray:
    """Rotation vector axis·angle (rad) of a rotation matrix, angle in [0, π] (from its quaternion)."""
    q = quaternion_wxyz(rotation)
    sine = np.linalg.norm(q[1:])
    if sine < 1e-15:
        return np.zeros(3)
    return q[1:] / sine * 2 * np.arctan2(sine, q[0])


def to_ur(frame: WorkFrame) -> str:
    """Universal Robots URScript pose ``p[x, y, z, rx, ry, rz]``: m, rotation vector axis·angle (rad)."""
    x, y, z = frame.origin_m
    rx, ry, rz = rotation_vector(frame.rotation)
    lines = _header(frame, "#", "Base frame (as a feature or plane pose)")
    lines += ["# a URDF from ur_description (the built-in ur5): F_b is its base_link, turned 180 deg about Z from the",
              "# controller's Base (the URDF's 'base' frame); in Base this pose is p[-x, -y, z, -rx, -ry, rz]",
              "# p[x, y, z, rx, ry, rz]: m, and the rotation vector (axis times angle, rad)",
              f"placement_frame = p[{x:.9f}, {y:.9f}, {z:.9f}, {rx:.10f}, {ry:.10f}, {rz:.10f}]"]
    return "\n".join(lines) + "\n"


def to_fanuc(frame: WorkFrame) -> str:
    """Fanuc user frame X, Y, Z mm; W, P, R deg about the fixed X, Y, Z axes in that order (R = Rz(R)·Ry(P)·Rx(W))."""
    x, y, z = frame.origin_m * 1e3
    r, p, w = np.degrees(zyx_angles(frame.rotation))
    lines = _header(frame, "!", "world frame (user frames are taught in World; World = the robot's own unless moved)")
    lines += ["! X, Y, Z mm; W about the fixed X, then P about the fixed Y, then R about the fixed Z (deg)",
              "! enter them under SETUP > Frames > User Frame > Direct Entry (or in PR[1], then UFRAME[1]=PR[1])",
              f"! USER FRAME 1: X {x:.6f} Y {y:.6f} Z {z:.6f} W {w:.8f} P {p:.8f} R {r:.8f}"]
    return "\n".join(lines) + "\n"


FORMATS: dict[str, Callable[[WorkFrame], str]] = {"gcode": to_gcode, "abb": to_abb, "kuka": to_kuka, "ur": to_ur,
                                                  "fanuc": to_fanuc}
