"""placement: energy-optimal placement of tool paths for serial and closed-loop robots.

The public API, in data-flow order: load a robot (:func:`load_robot`) and a path
(:func:`load_path`), put the robot in a cell (:func:`load_cell`, :func:`equip`), search the best
and worst placements by an objective (:func:`optimize_placement`, electric energy by default),
trade two or three objectives off (:func:`pareto_front`), map an objective over a grid
(:func:`sweep`), or evaluate placements yourself (:class:`Evaluator`). Underneath: the
end-effector motion (:class:`TaskTrajectory`), every joint's motion (:func:`joint_trajectory`),
the actuator efforts (:func:`inverse_dynamics`); :func:`check_robot` proves a robot model exact.

Plug-in families (objectives, limits, motor models, regeneration policies, transmissions,
kinematics solvers, robots) each have a base class and a registry that installed packages extend
through entry points; see :mod:`placement.registry`.

``__version__`` is the distribution's version (:func:`placement.distribution.version`). ``import placement``
loads the core only: the scene, the plots, Pareto fronts' NSGA-II, the workbench and a Dask cluster import
their optional packages (the extras, :mod:`placement.distribution`) when they are used.
"""

from placement.cell.cell_file import Cell, load_cell
from placement.contract.limit import LIMITS, Limit, Margin, MarginField
from placement.contract.objective import OBJECTIVES, Objective
from placement.distribution import version
from placement.drives.motors import MOTOR_MODELS, MotorModel, PowerParts, register_motor_model
from placement.drives.transmissions import TRANSMISSIONS, Transmission
from placement.dynamics.inverse import ActuatorTrajectory, actuator_efforts, inverse_dynamics
from placement.energy.integration import Energy
from placement.energy.regeneration import REGENERATION, RegenerationPolicy
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.evaluation.results import Evaluation, PlacementDetail
from placement.exceptions import (
    InfeasibleError,
    InputFileError,
    MissingExtraError,
    PlacementError,
    PlacementWarning,
    PluginError,
    SettingsError,
    UnknownMemberError,
)
from placement.kinematics import joint_trajectory
from placement.kinematics.base import SOLVERS, KinematicsSolver
from placement.kinematics.exceptions import UnreachableError
from placement.kinematics.generic import solve_configuration
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory
from placement.path.exceptions import PathFileError
from placement.path.load import load_path
from placement.path.toolpath import ToolPath
from placement.robot import Actuator, Closure
from placement.robot.equip import equip
from placement.robot.exceptions import RobotFileError, UnknownRobotError
from placement.robot.model import Robot
from placement.search.optimize import Optimum, PlacementResult, SearchSettings, optimize_placement
from placement.search.pareto import FrontMember, ParetoFront, pareto_front
from placement.search.space import PlacementSpace, default_space
from placement.search.sweep import SweepResult, sweep
from placement.workshop.catalog import robot_names
from placement.workshop.checks import CheckReport, check_robot
from placement.workshop.load import load_robot

__version__ = version()

__all__ = [
    "LIMITS",
    "MOTOR_MODELS",
    "OBJECTIVES",
    "REGENERATION",
    "SOLVERS",
    "TRANSMISSIONS",
    "Actuator",
    "ActuatorTrajectory",
    "Cell",
    "CheckReport",
    "Closure",
    "Energy",
    "Evaluation",
    "Evaluator",
    "EvaluatorSettings",
    "FrontMember",
    "InfeasibleError",
    "InputFileError",
    "JointTrajectory",
    "KinematicsSolver",
    "Limit",
    "Margin",
    "MarginField",
    "MissingExtraError",
    "MotorModel",
    "Objective",
    "Optimum",
    "ParetoFront",
    "PathFileError",
    "PlacementDetail",
    "PlacementError",
    "PlacementResult",
    "PlacementSpace",
    "PlacementWarning",
    "PluginError",
    "PowerParts",
    "RegenerationPolicy",
    "Robot",
    "RobotFileError",
    "SearchSettings",
    "SettingsError",
    "SweepResult",
    "TaskTrajectory",
    "ToolPath",
    "Transmission",
    "UnknownMemberError",
    "UnknownRobotError",
    "UnreachableError",
    "actuator_efforts",
    "check_robot",
    "default_space",
    "equip",
    "inverse_dynamics",
    "joint_trajectory",
    "load_cell",
    "load_path",
    "load_robot",
    "optimize_placement",
    "pareto_front",
    "register_motor_model",
    "robot_names",
    "solve_configuration",
    "sweep",
]
