"""Robots in Gepetto's example-parallel-robots format: a folder with ``robot.urdf`` and ``robot.yaml``.

The format (https://github.com/Gepetto/example-parallel-robots, ``loader_tools.py``) cuts every
loop of the URDF once and names the cut in ``robot.yaml``, whose fields are all lists written by
Python's ``str()``, so also valid YAML::

    closed_loop: [['closedloop1_A', 'closedloop1_B']]   # pairs of URDF frames (links or joints)
    type: ['3d']                                       # per pair: 3d/3D (a point) or 6d/6D (a weld)
    name_mot: ['mot1', 'mot2']                         # the actuated joints
    joint_name: ['free_joint']                         # optional: URDF joints the loader replaces ...
    joint_type: ['FIXED']                              # ... by SPHERICAL, CARDAN or FIXED

Here a pair of ``type`` 3d becomes a ``point`` closure and 6d a ``weld``; ``name_mot`` lists the
actuators; a FIXED joint becomes a locked joint at 0. SPHERICAL and CARDAN joints have several
coordinates, which placement does not model: such a file is an error naming the entry. One key
is ours, optional: ``end_effector: FRAME``, the URDF frame that follows the path.

The format says nothing of the drives, the end effector, gravity or the workspace, so loading
fills them with stated estimates, listed in one :class:`EstimatesWarning` and marked ``EST``
under the sidecar's ``sources``:

- end effector: ``end_effector`` if given, else the first URDF link whose name contains
  ``effector``, else the first frame of the first ``closed_loop`` pair (where a loop's arms meet);
  a position task.
- gravity: 9.81 m/s² along the base's -z.
- drives, one per actuated joint, from the URDF's ``effort`` E and ``velocity`` V limits: a
  3-phase PMSM of rated speed ω_m = 314.16 rad/s (3000 rpm) through a gear of ratio
  N = max(1, ω_m / V) (revolute joint) or a ball screw of lead 2π·V/ω_m (prismatic joint), so that
  its rated speed gives V; peak torque τ = E / N (or E·lead/2π); peak current 10 A, so
  K_t = τ / 10 A and K_e = K_t / 3; resistance R such that the copper loss at peak torque,
  3·R·(10 A)², equals the peak power τ·ω_m; inductance L = R × 1 ms; rotor inertia τ × 10 ms / ω_m
  (it reaches ω_m in 10 ms at peak torque); no friction.
- actuated joint range: [-π, π] rad for a revolute joint whose URDF gives no limits.
- reference configuration: every joint at 0, the exported pose, whose loops are usually open:
  loading then says to run ``placement assemble``.

``placement assemble FOLDER --write`` closes the loops and writes everything, with the closed
``reference_configuration``, the joints it locks (freedoms no actuator drives, such as two coaxial
pins a weld closure leaves spinning), an estimated workspace and, for a planar mechanism, its
plane, to ``placement.yaml`` beside ``robot.yaml``: an
ordinary sidecar, loaded instead of ``robot.yaml`` from then on (for the folder or its
``robot.yaml``), where the estimates can be replaced. Deleting it goes back to ``robot.yaml``.

The estimated workspace is a box the path search can trust, found from what the actuators reach
(:mod:`placement.workshop.reach`): the actuators' ranges are sampled on a grid (at most 2 500
nodes) flooded from the closed pose by continuation, the passive joints solved at each node,
stopping at singularities (condition number 1e3 of the closure or task Jacobian, or a sign change
of the task map's determinant) and where the passive joints would jump to another branch; the
box, along the directions the end effector moves in, is the largest inside the positions reached
(the images of the grid's simplices), and the numeric solver must reach every point of a grid
over it from the closed pose, with the actuators in range (else the box is chosen again without
the points it missed). Across those directions it is ±1 mm around the end effector. A mechanism
with more actuators than such directions, or moving in a plane so tilted that as many of the base's
axes do not span it, gets the former estimate instead: a box around the end effector of half-side
20 % of its distance from the base, shrunk to the part the solver reaches (the source under
``sources`` says which, and why).
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path
from typing import Annotated, Any, Literal
from xml.etree import ElementTree

import numpy as np
import pinocchio as pin
import yaml
from pydantic import Field, ValidationError

from placement.exceptions import PlacementWarning
from placement.kinematics.base import SOLVERS
from placement.kinematics.generic import null_space_basis
from placement.kinematics.trajectories import TaskTrajectory
from placement.placing.transform import plane_frame
from placement.robot.closures import LWA, closure_jacobian
from placement.robot.exceptions import RobotFileError
from placement.robot.formats import SIDECAR_NAME, URDF_NAME, YAML_NAME, is_gepetto
from placement.robot.model import Robot
from placement.robot.sidecar import Plane, Sidecar
from placement.schema import Strict, read_yaml
from placement.workshop.reach import ReachedBox, reached_box

MOTOR_SPEED_RAD_S = 314.16  # rated speed of the estimated motors (3000 rpm)
PEAK_CURRENT_A = 10.0
PHASES = 3
ELECTRICAL_TIME_S = 1e-3  # L / R
ACCELERATION_TIME_S = 0.01  # time the rotor alone takes to reach its rated speed at peak torque
GRAVITY_M_S2 = (0.0, 0.0, -9.81)
WORKSPACE_FRACTION = 0.2  # half-side of the workspace box per m of base to end-effector distance
FLAT_HALF_SIDE_M = 0.001  # half-side across the directions the end effector cannot move in
REACH_GRID = 9  # points per side of the grid whose reachable part bounds the estimated workspace
JOINT_TYPES = ("revolute", "continuous", "prismatic")


class EstimatesWarning(PlacementWarning):
    """A robot loads with quantities its files do not give, estimated as stated in the message."""


class StaleSidecarWarning(PlacementWarning):
    """A ``placement.yaml`` is loaded although the ``robot.yaml`` it was written from changed since."""


class GepettoFile(Strict):
    """``robot.yaml`` of Gepetto's example-parallel-robots (see the module's docstring)."""

    closed_loop: list[tuple[str, str]] = []
    type: list[Literal["3d", "3D", "6d", "6D"]] = []
    name_mot: Annotated[list[str], Field(min_length=1)]
    joint_name: list[str] = []
    joint_type: list[str] = []
    end_effector: str | None = None


class _Urdf:
    """The names and limits of a URDF, read without building a model."""

    def __init__(self, path: Path) -> None:
        try:
            root = ElementTree.parse(path).getroot()
        except (ElementTree.ParseError, UnicodeDecodeError, OSError) as error:
            raise RobotFileError(path, "", f"not a readable XML file: {str(error)[:200]}") from None
        self.path = path
        self.name = root.get("name", "")
        self.links = [link.get("name", "") for link in root.findall("link")]
        self.joints = {joint.get("name", ""): joint for joint in root.findall("joint")}

    def has_frame(self, name: str) -> bool:
        return name in self.links or name in self.joints

    def limit(self, joint: str, attribute: str) -> float | None:
        """A ``<limit>`` attribute of ``joint`` (m, rad, N, N m, m/s or rad/s), None when absent."""
        element = self.joints[joint].find("limit")
        text = element.get(attribute) if element is not None else None
        try:
            return float(text) if text is not None else None
        except ValueError:
            raise RobotFileError(self.path, f"joint '{joint}' limit {attribute}", f"not a number: '{text}'"[:80]) from None


def folder_sidecar(path: Path) -> Path | None:
    """The file a robot path loads from, or None when ``path`` names no file or robot folder.

    A folder loads from its ``placement.yaml``, else the sidecar named after it (``FOLDER/FOLDER.yaml``, as the
    built-in robots and ``calibrate --out`` lay them out), else its ``robot.yaml``; a Gepetto ``robot.yaml``
    with a ``placement.yaml`` beside it loads from that ``placement.yaml``; any other file is itself.
    A ``placement.yaml`` older than the Gepetto ``robot.yaml`` beside it is loaded all the same,
    with a :class:`StaleSidecarWarning`.

    Raises:
        RobotFileError: A folder holds neither file.
    """
    if path.is_dir():
        for name in (SIDECAR_NAME, f"{path.name}.yaml", YAML_NAME):
            if (path / name).is_file():
                return _warned_if_stale(path / name)
        raise RobotFileError(path, "", f"a robot folder needs a sidecar {SIDECAR_NAME} or {path.name}.yaml, or "
                             f"{YAML_NAME} and {URDF_NAME} "
                             "in Gepetto's example-parallel-robots format")
    if not path.is_file():
        return None
    beside = path.parent / SIDECAR_NAME
    return _warned_if_stale(beside if beside.is_file() and is_gepetto(path) else path)


def _warned_if_stale(sidecar: Path) -> Path:
    """``sidecar``, after a warning when it is a ``placement.yaml`` older than the Gepetto ``robot.yaml`` beside it."""
    source = sidecar.parent / YAML_NAME
    if sidecar.name != SIDECAR_NAME or not is_gepetto(source) or source.stat().st_mtime <= sidecar.stat().st_mtime:
        return sidecar
    text = (f"{sidecar} is older than {source}, which is ignored while {SIDECAR_NAME} exists; delete {SIDECAR_NAME} "
            f"and run 'python -m placement assemble {sidecar.parent} --write' to write it again from {YAML_NAME}, or "
            f"make the same change in {SIDECAR_NAME} (re-running assemble --write on it rewrites its "
            "reference_configuration only)")
    warnings.warn_explicit(text, StaleSidecarWarning, str(sidecar), 0, registry=_SHOWN)
    return sidecar


def sidecar_beside(path: Path) -> Path:
    """Where ``placement assemble --write`` saves the sidecar of the Gepetto ``robot.yaml`` at ``path``."""
    return path.parent / SIDECAR_NAME


def read_gepetto(path: Path) -> Sidecar:
    """The sidecar of a Gepetto ``robot.yaml``, with its estimates; warns once, listing them.

    Raises:
        RobotFileError: ``robot.yaml`` breaks the format, or names what its URDF lacks (the message
            names the file and the field).
    """
    document, estimates = generate(path)
    sidecar = _validated(path, document)
    warnings.warn_explicit(_estimates_text(path, estimates), EstimatesWarning, str(path), 0, registry=_SHOWN)
    return sidecar


_SHOWN: dict[Any, Any] = {}  # the warnings shown: once per robot and process


def generate(path: Path) -> tuple[dict[str, Any], list[str]]:
    """The sidecar document of a Gepetto ``robot.yaml`` (before validation) and its estimates, one line each."""
    spec = read_yaml(path, GepettoFile, RobotFileError)
    urdf_path = path.parent / URDF_NAME
    if not urdf_path.is_file():
        raise RobotFileError(path, "", f"Gepetto's format needs the URDF {URDF_NAME} beside it: {urdf_path} not found")
    urdf = _Urdf(urdf_path)
    document: dict[str, Any] = {
        "name": path.parent.resolve().name[:80] or urdf.name[:80] or "robot",
        "description": "exported in Gepetto's example-parallel-robots format; drives, gravity and workspace estimated",
        "urdf": URDF_NAME,
        "gravity_m_s2": list(GRAVITY_M_S2),
        "closures": _closures(path, spec, urdf),
        "locked_joints": _locked_joints(path, spec, urdf),
        "actuators": [], "drives": {},
        "sources": {"closures": "DERIVED: robot.yaml closed_loop and type",
                    "actuators": "DERIVED: robot.yaml name_mot; speed limits from the URDF",
                    "gravity_m_s2": "EST: the URDF's -z is down"},
    }
    frame, why = _end_effector(path, spec, urdf)
    document["end_effector"] = {"frame": frame, "task": "position"}
    estimates = [f"gravity_m_s2: {list(GRAVITY_M_S2)} (the URDF's -z is down)"]
    if why:
        document["sources"]["end_effector"] = f"EST: {why}"
        estimates.append(f"end_effector: frame '{frame}', position task ({why})")
    for i, joint in enumerate(spec.name_mot):
        estimates.extend(_actuator(path, urdf, i, joint, document))
    if not document["locked_joints"]:
        del document["locked_joints"]
    return document, estimates


def _closures(path: Path, spec: GepettoFile, urdf: _Urdf) -> list[dict[str, Any]]:
    if len(spec.type) != len(spec.closed_loop):
        raise RobotFileError(path, "type", f"expected one type (3d or 6d) per closed_loop pair: {len(spec.closed_loop)} "
                             f"pair(s), {len(spec.type)} type(s)")
    closures = []
    for i, (pair, kind) in enumerate(zip(spec.closed_loop, spec.type)):
        for k, frame in enumerate(pair):
            if not urdf.has_frame(frame):
                raise RobotFileError(path, f"closed_loop.{i}.{k}", f"no frame '{frame[:80]}' in {URDF_NAME} (links and "
                                     "joints are frames)")
        closures.append({"name": f"{pair[0]}-{pair[1]}", "type": "point" if kind in ("3d", "3D") else "weld",
                         "frames": list(pair)})
    return closures


def _locked_joints(path: Path, spec: GepettoFile, urdf: _Urdf) -> dict[str, float]:
    if len(spec.joint_type) != len(spec.joint_name):
        raise RobotFileError(path, "joint_type", f"expected one type per joint_name entry: {len(spec.joint_name)} "
                             f"name(s), {len(spec.joint_type)} type(s)")
    locked = {}
    for i, (name, kind) in enumerate(zip(spec.joint_name, spec.joint_type)):
        if name not in urdf.joints:
            raise RobotFileError(path, f"joint_name.{i}", f"no joint '{name[:80]}' in {URDF_NAME}")
        if kind != "FIXED":
            raise RobotFileError(path, f"joint_type.{i}", f"'{kind[:40]}' for joint '{name[:80]}': placement models "
                                 "one-coordinate joints only, so it takes FIXED here; model a SPHERICAL or CARDAN joint "
                                 f"as three or two revolute joints in {URDF_NAME} and drop its entry")
        locked[name] = 0.0
    return locked


def _end_effector(path: Path, spec: GepettoFile, urdf: _Urdf) -> tuple[str, str]:
    """The end-effector frame, and why it was chosen ("" when robot.yaml names it)."""
    if spec.end_effector is not None:
        if not urdf.has_frame(spec.end_effector):
            raise RobotFileError(path, "end_effector", f"no frame '{spec.end_effector[:80]}' in {URDF_NAME}")
        return spec.end_effector, ""
    named = [link for link in urdf.links if "effector" in link.lower()]
    if named:
        return named[0], "the first link whose name contains 'effector'"
    if spec.closed_loop:
        return spec.closed_loop[0][0], "no link is named *effector*: the first frame of closed_loop 0, where a loop closes"
    raise RobotFileError(path, "end_effector", f"no closed_loop and no link named *effector* in {URDF_NAME}: name the "
                         "frame that follows the path, e.g. end_effector: tool")


def _actuator(path: Path, urdf: _Urdf, i: int, joint: str, document: dict[str, Any]) -> list[str]:
    """Add actuator ``i`` and its estimated drive to ``document``; returns the estimates, one line each."""
    element = urdf.joints.get(joint)
    if element is None or element.get("type") not in JOINT_TYPES:
        what = "no joint" if element is None else f"a {element.get('type')} joint"
        raise RobotFileError(path, f"name_mot.{i}", f"'{joint[:80]}' is {what} in {URDF_NAME}: expected a revolute "
                             "or prismatic joint")
    prismatic = element.get("type") == "prismatic"
    effort, velocity = urdf.limit(joint, "effort"), urdf.limit(joint, "velocity")
    for name, value in (("effort", effort), ("velocity", velocity)):
        if value is None or not math.isfinite(value) or value <= 0:
            raise RobotFileError(urdf.path, f"joint '{joint}' limit {name}", f"must be a number > 0 (got {value}) to "
                                 f"estimate the drive of actuated joint '{joint}' (name_mot.{i} in {YAML_NAME}): "
                                 f"give the joint <limit {name}=\"...\"/> ({'N or N m' if name == 'effort' else 'm/s or rad/s'})")
    assert effort is not None and velocity is not None  # checked above
    actuator: dict[str, Any] = {"joint": joint, "drive": joint}
    estimates = []
    unbounded = element.get("type") == "continuous" or urdf.limit(joint, "lower") is None or urdf.limit(joint, "upper") is None
    if not prismatic and unbounded:  # a continuous joint has no position limits, whatever its <limit> says
        actuator.update(position_min=-math.pi, position_max=math.pi)
        for field in ("position_min", "position_max"):
            document["sources"][f"actuators.{i}.{field}"] = "EST: the URDF gives no limits; a full turn"
        estimates.append(f"actuators.{i} ({joint}): range [-pi, pi] rad (the URDF gives no limits)")
    drive, text = estimated_drive(effort, velocity, prismatic)
    document["actuators"].append(actuator)
    document["drives"][joint] = drive
    document["sources"][f"drives.{joint}"] = f"EST: {text}"
    return [*estimates, f"drives.{joint}: {text}"]


def estimated_drive(effort: float, velocity: float, prismatic: bool, origin: str = "the URDF's") -> tuple[dict[str, Any], str]:
    """A drive for a joint of URDF limits ``effort`` (N or N m) and ``velocity`` (m/s or rad/s); ``origin`` says
    where they come from in the line returned.

    Returns:
        The sidecar's drive mapping (see the module's docstring for the rule) and one line saying it.
    """
    if prismatic:
        lead = _rounded(2 * math.pi * velocity / MOTOR_SPEED_RAD_S)
        transmission: dict[str, Any] = {"type": "ball_screw", "lead_m": lead, "efficiency": 1.0}
        torque, said = effort * lead / (2 * math.pi), f"ball screw of lead {lead * 1e3:.4g} mm"
        limits = f"effort {effort:g} N and velocity {velocity:g} m/s"
    else:
        ratio = max(1.0, _rounded(MOTOR_SPEED_RAD_S / velocity))
        transmission = {"type": "gear", "ratio": ratio, "efficiency": 1.0}
        torque, said = effort / ratio, f"gear {ratio:.4g}:1"
        limits = f"effort {effort:g} N m and velocity {velocity:g} rad/s"
    resistance = torque * MOTOR_SPEED_RAD_S / (PHASES * PEAK_CURRENT_A**2)
    k_t = _rounded(torque / PEAK_CURRENT_A)
    motor = {"model": "pmsm", "torque_constant_Nm_per_A": k_t, "back_emf_constant_V_s_per_rad": _rounded(k_t / PHASES),
             "resistance_ohm": _rounded(resistance), "inductance_H": _rounded(resistance * ELECTRICAL_TIME_S),
             "phases": PHASES, "rotor_inertia_kg_m2": _rounded(torque * ACCELERATION_TIME_S / MOTOR_SPEED_RAD_S),
             "max_torque_Nm": _rounded(torque), "max_speed_rad_s": MOTOR_SPEED_RAD_S}
    text = (f"{said}, 3-phase motor of {motor['max_torque_Nm']:g} N m peak at {MOTOR_SPEED_RAD_S:g} rad/s, "
            f"K_t {k_t:g} N m/A, R {motor['resistance_ohm']:g} ohm, L {motor['inductance_H']:g} H, rotor "
            f"{motor['rotor_inertia_kg_m2']:g} kg m^2 (from {origin} {limits})")
    return {"transmission": transmission, "motor": motor}, text


def _rounded(value: float) -> float:
    """An estimate to 4 significant digits: as precise as it is."""
    return float(f"{value:.4g}")


def _validated(path: Path, document: dict[str, Any]) -> Sidecar:
    try:
        return Sidecar.model_validate(document)
    except ValidationError as problem:
        first = problem.errors()[0]
        raise RobotFileError(path, ".".join(map(str, first["loc"])), f"the estimate from {URDF_NAME} is invalid: "
                             f"{first['msg']}") from None


def _estimates_text(path: Path, estimates: list[str]) -> str:
    folder = path.parent
    return (f"{path} is in Gepetto's example-parallel-robots format, which gives no drives, end effector, gravity or "
            f"workspace; these {len(estimates)} quantities are estimates:\n"
            + "".join(f"  - {line}\n" for line in estimates)
            + f"  'python -m placement assemble {folder} --write' closes the loops and writes them, each marked EST "
            f"under sources, with an estimated workspace, to {folder / SIDECAR_NAME}, loaded instead of {YAML_NAME} "
            "from then on: replace them there")


def sidecar_text(path: Path, robot: Robot, reference: dict[str, float], locks: dict[str, float] | None = None,
                 reason: str = "") -> str:
    """The sidecar of the Gepetto ``robot.yaml`` at ``path``, its loops closed at ``reference``, as YAML text
    (:func:`placement.workshop.assemble.write_gepetto_sidecar` writes it beside, if it loads).

    Args:
        path: The ``robot.yaml``.
        robot: The robot loaded from it with the ``locks`` held, at its closed reference configuration.
        reference: The closed configuration {joint: value (m or rad)}, without the ``locks``.
        locks: {joint: value (m or rad)} added to ``locked_joints``, each marked EST under ``sources``.
        reason: Why they are locked.
    """
    document, _ = generate(path)
    document["reference_configuration"] = reference
    document["sources"]["reference_configuration"] = "DERIVED: placement assemble closed the loops"
    if locks:
        document["locked_joints"] = {**document.get("locked_joints", {}), **locks}
        document["sources"].update({f"locked_joints.{name}": f"EST: {reason}" for name in locks})
    document.update(estimated_workspace(robot, document["sources"]))
    order = ("name", "description", "urdf", "gravity_m_s2", "end_effector", "reference_configuration", "locked_joints",
             "closures", "actuators", "drives", "workspace", "placement", "sources")
    fields = {key: document[key] for key in order if key in document and key != "sources"}
    header = (f"# Written by 'placement assemble --write' from {YAML_NAME} (Gepetto's example-parallel-robots format)\n"
              f"# and {URDF_NAME}. Loaded instead of {YAML_NAME} while it exists: replace the estimates (EST under\n"
              "# sources) with your machine's numbers.\n")
    body = yaml.safe_dump(fields, sort_keys=False, default_flow_style=None, width=120)
    return header + body + yaml.safe_dump({"sources": document["sources"]}, sort_keys=False, width=10_000)


def estimated_workspace(robot: Robot, sources: dict[str, str]) -> dict[str, Any]:
    """The estimated ``workspace``, and ``placement`` for a mechanism moving in a plane: ``free: [x, y, phi]``
    in a horizontal plane, else the plane (its normal is the direction the end effector cannot move in).

    Along the directions the end effector moves in at ``robot.reference_q`` (its loops closed), the box
    is the largest inside what the actuators reach within their ranges, checked by the numeric
    solver (:func:`placement.workshop.reach.reached_box`), when there are as many actuators as such
    directions and these lie along the base's axes; across them, ``FLAT_HALF_SIDE_M`` either side of
    the end effector. Otherwise (a redundant mechanism, or one moving in a plane at about 45° to the
    base's axes) the box is
    the former estimate: a box around the end effector of half-side ``WORKSPACE_FRACTION`` of its
    distance from the base along those directions, shrunk to the bounding box of the points of a
    ``REACH_GRID``-per-side grid over it (in the plane, for a planar mechanism) that the numeric
    solver reaches from the reference configuration (:func:`_reachable_box`); the source says why.
    """

    model, data, q = robot.model, robot.model.createData(), robot.reference_q
    basis, _, _ = null_space_basis(robot, closure_jacobian(robot, data, q))
    task = pin.getFrameJacobian(model, data, robot.end_effector_frame_id, LWA)[:3] @ basis
    u, singular, _ = np.linalg.svd(task)
    directions = u[:, : int((singular > 1e-9 * max(singular.max(initial=0.0), 1e-300)).sum())]
    weight = (directions**2).sum(axis=1)
    moving = weight >= 0.5 * weight.max(initial=0.0) if weight.max(initial=0.0) > 0 else np.zeros(3, bool)
    center = data.oMf[robot.end_effector_frame_id].translation.copy()
    normal = u[:, 2] if directions.shape[1] == 2 else None
    if directions.shape[1] != len(robot.actuators):
        reached: ReachedBox | str = (f"the rule from the actuators' reach takes as many actuators ({len(robot.actuators)}) "
                                     f"as directions the end effector moves in ({directions.shape[1]})")
    elif int(moving.sum()) != directions.shape[1]:
        reached = "the directions the end effector moves in lie across more of the base's axes than they number"
    else:
        reached = reached_box(robot, directions, np.flatnonzero(moving), center, normal)
    if isinstance(reached, ReachedBox):
        low, high = reached.low_m, reached.high_m
        sources["workspace"] = f"EST: {reached.text}; {FLAT_HALF_SIDE_M * 1e3:g} mm across them"
    else:
        half = max(WORKSPACE_FRACTION * float(np.linalg.norm(center)), 0.01)
        low, high = _reachable_box(robot, center, np.where(moving, half, 0.0), normal)
        if np.any(moving & ~(high > low)):
            _refuse_unreached(robot, directions, center)
        sources["workspace"] = (f"EST: the part the solver reaches (a {REACH_GRID}-per-side grid) of a box around the end "
                                f"effector at reference_configuration, half-side {half:.4g} m (20 % of its distance from "
                                f"the base) along the directions it moves in, {FLAT_HALF_SIDE_M * 1e3:g} mm across them, "
                                f"as {reached}")
    low, high = np.where(moving, low, center - FLAT_HALF_SIDE_M), np.where(moving, high, center + FLAT_HALF_SIDE_M)
    result: dict[str, Any] = {"workspace": {"type": "box", "min_m": _micrometres(low), "max_m": _micrometres(high),
                                            "points_m": {"reference": _micrometres(center)}}}
    if moving.tolist() == [True, True, False]:
        result["placement"] = {"free": ["x", "y", "phi"]}
        fix = f"; give --fix z={center[2] * 1e3:.6g} (mm)" if abs(center[2]) > 1e-9 else ""
        sources["placement"] = f"DERIVED: the end effector moves in the plane z = {center[2]:.6g} m: paths lie in it{fix}"
    elif directions.shape[1] == 2:
        signed, point = _plane_normal(u[:, 2]), _micrometres(center)
        result["placement"] = {"plane": {"normal": signed, "point_m": point}}
        sources["placement"] = (f"DERIVED: the end effector moves in the plane of normal {signed} through {point} m "
                                "(its position at reference_configuration): paths lie in it")
    return result


def _refuse_unreached(robot: Robot, directions: np.ndarray, center: np.ndarray) -> None:
    """Refuse an end effector around which the solver reaches no position but the reference one: a mechanism whose
    actuators turn its tool rather than place it (a spherical parallel mechanism's, its centre or a point near it)."""
    frame = robot.model.frames[robot.end_effector_frame_id].name
    raise RobotFileError(robot.sidecar_path, "end_effector.frame",
                         f"the numeric solver reaches no position of the end effector '{frame}' around "
                         f"{(np.round(center, 6) + 0.0).tolist()} m but that one, at the closed reference configuration: its "
                         f"{len(robot.actuators)} actuator(s) move it in {directions.shape[1]} direction(s) only, as a "
                         "mechanism that turns its tool (a spherical one) rather than places it; a path needs a tool "
                         "point the actuators place: choose another frame (--tool, or end_effector.frame), or write a "
                         "sidecar with a workspace of your own (docs/adding_a_robot.md)")


def _reachable_box(robot: Robot, center: np.ndarray, half: np.ndarray,
                   normal: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """The bounding box (m) of the points of a ``REACH_GRID``-per-side grid over ``center`` ± ``half`` (m, 0 along
    the axes the end effector does not move along), moved onto the plane through ``center`` of ``normal`` when
    given, that the generic solver reaches from the reference configuration (on its branch, not singular)."""

    axes = [np.linspace(c - h, c + h, REACH_GRID) if h > 0 else np.array([c]) for c, h in zip(center, half)]
    points = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    if normal is not None:
        points -= np.outer((points - center) @ normal, normal)
    still = np.zeros_like(points)
    _, reachable, _ = SOLVERS.get("numeric")(robot).solve(TaskTrajectory(points, still, still), len(points))
    reached = np.vstack([center, points[reachable]])
    return reached.min(axis=0), reached.max(axis=0)


def _plane_normal(normal: np.ndarray) -> list[float]:
    """A plane's unit normal, rounded to 6 decimals, signed so that the plane's y axis (see
    :func:`placement.placing.transform.plane_frame`) does not point down (along -Z_b): placements read y upwards."""

    rounded = [round(float(c), 6) + 0.0 for c in normal]
    rotation, _ = plane_frame(Plane.model_validate({"normal": rounded}))
    return rounded if rotation[2, 1] >= -1e-12 else [-c + 0.0 for c in rounded]


def _micrometres(point: np.ndarray) -> list[float]:
    """A point (m) rounded to the micrometre, for a readable file."""
    return [round(float(x), 6) + 0.0 for x in point]
