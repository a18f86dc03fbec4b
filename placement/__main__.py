"""Command line: ``python -m placement`` (also installed as ``placement``).

    placement --robot orthoglide --path examples/rect.yaml    best and worst placements, gain
    placement --robot orthoglide --path rect.yaml --at x=0,y=0,z=0,phi=0    one placement
    placement robots                                           list the built-in robots
    placement check ROBOT                                      describe a robot, prove its model exact

Exit codes: 0 success, 1 a physics check failed, 2 bad input or no feasible placement (the
message says what and where).
"""

from __future__ import annotations

import argparse
import dataclasses
import sys

import numpy as np
from tqdm import tqdm

from placement.checks import check_robot
from placement.evaluation import Evaluator
from placement.exceptions import PlacementError
from placement.frames import ANGLES, VARIABLES
from placement.optimize import SearchSettings, default_space, optimize_placement
from placement.path import Timing, ToolPath, load_path
from placement.report import (REGENERATION_TEXT, detail_json, format_detail, format_result, write_json,
                              write_trace)
from placement.energy import REGENERATION_MODES
from placement.robot import Robot, builtin_robots, load_robot
from placement.sidecar import BallScrew

SUBCOMMANDS = ("robots", "check")


class UsageError(PlacementError):
    """A command-line option has a value it cannot take."""


def build_parser() -> argparse.ArgumentParser:
    """The parser of the main job: place a path on a robot."""
    parser = argparse.ArgumentParser(
        prog="placement", description="Find where to place a tool path in a robot's workspace so that the "
        "actuators draw the least electric energy while every limit holds.",
        epilog="Other commands: 'placement robots' lists the built-in robots; 'placement check ROBOT' describes "
               "a robot and proves its dynamic model exact.")
    parser.add_argument("--robot", required=True, help="built-in robot name or path to a robot sidecar YAML")
    parser.add_argument("--path", required=True, help="path file (YAML), e.g. examples/rect.yaml")
    direction = parser.add_mutually_exclusive_group()
    direction.add_argument("--minimize", action="store_true", help="only search the least-energy placement")
    direction.add_argument("--maximize", action="store_true", help="only search the most-energy placement")
    parser.add_argument("--at", metavar="x=..,y=..,phi=..",
                        help="evaluate one placement instead of searching (mm and deg unless a value ends in m or rad)")
    parser.add_argument("--free", metavar="x,y,z,phi", help="free placement variables (default: x,y,z,phi)")
    parser.add_argument("--fix", metavar="z=0,theta=0", help="values of fixed variables (mm, deg; default 0)")
    parser.add_argument("--regen", choices=REGENERATION_MODES, default="clip",
                        help="what happens to braking energy (default: clip, no regeneration)")
    parser.add_argument("--timing", choices=("paper", "realistic"), help="override the path file's timing law")
    parser.add_argument("--max-acceleration", type=float, metavar="M_S2",
                        help="tool acceleration bound of the realistic timing law (m/s^2)")
    parser.add_argument("--max-jerk", type=float, metavar="M_S3", help="tool jerk bound of the realistic timing law (m/s^3)")
    parser.add_argument("--time-step", type=float, metavar="S", help="path sampling step (s; default: the path file's)")
    parser.add_argument("--seed", type=int, default=0, help="random seed of the search (default 0)")
    parser.add_argument("--json", metavar="FILE", help="write the results as JSON (SI units)")
    parser.add_argument("--trace", metavar="FILE",
                        help="write a per-sample CSV trace of the placement given by --at, else of the best one")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    return parser


def build_command_parser() -> argparse.ArgumentParser:
    """The parser of the 'robots' and 'check' commands."""
    parser = argparse.ArgumentParser(prog="placement")
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


def parse_values(text: str, option: str) -> dict[str, float]:
    """'x=10,phi=30' -> SI values; lengths in mm and angles in deg unless suffixed m / rad."""
    values = {}
    for item in filter(None, (part.strip() for part in text.split(","))):
        name, _, raw = item.partition("=")
        name = name.strip()
        if name not in VARIABLES or not raw:
            raise UsageError(f"{option}: expected name=value with names from {', '.join(VARIABLES)}, got '{item}'")
        angle = name in ANGLES
        units = {"rad": 1.0, "deg": np.pi / 180} if angle else {"mm": 1e-3, "m": 1.0}
        unit = next((u for u in sorted(units, key=len, reverse=True) if raw.strip().endswith(u)), None)
        number = raw.strip()[: -len(unit)] if unit else raw.strip()
        try:
            values[name] = float(number) * units[unit or ("deg" if angle else "mm")]
        except ValueError:
            raise UsageError(f"{option}: '{raw}' is not a number for {name}") from None
    return values


