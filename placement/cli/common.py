"""What the subcommands share: option parsing in display units, path options, output checks."""

from __future__ import annotations

import argparse
import dataclasses
import os
import signal
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from placement.cell.cell_file import load_cell
from placement.cli.exceptions import UsageError
from placement.cli.redundancy import add_redundancy_options, apply_redundancy_options
from placement.contract.objective import OBJECTIVES
from placement.distribution import Feature, require
from placement.energy.regeneration import REGENERATION
from placement.evaluation.parallel import SCHEDULER_VARIABLE
from placement.kinematics.base import solver_name
from placement.kinematics.closed_form import touch_joint_motion_kernel
from placement.kinematics.warmup import touch_kernels
from placement.limits.collision import collision_scene
from placement.path.load import ControllerSettings, load_path
from placement.path.path_file import MAX_FEED_M_S, MM_PER_MIN_M_S
from placement.path.toolpath import ToolPath
from placement.robot.equip import equip
from placement.robot.formats import DescriptionOptions, is_description
from placement.robot.model import Robot
from placement.robot.urdf import ERD_PREFIX
from placement.robot.xacro import is_xacro
from placement.timing.rules import override_timing, timing_for
from placement.workshop.catalog import ERD_FORM, builtin_robots_dir, sidecar_path
from placement.workshop.estimates import (
    erd_name,
    estimate_warning,
    load_description_robot,
    load_erd_robot,
    write_estimated_sidecar,
)
from placement.workshop.load import load_robot

MIN_INITIAL_FEED_MM_MIN = 1.0  # --initial-feed below this is taken for a value in m/s: no machine cuts slower


def whole_number(low: int, high: int) -> Callable[[str], int]:
    """An argparse type: a whole number from ``low`` to ``high``."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number, got '{text[:40]}'") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"expected a whole number from {low:,} to {high:,}, got {value:,}")
        return value

    return parse


def positive_number(text: str) -> float:
    """An argparse type: a finite number > 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got '{text[:40]}'") from None
    if not 0 < value < np.inf:
        raise argparse.ArgumentTypeError(f"expected a finite number > 0, got '{text[:40]}'")
    return value


