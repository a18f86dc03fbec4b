"""The 'calibrate' command: fit drive constants to a machine's measured log.

    placement calibrate ROBOT --log log.csv --fit resistance_ohm,coulomb [--out FOLDER] [--png FILE]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from placement.cli.common import check_outputs, require_features, require_sidecar, robot_files
from placement.cli.exceptions import UsageError
from placement.distribution import PLOTS
from placement.robot.model import Robot
from placement.workshop.calibration import (
    FITTABLE,
    UNITS,
    Calibration,
    calibrate,
    constant_value,
    read_log,
    write_calibrated,
)
from placement.workshop.load import load_robot


def add_parser(commands: argparse._SubParsersAction) -> None:
    """The 'calibrate' subcommand's options."""
    command = commands.add_parser("calibrate", help="fit drive constants to a measured log of current or power")
    command.add_argument("robot", help="robot name or path to a sidecar YAML file")
    command.add_argument("--log", required=True, help="CSV: t; x, y, z or q_JOINT; power_JOINT and/or current_JOINT; optionally "
                         "qd_JOINT and qdd_JOINT, tool_force_x/y/z (a --trace file, as it is)")
    command.add_argument("--fit", required=True, metavar="NAME,...",
                         help=f"constants to fit, for every drive: some of {', '.join(FITTABLE)}")
    command.add_argument("--held-out", type=float, default=0.3, metavar="SHARE",
                         help="share of the log, at its end, kept out of the fit to measure the prediction (default 0.3)")
    command.add_argument("--out", metavar="FOLDER", help="write a copy of the robot folder with the calibrated sidecar")
    command.add_argument("--png", metavar="FILE", help="plot measured against predicted values (PNG and SVG)")


def run(args: argparse.Namespace) -> int:
    """Fit, print the constants with their 95 % intervals and the errors; write the outputs asked for."""
    require_sidecar(args.robot, "calibrate")
    check_outputs(("--png", args.png), inputs=(args.log, *robot_files(args.robot)))
    require_features((args.png, PLOTS))
    if args.out is not None and Path(args.out).exists():
        raise UsageError(f"--out: '{args.out}' exists; name a new folder")
    if not 0 < args.held_out < 1:
        raise UsageError(f"--held-out: expected a share between 0 and 1, got {args.held_out}")
    fit = [name.strip() for name in args.fit.split(",") if name.strip()]
    unknown = [name for name in fit if name not in FITTABLE]
    if unknown or not fit:
        raise UsageError(f"--fit: expected some of {', '.join(FITTABLE)}, got '{args.fit[:80]}'")
    robot = load_robot(args.robot)
    log = read_log(args.log, robot)
    result = calibrate(robot, log, fit, args.held_out)
    print(report(result, len(log.t_s), robot))
    if args.out:
        sidecar = write_calibrated(robot, result, args.out, Path(args.log).name)
        print(f"calibrated robot written to {sidecar}")
    if args.png:
        from placement.output.plots import calibration_figure, save  # the [viz] extra (matplotlib, meshcat): imported only here

        save(calibration_figure(result, [a.joint for a in robot.actuators]), str(args.png).removesuffix(".png"))
        print(f"figure written to {args.png} (and .svg)")
    return 0


def report(result: Calibration, samples: int, before: Robot) -> str:
    """The constants before and after the fit, with the 95 % intervals, and the fit's and the prediction's errors."""
    lines = [f"fitted on the first {result.split} of {samples} samples; the last {samples - result.split} held out"]
    for drive, values in result.values.items():
        lines.append(f"  drive {drive}")
        lines.append(f"    {'constant':<26s} {'before':>12s}    {'after':>12s}  95 % interval")
        for constant, value in values.items():
            old = constant_value(before.named_drives[drive], constant)
            lines.append(f"    {constant:<26s} {old:12.6g} -> {value:12.6g}  ± {result.confidence_95[drive][constant]:.3g}")
    if result.at_bounds:
        lines.append(f"  note: {', '.join(result.at_bounds)} ended on a bound of its range (see FITTABLE): the log "
                     "asks for a value the range excludes, or the constant is not needed")
    for quantity, rmse in result.fit_rmse.items():
        lines.append(f"  RMS error of the {quantity}: {rmse:.4g} {UNITS[quantity]} fitted, "
                     f"{result.held_out_rmse[quantity]:.4g} {UNITS[quantity]} held out")
    return "\n".join(lines)
