"""The 'assemble' command: close the loops of a robot exported with them open.

    placement assemble ROBOT [--near joint=value,...] [--write] [--no-lock]

It solves the closure equations from the sidecar's ``reference_configuration`` (see
:mod:`placement.workshop.assemble`), reports the gaps before and after and how far the closed
configuration is from a singularity, and prints the ``reference_configuration`` block to paste
into the sidecar, or with ``--write`` rewrites that block in the sidecar file itself. When the
closures leave passive joints free that move neither the end effector nor any actuator (a pin cut
by a weld closure spinning about its axis), it locks one joint of each group that moves together,
at its closed value, under ``locked_joints`` (``--no-lock``: it refuses instead, naming them).
"""

from __future__ import annotations

import argparse
import dataclasses

from placement.cli.common import parse_joint_values, require_sidecar
from placement.cli.exceptions import UsageError
from placement.kinematics.base import SINGULAR_CONDITION
from placement.robot.build import PRISMATIC_JOINTS
from placement.robot.closures import closure_residuals
from placement.robot.model import Robot
from placement.workshop.assemble import (
    SINGULAR_SIGMA,
    Assembly,
    ClosureGap,
    assemble,
    internal_freedoms,
    joint_q_index,
    locked_robot,
    movable_joints,
    outside_limits,
    reference_block,
    reference_values,
    singularity_measures,
    write_gepetto_sidecar,
    write_reference_configuration,
)
from placement.workshop.catalog import builtin_robots_dir, sidecar_path
from placement.workshop.gepetto import YAML_NAME, is_gepetto, sidecar_beside
from placement.workshop.load import _load_robot

LOCK_REASON = ("placement assemble: locked at its closed value; with it free, the closures leave it and the joints "
               "moving with it spinning about their axis, moving neither the end effector nor any actuator")


def add_parser(commands: argparse._SubParsersAction) -> None:
    """The 'assemble' subcommand's options."""
    command = commands.add_parser("assemble", help="close the loops of a robot whose reference configuration is open")
    command.add_argument("robot", help="robot name or path to a sidecar YAML file")
    command.add_argument("--near", metavar="JOINT=VALUE,...",
                         help="start from these joint values instead of the sidecar's reference_configuration "
                              "(rad or m, the joint's own unit; a value may end in rad or m)")
    command.add_argument("--write", action="store_true",
                         help="rewrite reference_configuration in the sidecar file (the rest of the file is kept)")
    command.add_argument("--no-lock", action="store_true",
                         help="do not lock the passive joints that no actuator drives and that do not move the end "
                              "effector (a pin spinning about its axis): refuse, naming them, instead")


def _near(robot: Robot, text: str | None) -> dict[str, float]:
    """--near as {joint: value (m or rad)}, every joint known and in its unit."""
    if text is None:
        return {}
    values = {}
    for name, (value, unit) in parse_joint_values(text, "--near").items():
        if joint_q_index(robot, name) is None:
            raise UsageError(f"--near: unknown joint '{name[:40]}'; expected one of {', '.join(movable_joints(robot))}")
        prismatic = robot.model.joints[robot.model.getJointId(name)].shortname() in PRISMATIC_JOINTS
        if unit and unit != ("m" if prismatic else "rad"):
            raise UsageError(f"--near: {name} is a {'prismatic joint (m)' if prismatic else 'revolute joint (rad)'}, "
                             f"got a value in {unit}")
        values[name] = value
    return values


def _gap_text(gaps: tuple[ClosureGap, ...]) -> str:
    worst_position = max(gaps, key=lambda gap: gap.position_m)
    text = f"{worst_position.position_m:.3g} m (closure '{worst_position.name}')"
    angles = [gap for gap in gaps if gap.angle_rad is not None]
    if angles:
        worst_angle = max(angles, key=lambda gap: gap.angle_rad or 0.0)
        text += f", {worst_angle.angle_rad:.3g} rad (closure '{worst_angle.name}')"
    return text


def _print_singularities(result: Assembly) -> None:
    """How far the closed configuration is from a singularity, or that it is singular."""
    print("  distance from singularities:")
    if result.passive_sigma_min <= SINGULAR_SIGMA:
        print(f"    passive joints: singular (smallest singular value of their closure Jacobian "
              f"{result.passive_sigma_min:.3g}): the actuated joints do not determine them (a motor missing, a joint to lock, "
              "or a singular posture)")
        print("    actuators to end effector: undefined while the passive joints are singular")
        return
    print(f"    passive joints: smallest singular value of their closure Jacobian {result.passive_sigma_min:.3g} "
          "(near 0, the passive joints are near a singular, uncertain assembly)")
    print(f"    actuators to end effector: condition number {result.task_condition:.3g} "
          f"(1 is isotropic; beyond {SINGULAR_CONDITION:.0e} the solvers call the configuration singular)")