def non_negative(text: str) -> float:
    """An argparse type: a finite number ≥ 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got '{text[:40]}'") from None
    if not 0 <= value < np.inf:
        raise argparse.ArgumentTypeError(f"expected a finite number ≥ 0, got '{text[:40]}'")
    return value


def parent() -> argparse.ArgumentParser:
    """An empty parent parser, whose options a command takes with ``parents=[...]``."""
    return argparse.ArgumentParser(add_help=False)


def job_options(*, several_paths: bool = False) -> argparse.ArgumentParser:
    """--robot, --tool, --cell and --path: the robot, where it works, and the path it follows (a parent parser).

    Args:
        several_paths: Whether --path takes one or more files (the main job), else exactly one.
    """
    options = parent()
    options.add_argument("--robot", required=True, help="built-in robot name, a robot sidecar YAML, a robot "
                         "description (URDF, xacro, MJCF .xml) with --tool, or erd:NAME (an example-robot-data arm, with --tool)")
    _add_description(options)
    _add_cell(options)
    add_redundancy_options(options)
    if several_paths:
        options.add_argument("--path", required=True, nargs="+", help="path file(s) (YAML), e.g. examples/rect.yaml")
    else:
        options.add_argument("--path", required=True, help="path file (YAML), e.g. examples/rect.yaml")
    return options


def tool_option() -> argparse.ArgumentParser:
    """--tool and the description's options alone, for a command whose robot is a positional argument (a parent
    parser)."""
    return _parent_with(_add_description)


def cell_option() -> argparse.ArgumentParser:
    """--cell alone, for a command that names its robots otherwise (a parent parser)."""
    return _parent_with(_add_cell)


def _parent_with(*adders: Callable[[argparse.ArgumentParser], None]) -> argparse.ArgumentParser:
    """A parent parser with the options each of ``adders`` adds."""
    options = parent()
    for add in adders:
        add(options)
    return options


def massless_option() -> argparse.ArgumentParser:
    """--allow-massless: load a robot whose physics is incomplete, knowingly (a parent parser)."""
    options = parent()
    options.add_argument("--allow-massless", action="store_true",
                         help="load a robot whose moving links have no inertia (a URDF without <inertial>) or whose "
                              "actuated joints have neither drive nor effort limit, with a warning: the energies "
                              "leave out their inertia (without it, such a robot is refused; better, give the values "
                              "under the sidecar's links)")
    return options


def _add_description(options: argparse.ArgumentParser) -> None:
    options.add_argument("--tool", metavar="FRAME",
                         help="with --robot FILE (a URDF, xacro or MJCF description) or erd:NAME (any serial arm of "
                              "example-robot-data): the link or joint (an MJCF's body or site) that follows the path, "
                              "e.g. tool0; drives, workspace and posture are estimated")
    options.add_argument("--robot-arg", action="append", default=[], metavar="NAME:=VALUE",
                         help="an argument of a xacro description (repeatable), e.g. ur_type:=ur5e")
    options.add_argument("--package-path", action="append", default=[], metavar="DIR",
                         help="a folder where the description's package:// meshes and $(find PKG) are looked for "
                              "first (repeatable): a package, or a folder holding packages")
    options.add_argument("--effort", action="append", default=[], metavar="JOINT=VALUE",
                         help="with --tool: an actuated joint's effort bound (N m, or N for a sliding joint; "
                              "repeatable), for a description that bounds none (onshape-to-robot's MJCF exports), "
                              "e.g. motor1=1.5: its drive is estimated from it")
    options.add_argument("--write-sidecar", metavar="FILE",
                         help="with --tool: write the estimated sidecar to FILE (YAML), to refine and load instead")


def _add_cell(options: argparse.ArgumentParser) -> None:
    options.add_argument("--cell", metavar="FILE",
                         help="a cell file (YAML): obstacles the robot must clear, keep-out zones, the region where "
                              "the workpiece may be placed, and a tool body; collisions then become a limit")


def model_options() -> argparse.ArgumentParser:
    """--objective and --regen: what placements are ranked by, and what braking energy does (a parent parser)."""
    options = parent()
    options.add_argument("--objective", default="energy", metavar="NAME",
                         help=f"what placements are ranked by: {', '.join(OBJECTIVES.names())} (default: energy, "
                              "the electric energy)")
    _add_regeneration(options)
    return options


def regeneration_option() -> argparse.ArgumentParser:
    """--regen: what braking energy does (a parent parser)."""
    return _parent_with(_add_regeneration)


def _add_regeneration(options: argparse.ArgumentParser) -> None:
    options.add_argument("--regen", choices=REGENERATION.names(), default="clip",
                         help="what happens to braking energy (default: clip, no regeneration)")


def sampling_options() -> argparse.ArgumentParser:
    """Options that override how a path file is read, timed and sampled (see configured_path; a parent parser)."""
    options = parent()
    _add_controller(options)
    options.add_argument("--timing", choices=("paper", "realistic", "optimal"),
                         help="override the path file's timing law (optimal: as fast as the robot allows at each "
                              "placement, the feed an upper bound)")
    options.add_argument("--max-acceleration", type=positive_number, metavar="M_S2",
                         help="tool acceleration bound of the realistic timing law (m/s^2)")
    options.add_argument("--max-jerk", type=positive_number, metavar="M_S3",
                         help="tool jerk bound of the realistic timing law (m/s^3)")
    options.add_argument("--time-step", type=positive_number, metavar="S",
                         help="path sampling step (s; default: the path file's)")
    return options


def _add_controller(options: argparse.ArgumentParser) -> None:
    """--initial-feed and --tool-diameter: what RS-274 leaves to the controller, for a G-code program."""
    options.add_argument("--initial-feed", type=initial_feed_mm_min, metavar="MM_PER_MIN",
                         help="a G-code program's feed moves before its first F run at this feed, the controller's "
                              "modal feed, in mm/min as F in a G21 program (1 in/min = 25.4 mm/min; default: the path "
                              "file's shape.initial_feed_m_s, else such a move is refused)")
    options.add_argument("--tool-diameter", type=tool_diameter, action="append", default=[], metavar="T=MM",
                         help="tool T's diameter in mm, which cutter radius compensation (G41, G42 with D or the "
                              "loaded tool) offsets a G-code program's path by; repeatable, e.g. --tool-diameter "
                              "8=6.35 (T8=6.35 also reads); over the path file's shape.tool_diameters_mm")


def initial_feed_mm_min(text: str) -> float:
    """--initial-feed's value: a feed in mm/min, from MIN_INITIAL_FEED_MM_MIN to the path file's largest feed."""
    value = positive_number(text)
    if value < MIN_INITIAL_FEED_MM_MIN:
        raise argparse.ArgumentTypeError(f"expected a feed in mm/min, got {value:g}: a value in m/s? "
                                         f"{value:g} m/s = {value * MM_PER_MIN_M_S:g} mm/min")
    if value > MAX_FEED_M_S * MM_PER_MIN_M_S:
        raise argparse.ArgumentTypeError(f"expected a feed in mm/min of at most {MAX_FEED_M_S * MM_PER_MIN_M_S:g}, "
                                         f"got {value:g}")
    return value


def tool_diameter(text: str) -> tuple[int, float]:
    """--tool-diameter's value: T=MM (or TT=MM), the tool's number and its diameter in mm."""
    tool, separator, diameter = text.strip().partition("=")
    tool = tool.strip().removeprefix("T").removeprefix("t")
    if not separator or not tool.isdigit():
        raise argparse.ArgumentTypeError(f"expected T=MM, a tool number and its diameter in mm (e.g. 8=6.35), got "
                                         f"'{text[:40]}'")
    try:
        value = float(diameter)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected tool {tool}'s diameter in mm, got '{diameter[:40]}'") from None
    if not np.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite diameter in mm for tool {tool}, got '{diameter[:40]}'")
    return int(tool), value


def controller_settings(args: argparse.Namespace) -> ControllerSettings:
    """The command line's --initial-feed and --tool-diameter (each optional on the command).

    Raises:
        UsageError: A tool given twice.
    """
    diameters: dict[int, float] = {}
    for tool, diameter_mm in getattr(args, "tool_diameter", None) or []:
        if tool in diameters:
            raise UsageError(f"--tool-diameter: tool {tool} is given twice ({diameters[tool]:g} and {diameter_mm:g} mm)")
        diameters[tool] = diameter_mm
    feed = getattr(args, "initial_feed", None)
    return ControllerSettings(None if feed is None else feed / MM_PER_MIN_M_S, diameters)


def margin_option() -> argparse.ArgumentParser:
    """--margin: the share of every limit a feasible placement keeps free, in percent (a parent parser)."""
    options = parent()
    options.add_argument("--margin", type=margin_percent, default=0.0, metavar="PERCENT",
                         help="keep this share of every limit's range, speed, torque or workspace side free at every "
                              "sample, and a collision's clearance this many mm per 100 mm beyond the cell's margin "
                              "(default 0: the limits themselves)")
    options.add_argument("--max-deflection-um", type=positive_number, metavar="UM",
                         help="the largest deflection of the tool under the path's process forces a placement may "
                              "have (µm; the robot's sidecar gives its joints' stiffness), overriding the path file's "
                              "max_deflection_um")
    options.add_argument("--loaded-stiffness", action="store_true",
                         help="the tool's deflection at the nonlinear equilibrium under the finite process forces (the "
                              "loaded, complementary stiffness correction) instead of the linear C·w, in the deflection "
                              "objectives, limit and report, which gives the change it makes (the path file's "
                              "loaded_stiffness)")
    return options


def placement_options() -> argparse.ArgumentParser:
    """--free and --fix: which placement variables a search frees, and the values of the others (a parent parser)."""
    options = parent()
    options.add_argument("--free", metavar="y=-40:40,x,phi",
                         help="free placement variables, each optionally with bounds name=MIN:MAX (mm, deg) "
                              "overriding the robot's (default: the robot's, e.g. x,y,z,phi for the Orthoglide); also "
                              "spin (the tool about its axis) and a redundant joint's knots JOINT@K (deg, or mm for "
                              "a prismatic joint such as a track), which alone are freed on top of the robot's (e.g. "
                              "--free spin=-180:180, --free track@0=-500:500)")
    options.add_argument("--fix", metavar="z=0,theta=0", help="values of fixed variables (mm, deg; default 0)")
    return options


def seed_option() -> argparse.ArgumentParser:
    """--seed: the random seed of the searches (a parent parser)."""
    options = parent()
    options.add_argument("--seed", type=whole_number(0, 2**32 - 1), default=0, help="random seed of the search (default 0)")
    return options


def margin_percent(text: str) -> float:
    """--margin's value: a percentage from 0 to under 100."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a percentage, got '{text[:40]}'") from None
    if not 0.0 <= value < 100.0:
        raise argparse.ArgumentTypeError(f"expected a percentage from 0 to under 100, got '{text[:40]}'")
    return value


