"""A stand-in for a separately installed package that adds plug-in family members.

It is declared as an installed distribution (``placement_demo_plugin-0.1.dist-info``) whose entry
points register an objective and a motor model, exactly as ``pip install`` of a package with
``[project.entry-points."placement.objectives"]`` would.
"""

import numpy as np

from placement.batch import EvaluatedBatch
from placement.drives.motors import Motor, Pmsm, PowerParts
from placement.objectives import Objective


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


peak_motor_speed = PeakMotorSpeed()
standby_pmsm = StandbyPmsm()
