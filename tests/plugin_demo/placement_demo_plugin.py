"""A stand-in for a separately installed package that adds plug-in family members.

It is declared as an installed distribution (``placement_demo_plugin-0.1.dist-info``) whose entry
points register an objective, a motor model and a limit, exactly as ``pip install`` of a package
with ``[project.entry-points."placement.objectives"]`` would. It imports what it builds on from the
plug-in contract, :mod:`placement.contract`, and the motor model it extends from :mod:`placement.drives.motors`.
"""

import numpy as np

from placement.contract import EvaluatedBatch, Limit, MarginField, Objective, PathBound
from placement.drives.motors import Motor, Pmsm, PowerParts


class PeakMotorSpeed(Objective):
    """Largest |motor speed| over the path and the motors."""

    title = "peak motor speed"
    unit = "rad/s"

    def __call__(self, batch: EvaluatedBatch) -> np.ndarray:
        return np.abs(batch.motor.speed_rad_s).max(axis=(1, 2))


class StandbyPmsm(Pmsm):
    """The paper's motor plus a constant drive standby power ``parameters.standby_W`` (W)."""

    def check(self, motor: Motor) -> None:
        super().check(motor)
        if "standby_W" not in motor.parameters:
            raise ValueError("the standby_pmsm model needs parameters.standby_W")

    def interval_power(self, motor, speed_rad_s, current_A, dt_s):
        parts = super().interval_power(motor, speed_rad_s, current_A, dt_s)
        standby = motor.parameters["standby_W"] * (dt_s > 0)
        return PowerParts(parts.joule_W + standby, parts.inductive_W, parts.back_emf_W)


class HalfJointSpeed(Limit):
    """Every actuated joint at half its top speed at most (a shop's rule for a machine's first runs)."""

    share = 0.5

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        top = self._top(batch.robot)
        names = tuple(a.joint for a in batch.robot.actuators)
        return [MarginField("half joint speed", (top - np.abs(batch.velocity)) / top, batch.velocity,
                            np.broadcast_to(top, batch.velocity.shape), names, ("",) * len(names))]

    def path_bounds(self, robot, dynamics) -> list[PathBound]:
        return [PathBound("half joint speed", dynamics.joint_velocity, self._top(robot))]

    def _top(self, robot) -> np.ndarray:
        return self.share * np.array([a.velocity_max for a in robot.actuators])


peak_motor_speed = PeakMotorSpeed()
half_joint_speed = HalfJointSpeed()
standby_pmsm = StandbyPmsm()