def parse_joint_values(text: str, option: str) -> dict[str, tuple[float, str]]:
    """'a1=0.5,slider_x=0.3m' -> {joint: (value, unit)}, in the joint's own unit (rad or m).

    A value may end in ``rad`` or ``m`` to say which it is (the unit is '' when it does not);
    whether the joint exists and takes that unit is for the caller to check.

    Raises:
        UsageError: An item that is not name=number, a repeated name, a non-finite value.
    """
    values: dict[str, tuple[float, str]] = {}
    for item in filter(None, (part.strip() for part in text.split(","))):
        name, _, raw = (part.strip() for part in item.partition("="))
        if not name or not raw:
            raise UsageError(f"{option}: expected joint=value (rad or m), got '{item[:40]}'")
        if name in values:
            raise UsageError(f"{option}: {name[:40]} is given twice")
        unit = next((u for u in ("rad", "m") if raw.endswith(u)), "")
        try:
            value = float(raw[: len(raw) - len(unit)])
        except ValueError:
            raise UsageError(f"{option}: '{raw[:40]}' is not a number (rad or m) for {name[:40]}") from None
        if not np.isfinite(value):
            raise UsageError(f"{option}: {name[:40]} must be a finite number, got '{raw[:40]}'")
        values[name] = (value, unit)
    if not values:
        raise UsageError(f"{option}: expected joint=value,... (rad or m), got '{text[:40]}'")
    return values