def run(args: argparse.Namespace) -> int:
    """Close one robot's loops, report, and print or write its reference configuration."""
    require_sidecar(args.robot, "assemble")
    path = sidecar_path(args.robot)
    if args.write and path.resolve().is_relative_to(builtin_robots_dir().resolve()):
        raise UsageError(f"--write: '{path}' is a built-in robot shipped with placement; copy its folder and "
                         "assemble the copy")
    robot = _load_robot(path, check_closures=False)
    result = assemble(robot, _near(robot, args.near))
    actuated = ", ".join(a.joint for a in robot.actuators)
    passive = robot.model.nv - len(robot.actuators)
    print(f"{robot.name}: {len(robot.closures)} closure(s), {passive} passive joint(s), actuated {actuated}")
    print(f"  start: reference_configuration{' with --near ' + args.near if args.near else ''}")
    print(f"  largest gap before: {_gap_text(result.gaps_before)}")
    print(f"  largest gap after:  {_gap_text(result.gaps_after)}")
    if result.actuated_held:
        print(f"  closed by moving the passive joints only; the actuated joints kept their start values "
              f"({result.iterations} iterations)")
    else:
        moved = [f"{a.joint} by {result.q[a.q_index] - result.start_q[a.q_index]:+.4g} {'m' if a.prismatic else 'rad'}"
                 for a in robot.actuators]
        print(f"  the passive joints alone could not close the loops: the actuated joints moved too ({', '.join(moved)})")
    values = reference_values(robot, result)
    locks = {} if args.no_lock else internal_freedoms(robot, result.q)
    if locks:
        values = {name: value for name, value in values.items() if name not in locks}
        held = locked_robot(robot, values, locks)
        sigma_min, condition = singularity_measures(held, held.model.createData(), held.reference_q)
        result = dataclasses.replace(result, passive_sigma_min=sigma_min, task_condition=condition)
        print(f"  the closures leave {len(locks)} freedom(s) no actuator drives, moving neither the end effector nor "
              f"any closure (a pin spinning about its axis): locked {', '.join(locks)} at "
              f"{'its closed value' if len(locks) == 1 else 'their closed values'}")
    _print_singularities(result)
    for warning in outside_limits(robot, {**values, **locks}):
        print(f"  warning: {warning}")
    gepetto = is_gepetto(path)
    if not args.write:
        print(f"--write saves it, with the estimates, as the sidecar {sidecar_beside(path)}:" if gepetto else
              "paste into the sidecar, in place of its reference_configuration" + (", and add to its locked_joints:"
                                                                                     if locks else ":"))
        print(reference_block(values), end="")
        if locks:
            print(reference_block(locks).replace("reference_configuration:", "locked_joints:", 1), end="")
        return 0
    if gepetto:
        written = write_gepetto_sidecar(path, robot, values, locks, LOCK_REASON)
        print(f"wrote the sidecar {written.sidecar_path}: reference_configuration ({len(values)} joints), "
              + (f"locked_joints ({len(locks)} joints), " if locks else "") + "the estimates "
              f"(EST under sources) and an estimated workspace; it is loaded instead of {YAML_NAME} from now on")
    else:
        written = write_reference_configuration(path, values, locks, LOCK_REASON)
        print(f"wrote reference_configuration ({len(values)} joints)"
              + (f" and locked_joints ({len(locks)} joints, EST under sources)" if locks else "") + f" to {path}")
    gap = float(abs(closure_residuals(written, written.model.createData(), written.reference_q)).max(initial=0.0))
    print(f"  it loads; largest closure residual {gap:.1e} (m, rad)")
    if written.massless_links:
        print(f"  warning: {len(written.massless_links)} moving link(s) have no inertia "
              f"({', '.join(written.massless_links[:8])}{', ...' if len(written.massless_links) > 8 else ''}): the "
              f"commands refuse it until {written.sidecar_path}'s links gives their mass_kg, com_m and inertia_kg_m2, "
              "or with --allow-massless")
    return 0
