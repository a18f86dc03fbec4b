"""Implausible physics refused as a robot loads: moving links without inertia, actuated joints nothing bounds, and
link masses out of all proportion.

A URDF exported without inertials (ROS-Industrial's descriptions have none), with ``effort="0"``, or with a mass
in the wrong unit loads into a model whose energies are nonsense: a massless arm takes no energy to move.
:func:`check_plausible` refuses such a robot, naming the links or joints and the field, unless the sidecar gives the
values (``links``: a link's mass, centre of mass and inertia; an actuator's drive), or the caller proceeds
knowingly (``allow_massless``, ``--allow-massless`` on the command line), which a :class:`MasslessWarning` then says.

The rules, on Pinocchio's model (one body per movable joint, each carrying its link and the links fixed to it,
locked joints merged too; every body moves):

- A body is *without inertia* when its mass is below ``MASSLESS_KG`` (1 mg: Gepetto's exports give frame links
  1e-9 kg), or its rotational inertia about its centre of mass is not positive definite (its smallest principal
  moment at most ``FLAT_SHARE`` of its largest; a point mass, say).
- It is still legitimate, a connector whose motion a body with inertia carries, when it is welded by a ``weld``
  closure to the ground or to such a body (a stub cut from a loop: the Orthoglide's and the Delta's platform
  stubs), or when it has no extent (every joint it carries, and every closure frame on it, at its own joint's
  origin, within ``SAME_POINT_M``) and carries such a body (the intermediate bodies of a universal or spherical
  joint made of revolute joints). "Such a body" is one with inertia or a legitimate one, applied until nothing
  changes: a whole moving subtree without mass is never legitimate.
- An actuated joint without a drive needs a URDF effort limit above 0 (with a drive, its motor bounds the effort).
- A moving link heavier than ``ABSURD_LINK_RATIO`` (10 000) times the median mass of the moving bodies that have
  mass is refused unless the sidecar's ``links`` gives it: a mass in the wrong unit (the ``check`` command warns
  of a link 100 times the median link mass). The median is the bodies', which the URDF's massless or dummy frame
  links do not drag down.
"""

from __future__ import annotations

import statistics
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pinocchio as pin

from placement.exceptions import PlacementWarning, listed
from placement.robot.exceptions import RobotFileError
from placement.robot.formats import is_gepetto
from placement.robot.mjcf import is_mjcf
from placement.robot.model import Closure, Robot
from placement.robot.urdf import UrdfContents
from placement.robot.xacro import is_xacro

MASSLESS_KG = 1e-6  # a body lighter than this has no mass (kg)
FLAT_SHARE = 1e-9  # a rotational inertia whose smallest principal moment is at most this share of its largest is flat
SAME_POINT_M = 1e-6  # a connector's joints and closure frames lie this close to its own joint's origin (m)
ABSURD_LINK_RATIO = 10_000.0  # a moving link this many times the median link mass is refused
SIDECAR_SUFFIXES = (".yaml", ".yml")  # a robot loaded from any other file was estimated from its description
NAMED = 8  # names listed in a message, then "and N more"
ALLOW = "--allow-massless (load_robot(..., allow_massless=True))"


class MasslessWarning(PlacementWarning):
    """A robot loads as asked (``allow_massless``) with moving links without inertia or actuated joints without an
    effort bound: its energies leave out the missing inertia."""


