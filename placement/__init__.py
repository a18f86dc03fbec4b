"""placement: energy-optimal placement of tool paths for serial and closed-loop robots.

The public API, in data-flow order: load a robot (:func:`load_robot`) and a path
(:func:`load_path`), search the least- and most-energy placements (:func:`optimize_placement`),
or evaluate placements yourself (:class:`Evaluator`). Underneath: the end-effector motion
(:class:`TaskTrajectory`), every joint's motion (:func:`joint_trajectory`), the actuator efforts
(:func:`inverse_dynamics`); :func:`check_robot` proves a robot model exact.
"""

from placement.checks import CheckReport, check_robot
from placement.dynamics import ActuatorTrajectory, actuator_efforts, inverse_dynamics
from placement.energy import REGENERATION_MODES, Energy, register_motor_model
from placement.evaluation import Evaluation, Evaluator, PlacementDetail
from placement.exceptions import (InputFileError, PathFileError, PlacementError, RobotFileError, UnknownRobotError,
                                  UnreachableError)
from placement.frames import PlacementSpace
from placement.kinematics import JointTrajectory, TaskTrajectory, joint_trajectory, solve_configuration
from placement.optimize import Optimum, PlacementResult, SearchSettings, default_space, optimize_placement
from placement.path import ToolPath, load_path
from placement.robot import Actuator, Closure, Robot, builtin_robots, load_robot

__all__ = [
    "REGENERATION_MODES",
    "Actuator",
    "ActuatorTrajectory",
    "CheckReport",
    "Closure",
    "Energy",
    "Evaluation",
    "Evaluator",
    "InputFileError",
    "JointTrajectory",
    "Optimum",
    "PathFileError",
    "PlacementDetail",
    "PlacementError",
    "PlacementResult",
    "PlacementSpace",
    "Robot",
    "RobotFileError",
    "SearchSettings",
    "TaskTrajectory",
    "ToolPath",
    "UnknownRobotError",
    "UnreachableError",
    "actuator_efforts",
    "builtin_robots",
    "check_robot",
    "default_space",
    "inverse_dynamics",
    "joint_trajectory",
    "load_path",
    "load_robot",
    "optimize_placement",
    "register_motor_model",
    "solve_configuration",
]