def configured_path(args: argparse.Namespace) -> ToolPath:
    """The path file with the command line's timing overrides."""
    path = load_path(args.path)
    if args.timing or args.max_acceleration or args.max_jerk:
        timing = path.timing
        try:
            timing = Timing(mode=args.timing or timing.mode,
                            max_acceleration_m_s2=args.max_acceleration or timing.max_acceleration_m_s2,
                            max_jerk_m_s3=args.max_jerk or timing.max_jerk_m_s3)
        except ValueError as error:
            raise UsageError(f"--timing: {error.errors()[0]['msg'].removeprefix('Value error, ')}; "
                             "give --max-acceleration and --max-jerk or set them in the path file") from None
        path = dataclasses.replace(path, timing=timing)
    if args.time_step is not None and args.time_step <= 0:
        raise UsageError("--time-step must be > 0 s")
    return path


def run_placement(args: argparse.Namespace) -> int:
    """The main job; returns the exit code."""
    robot = load_robot(args.robot)
    path = configured_path(args)
    samples = path.sample(args.time_step)
    print(f"{path.name} on {robot.name}: {len(path.segments)} segment(s), {path.length_m * 1e3:.1f} mm, "
          f"feed {path.feed_m_s:g} m/s, {path.timing.mode} timing, {len(samples)} samples over "
          f"{samples.t_s[-1]:.3f} s; energy: {REGENERATION_TEXT[args.regen]}")
    document: dict = {"robot": robot.name, "path": path.name, "regeneration": args.regen,
                      "timing": path.timing.mode, "samples": len(samples)}
    if args.at is not None:
        given = parse_values(args.at, "--at")
        evaluator = Evaluator(robot, path, args.regen, args.time_step)
        detail = evaluator.detail(np.array([given.get(name, 0.0) for name in VARIABLES]))
        print("\n" + format_detail("placement given by --at", robot, detail))
        document["at"] = detail_json(robot, detail)
        traced = detail
    else:
        free = tuple(n.strip() for n in args.free.split(",")) if args.free else None
        space = default_space(robot, free=free, fixed=parse_values(args.fix or "", "--fix"))
        print(f"search: {', '.join(space.free)} free; seed {args.seed}")
        settings = SearchSettings(seed=args.seed)
        directions = 1 if args.minimize or args.maximize else 2
        with tqdm(desc="searching", total=directions * settings.max_generations, unit=" generation",
                  disable=args.quiet, file=sys.stderr, leave=False) as bar:
            result = optimize_placement(robot, path, space=space, regeneration=args.regen,
                                        minimize_energy=not args.maximize, maximize_energy=not args.minimize,
                                        time_step_s=args.time_step, settings=settings, progress=bar.update)
        print("\n" + format_result(robot, result))
        for key, optimum in (("best", result.best), ("worst", result.worst)):
            if optimum is not None:
                document[key] = detail_json(robot, optimum.detail, optimum)
        if result.gain is not None:
            document["gain"] = result.gain
        if result.infeasible:
            document["infeasible"] = result.infeasible
        traced = (result.best or result.worst).detail if (result.best or result.worst) else None
    if args.json:
        write_json(args.json, document)
    if args.trace and traced is not None:
        write_trace(args.trace, robot, traced)
    if args.at is None and result.infeasible:
        print(f"error: no feasible placement: {result.infeasible}", file=sys.stderr)
        return 2
    return 0


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code."""
    argv = sys.argv[1:] if argv is None else argv
    try:
        if argv and argv[0] in SUBCOMMANDS:
            args = build_command_parser().parse_args(argv)
            if args.command == "robots":
                for name in builtin_robots():
                    print(f"{name:<14s} {load_robot(name).sidecar.description}")
                return 0
            return run_check(args.robot, args.samples)
        return run_placement(build_parser().parse_args(argv))
    except PlacementError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