def check_plausible(robot: Robot, urdf: UrdfContents, *, allow_massless: bool = False) -> tuple[str, ...]:
    """Refuse a robot whose physics is implausible (rules: the module's docstring).

    Args:
        robot: The robot built from its files, before its tool is mounted.
        urdf: Its URDF's names and link masses (the sidecar's ``links`` in).
        allow_massless: Load anyway a robot with links without inertia or actuated joints without an effort bound,
            saying so in one :class:`MasslessWarning`.

    Returns:
        The links without inertia let through by ``allow_massless`` (the first link of each such body), else ().

    Raises:
        RobotFileError: A moving link without inertia, an actuated joint without an effort bound (both unless
            ``allow_massless``), or a moving link of absurd mass; the message names the sidecar, the field, the links
            or joints, and the ways out.
    """
    _refuse_absurd_masses(robot, urdf)
    lacking = links_without_inertia(robot)
    unbounded = [i for i, actuator in enumerate(robot.actuators)
                 if actuator.drive is None and not robot.model.effortLimit[actuator.v_index] > 0]
    if allow_massless:
        if lacking or unbounded:
            warnings.warn(_allowed_text(robot, lacking, unbounded), MasslessWarning, stacklevel=2)
        return tuple(lacking)
    if lacking:
        raise RobotFileError(robot.sidecar_path, f"urdf.link.{lacking[0]}.inertial", _lacking_text(robot, lacking))
    if unbounded:
        first = robot.actuators[unbounded[0]]
        raise RobotFileError(robot.sidecar_path, f"actuators.{unbounded[0]}.drive",
                             f"actuated joint(s) {_names([robot.actuators[i].joint for i in unbounded])} have no drive "
                             f"and effort limit 0 in {_description(robot)} (<limit effort>): nothing bounds their "
                             f"effort; name a drive for each (its motor's max_torque_Nm bounds it) or give "
                             f"urdf.joint.{first.joint}.limit.effort in the URDF, or pass {ALLOW} to go on knowingly")
    return ()


def massless_note(robot: Robot) -> str | None:
    """What a report says of a robot loaded with moving links without inertia (``allow_massless``), else None."""
    if not robot.massless_links:
        return None
    return (f"the energies exclude the weight and inertia of {len(robot.massless_links)} moving link(s) without "
            f"inertia, loaded as asked (--allow-massless): {_names(robot.massless_links)}")


def links_without_inertia(robot: Robot) -> list[str]:
    """The moving links without inertia that no rule makes legitimate (the module's docstring), one per body: the
    link its joint carries, in model order."""
    return model_links_without_inertia(robot.model, robot.closures)


def model_links_without_inertia(model: pin.Model, closures: Sequence[Closure] = ()) -> list[str]:
    """:func:`links_without_inertia` of a model and its closures (none: a serial arm's model before its sidecar)."""
    lacking = {j for j in range(1, model.njoints) if _without_inertia(model.inertias[j])}
    if not lacking:
        return []
    children: dict[int, list[int]] = {j: [] for j in range(model.njoints)}
    for j in range(1, model.njoints):
        children[model.parents[j]].append(j)
    frames = [model.frames[i] for closure in closures for i in closure.frame_ids]
    welds = [tuple(model.frames[i].parentJoint for i in closure.frame_ids) for closure in closures
             if closure.kind == "weld"]
    carries = {0} | (set(range(1, model.njoints)) - lacking)
    changed = True
    while changed:
        changed = False
        for j in sorted(lacking - carries):
            welded = any(j in pair and (pair[0] in carries if pair[1] == j else pair[1] in carries) for pair in welds)
            pointlike = all(np.linalg.norm(model.jointPlacements[k].translation) <= SAME_POINT_M for k in children[j])
            pointlike = pointlike and all(np.linalg.norm(f.placement.translation) <= SAME_POINT_M
                                          for f in frames if f.parentJoint == j)
            if welded or (pointlike and any(k in carries for k in children[j])):
                carries.add(j)
                changed = True
    link = body_links(model)
    return [link[j] for j in sorted(lacking - carries)]


def body_links(model: pin.Model) -> dict[int, str]:
    """The link each body's joint carries (the first link frame on it), by joint id."""
    links: dict[int, str] = {}
    for frame in model.frames:
        if frame.type == pin.FrameType.BODY and frame.parentJoint not in links:
            links[frame.parentJoint] = frame.name
    return links


def _without_inertia(inertia: pin.Inertia) -> bool:
    """Whether a body's mass is below MASSLESS_KG or its rotational inertia about its centre of mass is flat."""
    if not inertia.mass >= MASSLESS_KG:
        return True
    moments = np.linalg.eigvalsh(inertia.inertia)
    return not moments[0] > FLAT_SHARE * moments[-1]