def configured_path(args: argparse.Namespace, file: str) -> ToolPath:
    """A path file with the command line's timing overrides, timed by the law its objectives need (said in a note
    when the file gives another; :func:`placement.timing.rules.timing_for`)."""
    path = load_path(file, controller=controller_settings(args))
    for note in path.notes:
        print(f"note: {note}")
    mode, reason = timing_for(objective_names(args), args.timing, path)
    if reason is not None:
        print(f"note: {reason}: {file} is timed by it, for every objective")
    path = override_timing(path, mode, args.max_acceleration, args.max_jerk)
    bound_um = getattr(args, "max_deflection_um", None)
    if bound_um is not None:
        path = dataclasses.replace(path, max_deflection_m=bound_um * 1e-6)
    return dataclasses.replace(path, loaded_stiffness=True) if getattr(args, "loaded_stiffness", False) else path


def objective_names(args: argparse.Namespace) -> list[str]:
    """The objectives a command was given (--objective, and --objectives where it has it), known ones only."""
    names = [getattr(args, "objective", None)] + (getattr(args, "objectives", None) or "").split(",")
    return [name.strip() for name in names if name and name.strip() in OBJECTIVES]


def require_features(*wanted: tuple[object, Feature]) -> None:
    """The optional features the options ask for, checked before any work: (option's value, feature) pairs, a
    feature being needed when its option's value is set (not None, empty or false).

    Raises:
        MissingExtraError: A feature asked for needs an extra that is not installed; the message names it.
    """
    for value, feature in wanted:
        if value:
            require(feature)


def check_outputs(*pairs: tuple[str, str | None], inputs: tuple[str, ...] = ()) -> None:
    """Every output file must be writable before hours of work are spent: (option, file) pairs.

    An output may not be a folder, a symbolic link or another non-regular file, an input file, or
    another output; its folder must exist and take a new file.
    """
    taken = {Path(file).resolve(): "an input file" for file in inputs}
    identities = {_identity(Path(file)): "an input file" for file in inputs if Path(file).is_file()}  # hard links
    figures = [(option, str(file).removesuffix(".png") + ".svg") for option, file in pairs
               if file is not None and option == "--png"]  # a figure is written as PNG and SVG
    for option, file in (*pairs, *figures):
        if file is None:
            continue
        target = Path(file)
        if len(target.name.encode()) > 255:
            raise UsageError(f"{option}: the file name is too long (more than 255 bytes)")
        if target.is_symlink():
            raise UsageError(f"{option}: '{file}' is a symbolic link; name the file itself")
        if target.is_dir():
            raise UsageError(f"{option}: '{file}' is a folder, expected a file name")
        if target.exists() and not target.is_file():
            raise UsageError(f"{option}: '{file}' is not a regular file")
        if target.resolve() in taken:
            raise UsageError(f"{option}: '{file}' is {taken[target.resolve()]}; it would be overwritten")
        if target.is_file() and _identity(target) in identities:
            raise UsageError(f"{option}: '{file}' is {identities[_identity(target)]} (another name of it); "
                             "it would be overwritten")
        taken[target.resolve()] = f"also the file of {option}"
        folder = target.absolute().parent
        if not folder.is_dir():
            raise UsageError(f"{option}: the folder of '{file}' does not exist")
        try:
            tempfile.TemporaryFile(dir=folder).close()
        except OSError:
            raise UsageError(f"{option}: '{file}' cannot be written (its folder takes no new file)") from None
        if target.exists() and not os.access(target, os.W_OK):
            raise UsageError(f"{option}: '{file}' cannot be written")


