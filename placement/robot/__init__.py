"""Robots as data: a URDF spanning tree plus a sidecar, loaded into a validated :class:`Robot`."""

from placement.robot.catalog import robot_names
from placement.robot.load import load_robot
from placement.robot.model import Actuator, Closure, Robot

__all__ = ["Actuator", "Closure", "Robot", "load_robot", "robot_names"]
