"""placement: energy-optimal placement of tool paths for serial and closed-loop robots.

The public API, in data-flow order: load a robot (:func:`load_robot`), describe the end-effector
motion (:class:`TaskTrajectory`), solve every joint's motion (:func:`joint_trajectory`) and the
actuator efforts (:func:`inverse_dynamics`); :func:`check_robot` proves a robot model exact.
"""

from placement.checks import CheckReport, check_robot
from placement.dynamics import ActuatorTrajectory, actuator_efforts, inverse_dynamics
from placement.exceptions import PlacementError, RobotFileError, UnknownRobotError, UnreachableError
from placement.kinematics import JointTrajectory, TaskTrajectory, joint_trajectory, solve_configuration
from placement.robot import Actuator, Closure, Robot, builtin_robots, load_robot

__all__ = [
    "Actuator",
    "ActuatorTrajectory",
    "CheckReport",
    "Closure",
    "JointTrajectory",
    "PlacementError",
    "Robot",
    "RobotFileError",
    "TaskTrajectory",
    "UnknownRobotError",
    "UnreachableError",
    "actuator_efforts",
    "builtin_robots",
    "check_robot",
    "inverse_dynamics",
    "joint_trajectory",
    "load_robot",
    "solve_configuration",
]
