"""Command line: ``python -m placement`` (also installed as ``placement``).

Subcommands:
    robots          list the built-in robots
    check ROBOT     load a robot (name or sidecar path), print what it is, and prove its model
                    exact on a demonstration trajectory (closures, solvers, forward dynamics,
                    power balance)

Exit codes: 0 success, 1 a physics check failed, 2 bad input (the message says what and where).
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from placement.checks import check_robot
from placement.exceptions import PlacementError
from placement.robot import Robot, builtin_robots, load_robot
from placement.sidecar import BallScrew


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the command line."""
    parser = argparse.ArgumentParser(prog="placement", description="Energy-optimal placement of tool paths "
                                     "in the workspace of serial and closed-loop robots.")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    commands.add_parser("robots", help="list the built-in robots")
    check = commands.add_parser("check", help="describe a robot and prove its dynamic model exact")
    check.add_argument("robot", help="built-in robot name or path to a sidecar YAML file")
    check.add_argument("--samples", type=int, default=100, help="samples of the check trajectory (default 100)")
    return parser


def describe(robot: Robot) -> str:
    """A human-readable summary of a loaded robot."""
    model = robot.model
    point = sum(c.kind == "point" for c in robot.closures)
    lines = [f"{robot.name}: {robot.sidecar.description}",
             f"  files: {robot.sidecar_path} + {robot.urdf_path.name}",
             f"  joints: {model.nv} ({len(robot.actuators)} actuated); closures: {len(robot.closures)} "
             f"({point} point, {len(robot.closures) - point} weld)",
             f"  end effector: frame '{model.frames[robot.end_effector_frame_id].name}', {robot.task} task; "
             f"kinematics: {'closed-form plug-in ' + robot.sidecar.kinematics_plugin if robot.closed_form else 'generic solver'}",
             f"  gravity: {list(robot.sidecar.gravity_m_s2)} m/s^2",
             "  actuators:"]
    for a in robot.actuators:
        unit, mass = ("m", "kg") if a.prismatic else ("rad", "kg m^2")
        text = (f"    {a.joint:<20s} [{a.position_min:.6f}, {a.position_max:.6f}] {unit}, "
                f"|speed| <= {a.velocity_max:g} {unit}/s")
        if a.drive is not None:
            t = a.drive.transmission
            ratio = f"ball screw {t.lead_m * 1e3:g} mm" if isinstance(t, BallScrew) else f"gear {t.ratio:g}:1"
            text += f", {ratio}, motor {a.drive.motor.max_torque_Nm:g} N m max, reflected inertia {a.reflected_inertia:.4g} {mass}"
        lines.append(text)
    workspace = robot.sidecar.workspace
    if workspace is not None:
        lines.append(f"  workspace: box {np.round(workspace.min_m, 6).tolist()} .. {np.round(workspace.max_m, 6).tolist()} m"
                     + (f"; points {', '.join(workspace.points_m)}" if workspace.points_m else ""))
    estimated = sum(text.startswith("EST") for text in robot.sidecar.sources.values())
    lines.append(f"  sources: {len(robot.sidecar.sources)} entries, {estimated} estimated (EST)")
    return "\n".join(lines)


def run_check(robot_name: str, samples: int) -> int:
    """Load, describe and check one robot; returns the exit code."""
    robot = load_robot(robot_name)
    print(describe(robot))
    report = check_robot(robot, samples)
    print(f"  physics check on a demonstration trajectory around the reference ({report.samples} samples):")
    print(f"    closure residual            {report.closure_gap:.1e} (m, rad)")
    if report.solver_gap is not None:
        print(f"    closed form vs generic      {report.solver_gap:.1e} (m, rad)")
    print(f"    forward dynamics round trip {report.forward_error:.1e} (joint acceleration error)")
    print(f"    power balance               {report.power_error_W:.1e} W of {report.peak_power_W:.3g} W peak")
    print(f"    peak efforts                {np.round(report.peak_effort, 3).tolist()}")
    print("  result: " + ("exact to round-off" if report.passed else "FAILED: the model is not consistent"))
    return 0 if report.passed else 1


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code."""
    args = build_parser().parse_args(argv)
    try:
        if args.command == "robots":
            for name in builtin_robots():
                print(f"{name:<14s} {load_robot(name).sidecar.description}")
            return 0
        return run_check(args.robot, args.samples)
    except PlacementError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