def _identity(file: Path) -> tuple[int, int]:
    status = file.stat()
    return status.st_dev, status.st_ino


def run_options(*, workers: str | None = None) -> argparse.ArgumentParser:
    """--scheduler (a Dask cluster, else the environment variable's, else this machine), --workers when the command
    runs its work in processes of its own, and --quiet (a parent parser).

    Args:
        workers: --workers's help, when the command takes it.
    """
    options = parent()
    if workers is not None:
        options.add_argument("--workers", type=whole_number(1, 1024), help=workers)
    options.add_argument("--scheduler", metavar="ADDRESS",
                         help=f"run the evaluations on the Dask cluster of this scheduler (e.g. tcp://10.0.0.5:8786; "
                              f"default: ${SCHEDULER_VARIABLE} if set, else this machine)")
    options.add_argument("--quiet", action="store_true", help="no progress bar")
    return options


def load_robot_argument(robot: str, args: argparse.Namespace, cell: str | None = None) -> Robot:
    """The robot a command line names: built-in, installed, a sidecar file, a description file (URDF, xacro, MJCF) or
    erd:NAME with --tool; in the cell of the file ``cell``, if given; with --allow-massless, even if moving links lack
    inertia (:mod:`placement.robot.plausibility`); its sidecar written where --write-sidecar says.

    An estimated robot's estimates are said once, as a warning on standard error. A robot solved by the
    compiled generic kinematics has it loaded here, with a word on standard error when it is being
    compiled (a machine's first run). A cell's collision scene is built here, and its notices (shapes
    taken from visuals, convex hulls, pairs left out) are printed.

    Args:
        robot: The robot argument.
        args: The command's options: --tool, --robot-arg, --package-path, --write-sidecar, --allow-massless (each
            optional).

    Raises:
        UsageError: --tool given for a robot that is not a description or erd:NAME, or a --robot-arg without ':='.
        PlacementError: The robot cannot be loaded (the message says why).
    """
    tool, allow_massless = getattr(args, "tool", None), getattr(args, "allow_massless", False)
    write_sidecar = getattr(args, "write_sidecar", None)
    options = description_options(args)
    name, path = erd_name(robot), Path(robot)
    estimated = name is not None or is_description(path)
    if not estimated and (tool is not None or write_sidecar):
        raise UsageError(f"--tool and --write-sidecar apply to robots given as a description file (URDF, xacro, MJCF) or "
                         f"{ERD_FORM}NAME; the sidecar of '{robot[:80]}' names its tool in end_effector.frame")
    if options.efforts and not is_description(path):
        raise UsageError(f"--effort applies to robots given as a description file (URDF, xacro, MJCF) with --tool; "
                         f"'{robot[:80]}' is not one (a sidecar gives each drive under drives)")
    if name is not None:
        loaded = load_erd_robot(name, tool, allow_massless=allow_massless)
    elif estimated:
        loaded = load_description_robot(path, tool, allow_massless=allow_massless, options=options)
    else:
        loaded = load_robot(robot, allow_massless=allow_massless, options=options)
    loaded = apply_redundancy_options(loaded, args, options)
    if options.xacro_args and not is_xacro(Path(loaded.urdf_source)):
        raise UsageError(f"--robot-arg applies to robots described in xacro; the description of '{robot[:80]}' is "
                         f"{Path(loaded.urdf_source).name}")
    if estimated:
        print(f"warning: {estimate_warning(loaded)}", file=sys.stderr)
    if write_sidecar:
        written = write_estimated_sidecar(Path(write_sidecar), loaded)
        print(f"wrote the estimated sidecar {written.sidecar_path}: replace its estimates (EST under sources) with "
              f"the robot's own values and load it with --robot {written.sidecar_path}", file=sys.stderr)
    if solver_name(loaded) == "numeric":
        compile_noticed(touch_kernels, "the generic kinematics", "some 10 to 20 s")
    elif solver_name(loaded) == "closed_form":
        compile_noticed(touch_joint_motion_kernel, "the closed-form kinematics", "some 5 to 10 s")
    if cell is None:
        return loaded
    equipped = equip(loaded, load_cell(cell))
    for notice in collision_scene(equipped).notices:
        print(f"note: {notice}")
    return equipped


