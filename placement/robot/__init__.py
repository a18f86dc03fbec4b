"""Robots as data: a URDF spanning tree plus a sidecar, built into a validated :class:`Robot`.

Loading by name or file, with the kinematics checked, is :func:`placement.workshop.load.load_robot`.
"""

from placement.robot.model import Actuator, Closure, Robot

__all__ = ["Actuator", "Closure", "Robot"]
