"""Load a robot by name or file: built-in robots, sidecars and Gepetto folders, checked whole.

``load_robot("orthoglide")`` loads a built-in robot; ``load_robot("path/to/robot.yaml")`` loads
any sidecar, and a Gepetto ``robot.yaml`` (its folder too) with its estimates. Loading builds the
robot (:func:`placement.robot.build.build_robot`: every name against the URDF, the physical sense
of every number, the loops closed, the mobility), checks its kinematics
(:func:`placement.kinematics.validation.check_kinematics`) and mounts its tool. Errors name the
file and the field.
"""

from __future__ import annotations

import warnings
from pathlib import Path

from placement.exceptions import PlacementError
from placement.files import staged
from placement.kinematics.validation import check_kinematics
from placement.robot.build import build_robot
from placement.robot.exceptions import AssemblyError
from placement.robot.formats import DescriptionOptions, is_gepetto
from placement.robot.model import Robot
from placement.robot.plausibility import MasslessWarning
from placement.robot.sidecar import Redundancy, Sidecar, read_sidecar
from placement.robot.tool import mount_tool
from placement.workshop.catalog import sidecar_path
from placement.workshop.gepetto import read_gepetto


def load_robot(name_or_path: str | Path, *, allow_massless: bool = False,
               options: DescriptionOptions = DescriptionOptions()) -> Robot:
    """Load a built-in robot by name, or any robot from its sidecar YAML file.

    Args:
        name_or_path: A robot name (see :func:`placement.workshop.catalog.robot_names`) or a sidecar path.
        allow_massless: Load a robot whose moving links lack inertia (a URDF without ``<inertial>``), or whose
            actuated joints have neither a drive nor a URDF effort limit, with a
            :class:`placement.robot.plausibility.MasslessWarning`: its energies leave out the missing inertia
            (``Robot.massless_links`` names the links). Without, such a robot is refused.
        options: Package folders and xacro arguments beyond the sidecar's (``--package-path``, ``--robot-arg``).

    Returns:
        The validated robot.

    Raises:
        UnknownRobotError: Neither a built-in name nor an existing file.
        RobotFileError: The sidecar or its URDF is wrong, or its physics implausible (the message names file and
            field; :mod:`placement.robot.plausibility`).
    """
    return _load_robot(name_or_path, allow_massless=allow_massless, options=options)


def _load_robot(name_or_path: str | Path, *, check_closures: bool = True, allow_massless: bool = False,
                options: DescriptionOptions = DescriptionOptions()) -> Robot:
    """:func:`load_robot`; ``check_closures=False`` accepts loops open at the reference configuration.

    Without the closure check, the checks that need the loops closed (mobility, plug-in agreement)
    are skipped too, and the physics is not checked: the robot is only fit for
    :mod:`placement.workshop.assemble` to close its loops.
    """
    path = sidecar_path(name_or_path)
    sidecar = read_gepetto(path) if is_gepetto(path) else read_sidecar(path)
    return robot_from_sidecar(path, sidecar, check_closures=check_closures, allow_massless=allow_massless,
                              options=options)


def write_if_it_loads(path: Path, text: str) -> Robot:
    """Write the sidecar ``text`` to ``path`` only if it loads, every check passing (loops closed).

    The text goes to a temporary file beside ``path``, so that its URDF and plug-in resolve as they
    will from ``path``; it is loaded from there and only then renamed to ``path``. A sidecar that
    does not load leaves ``path`` as it was (or absent). Moving links without inertia do not stop it (as
    ``allow_massless``, without its warning): the file written is where their inertials go (its ``links``);
    the robot returned names them (``massless_links``).

    Args:
        path: The sidecar file to write.
        text: Its new content (UTF-8 YAML).

    Returns:
        The robot loaded from the new file.

    Raises:
        AssemblyError: The text does not load; the message names ``path`` and the loading error.
    """
    with staged(path, text) as temporary:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", MasslessWarning)
                robot = load_robot(temporary, allow_massless=True)
        except PlacementError as error:
            said = str(error).replace(str(temporary), str(path))
            raise AssemblyError(f"{path} not written: it would not load: {said}") from None
    robot.sidecar_path = path
    return robot


def robot_from_sidecar(path: Path, sidecar: Sidecar, *, check_closures: bool = True,
                       allow_massless: bool = False, options: DescriptionOptions = DescriptionOptions()) -> Robot:
    """A robot from a validated sidecar held in memory (one generated from a URDF, say), checked and with its tool.

    Args:
        path: Where the sidecar stands: its folder resolves a relative URDF, and errors name it.
        sidecar: The sidecar.
        check_closures: As for :func:`_load_robot`.
        allow_massless: As for :func:`load_robot`.
        options: As for :func:`load_robot`.

    Raises:
        RobotFileError: The sidecar disagrees with its URDF, or the physics is implausible (the message names
            ``path`` and field).
    """
    robot = build_robot(path, sidecar, check_closures=check_closures, allow_massless=allow_massless, options=options)
    check_kinematics(robot, plugin=check_closures)
    return robot if sidecar.tool is None else mount_tool(robot, sidecar.tool)


def edit_redundancy(robot: Robot, locks: dict[str, float], knots: int | None = None, *, spin: bool = False,
                    allow_massless: bool = False, options: DescriptionOptions = DescriptionOptions()) -> Robot:
    """``robot`` with more joints held fixed (``--lock JOINT=VALUE``) and its redundant joints' profiles given
    ``knots`` knots (``--knots``), its tool's spin a placement variable with ``spin``. A locked joint leaves the
    model, the actuators, the reference configuration and the redundant joints, exactly as if the sidecar had
    listed it under ``locked_joints``.

    Args:
        robot: A robot loaded from its sidecar (without a cell).
        locks: {joint: value (m or rad)}: movable joints of ``robot``.
        knots: Knots of each redundant joint's profile (default: the sidecar's).
        spin: Make the tool's spin about its axis a placement variable (else as the sidecar says).
        allow_massless: As for :func:`load_robot`.
        options: As for :func:`load_robot`.

    Raises:
        RobotFileError: A value outside the joint's limits, or a robot the path no longer determines (the message
            names the sidecar's field).
    """
    sidecar = robot.edited_sidecar()
    redundant = [name for name in robot.redundant_joints if name not in locks]
    spin = spin or robot.tool_spin
    update = {"joints": redundant, "spin": spin, **({} if knots is None else {"knots": knots})}
    redundancy = None if not (redundant or spin) else (sidecar.redundancy or Redundancy(spin=True)).model_copy(
        update=update)
    sources = {key: text for key, text in sidecar.sources.items()
               if redundancy is not None or key.split(".")[0] != "redundancy"}
    edited = robot.edited_sidecar(
        locked_joints={**robot.locked_joints, **locks},
        actuators=[actuator for actuator in sidecar.actuators if actuator.joint not in locks],
        reference_configuration={name: value for name, value in robot.reference_configuration.items()
                                 if name not in locks},
        redundancy=redundancy, sources=sources)
    return robot_from_sidecar(robot.sidecar_path, edited, allow_massless=allow_massless, options=options)
