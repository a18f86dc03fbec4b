"""The 'check' command: describe a robot and prove its dynamic model exact.

    placement check ROBOT [--samples N] [--amplitude AMPLITUDE_M] [--allow-massless]

The check moves the end effector around its reference position by an amplitude scaled to the
robot's size (see :func:`placement.workshop.checks.default_amplitude`) unless ``--amplitude`` gives one,
and ends with plausibility warnings about the robot files (heavy links, efforts beyond the
drives, joints without URDF limits). A robot whose moving links have no inertia is refused as it
loads (exit 2, naming the links), unless ``--allow-massless``: it is then checked, with a warning.
"""

from __future__ import annotations

import argparse

import numpy as np

from placement.cli.common import load_robot_argument, massless_option, positive_number, tool_option, whole_number
from placement.cli.exceptions import UsageError
from placement.kinematics.base import solver_name
from placement.kinematics.exceptions import UnreachableError
from placement.robot.model import Robot
from placement.workshop.checks import CheckReport, check_robot


def add_parser(commands: argparse._SubParsersAction) -> None:
    """The 'check' subcommand's options."""
    check = commands.add_parser("check", help="describe a robot and prove its dynamic model exact",
                                parents=[tool_option(), massless_option()])
    check.add_argument("robot", help="robot name, path to a sidecar YAML file, or erd:NAME (with --tool)")
    check.add_argument("--samples", type=whole_number(10, 100_000), default=100,
                       help="samples of the check trajectory (default 100)")
    check.add_argument("--amplitude", type=positive_number, metavar="AMPLITUDE_M",
                       help="amplitude of the check motion along each direction (m; default 5%% of the workspace "
                            "box's smallest side along the motion, or of the base to end-effector distance at the "
                            "reference configuration when the sidecar declares no workspace)")


def _solver_text(robot: Robot) -> str:
    name = solver_name(robot)
    if name == "closed_form":
        return f"closed-form plug-in {robot.kinematics_plugin}"
    return "generic solver" if name == "numeric" else f"solver '{name}'"


def describe(robot: Robot) -> str:
    """A human-readable summary of a loaded robot."""
    model = robot.model
    point = sum(c.kind == "point" for c in robot.closures)
    lines = [f"{robot.name}: {robot.description}",
             f"  files: {robot.sidecar_path} + {robot.urdf_path.name}",
             f"  joints: {model.nv} ({len(robot.actuators)} actuated); closures: {len(robot.closures)} "
             f"({point} point, {len(robot.closures) - point} weld)",
             f"  end effector: frame '{model.frames[robot.end_effector_frame_id].name}', {robot.task} task; "
             f"kinematics: {_solver_text(robot)}",
             f"  gravity: {list(robot.gravity_m_s2)} m/s^2",
             "  actuators:"]
    for a in robot.actuators:
        unit, mass = ("m", "kg") if a.prismatic else ("rad", "kg m^2")
        text = (f"    {a.joint:<20s} [{a.position_min:.6f}, {a.position_max:.6f}] {unit}, "
                f"|speed| <= {a.velocity_max:g} {unit}/s")
        if a.drive is not None:
            text += (f", {a.drive.transmission.describe()}, motor {a.drive.motor.max_torque_Nm:g} N m max, "
                     f"reflected inertia {a.reflected_inertia:.4g} {mass}")
        lines.append(text)
    workspace = robot.workspace
    if workspace is not None:
        lines.append(f"  workspace: box {np.round(workspace.min_m, 6).tolist()} .. {np.round(workspace.max_m, 6).tolist()} m"
                     + (f"; points {', '.join(workspace.points_m)}" if workspace.points_m else ""))
    estimated = sum(text.startswith("EST") for text in robot.sources.values())
    lines.append(f"  sources: {len(robot.sources)} entries, {estimated} estimated (EST)")
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    """Load, describe and check one robot; returns the exit code."""
    robot = load_robot_argument(args.robot, args)
    print(describe(robot))
    try:
        report = check_robot(robot, args.samples, args.amplitude)
    except UnreachableError as error:
        given = f"--amplitude {args.amplitude:g} m" if args.amplitude is not None else "the default amplitude"
        raise UsageError(f"the check motion of {given} leaves the reachable region ({error}); "
                         "give a smaller --amplitude") from None
    print(f"  physics check on a demonstration trajectory around the reference ({report.samples} samples, "
          f"amplitude {report.amplitude_m:.4g} m: {report.amplitude_basis}):")
    print(f"    closure residual            {report.closure_gap:.1e} (m, rad)")
    if report.solver_gap is not None:
        print(f"    closed form vs generic      {report.solver_gap:.1e} (m, rad)")
    print(f"    forward dynamics round trip {report.forward_error:.1e} (joint acceleration error)")
    print(f"    power balance               {report.power_error_W:.1e} W of {report.peak_power_W:.3g} W peak")
    print(f"    peak efforts                {np.round(report.peak_effort, 3).tolist()}")
    _print_warnings(report)
    print("  result: " + ("exact to round-off" if report.passed else "FAILED: the model is not consistent"))
    return 0 if report.passed else 1


def _print_warnings(report: CheckReport) -> None:
    if not report.warnings:
        print("  plausibility: no warnings (link masses, efforts against the drives, peak currents, URDF joint limits)")
    else:
        print(f"  plausibility: {len(report.warnings)} warning(s)")
    for warning in report.warnings:
        print(f"    warning: {warning}")
