"""Which bodies of a collision scene are checked against which, and the clearance each pair needs.

- Every robot body (link or tool) against every obstacle (clearance: the cell's ``margin_m``) and
  keep-out zone (clearance 0), except the pairs the cell's ``ignore`` lists.
- Robot bodies against each other (clearance 0), when both have shapes declared for collisions (a
  link drawn by its visuals only is checked against the cell alone), except bodies on one joint (one rigid body);
  links adjacent in the kinematic graph: parent and child, or joined by a loop closure, looking
  through bodies without shapes (a parallel robot's wrist joints, say); the pairs the sidecar's
  ``collision.ignore_pairs`` lists. The tool is skipped only against the links of its own body.

Pairs already touching at the reference configuration are dropped by :class:`placement.collision.distances.CollisionScene`,
which knows distances; pairs between bodies fixed to the base never change and are checked there once.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import pinocchio as pin

from placement.cell.cell_file import Cell
from placement.cell.exceptions import CellFileError
from placement.collision.geometry import KEEP_OUT, LINK, OBSTACLE, TOOL, Body
from placement.robot.exceptions import RobotFileError
from placement.robot.model import Robot


@dataclass(frozen=True)
class Pair:
    """Two bodies to keep apart.

    Attributes:
        first: Index of the robot body (for a robot-cell pair) or of the first link, in the scene's bodies.
        second: Index of the cell body or of the second robot body.
        required_m: The clearance the pair needs (m).
    """

    first: int
    second: int
    required_m: float


def select_pairs(robot: Robot, cell: Cell | None, bodies: Sequence[Body]) -> list[Pair]:
    """The pairs to check, robot-cell pairs first (see the module's rules).

    Raises:
        CellFileError: ``ignore`` names a pair that is not a robot body and a cell body.
        RobotFileError: ``collision.ignore_pairs`` names something that is not a link of the robot or its tool.
    """
    names = {body.name: i for i, body in enumerate(bodies)}
    ignored = _cell_ignored(robot, cell, bodies) | _sidecar_ignored(robot, bodies)
    margin = cell.margin_m if cell is not None else 0.0
    robot_bodies = [i for i, body in enumerate(bodies) if body.is_robot]
    pairs = [Pair(i, j, margin if bodies[j].kind == OBSTACLE else 0.0)
             for i in robot_bodies for j, other in enumerate(bodies)
             if other.kind in (OBSTACLE, KEEP_OUT) and frozenset((bodies[i].name, other.name)) not in ignored]
    adjacent = _adjacent_joints(robot, {body.joint for body in bodies if body.kind == LINK})
    for a, i in enumerate(robot_bodies):
        for j in robot_bodies[a + 1:]:
            first, second = bodies[i], bodies[j]
            if not (first.declared and second.declared):
                continue
            joined = (first.joint == second.joint if TOOL in (first.kind, second.kind)
                      else second.joint in adjacent[first.joint])
            if not joined and frozenset((first.name, second.name)) not in ignored:
                pairs.append(Pair(names[first.name], names[second.name], 0.0))
    return pairs


def _cell_ignored(robot: Robot, cell: Cell | None, bodies: Sequence[Body]) -> set[frozenset[str]]:
    """The cell's ``ignore`` pairs, each a robot link (or the tool) and a cell body."""
    if cell is None:
        return set()
    robot_names = _link_names(robot.model) | {body.name for body in bodies if body.kind == TOOL}
    cell_names = set(cell.obstacles) | set(cell.keep_out)
    for i, (first, second) in enumerate(cell.ignore):
        if not ({first, second} & robot_names and {first, second} & cell_names) or first == second:
            raise CellFileError(cell.path, f"ignore.{i}", f"expected a robot link (or the tool) and an obstacle or "
                                f"keep-out zone, got [{first[:80]}, {second[:80]}]; links: {_some(robot_names)}; "
                                f"cell bodies: {_some(cell_names)}")
    return {frozenset(pair) for pair in cell.ignore}


def _sidecar_ignored(robot: Robot, bodies: Sequence[Body]) -> set[frozenset[str]]:
    """The sidecar's ``collision.ignore_pairs``, each two links of the robot (or a link and the tool)."""
    names = _link_names(robot.model) | {body.name for body in bodies if body.kind == TOOL}
    pairs = robot.collision_ignore_pairs
    for i, pair in enumerate(pairs):
        for k, name in enumerate(pair):
            if name not in names:
                raise RobotFileError(robot.sidecar_path, f"collision.ignore_pairs.{i}.{k}",
                                     f"no link '{name[:80]}' in robot '{robot.name}'; links: {_some(names)}")
    return {frozenset(pair) for pair in pairs}


def _adjacent_joints(robot: Robot, carried: set[int]) -> dict[int, set[int]]:
    """For every joint, the joints whose bodies touch its body by construction.

    The kinematic graph joins each joint to its parent and the two joints of each loop closure; two
    joints are adjacent when a path joins them whose inner joints carry no shapes (``carried``).
    """
    model = robot.model
    edges: dict[int, set[int]] = {j: set() for j in range(model.njoints)}
    links = [(int(model.parents[j]), j) for j in range(1, model.njoints)]
    links += [(int(model.frames[c.frame_ids[0]].parentJoint), int(model.frames[c.frame_ids[1]].parentJoint))
              for c in robot.closures]
    for a, b in links:
        edges[a].add(b)
        edges[b].add(a)
    adjacent = {}
    for start in range(model.njoints):
        reached, frontier = {start}, [start]
        while frontier:
            node = frontier.pop()
            for other in edges[node] - reached:
                reached.add(other)
                if other not in carried:
                    frontier.append(other)
        adjacent[start] = reached
    return adjacent


def _link_names(model: pin.Model) -> set[str]:
    """The names of the model's links (body frames)."""
    return {frame.name for frame in model.frames if frame.type == pin.FrameType.BODY}


def _some(names: set[str], most: int = 12) -> str:
    shown = sorted(names)
    return ", ".join(shown[:most]) + (", ..." if len(shown) > most else "") if shown else "(none)"