def description_options(args: argparse.Namespace) -> DescriptionOptions:
    """--package-path, --robot-arg (NAME:=VALUE, as ROS's launch files write them) and --effort (JOINT=VALUE) as
    description options.

    Raises:
        UsageError: A --robot-arg without ':=' or without a name, a folder that does not exist, or a bad --effort.
    """
    arguments = {}
    for item in getattr(args, "robot_arg", []):
        name, separator, value = item.partition(":=")
        if not separator or not name.strip():
            raise UsageError(f"--robot-arg: expected NAME:=VALUE (a xacro argument, e.g. ur_type:=ur5e), got '{item[:60]}'")
        arguments[name.strip()] = value.strip()
    folders = tuple(Path(folder) for folder in getattr(args, "package_path", []))
    missing = [str(folder) for folder in folders if not folder.is_dir()]
    if missing:
        raise UsageError(f"--package-path: no such folder: {', '.join(missing)[:200]}")
    return DescriptionOptions(folders, arguments, _efforts(getattr(args, "effort", [])))


def _efforts(items: list[str]) -> dict[str, float]:
    """--effort JOINT=VALUE items as bounds by joint name (N or N m).

    Raises:
        UsageError: An item without '=', without a name, or whose value is not a positive finite number.
    """
    efforts = {}
    for item in items:
        name, separator, text = item.partition("=")
        try:
            value = float(text)
        except ValueError:
            value = float("nan")
        if not separator or not name.strip() or not 0 < value < float("inf"):
            raise UsageError(f"--effort: expected JOINT=VALUE, a joint's name and its effort bound, a positive number "
                             f"in N m (N for a sliding joint), e.g. motor1=1.5; got '{item[:60]}'")
        efforts[name.strip()] = value
    return efforts


def compile_noticed(work: Callable[[], None], what: str, expected: str, patience_s: float = 2.0) -> float | None:
    """Run ``work`` (load compiled kernels from the disk cache, or compile them on a machine's first run), saying on
    stderr what is compiled and how long it took when that takes longer than ``patience_s`` (s).

    Args:
        work: Loads or compiles the kernels.
        what: What is compiled, e.g. "the generic kinematics".
        expected: How long a first compile takes, e.g. "some 10 to 20 s".
        patience_s: Longest silent wait (s).

    Returns:
        The whole wait (s) when it was announced, else None.
    """
    start = time.perf_counter()
    worker = threading.Thread(target=work, daemon=True)
    worker.start()
    worker.join(patience_s)
    if not worker.is_alive():
        return None
    print(f"compiling {what} for this machine (once, {expected}; later runs load it from the cache) ...",
          file=sys.stderr, flush=True)
    worker.join()
    waited_s = time.perf_counter() - start
    print(f"compiled {what} in {waited_s:.0f} s", file=sys.stderr, flush=True)
    return waited_s


def require_sidecar(robot: str, command: str) -> None:
    """Refuse ``erd:NAME`` for a command that reads or writes the robot's sidecar file.

    Raises:
        UsageError: ``robot`` is ``erd:NAME``; the message says how to write a sidecar for it.
    """
    name = erd_name(robot)
    if name is None:
        return
    model = builtin_robots_dir() / "ur5" / "ur5.yaml"
    raise UsageError(f"{command} needs a robot folder or sidecar file, not {robot[:80]}, whose estimated sidecar exists "
                     f"only in memory: write one for it, e.g. copy {model} (a serial arm's sidecar) and set "
                     f"'urdf: {ERD_PREFIX}{name[:80]}' and your drives in the copy (docs/adding_a_robot.md, "
                     "1. A serial arm by name), then give the copy's path")


def robot_files(robot: str, cell: str | None = None) -> tuple[str, ...]:
    """The files of a robot's folder (sidecar, URDF, plug-in), and its cell file if given: inputs no output may
    overwrite."""
    cell_files = (cell,) if cell is not None else ()
    if erd_name(robot) is not None:  # example-robot-data's files, not a folder of the user's
        return cell_files
    folder = sidecar_path(robot).parent
    return tuple(str(file) for file in folder.iterdir() if file.is_file()) + cell_files


def serve_until_stopped() -> None:
    """Return when Enter is pressed; when the input has ended already (a server started in the background, with
    nohup or from a service), when the process is interrupted (Ctrl-C) or terminated instead."""
    try:
        input()
    except EOFError:
        stop = threading.Event()
        signal.signal(signal.SIGTERM, lambda *_: stop.set())
        try:
            while not stop.wait(1.0):
                pass
        except KeyboardInterrupt:
            pass