def _lacking_text(robot: Robot, lacking: Sequence[str]) -> str:
    """The refusal of moving links without inertia: which, why it matters, and the ways out."""
    model, link = robot.model, body_links(robot.model)
    light = {link[j] for j in range(1, model.njoints) if not model.inertias[j].mass >= MASSLESS_KG}
    massless, flat = [name for name in lacking if name in light], [name for name in lacking if name not in light]
    kinds = ([f"{_names(massless)} without mass (no <inertial>, or below {MASSLESS_KG:g} kg)"] if massless else []) + (
        [f"{_names(flat)} with a rotational inertia that is not positive definite"] if flat else [])
    first = lacking[0]
    where = (f"an <inertial> for each body in {_description(robot)} (mass, pos, and diaginertia or fullinertia)"
             if is_mjcf(robot.urdf_path) else
             f"an <inertial> for each in {_description(robot)} (or, once 'placement assemble "
             f"{robot.sidecar_path.parent} --write' has written its sidecar, their values under the sidecar's links)"
             if is_gepetto(robot.sidecar_path) else
             f"each link's mass_kg, com_m (m) and inertia_kg_m2 (about the centre of mass, link axes) under the "
             f"sidecar's links, e.g. links: {{{first}: {{mass_kg: ..., com_m: [...], inertia_kg_m2: [ixx, iyy, izz, "
             f"ixy, ixz, iyz]}}}} with a sources entry links.{first}, or an <inertial> in {_description(robot)}")
    direct = robot.sidecar_path.suffix.lower() not in SIDECAR_SUFFIXES  # the direct route: no sidecar file yet
    if direct and not is_mjcf(robot.urdf_path):
        where += " (--allow-massless --write-sidecar FILE writes the estimated sidecar, for you to add them to)"
    return (f"{len(lacking)} moving link(s) of {_description(robot)} have no inertia: {'; '.join(kinds)}; every "
            f"energy would leave out their weight and inertia: give {where}; or pass {ALLOW} to go on knowingly")


def _allowed_text(robot: Robot, lacking: Sequence[str], unbounded: Sequence[int]) -> str:
    """The warning of a robot loaded with ``allow_massless``."""
    parts = ([f"{len(lacking)} moving link(s) without inertia ({_names(lacking)}): its energies leave out their "
              "weight and inertia"] if lacking else []) + (
        [f"actuated joint(s) without drive or effort limit ({_names([robot.actuators[i].joint for i in unbounded])}): "
         "nothing bounds their effort"] if unbounded else [])
    return f"{robot.name}: loaded as asked (--allow-massless) with {'; and with '.join(parts)}"


def _refuse_absurd_masses(robot: Robot, urdf: UrdfContents) -> None:
    """A moving link of the URDF heavier than ABSURD_LINK_RATIO times the median mass of the moving bodies, unless
    the sidecar's ``links`` gives it."""
    model = robot.model
    weighed = [model.inertias[j].mass for j in range(1, model.njoints) if model.inertias[j].mass >= MASSLESS_KG]
    if not weighed:
        return
    median = statistics.median(weighed)
    moving = {f.name for f in model.frames if f.type == pin.FrameType.BODY and f.parentJoint > 0}
    given = set(robot.sidecar.links)
    heavy = [(name, mass) for name, mass in urdf.masses.items()
             if name in moving and name not in given and mass > ABSURD_LINK_RATIO * median]
    if heavy:
        name, mass = heavy[0]
        others = f" (and {_names([n for n, _ in heavy[1:]])})" if heavy[1:] else ""
        raise RobotFileError(robot.sidecar_path, f"urdf.link.{name}.inertial.mass",
                             f"link '{name}' of {_description(robot)} weighs {mass:.4g} kg{others}, more than "
                             f"{ABSURD_LINK_RATIO:g} times the median moving body's {median:.4g} kg: a mass in the wrong "
                             f"unit? correct its <mass> in the URDF, or give its mass_kg, com_m and inertia_kg_m2 "
                             f"under the sidecar's links.{name} (with a sources entry) if it truly weighs that much")


def _description(robot: Robot) -> str:
    """The description file as the user knows it: a xacro's name, not its expansion's in the cache."""
    given = Path(robot.urdf_source)
    return given.name if is_xacro(given) else robot.urdf_path.name


def _names(names: Sequence[str]) -> str:
    """Up to NAMED names, then how many more."""
    return listed(names, NAMED)
